/* refine in 3-D: a cube of Kuhn tetrahedra, a split step that puts a node near
   the end of an edge (slivers, as a split-mode cut makes them), then conformal
   longest-edge bisection (lib/refine/bisect3d.c): every face in at most two tets
   with opposite orientations and open faces only on the cube's surface, volume
   kept, every tet positive, the worst tet never worse (slivers with a short
   edge are left: no bisection improves them, and the worst of the whole mesh
   never worse), the tets a split wrote better than the worst before (qUAl),
   while the count of bad tets grows by at most the tets added (the children of
   a split star may stay above the bound, none is worse than the star's worst; a
   tet no split improves stays, unwritten); the update invariant (K from scratch
   = eq. 3.1); a later step re-cutting a bisected tet is refused with its
   message. */
#include <math.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_refine.h"
#include "t.h"

static void cube(aug_mesh *m, int n)
{
    aug_mesh_init(m);
    m->dim = 3, m->nv = 4, m->etype = AUG_TET4;
    int q = n + 1;
    m->nn = (int64_t)q * q * q;
    m->x = malloc((size_t)m->nn * 3 * sizeof *m->x);
    for (int k = 0; k < q; k++)
        for (int j = 0; j < q; j++)
            for (int i = 0; i < q; i++) {
                double *p = m->x + 3 * ((k * q + j) * q + i);
                p[0] = (double)i / n, p[1] = (double)j / n, p[2] = (double)k / n;
            }
    m->ne = 6 * (int64_t)n * n * n;
    m->conn = malloc((size_t)m->ne * 4 * sizeof *m->conn);
    m->mat = calloc((size_t)m->ne, sizeof *m->mat);
    /* Kuhn: the 6 paths from corner 0 to corner 7 of each cell */
    static const int perm[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
    int64_t e = 0;
    for (int k = 0; k < n; k++)
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++)
                for (int s = 0; s < 6; s++) {
                    int c = 0, v[4];
                    v[0] = 0;
                    for (int t = 0; t < 3; t++) c += perm[s][t], v[t + 1] = c;
                    int32_t id[4];
                    for (int t = 0; t < 4; t++)
                        id[t] = ((k + (v[t] >> 2 & 1)) * q + j + (v[t] >> 1 & 1)) * q + i + (v[t] & 1);
                    m->conn[4 * e] = id[0], m->conn[4 * e + 1] = id[1];
                    m->conn[4 * e + 2] = id[2], m->conn[4 * e + 3] = id[3];
                    if (aug_elem_measure(m, e) < 0) { /* orient positively */
                        int32_t x = m->conn[4 * e + 2];
                        m->conn[4 * e + 2] = m->conn[4 * e + 3], m->conn[4 * e + 3] = x;
                    }
                    e++;
                }
    m->nmat = 1;
    m->mats = calloc(1, sizeof *m->mats);
    strcpy(m->mats[0].name, "cube");
    m->mats[0].E = 100, m->mats[0].nu = 0.3, m->mats[0].rho = 1, m->mats[0].t = 1;
    m->nfix = 3 * (int64_t)q * q; /* z = 0 fixed */
    m->fix_dof = malloc((size_t)m->nfix * sizeof *m->fix_dof);
    m->fix_val = calloc((size_t)m->nfix, sizeof *m->fix_val);
    for (int64_t i = 0; i < (int64_t)q * q; i++)
        for (int c = 0; c < 3; c++) m->fix_dof[3 * i + c] = (int32_t)(3 * i + c);
    m->have = AUG_HAVE_NODE | AUG_HAVE_ELEM | AUG_HAVE_MATL | AUG_HAVE_FIXD;
}

/* a split step: node at fraction s of edge a-b, every tet around the edge split */
static void split_edge(const aug_mesh *m, int32_t a, int32_t b, double s, int32_t step, aug_mdelta *d)
{
    aug_mdelta_init(d);
    d->step = step;
    d->nnew = 1;
    d->parent = malloc(sizeof *d->parent);
    d->x = malloc(3 * sizeof *d->x);
    d->parent[0] = s < 0.5 ? a : b;
    for (int c = 0; c < 3; c++) d->x[c] = (1 - s) * m->x[3 * a + c] + s * m->x[3 * b + c];
    int32_t p = (int32_t)m->nn;
    d->elem = malloc((size_t)m->ne * sizeof *d->elem);
    d->conn = malloc((size_t)m->ne * 4 * sizeof *d->conn);
    d->conn_add = malloc((size_t)m->ne * 4 * sizeof *d->conn_add);
    d->mat_add = calloc((size_t)m->ne, sizeof *d->mat_add);
    for (int64_t e = 0; e < m->ne; e++) {
        const int32_t *v = m->conn + 4 * e;
        int ia = -1, ib = -1;
        for (int j = 0; j < 4; j++) ia = v[j] == a ? j : ia, ib = v[j] == b ? j : ib;
        if (ia < 0 || ib < 0) continue;
        int32_t *c1 = d->conn + 4 * d->nmod, *c2 = d->conn_add + 4 * d->nadd;
        memcpy(c1, v, 4 * sizeof *v);
        memcpy(c2, v, 4 * sizeof *v);
        c1[ib] = p, c2[ia] = p;
        d->mat_add[d->nadd++] = m->mat[e];
        d->elem[d->nmod++] = (int32_t)e;
    }
}

/* total volume (-1 if a tet is not positive); bad = tets with R / (3 r) above
   bound, worst = the largest R / (3 r) */
static double tvol(const aug_mesh *m, int64_t *bad, double bound, double *worst)
{
    double v = 0;
    *bad = 0;
    *worst = 0;
    for (int64_t e = 0; e < m->ne; e++) {
        double x = aug_elem_measure(m, e);
        if (!(x > 0)) return -1;
        v += x;
        aug_quality q;
        aug_elem_quality(m, e, &q);
        *bad += q.aspect > bound;
        *worst = fmax(*worst, q.aspect);
    }
    return v;
}

static int cmp3(const void *x, const void *y)
{
    const int32_t *a = x, *b = y;
    for (int i = 0; i < 3; i++)
        if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
    return 0;
}

/* faces: at most two tets, opposite orientations; open faces on the cube surface */
static int64_t faces_bad(const aug_mesh *m)
{
    static const int F[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    int64_t nf = 4 * m->ne, bad = 0;
    int32_t(*f)[5] = malloc((size_t)nf * sizeof *f);
    for (int64_t e = 0; e < m->ne; e++)
        for (int k = 0; k < 4; k++) {
            int32_t *g = f[4 * e + k];
            for (int j = 0; j < 3; j++) g[j] = m->conn[4 * e + F[k][j]];
            /* rotate the smallest first, keep orientation; g[3]: orientation key */
            while (g[0] > g[1] || g[0] > g[2]) {
                int32_t x = g[0];
                g[0] = g[1], g[1] = g[2], g[2] = x;
            }
            g[3] = g[1] < g[2] ? 0 : 1;
            if (g[3]) {
                int32_t x = g[1];
                g[1] = g[2], g[2] = x;
            }
            g[4] = (int32_t)e;
        }
    qsort(f, (size_t)nf, sizeof *f, cmp3);
    for (int64_t i = 0; i < nf;) {
        int64_t j = i + 1;
        while (j < nf && !memcmp(f[i], f[j], 3 * sizeof(int32_t))) j++;
        if (j - i > 2) bad++;
        else if (j - i == 2 && f[i][3] == f[i + 1][3]) bad++;
        else if (j - i == 1) {
            int on = 0;
            for (int c = 0; c < 3 && !on; c++) {
                double lo = INFINITY, hi = -INFINITY;
                for (int64_t k = 0; k < m->nn; k++) lo = fmin(lo, m->x[3 * k + c]), hi = fmax(hi, m->x[3 * k + c]);
                double x0 = m->x[3 * f[i][0] + c];
                on = (x0 == lo || x0 == hi) && m->x[3 * f[i][1] + c] == x0 && m->x[3 * f[i][2] + c] == x0;
            }
            bad += !on;
        }
        i = j;
    }
    free(f);
    return bad;
}

static void bisect_slivers(void)
{
    cholmod_common cm;
    cholmod_start(&cm);
    aug_mesh C, D;
    cube(&C, 4);
    cube(&D, 4);
    aug_refine_opt o;
    aug_refine_opt_default(&o);
    aug_refiner R;
    aug_err e;
    T_CHECK(aug_refiner_init(&R, &C, &o, &e) == 0, "init: %s", e.msg);
    int64_t bad0;
    double w0, wc, w1;
    double v0 = tvol(&C, &bad0, o.max_aspect3, &w0);
    T_CHECK(bad0 == 0, "%lld bad tets in the Kuhn cube (worst %.3g)", (long long)bad0, w0);
    cholmod_sparse *K0 = aug_assemble_cut(&D, R.nn0, R.map0, R.nfree0, &cm, &e);
    /* the interior edge from node (2,2,2) to (3,3,3), split at 4% */
    int32_t a = (2 * 5 + 2) * 5 + 2, b = (3 * 5 + 3) * 5 + 3;
    aug_mdelta d, out;
    split_edge(&C, a, b, 0.04, 1, &d);
    aug_mesh cutview;
    cube(&cutview, 4);
    aug_mesh_apply(&cutview, &d, &e);
    int64_t badc;
    tvol(&cutview, &badc, o.max_aspect3, &wc);
    aug_update u;
    aug_refine_q q;
    T_CHECK(aug_refine_step(&R, &d, NULL, NULL, 0, &out, NULL, &u, &q, &e) == 0, "refine: %s", e.msg);
    T_CHECK(aug_mesh_apply(&D, &out, &e) == 0, "apply: %s", e.msg);
    int64_t bad1;
    double v1 = tvol(&D, &bad1, o.max_aspect3, &w1);
    T_CHECK(v1 > 0, "a tet is inverted or flat");
    T_CHECK(fabs(v1 - v0) < 1e-12, "volume %.17g, was %.17g", v1, v0);
    int64_t fb = faces_bad(&D);
    T_CHECK(fb == 0, "%lld non-conformal faces", (long long)fb);
    T_CHECK(badc > bad0, "the split made no bad tet");
    /* a node 4% along an edge makes wedges with one short edge, which no edge
       bisection improves: refine must leave them no worse */
    T_CHECK(bad1 <= badc && q.aspect_max <= q.aspect_max0 && w1 <= wc, "bad tets %lld -> %lld, worst %.3g -> %.3g"
            " (mesh %.3g -> %.3g)", (long long)badc, (long long)bad1, q.aspect_max0, q.aspect_max, wc, w1);
    printf("# 3-D: split made %lld bad tets (max aspect %.3g), refine left %lld (max %.3g); "
           "%lld bisections, %lld tets added\n",
           (long long)badc, q.aspect_max0, (long long)bad1, q.aspect_max, (long long)q.bisections,
           (long long)q.added);
    /* update invariant */
    cholmod_sparse *K1 = aug_assemble_cut(&D, R.nn0, R.map0, R.nfree0, &cm, &e);
    int64_t n0 = (int64_t)K0->nrow, n1 = (int64_t)K1->nrow, s = (int64_t)u.m + u.k;
    T_CHECK(n1 == n0 + u.k, "order %lld, expected %lld + %d", (long long)n1, (long long)n0, u.k);
    if (n1 == n0 + u.k) {
        double *A = calloc((size_t)(n1 * n1), sizeof *A), *Bm = calloc((size_t)(n1 * n1), sizeof *Bm);
        const int32_t *p0 = K0->p, *i0 = K0->i, *p1 = K1->p, *i1 = K1->i;
        const double *x0 = K0->x, *x1 = K1->x;
        for (int64_t j = 0; j < n0; j++)
            for (int32_t k = p0[j]; k < p0[j + 1]; k++) A[i0[k] + j * n1] = A[j + i0[k] * n1] = x0[k];
        for (int64_t j = n0; j < n1; j++) A[j + j * n1] = 1;
        for (int64_t j = 0; j < n1; j++)
            for (int32_t k = p1[j]; k < p1[j + 1]; k++) Bm[i1[k] + j * n1] = Bm[j + i1[k] * n1] = x1[k];
        for (int64_t x = 0; x < s; x++)
            for (int64_t y = 0; y < s; y++) {
                int64_t hx = x < u.m ? u.H[x] : n0 + x - u.m, hy = y < u.m ? u.H[y] : n0 + y - u.m;
                A[hx + hy * n1] -= u.E[x + y * s] + (x >= u.m && x == y);
            }
        double dm = 0, km = 0;
        for (int64_t i = 0; i < n1 * n1; i++) dm = fmax(dm, fabs(A[i] - Bm[i])), km = fmax(km, fabs(Bm[i]));
        T_CHECK(dm < 1e-13 * km, "K from scratch differs from the update form by %.3g", dm / km);
        free(A), free(Bm);
    }
    cholmod_free_sparse(&K0, &cm);
    cholmod_free_sparse(&K1, &cm);
    aug_update_free(&u);
    aug_mdelta_free(&d);
    aug_mdelta_free(&out);
    aug_mesh_free(&cutview);
    aug_refiner_free(&R);
    aug_mesh_free(&C);
    aug_mesh_free(&D);
    cholmod_finish(&cm);
}

/* a deterministic jitter of the interior nodes (amplitude amp of the spacing) */
static void jitter(aug_mesh *m, int n, double amp)
{
    uint32_t r = 12345;
    for (int64_t i = 0; i < m->nn; i++)
        for (int c = 0; c < 3; c++) {
            r = r * 1664525u + 1013904223u;
            double x = m->x[3 * i + c];
            if (x > 0 && x < 1) m->x[3 * i + c] += amp / n * ((r >> 8) / 16777216.0 - 0.5);
        }
}

/* jittered Kuhn tets, all in one step: the refine step splits what it can
   improve (the worst tet better, conformal, volume kept); a later
   step re-cutting a bisected tet is refused with its message */
static void jittered(void)
{
    aug_mesh C, D;
    cube(&C, 4);
    cube(&D, 4);
    jitter(&C, 4, 0.5);
    jitter(&D, 4, 0.5);
    aug_refine_opt o;
    aug_refine_opt_default(&o);
    o.max_aspect3 = 1.5; /* strict: most tets are "bad" */
    aug_refiner R;
    aug_err e;
    T_CHECK(aug_refiner_init(&R, &C, &o, &e) == 0, "init: %s", e.msg);
    int64_t bad0;
    double w0, w1;
    double v0 = tvol(&D, &bad0, 1.5, &w0);
    /* a step that re-writes every tet as it is (every tet is the step's) */
    int32_t a = (2 * 5 + 2) * 5 + 2;
    aug_mdelta d, out;
    aug_mdelta_init(&d);
    d.step = 1;
    d.parent = malloc(sizeof *d.parent); /* empty, not NULL */
    d.x = malloc(3 * sizeof *d.x);
    d.conn_add = malloc(4 * sizeof *d.conn_add);
    d.mat_add = malloc(sizeof *d.mat_add);
    d.nmod = C.ne;
    d.elem = malloc((size_t)C.ne * sizeof *d.elem);
    d.conn = malloc((size_t)C.ne * 4 * sizeof *d.conn);
    for (int64_t t = 0; t < C.ne; t++) d.elem[t] = (int32_t)t;
    memcpy(d.conn, C.conn, (size_t)C.ne * 4 * sizeof *d.conn);
    aug_mesh cutview;
    cube(&cutview, 4);
    jitter(&cutview, 4, 0.5);
    aug_mesh_apply(&cutview, &d, &e);
    aug_refine_q q;
    T_CHECK(aug_refine_step(&R, &d, NULL, NULL, 0, &out, NULL, NULL, &q, &e) == 0, "refine: %s", e.msg);
    T_CHECK(aug_mesh_apply(&D, &out, &e) == 0, "apply: %s", e.msg);
    int64_t bad1;
    double v1 = tvol(&D, &bad1, 1.5, &w1);
    T_CHECK(v1 > 0 && fabs(v1 - v0) < 1e-12, "volume %.17g, was %.17g", v1, v0);
    T_CHECK(w1 <= w0, "the mesh's worst tet %.3g -> %.3g", w0, w1);
    T_CHECK(bad1 <= bad0 + q.added, "bad tets %lld -> %lld with %lld tets added", (long long)bad0,
            (long long)bad1, (long long)q.added);
    T_CHECK(faces_bad(&D) == 0, "not conformal");
    T_CHECK(q.bisections > 0, "no split improved anything");
    T_CHECK(q.aspect_max < q.aspect_max0, "worst aspect %.3g -> %.3g", q.aspect_max0, q.aspect_max);
    printf("# jittered: %lld bisections, %lld tets added; bad tets %lld -> %lld; step's worst aspect %.3g -> %.3g,"
           " mean %.3g -> %.3g\n", (long long)q.bisections, (long long)q.added, (long long)bad0, (long long)bad1,
           q.aspect_max0, q.aspect_max, q.aspect_mean0, q.aspect_mean);
    /* re-cut: split an edge at some node whose tets refine bisected */
    int refused = 0;
    for (int32_t v = 0; v < cutview.nn * cutview.nn && !refused; v++) {
        a = v / (int32_t)cutview.nn;
        if (v % cutview.nn == a) continue;
        aug_mdelta d2, out2;
        split_edge(&cutview, a, v % (int32_t)cutview.nn, 0.5, 2, &d2);
        int hit = 0;
        for (int64_t i = 0; i < d2.nmod; i++) hit |= R.cel[d2.elem[i]] < 0;
        if (d2.nmod && hit) {
            int rc = aug_refine_step(&R, &d2, NULL, NULL, 0, &out2, NULL, NULL, &q, &e);
            T_CHECK(rc == AUG_EDATA && strstr(e.msg, "re-cutting refined tetrahedra"), "re-cut: rc %d %s", rc,
                    e.msg);
            refused = 1;
        }
        aug_mdelta_free(&d2);
    }
    T_CHECK(refused, "no bisected tet to re-cut");
    aug_mdelta_free(&d);
    aug_mdelta_free(&out);
    aug_mesh_free(&cutview);
    aug_refiner_free(&R);
    aug_mesh_free(&C);
    aug_mesh_free(&D);
}

int main(void)
{
    T_RUN(bisect_slivers);
    T_RUN(jittered);
    T_EXIT();
}
