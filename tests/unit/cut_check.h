/* Test helpers for the cut tests: structured meshes made in code, and the
   invariant checker (K_t from scratch == K_0 padded minus the accumulated
   updates, loads, measure, conformity). */
#ifndef CUT_CHECK_H
#define CUT_CHECK_H
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_rng.h>
#include "augcut.h"

static inline void cc_add_set(aug_mesh *m, const char *name, const int32_t *nodes, int64_t n)
{
    m->sets = realloc(m->sets, (size_t)(m->nset + 1) * sizeof *m->sets);
    aug_set *s = &m->sets[m->nset++];
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "%s", name);
    s->n = n;
    s->nodes = malloc((size_t)(n + 1) * sizeof *s->nodes);
    memcpy(s->nodes, nodes, (size_t)n * sizeof *nodes);
}

static inline void cc_materials(aug_mesh *m, int nmat)
{
    m->nmat = nmat;
    m->mats = calloc((size_t)nmat, sizeof *m->mats);
    for (int i = 0; i < nmat; i++) {
        m->mats[i].id = i + 1;
        snprintf(m->mats[i].name, sizeof m->mats[i].name, "mat%d", i);
        m->mats[i].E = i == 0 ? 1.0 : 1000.0; /* a material jump of 1e3 */
        m->mats[i].nu = i == 0 ? 0.3 : 0.45;
        m->mats[i].rho = 1;
        m->mats[i].t = 1;
    }
    m->have |= AUG_HAVE_MATL;
}

/* fix every component of the nodes with coordinate `axis` == 0 (values: val*random or 0);
   loads on the nodes at the far end */
static inline void cc_bc(aug_mesh *m, int axis, double far, gsl_rng *r, double fixval)
{
    int dim = m->dim;
    int64_t nf = 0, nl = 0;
    int32_t *fs = malloc((size_t)m->nn * sizeof *fs), *ls = malloc((size_t)m->nn * sizeof *ls);
    m->fix_dof = malloc((size_t)(m->nn * dim) * sizeof *m->fix_dof);
    m->fix_val = malloc((size_t)(m->nn * dim) * sizeof *m->fix_val);
    m->load_dof = malloc((size_t)(m->nn * dim) * sizeof *m->load_dof);
    m->load_val = malloc((size_t)(m->nn * dim) * sizeof *m->load_val);
    m->nfix = m->nload = 0;
    for (int64_t i = 0; i < m->nn; i++) {
        double x = m->x[i * dim + axis];
        if (x == 0) {
            fs[nf++] = (int32_t)i;
            for (int c = 0; c < dim; c++) {
                m->fix_dof[m->nfix] = (int32_t)(i * dim + c);
                m->fix_val[m->nfix++] = r ? fixval * (gsl_rng_uniform(r) - 0.5) : 0.0;
            }
        }
        if (fabs(x - far) < 1e-12) {
            ls[nl++] = (int32_t)i;
            for (int c = 0; c < dim; c++) {
                m->load_dof[m->nload] = (int32_t)(i * dim + c);
                m->load_val[m->nload++] = r ? gsl_rng_uniform(r) - 0.5 : (c == 0 ? 0.01 : 0.0);
            }
        }
    }
    cc_add_set(m, "fixed", fs, nf);
    cc_add_set(m, "far", ls, nl);
    free(fs);
    free(ls);
    m->have |= AUG_HAVE_FIXD | AUG_HAVE_LOAD;
}

/* nx x ny x nz hexahedral cells of size lx/nx .. split into 6 tets each
   (Kuhn: the paths from corner 000 to 111), fixed at z = 0 */
static inline void cc_brick(aug_mesh *m, int nx, int ny, int nz, double lx, double ly, double lz,
                     gsl_rng *r, double fixval)
{
    aug_mesh_init(m);
    m->dim = 3;
    m->etype = AUG_TET4;
    m->nv = 4;
    m->nn = (int64_t)(nx + 1) * (ny + 1) * (nz + 1);
    m->x = malloc((size_t)(m->nn * 3) * sizeof *m->x);
#define NID(i, j, k) ((int32_t)(((k) * (ny + 1) + (j)) * (nx + 1) + (i)))
    for (int k = 0; k <= nz; k++)
        for (int j = 0; j <= ny; j++)
            for (int i = 0; i <= nx; i++) {
                double *p = m->x + (int64_t)NID(i, j, k) * 3;
                p[0] = lx * i / nx;
                p[1] = ly * j / ny;
                p[2] = lz * k / nz;
            }
    m->ne = (int64_t)nx * ny * nz * 6;
    m->conn = malloc((size_t)(m->ne * 4) * sizeof *m->conn);
    m->mat = malloc((size_t)m->ne * sizeof *m->mat);
    static const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    int64_t el = 0;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++)
                for (int p = 0; p < 6; p++) {
                    int c[3] = {i, j, k};
                    int32_t *t = m->conn + el * 4;
                    t[0] = NID(c[0], c[1], c[2]);
                    for (int s = 0; s < 3; s++) {
                        c[perm[p][s]]++;
                        t[s + 1] = NID(c[0], c[1], c[2]);
                    }
                    m->mat[el] = k >= nz / 2; /* two materials, top and bottom */
                    el++;
                }
#undef NID
    cc_materials(m, 2);
    m->have |= AUG_HAVE_NODE | AUG_HAVE_ELEM;
    for (int64_t e = 0; e < m->ne; e++)
        if (aug_elem_measure(m, e) < 0) {
            int32_t t = m->conn[e * 4 + 1];
            m->conn[e * 4 + 1] = m->conn[e * 4 + 2];
            m->conn[e * 4 + 2] = t;
        }
    cc_bc(m, 2, lz, r, fixval);
}

/* the same brick as nx x ny x nz trilinear hexahedra (gmsh node order), two
   materials (top and bottom halves), fixed at z = 0 */
static inline void cc_hexbrick(aug_mesh *m, int nx, int ny, int nz, double lx, double ly, double lz,
                               gsl_rng *r, double fixval)
{
    cc_brick(m, nx, ny, nz, lx, ly, lz, NULL, 0);
    free(m->conn);
    free(m->mat);
    free(m->fix_dof), free(m->fix_val), free(m->load_dof), free(m->load_val);
    for (int i = 0; i < m->nset; i++) free(m->sets[i].nodes);
    m->nset = 0;
    m->etype = AUG_HEX8;
    m->nv = 8;
    m->ne = (int64_t)nx * ny * nz;
    m->conn = malloc((size_t)(m->ne * 8) * sizeof *m->conn);
    m->mat = malloc((size_t)m->ne * sizeof *m->mat);
    static const int bits[8] = {0, 1, 3, 2, 4, 5, 7, 6}; /* x=1 y=2 z=4 */
    int64_t el = 0;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++, el++) {
                for (int a = 0; a < 8; a++)
                    m->conn[el * 8 + a] = (int32_t)(((k + (bits[a] >> 2 & 1)) * (ny + 1) + j + (bits[a] >> 1 & 1)) *
                                                        (nx + 1) + i + (bits[a] & 1));
                m->mat[el] = k >= nz / 2;
            }
    cc_bc(m, 2, lz, r, fixval);
}

/* nx x ny squares of [0,lx]x[0,ly], each split along the same diagonal, fixed at x = 0 */
static inline void cc_square(aug_mesh *m, int nx, int ny, double lx, double ly, gsl_rng *r, double fixval)
{
    aug_mesh_init(m);
    m->dim = 2;
    m->etype = AUG_TRI3;
    m->nv = 3;
    m->nn = (int64_t)(nx + 1) * (ny + 1);
    m->x = malloc((size_t)(m->nn * 2) * sizeof *m->x);
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) {
            m->x[(j * (nx + 1) + i) * 2] = lx * i / nx;
            m->x[(j * (nx + 1) + i) * 2 + 1] = ly * j / ny;
        }
    m->ne = (int64_t)nx * ny * 2;
    m->conn = malloc((size_t)(m->ne * 3) * sizeof *m->conn);
    m->mat = malloc((size_t)m->ne * sizeof *m->mat);
    int64_t el = 0;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            int32_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
            int32_t t1[3] = {a, b, c}, t2[3] = {a, c, d};
            memcpy(m->conn + el * 3, t1, sizeof t1);
            m->mat[el++] = i >= nx / 2;
            memcpy(m->conn + el * 3, t2, sizeof t2);
            m->mat[el++] = i >= nx / 2;
        }
    cc_materials(m, 2);
    m->have |= AUG_HAVE_NODE | AUG_HAVE_ELEM;
    cc_bc(m, 0, lx, r, fixval);
}

/* ---- the invariant checker ---- */
typedef struct cc_track {
    int64_t nn0, nfree0, n, cap;
    int32_t *map0;
    double *K, *f;          /* dense accumulated K_t (cap x cap storage, n used), f_t */
    double vol0;
    double *ang0;           /* 2-D: angle sum at each original node */
    double lo[2], hi[2];    /* 2-D: the rectangle */
    char why[400];
} cc_track;

static inline double cc_total_measure(const aug_mesh *m, double *minv)
{
    double s = 0, mn = INFINITY;
    for (int64_t e = 0; e < m->ne; e++) {
        double v = aug_elem_measure(m, e);
        s += v;
        if (v < mn) mn = v;
    }
    if (minv) *minv = mn;
    return s;
}

static inline void cc_dense(const cholmod_sparse *A, double *D, int64_t ld)
{
    const int *Ap = A->p, *Ai = A->i;
    const double *Ax = A->x;
    for (size_t j = 0; j < A->ncol; j++)
        for (int p = Ap[j]; p < Ap[j + 1]; p++) {
            D[Ai[p] + (int64_t)j * ld] += Ax[p];
            if ((size_t)Ai[p] != j) D[j + (int64_t)Ai[p] * ld] += Ax[p];
        }
}

static inline double cc_angle(const double *o, const double *a, const double *b)
{
    double u[2] = {a[0] - o[0], a[1] - o[1]}, v[2] = {b[0] - o[0], b[1] - o[1]};
    return atan2(fabs(u[0] * v[1] - u[1] * v[0]), u[0] * v[0] + u[1] * v[1]);
}

static inline void cc_angles(const aug_mesh *m, double *ang)
{
    memset(ang, 0, (size_t)m->nn * sizeof *ang);
    for (int64_t e = 0; e < m->ne; e++) {
        const int32_t *c = m->conn + e * 3;
        for (int k = 0; k < 3; k++)
            ang[c[k]] += cc_angle(m->x + c[k] * 2, m->x + c[(k + 1) % 3] * 2, m->x + c[(k + 2) % 3] * 2);
    }
}

/* start tracking: K_0, f_0 from scratch; also compared with the factor
   helper's aug_assemble / aug_load_vector (independent code) */
static inline int cc_init(cc_track *T, const aug_mesh *m, cholmod_common *cm)
{
    aug_err e;
    memset(T, 0, sizeof *T);
    T->nn0 = m->nn;
    T->map0 = malloc((size_t)(m->nn * m->dim) * sizeof *T->map0);
    T->nfree0 = aug_dofmap(m, T->map0);
    T->n = T->nfree0;
    T->cap = T->n + 1200 * m->dim;
    T->K = calloc((size_t)(T->cap * T->cap), sizeof *T->K);
    T->f = calloc((size_t)T->cap, sizeof *T->f);
    cholmod_sparse *A = aug_assemble_cut(m, T->nn0, T->map0, T->nfree0, cm, &e);
    if (!A) {
        snprintf(T->why, sizeof T->why, "assemble_cut: %s", e.msg);
        return -1;
    }
    cc_dense(A, T->K, T->cap);
    cholmod_free_sparse(&A, cm);
    if (aug_load_cut(m, T->nn0, T->map0, T->nfree0, T->f, &e)) return -1;
    /* cross-check with the factor layer's assembly */
    cholmod_sparse *B = aug_assemble(m, T->map0, T->nfree0, AUG_MAT_K, cm, &e);
    if (!B) {
        snprintf(T->why, sizeof T->why, "aug_assemble: %s", e.msg);
        return -1;
    }
    double *D = calloc((size_t)(T->n * T->n) + 1, sizeof *D), mx = 0, df = 0;
    cc_dense(B, D, T->n);
    cholmod_free_sparse(&B, cm);
    for (int64_t j = 0; j < T->n; j++)
        for (int64_t i = 0; i < T->n; i++) {
            mx = fmax(mx, fabs(D[i + j * T->n]));
            df = fmax(df, fabs(D[i + j * T->n] - T->K[i + j * T->cap]));
        }
    free(D);
    if (df > 1e-12 * mx) {
        snprintf(T->why, sizeof T->why, "K0 differs from aug_assemble by %g (max %g)", df, mx);
        return -1;
    }
    double *f2 = calloc((size_t)T->n + 1, sizeof *f2), fm = 0;
    df = 0;
    if (aug_load_vector(m, T->map0, T->nfree0, f2, &e)) return -1;
    for (int64_t i = 0; i < T->n; i++) {
        fm = fmax(fm, fabs(f2[i]));
        df = fmax(df, fabs(f2[i] - T->f[i]));
    }
    free(f2);
    if (df > 1e-12 * (fm + 1)) {
        snprintf(T->why, sizeof T->why, "f0 differs from aug_load_vector by %g", df);
        return -1;
    }
    T->vol0 = cc_total_measure(m, NULL);
    if (m->dim == 2) {
        T->ang0 = malloc((size_t)m->nn * sizeof *T->ang0);
        cc_angles(m, T->ang0);
        T->lo[0] = T->lo[1] = INFINITY;
        T->hi[0] = T->hi[1] = -INFINITY;
        for (int64_t i = 0; i < m->nn; i++)
            for (int k = 0; k < 2; k++) {
                T->lo[k] = fmin(T->lo[k], m->x[i * 2 + k]);
                T->hi[k] = fmax(T->hi[k], m->x[i * 2 + k]);
            }
    }
    return 0;
}

static inline void cc_free(cc_track *T)
{
    free(T->map0);
    free(T->K);
    free(T->f);
    free(T->ang0);
    memset(T, 0, sizeof *T);
}

/* K_t = [K_{t-1} 0; 0 I] - Hbar (E + [0 0; 0 I]) Hbar',  f_t = [f_{t-1}; 0] + Hbar df */
static inline int cc_apply(cc_track *T, const aug_update *u)
{
    int64_t n = T->n, s = u->m + u->k;
    if (n + u->k > T->cap) {
        snprintf(T->why, sizeof T->why, "test capacity exceeded");
        return -1;
    }
    for (int64_t i = n; i < n + u->k; i++) {
        T->K[i + i * T->cap] = 1.0;
        T->f[i] = 0;
    }
    int64_t *g = malloc((size_t)(s + 1) * sizeof *g);
    for (int64_t p = 0; p < s; p++) g[p] = p < u->m ? u->H[p] : n + (p - u->m);
    for (int64_t q = 0; q < s; q++) {
        for (int64_t p = 0; p < s; p++)
            T->K[g[p] + g[q] * T->cap] -= u->E[p + q * s] + (p == q && p >= u->m ? 1.0 : 0.0);
        T->f[g[q]] += u->df[q];
    }
    free(g);
    T->n = n + u->k;
    return 0;
}

/* compare with the mesh assembled from scratch; measure and conformity */
static inline int cc_check(cc_track *T, const aug_mesh *m, cholmod_common *cm, int step)
{
    aug_err e;
    int64_t n = aug_cut_order(m, T->nn0, T->nfree0);
    if (n != T->n) {
        snprintf(T->why, sizeof T->why, "step %d: order %lld, updates give %lld", step, (long long)n,
                 (long long)T->n);
        return -1;
    }
    cholmod_sparse *A = aug_assemble_cut(m, T->nn0, T->map0, T->nfree0, cm, &e);
    double *D = calloc((size_t)(n * n) + 1, sizeof *D), *f = calloc((size_t)n + 1, sizeof *f);
    cc_dense(A, D, n);
    cholmod_free_sparse(&A, cm);
    aug_load_cut(m, T->nn0, T->map0, T->nfree0, f, &e);
    double mx = 0, dk = 0, fm = 0, dfm = 0, vmax = 0;
    int64_t wi = 0, wj = 0;
    for (int64_t j = 0; j < n; j++)
        for (int64_t i = 0; i < n; i++) {
            double a = D[i + j * n], b = T->K[i + j * T->cap];
            mx = fmax(mx, fabs(a));
            if (fabs(a - b) > dk) {
                dk = fabs(a - b);
                wi = i;
                wj = j;
            }
        }
    for (int64_t i = 0; i < m->nfix; i++) vmax = fmax(vmax, fabs(m->fix_val[i]));
    for (int64_t i = 0; i < n; i++) {
        fm = fmax(fm, fabs(f[i]));
        dfm = fmax(dfm, fabs(f[i] - T->f[i]));
    }
    free(D);
    free(f);
    if (dk > 1e-12 * mx) {
        snprintf(T->why, sizeof T->why, "step %d: K differs by %.3g at (%lld,%lld), max|K| %.3g",
                 step, dk, (long long)wi, (long long)wj, mx);
        return -1;
    }
    if (dfm > 1e-12 * (fm + mx * vmax)) {
        snprintf(T->why, sizeof T->why, "step %d: f differs by %.3g (max|f| %.3g)", step, dfm, fm);
        return -1;
    }
    double mn, vol = cc_total_measure(m, &mn);
    if (fabs(vol - T->vol0) > 1e-12 * T->vol0) {
        snprintf(T->why, sizeof T->why, "step %d: measure %.17g, was %.17g", step, vol, T->vol0);
        return -1;
    }
    if (!(mn > 1e-14 * T->vol0)) {
        snprintf(T->why, sizeof T->why, "step %d: an element of measure %g", step, mn);
        return -1;
    }
    return 0;
}

/* faces (sorted node tuples) used by 1 and by 2 elements; -1 if any by more */
typedef struct cc_faces {
    int64_t one, two, more;
} cc_faces;

static inline int cmp_face(const void *a, const void *b)
{
    return memcmp(a, b, 3 * sizeof(int32_t)) < 0 ? -1 : memcmp(a, b, 3 * sizeof(int32_t)) > 0;
}

static inline int cmp_face3(const void *a, const void *b)
{
    const int32_t *x = a, *y = b;
    for (int k = 0; k < 3; k++)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

/* facets of an element, written here from gmsh's conventions (not the
   library's tables): tri3 edges, tet4 triangles (every node but one), hex8
   quadrilaterals; facet f of element e as its sorted nodes, padded with -1 */
static inline int cc_nfacets(const aug_mesh *m) { return m->nv == 8 ? 6 : m->nv; }

static inline void cc_facet(const aug_mesh *m, int64_t e, int f, int32_t q[4])
{
    static const int hexf[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 4, 5}, {1, 2, 5, 6}, {2, 3, 6, 7}, {0, 3, 4, 7}};
    int nv = m->nv, k = 0;
    q[2] = q[3] = -1;
    if (nv == 8)
        for (k = 0; k < 4; k++) q[k] = m->conn[e * 8 + hexf[f][k]];
    else
        for (int a = 0; a < nv; a++)
            if (a != f) q[k++] = m->conn[e * nv + a];
    for (int i = 1; i < k; i++)
        for (int j = i; j > 0 && q[j - 1] > q[j]; j--) {
            int32_t t = q[j];
            q[j] = q[j - 1];
            q[j - 1] = t;
        }
}

static inline int cmp_face4(const void *a, const void *b)
{
    const int32_t *x = a, *y = b;
    for (int k = 0; k < 4; k++)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

static inline cc_faces cc_count_faces(const aug_mesh *m)
{
    int nf = cc_nfacets(m);
    int64_t n = m->ne * nf;
    int32_t *F = malloc((size_t)(n * 4 + 1) * sizeof *F);
    for (int64_t e = 0; e < m->ne; e++)
        for (int f = 0; f < nf; f++) cc_facet(m, e, f, F + (e * nf + f) * 4);
    qsort(F, (size_t)n, 4 * sizeof *F, cmp_face4);
    cc_faces r = {0, 0, 0};
    for (int64_t i = 0; i < n;) {
        int64_t j = i;
        while (j < n && cmp_face4(F + j * 4, F + i * 4) == 0) j++;
        if (j - i == 1) r.one++;
        else if (j - i == 2) r.two++;
        else r.more++;
        i = j;
    }
    (void)cmp_face;
    free(F);
    return r;
}

/* 2-D conformity: no T-junction (a node inside an edge held by one triangle
   whose two halves are edges too); and at every node position the angles of
   all triangles around it (over all the nodes there) plus pi for each
   one-triangle edge running through it (the far side of an open cut) sum to
   2 pi inside, pi on an edge of the rectangle, pi/2 at its corners: no gap,
   no overlap. */
typedef struct cc_pt {
    double x, y, a;
    int done;
} cc_pt;

static inline int cmp_pt(const void *a, const void *b)
{
    const cc_pt *p = a, *q = b;
    if (p->x != q->x) return p->x < q->x ? -1 : 1;
    return (p->y > q->y) - (p->y < q->y);
}

static inline int cc_has_edge(const aug_mesh *m, int32_t a, int32_t b)
{
    for (int64_t e = 0; e < m->ne; e++) {
        const int32_t *c = m->conn + e * 3;
        int ha = c[0] == a || c[1] == a || c[2] == a, hb = c[0] == b || c[1] == b || c[2] == b;
        if (ha && hb) return 1;
    }
    return 0;
}

/* parameter of p on segment ab when p lies on it strictly inside, else -1 */
static inline double cc_inside(const double *a, const double *b, const double *p)
{
    double d[2] = {b[0] - a[0], b[1] - a[1]}, L2 = d[0] * d[0] + d[1] * d[1];
    double s = ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / L2;
    double cr = fabs((p[0] - a[0]) * d[1] - (p[1] - a[1]) * d[0]) / sqrt(L2);
    return (s > 1e-9 && s < 1 - 1e-9 && cr < 1e-11) ? s : -1;
}

static inline int cc_check_angles(cc_track *T, const aug_mesh *m, int step)
{
    /* one-triangle edges */
    int64_t ne3 = m->ne * 3, nb = 0;
    int32_t *E = malloc((size_t)(ne3 * 3 + 1) * sizeof *E), *B = malloc((size_t)(ne3 * 2 + 1) * sizeof *B);
    for (int64_t e = 0; e < m->ne; e++)
        for (int k = 0; k < 3; k++) {
            int32_t a = m->conn[e * 3 + k], b = m->conn[e * 3 + (k + 1) % 3];
            E[(e * 3 + k) * 3] = a < b ? a : b;
            E[(e * 3 + k) * 3 + 1] = a < b ? b : a;
            E[(e * 3 + k) * 3 + 2] = 0;
        }
    qsort(E, (size_t)ne3, 3 * sizeof *E, cmp_face3);
    for (int64_t i = 0; i < ne3;) {
        int64_t j = i;
        while (j < ne3 && E[j * 3] == E[i * 3] && E[j * 3 + 1] == E[i * 3 + 1]) j++;
        if (j - i == 1) {
            B[nb * 2] = E[i * 3];
            B[nb * 2 + 1] = E[i * 3 + 1];
            nb++;
        }
        i = j;
    }
    free(E);
    double *ang = malloc((size_t)m->nn * sizeof *ang);
    cc_angles(m, ang);
    cc_pt *p = malloc((size_t)m->nn * sizeof *p);
    for (int64_t i = 0; i < m->nn; i++) p[i] = (cc_pt){m->x[i * 2], m->x[i * 2 + 1], ang[i], 0};
    qsort(p, (size_t)m->nn, sizeof *p, cmp_pt);
    int bad = 0;
    for (int64_t i = 0; i < m->nn && !bad; i++) {
        if (p[i].done) continue;
        /* the nodes at this point (the two sides of a crossed cut may differ in the last bits) */
        double s = 0;
        for (int64_t j = i; j < m->nn && p[j].x - p[i].x <= 1e-11; j++)
            if (!p[j].done && fabs(p[j].y - p[i].y) <= 1e-11) {
                s += p[j].a;
                p[j].done = 1;
            }
        double x = p[i].x, y = p[i].y, want = 2 * M_PI, q[2] = {x, y};
        for (int64_t k = 0; k < nb; k++)
            if (cc_inside(m->x + B[k * 2] * 2, m->x + B[k * 2 + 1] * 2, q) > 0) s += M_PI;
        int onx = x == T->lo[0] || x == T->hi[0], ony = y == T->lo[1] || y == T->hi[1];
        if (onx && ony) want = M_PI / 2;
        else if (onx || ony) want = M_PI;
        if (fabs(s - want) > 1e-9) {
            snprintf(T->why, sizeof T->why, "step %d: angles at (%.17g, %.17g) sum to %.12g, want %.12g",
                     step, x, y, s, want);
            bad = 1;
        }
    }
    for (int64_t k = 0; k < nb && !bad; k++)
        for (int64_t v = 0; v < m->nn && !bad; v++) {
            int32_t a = B[k * 2], b = B[k * 2 + 1];
            if (cc_inside(m->x + a * 2, m->x + b * 2, m->x + v * 2) > 0 &&
                cc_has_edge(m, a, (int32_t)v) && cc_has_edge(m, (int32_t)v, b)) {
                snprintf(T->why, sizeof T->why, "step %d: hanging node %lld on edge (%d, %d)", step,
                         (long long)v, a, b);
                bad = 1;
            }
        }
    free(p);
    free(ang);
    free(B);
    return bad ? -1 : 0;
}

/* smallest / largest eigenvalue of the dense symmetric K_t of the tracker */
static inline double cc_min_eig_ratio(const cc_track *T)
{
    int64_t n = T->n;
    gsl_matrix *A = gsl_matrix_alloc((size_t)n, (size_t)n);
    for (int64_t i = 0; i < n; i++)
        for (int64_t j = 0; j < n; j++) gsl_matrix_set(A, (size_t)i, (size_t)j, T->K[i + j * T->cap]);
    gsl_vector *w = gsl_vector_alloc((size_t)n);
    gsl_eigen_symm_workspace *ws = gsl_eigen_symm_alloc((size_t)n);
    gsl_eigen_symm(A, w, ws);
    double mn = INFINITY, mx = 0;
    for (int64_t i = 0; i < n; i++) {
        mn = fmin(mn, gsl_vector_get(w, (size_t)i));
        mx = fmax(mx, fabs(gsl_vector_get(w, (size_t)i)));
    }
    gsl_eigen_symm_free(ws);
    gsl_vector_free(w);
    gsl_matrix_free(A);
    return mn / mx;
}

static inline void cc_mesh_copy(aug_mesh *t, const aug_mesh *m)
{
    *t = *m;
#define DUP(F, N)                                                        \
    do {                                                                 \
        t->F = malloc((size_t)((N) + 1) * sizeof *m->F);                 \
        if ((N) > 0) memcpy(t->F, m->F, (size_t)(N) * sizeof *m->F);    \
    } while (0)
    DUP(x, m->nn * m->dim);
    DUP(conn, m->ne * m->nv);
    DUP(mat, m->ne);
    DUP(mats, m->nmat);
    DUP(fix_dof, m->nfix);
    DUP(fix_val, m->nfix);
    DUP(load_dof, m->nload);
    DUP(load_val, m->nload);
    DUP(out_nodes, m->nout);
    DUP(sets, m->nset);
#undef DUP
    for (int i = 0; i < m->nset; i++) {
        t->sets[i].nodes = malloc((size_t)(m->sets[i].n + 1) * sizeof(int32_t));
        memcpy(t->sets[i].nodes, m->sets[i].nodes, (size_t)m->sets[i].n * sizeof(int32_t));
    }
}
#endif
