/* The membrane triangle (mem3) in 3-D: the element against the 2-D plane-stress
   triangle rotated, the patch test on a flat sheet in an arbitrary orientation,
   the zero-stiffness modes of single triangles, flat, curved and closed sheets
   against the rank of the bar framework of their edges, mass totals, and the
   singular-scene checks, the mesh records of a mem3 mesh, and the Winkler
   foundation (FNDN). */
#include <lapacke.h>
#include "t.h"
#include "fem_mesh.h"

static cholmod_common cm;

/* an orthogonal Q (columns: the images of x, y, z), det +1, from three angles */
static void rotation(double a, double b, double c, double Q[3][3])
{
    double Rz[3][3] = {{cos(a), -sin(a), 0}, {sin(a), cos(a), 0}, {0, 0, 1}};
    double Ry[3][3] = {{cos(b), 0, sin(b)}, {0, 1, 0}, {-sin(b), 0, cos(b)}};
    double Rx[3][3] = {{1, 0, 0}, {0, cos(c), -sin(c)}, {0, sin(c), cos(c)}};
    double T[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            T[i][j] = 0;
            for (int k = 0; k < 3; k++) T[i][j] += Ry[i][k] * Rx[k][j];
        }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            Q[i][j] = 0;
            for (int k = 0; k < 3; k++) Q[i][j] += Rz[i][k] * T[k][j];
        }
}

/* the mem3 copy of the 2-D mesh m2, node x -> o + Q (x, y, h(x, y)) */
typedef double (*height_fn)(double x, double y);
static void lift(aug_mesh *m, const aug_mesh *m2, double Q[3][3], const double *o, height_fn h)
{
    aug_mesh_copy(m, m2);
    free(m->x);
    m->dim = 3, m->etype = AUG_MEM3;
    m->x = malloc((size_t)m->nn * 3 * sizeof(double));
    for (int64_t i = 0; i < m->nn; i++) {
        double p[3] = {m2->x[i * 2], m2->x[i * 2 + 1], h ? h(m2->x[i * 2], m2->x[i * 2 + 1]) : 0};
        for (int r = 0; r < 3; r++) m->x[i * 3 + r] = o[r] + Q[r][0] * p[0] + Q[r][1] * p[1] + Q[r][2] * p[2];
    }
}

static void distort2(aug_mesh *m, double frac, double h)
{
    unsigned char *bd = calloc((size_t)m->nn, 1);
    aug_mesh_boundary_nodes(m, bd);
    for (int64_t i = 0; i < m->nn; i++)
        if (!bd[i])
            for (int c = 0; c < 2; c++) m->x[i * 2 + c] += frac * h * sin(3.7 * i + 1.3 * c + 0.5);
    free(bd);
}

/* number of eigenvalues <= tol lambda_max of the n x n symmetric A */
static int zero_count(int n, const double *A, double tol, double *lmax)
{
    double *B = malloc((size_t)n * n * sizeof *B), *w = malloc((size_t)n * sizeof *w);
    memcpy(B, A, (size_t)n * n * sizeof *B);
    LAPACKE_dsyev(LAPACK_COL_MAJOR, 'N', 'U', n, B, n, w);
    int z = 0;
    for (int i = 0; i < n; i++) z += w[i] <= tol * w[n - 1];
    if (lmax) *lmax = w[n - 1];
    free(B);
    free(w);
    return z;
}

/* the dense K of m over all 3 nn DOFs (nothing fixed) */
static double *dense_K(const aug_mesh *m)
{
    aug_mesh c;
    aug_mesh_copy(&c, m);
    c.nfix = 0;
    int32_t *map = malloc((size_t)c.nn * 3 * sizeof *map);
    int64_t nf = aug_dofmap(&c, map);
    aug_err e;
    cholmod_sparse *K = aug_assemble(&c, map, nf, AUG_MAT_K, &cm, &e);
    double *D = tm_dense(K);
    cholmod_free_sparse(&K, &cm);
    free(map);
    aug_mesh_free(&c);
    return D;
}

/* 3 nn - rank of the rigidity matrix of the bar framework whose bars are the
   edges of the triangles ([Asimow & Roth 1978]): the in-plane strain of a
   triangle vanishes exactly when its 3 edge lengths are stationary, so this
   is the dimension of the null space of the membrane K, computed without it
   (one row (p_i - p_j) at i, -(p_i - p_j) at j per edge; rank by LAPACK
   dgesdd, singular values > 1e-10 s_max) */
static int framework_kernel(const aug_mesh *m)
{
    int n = (int)m->nn * 3, ne = 0;
    int32_t (*ed)[2] = malloc((size_t)m->ne * 3 * sizeof *ed);
    for (int64_t t = 0; t < m->ne; t++)
        for (int k = 0; k < 3; k++) {
            int32_t a = m->conn[t * 3 + k], b = m->conn[t * 3 + (k + 1) % 3];
            if (a > b) { int32_t s = a; a = b; b = s; }
            int dup = 0;
            for (int q = 0; q < ne && !dup; q++) dup = ed[q][0] == a && ed[q][1] == b;
            if (!dup) ed[ne][0] = a, ed[ne][1] = b, ne++;
        }
    double *R = calloc((size_t)ne * n, sizeof *R), *s = malloc((size_t)(ne < n ? ne : n) * sizeof *s);
    for (int q = 0; q < ne; q++)
        for (int c = 0; c < 3; c++) {
            double d = m->x[ed[q][0] * 3 + c] - m->x[ed[q][1] * 3 + c];
            R[(size_t)(ed[q][0] * 3 + c) * ne + q] = d;
            R[(size_t)(ed[q][1] * 3 + c) * ne + q] = -d;
        }
    LAPACKE_dgesdd(LAPACK_COL_MAJOR, 'N', ne, n, R, ne, s, NULL, 1, NULL, 1);
    int rank = 0, k = ne < n ? ne : n;
    for (int i = 0; i < k; i++) rank += s[i] > 1e-10 * s[0];
    free(R);
    free(s);
    free(ed);
    return n - rank;
}

static const double origin[3] = {0.3, -1.2, 2.5};

/* Ke(mem3) = T' Ke(tri3) T, T = diag(Q2', Q2', Q2'), Q2 the first two columns
   of Q: the 2-D element of elem_stiffness.c rotated, for each triangle of a
   distorted mesh and three orientations */
static void test_element_is_rotated_plane_stress(void)
{
    aug_mesh m2, m3;
    tm_rect(&m2, 3, 2, 1.0, 0.8, 70.0, 0.33, 0.2);
    distort2(&m2, 0.25, 0.3);
    double ang[3][3] = {{0.3, 0.7, -1.1}, {2.0, -0.4, 0.9}, {0, M_PI / 2, 0}};
    for (int o = 0; o < 3; o++) {
        double Q[3][3];
        rotation(ang[o][0], ang[o][1], ang[o][2], Q);
        lift(&m3, &m2, Q, origin, NULL);
        for (int64_t e = 0; e < m2.ne; e++) {
            double K2[36], K3[81], kmax = 0, err = 0;
            aug_elem_stiffness(&m2, e, K2);
            aug_elem_stiffness(&m3, e, K3);
            T_CHECK(fabs(aug_elem_measure(&m3, e) - aug_elem_measure(&m2, e)) <= 1e-14,
                    "element %lld: area %g, 2-D %g", (long long)e, aug_elem_measure(&m3, e),
                    aug_elem_measure(&m2, e));
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++)
                    for (int i = 0; i < 3; i++)
                        for (int j = 0; j < 3; j++) {
                            double r = 0;
                            for (int k = 0; k < 2; k++)
                                for (int l = 0; l < 2; l++)
                                    r += Q[i][k] * Q[j][l] * K2[(b * 2 + l) * 6 + a * 2 + k];
                            double v = K3[(b * 3 + j) * 9 + a * 3 + i];
                            kmax = fmax(kmax, fabs(r));
                            err = fmax(err, fabs(v - r));
                        }
            T_CHECK(err <= 1e-13 * kmax, "orientation %d element %lld: |K3 - T'K2T| = %g of %g", o,
                    (long long)e, err, kmax);
        }
        aug_mesh_free(&m3);
    }
    aug_mesh_free(&m2);
}

/* a constant in-plane strain u2 = G x2 (G = [a b; c d], x2 the sheet's own
   coordinates) lifted to 3-D, u = Q2 G x2: the assembled K of the flat
   sheet in an arbitrary orientation gives zero force at every interior node
   (K u)_i = 0, and with u prescribed on the boundary the interior solution
   restricted to the sheet's plane (v = Q2 w, K_red = T' K_II T) reproduces
   u exactly */
static void test_patch_flat_sheet_any_orientation(void)
{
    aug_mesh m2, m;
    tm_rect(&m2, 5, 4, 1.0, 0.8, 70.0, 0.33, 0.2);
    distort2(&m2, 0.3, 0.2);
    double Q[3][3], G[2][2] = {{1e-3, -4e-4}, {7e-4, 2e-4}};
    rotation(0.9, -0.6, 1.3, Q);
    lift(&m, &m2, Q, origin, NULL);
    int n = (int)m.nn * 3;
    double *K = dense_K(&m), *u = malloc((size_t)n * sizeof *u), kmax = 0;
    for (int i = 0; i < n * n; i++) kmax = fmax(kmax, fabs(K[i]));
    for (int64_t i = 0; i < m.nn; i++) {
        const double *x2 = m2.x + i * 2;
        double w[2] = {G[0][0] * x2[0] + G[0][1] * x2[1], G[1][0] * x2[0] + G[1][1] * x2[1]};
        for (int r = 0; r < 3; r++) u[i * 3 + r] = Q[r][0] * w[0] + Q[r][1] * w[1];
    }
    unsigned char *bd = calloc((size_t)m.nn, 1);
    aug_mesh_boundary_nodes(&m, bd);
    double fmax_int = 0;
    int nint = 0;
    for (int64_t i = 0; i < m.nn; i++) {
        if (bd[i]) continue;
        nint++;
        for (int r = 0; r < 3; r++) {
            double s = 0;
            for (int k = 0; k < n; k++) s += K[(size_t)k * n + i * 3 + r] * u[k];
            fmax_int = fmax(fmax_int, fabs(s));
        }
    }
    T_CHECK(nint > 0 && fmax_int <= 1e-13 * kmax, "interior force %g (|K| %g)", fmax_int, kmax);
    /* the reduced solve: unknowns w_i (2 per interior node), v_i = Q2 w_i */
    int ni = 2 * nint, *id = malloc((size_t)m.nn * sizeof *id), q = 0;
    for (int64_t i = 0; i < m.nn; i++) id[i] = bd[i] ? -1 : q++;
    double *A = calloc((size_t)ni * ni, sizeof *A), *b = calloc((size_t)ni, sizeof *b);
    for (int64_t i = 0; i < m.nn; i++) {
        if (id[i] < 0) continue;
        for (int k = 0; k < 2; k++) {
            int row = id[i] * 2 + k;
            for (int64_t j = 0; j < m.nn; j++)
                for (int r = 0; r < 3; r++)
                    for (int c = 0; c < 3; c++) {
                        double kv = K[(size_t)(j * 3 + c) * n + i * 3 + r] * Q[r][k];
                        if (id[j] < 0) b[row] -= kv * u[j * 3 + c];
                        else
                            for (int l = 0; l < 2; l++) A[(size_t)(id[j] * 2 + l) * ni + row] += kv * Q[c][l];
                    }
        }
    }
    int *piv = malloc((size_t)ni * sizeof *piv);
    int info = LAPACKE_dgesv(LAPACK_COL_MAJOR, ni, 1, A, ni, piv, b, ni);
    double err = 0;
    for (int64_t i = 0; i < m.nn && !info; i++) {
        if (id[i] < 0) continue;
        for (int r = 0; r < 3; r++) {
            double v = Q[r][0] * b[id[i] * 2] + Q[r][1] * b[id[i] * 2 + 1];
            err = fmax(err, fabs(v - u[i * 3 + r]));
        }
    }
    T_CHECK(info == 0 && err <= 1e-12 * 1e-3, "reduced solve: info %d, |u - exact| = %g", info, err);
    free(piv);
    free(A);
    free(b);
    free(id);
    free(bd);
    free(K);
    free(u);
    aug_mesh_free(&m);
    aug_mesh_free(&m2);
}

static double bump(double x, double y) { return 0.4 * (x * x - 0.7 * y * y) + 0.2 * x * y; }
static double dome(double x, double y) { return sqrt(4.0 - (x - 0.5) * (x - 0.5) - (y - 0.4) * (y - 0.4)) - 1.9; }

/* zero eigenvalues (<= 1e-10 lambda_max) of the element and assembled K:
   one triangle in any orientation 6 (3 in-plane rigid + 3 out-of-plane:
   normal translation and 2 tilts, all rigid motions of 3-D); a flat sheet of
   nn nodes 3 + nn (any normal field w); a closed convex sheet (octahedron,
   Dehn's theorem) exactly 6; an open curved sheet (saddle, dome: free edges)
   more than 6, exactly the null space of its edge framework, at least
   3 nn - (its edges) */
static void test_zero_stiffness_modes(void)
{
    double Q[3][3];
    rotation(0.4, 1.1, -0.5, Q);
    aug_mesh m2, m;
    tm_rect(&m2, 4, 3, 1.0, 0.8, 70.0, 0.33, 0.2);
    distort2(&m2, 0.25, 0.25);
    lift(&m, &m2, Q, origin, NULL);
    for (int64_t e = 0; e < m.ne; e++) {
        double K[81];
        aug_elem_stiffness(&m, e, K);
        int z = zero_count(9, K, 1e-10, NULL);
        T_CHECK(z == 6, "flat triangle %lld: %d zero eigenvalues, want 6", (long long)e, z);
    }
    double *K = dense_K(&m);
    int z = zero_count((int)m.nn * 3, K, 1e-10, NULL);
    T_CHECK(z == 3 + (int)m.nn, "flat sheet of %lld nodes: %d zero eigenvalues, want %lld", (long long)m.nn, z,
            (long long)(3 + m.nn));
    T_CHECK(framework_kernel(&m) == z, "flat sheet: framework kernel %d, K %d", framework_kernel(&m), z);
    free(K);
    aug_mesh_free(&m);
    height_fn hs[2] = {bump, dome};
    for (int q = 0; q < 2; q++) {
        lift(&m, &m2, Q, origin, hs[q]);
        K = dense_K(&m);
        z = zero_count((int)m.nn * 3, K, 1e-10, NULL);
        int fk = framework_kernel(&m);
        T_CHECK(z == fk && z > 6, "curved open sheet %d: %d zero eigenvalues, framework %d", q, z, fk);
        for (int64_t e = 0; e < m.ne; e++) {
            double Ke[81];
            aug_elem_stiffness(&m, e, Ke);
            T_CHECK(zero_count(9, Ke, 1e-10, NULL) == 6, "curved sheet %d: triangle %lld", q, (long long)e);
        }
        free(K);
        aug_mesh_free(&m);
    }
    aug_mesh_free(&m2);
    /* the octahedron, vertices +-a_k e_k (a convex closed sheet) */
    aug_mesh o;
    aug_mesh_init(&o);
    o.dim = 3, o.etype = AUG_MEM3, o.nv = 3, o.nn = 6, o.ne = 8;
    double a[3] = {1.0, 1.3, 0.8};
    o.x = calloc(18, sizeof(double));
    for (int k = 0; k < 3; k++) o.x[(2 * k) * 3 + k] = a[k], o.x[(2 * k + 1) * 3 + k] = -a[k];
    o.conn = malloc(24 * sizeof(int32_t));
    o.mat = calloc(8, sizeof(int32_t));
    for (int t = 0; t < 8; t++) {
        o.conn[t * 3] = (t & 1), o.conn[t * 3 + 1] = 2 + ((t >> 1) & 1), o.conn[t * 3 + 2] = 4 + ((t >> 2) & 1);
    }
    tm_material(&o, 1, 5.0, 0.25, 1.0, 0.1);
    K = dense_K(&o);
    z = zero_count(18, K, 1e-10, NULL);
    T_CHECK(z == 6 && framework_kernel(&o) == 6, "octahedron: %d zero eigenvalues (framework %d), want 6", z,
            framework_kernel(&o));
    free(K);
    aug_mesh_free(&o);
}

/* the consistent and lumped mass of a curved sheet: each component's total
   is rho t (its area), the area a sum of |cross| / 2 computed here */
static void test_mass_totals(void)
{
    double Q[3][3];
    rotation(-0.7, 0.2, 0.6, Q);
    aug_mesh m2, m;
    tm_rect(&m2, 4, 3, 1.0, 0.8, 70.0, 0.33, 0.2);
    lift(&m, &m2, Q, origin, bump);
    m.mats[0].rho = 2.5;
    double area = 0;
    for (int64_t e = 0; e < m.ne; e++) {
        const double *p0 = m.x + m.conn[e * 3] * 3, *p1 = m.x + m.conn[e * 3 + 1] * 3, *p2 = m.x + m.conn[e * 3 + 2] * 3;
        double u[3], v[3];
        for (int c = 0; c < 3; c++) u[c] = p1[c] - p0[c], v[c] = p2[c] - p0[c];
        area += 0.5 * sqrt(pow(u[1] * v[2] - u[2] * v[1], 2) + pow(u[2] * v[0] - u[0] * v[2], 2) +
                           pow(u[0] * v[1] - u[1] * v[0], 2));
    }
    for (int lumped = 0; lumped < 2; lumped++) {
        double tot[3] = {0, 0, 0}, Me[81];
        for (int64_t e = 0; e < m.ne; e++) {
            aug_elem_mass(&m, e, lumped, Me);
            for (int i = 0; i < 9; i++)
                for (int j = 0; j < 9; j++)
                    if (i % 3 == j % 3) tot[i % 3] += Me[j * 9 + i];
        }
        for (int c = 0; c < 3; c++)
            T_CHECK(t_reldiff(tot[c], 2.5 * 0.2 * area) <= 1e-13, "lumped %d component %d: %g, want %g", lumped, c,
                    tot[c], 2.5 * 0.2 * area);
    }
    aug_mesh_free(&m);
    aug_mesh_free(&m2);
}

/* aug_check_support: a flat sheet clamped on its whole boundary is singular
   (the normal of an interior node, named); the same sheet curved (dome) is
   held; a curved sheet held on one edge is singular too (a corner's single
   triangle, or the rigid modes) */
static void test_support_checks(void)
{
    double Q[3][3];
    rotation(0.2, 0.3, 0.1, Q);
    aug_mesh m2, m;
    tm_rect(&m2, 4, 4, 1.0, 1.0, 70.0, 0.33, 0.2);
    unsigned char *bd = calloc((size_t)m2.nn, 1);
    aug_mesh_boundary_nodes(&m2, bd);
    aug_err e;
    lift(&m, &m2, Q, origin, NULL);
    tm_fix_nodes(&m, bd, NULL);
    int rc = aug_check_support(&m, &e);
    T_CHECK(rc == AUG_ESINGULAR && strstr(e.msg, "no stiffness along"), "flat clamped: rc %d (%s)", rc, e.msg);
    aug_mesh_free(&m);
    lift(&m, &m2, Q, origin, dome);
    tm_fix_nodes(&m, bd, NULL);
    rc = aug_check_support(&m, &e);
    T_CHECK(rc == 0, "dome clamped: rc %d (%s)", rc, e.msg);
    aug_mesh_free(&m);
    lift(&m, &m2, Q, origin, dome);
    for (int64_t i = 0; i < m.nn; i++) bd[i] = m2.x[i * 2 + 1] == 0;
    tm_fix_nodes(&m, bd, NULL);
    rc = aug_check_support(&m, &e);
    T_CHECK(rc == AUG_ESINGULAR, "dome on one edge: rc %d", rc);
    aug_mesh_free(&m);
    free(bd);
    aug_mesh_free(&m2);
}

/* the mesh records of m written and read back (aug_mesh_write, aug_mesh_absorb):
   0 and the copy in r, or the reader's error code with e naming the record */
static int record_trip(const aug_mesh *m, aug_mesh *r, aug_err *e)
{
    char *buf = NULL;
    size_t len;
    FILE *f = open_memstream(&buf, &len);
    aug_writer *w = aug_writer_open(f, "t", e);
    int rc = aug_mesh_write(w, m, e);
    aug_writer_close(w, e);
    aug_writer_free(w);
    fclose(f);
    aug_mesh_init(r);
    f = fmemopen(buf, len, "rb");
    aug_reader *rd = aug_reader_open(f, "mem", e);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    while (!rc && aug_read(rd, &rec, e) == 1)
        if (aug_mesh_is_record(rec.type)) rc = aug_mesh_absorb(r, &rec, e);
    if (!rc) rc = aug_mesh_validate(r, e);
    aug_rec_free(&rec);
    aug_reader_free(rd);
    fclose(f);
    free(buf);
    return rc;
}

/* formats/stream.md 5.3: ELEM etype 1002 (mem3) with nv 3 in a NODE of dim 3
   round-trips; a mem3 ELEM in dim 2, a tri3 ELEM in dim 3 and a degenerate
   (collinear) mem3 triangle are refused naming ELEM */
static void test_mesh_record(void)
{
    double Q[3][3];
    rotation(0.5, 0.5, 0.5, Q);
    aug_mesh m2, m, r;
    tm_rect(&m2, 2, 2, 1.0, 1.0, 70.0, 0.33, 0.2);
    lift(&m, &m2, Q, origin, bump);
    aug_err e;
    int rc = record_trip(&m, &r, &e);
    T_CHECK(rc == 0 && r.etype == AUG_MEM3 && r.dim == 3 && r.nv == 3 && r.nn == m.nn && r.ne == m.ne &&
                !memcmp(r.x, m.x, (size_t)m.nn * 3 * sizeof(double)) &&
                !memcmp(r.conn, m.conn, (size_t)m.ne * 3 * sizeof(int32_t)),
            "round trip: rc %d (%s)", rc, e.msg);
    aug_mesh_free(&r);
    m.etype = AUG_TRI3;
    rc = record_trip(&m, &r, &e);
    T_CHECK(rc != 0 && !strcmp(e.type, "ELEM") && strstr(e.msg, "dimension 3"), "tri3 in 3-D: rc %d %s %s",
            rc, e.type, e.msg);
    aug_mesh_free(&r);
    m2.etype = AUG_MEM3;
    rc = record_trip(&m2, &r, &e);
    T_CHECK(rc != 0 && !strcmp(e.type, "ELEM"), "mem3 in 2-D: rc %d %s %s", rc, e.type, e.msg);
    aug_mesh_free(&r);
    m2.etype = AUG_TRI3;
    m.etype = AUG_MEM3;
    const int32_t *c = m.conn + 3; /* triangle 1: its third node onto the line of the other two */
    for (int k = 0; k < 3; k++) m.x[c[2] * 3 + k] = 0.5 * (m.x[c[0] * 3 + k] + m.x[c[1] * 3 + k]);
    rc = record_trip(&m, &r, &e);
    T_CHECK(rc == AUG_EDATA && !strcmp(e.type, "ELEM") && strstr(e.msg, "degenerate"), "collinear: rc %d %s %s",
            rc, e.type, e.msg);
    aug_mesh_free(&r);
    aug_mesh_free(&m);
    aug_mesh_free(&m2);
}

/* a Winkler foundation k (FNDN): the element's zero modes drop to the 3
   in-plane rigid ones, and so do a flat sheet's (3 + nn without); the
   foundation part is k A (1 + delta_ab) / 12 n n' (the difference of the
   matrices with and without, against n from the corners); the FNDN record
   round-trips, and a negative k or a foundation on tri3 is refused */
static void test_foundation(void)
{
    double Q[3][3];
    rotation(0.8, -0.3, 0.4, Q);
    aug_mesh m2, m, r;
    tm_rect(&m2, 3, 3, 1.0, 1.0, 70.0, 0.33, 0.2);
    distort2(&m2, 0.2, 0.3);
    lift(&m, &m2, Q, origin, NULL);
    const double k = 3.5;
    double K0[81], K1[81];
    for (int64_t e = 0; e < m.ne; e++) {
        m.mats[0].kf = 0;
        aug_elem_stiffness(&m, e, K0);
        m.mats[0].kf = k;
        aug_elem_stiffness(&m, e, K1);
        T_CHECK(zero_count(9, K1, 1e-10, NULL) == 3, "triangle %lld on a foundation: %d zero modes", (long long)e,
                zero_count(9, K1, 1e-10, NULL));
        const int32_t *c = m.conn + e * 3;
        double a[3], b[3], n[3];
        for (int q = 0; q < 3; q++) a[q] = m.x[c[1] * 3 + q] - m.x[c[0] * 3 + q], b[q] = m.x[c[2] * 3 + q] - m.x[c[0] * 3 + q];
        n[0] = a[1] * b[2] - a[2] * b[1], n[1] = a[2] * b[0] - a[0] * b[2], n[2] = a[0] * b[1] - a[1] * b[0];
        double A = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), err = 0;
        for (int q = 0; q < 3; q++) n[q] /= 2 * A;
        for (int i = 0; i < 9; i++)
            for (int j = 0; j < 9; j++) {
                double want = k * A * (1.0 + (i / 3 == j / 3)) / 12 * n[i % 3] * n[j % 3];
                err = fmax(err, fabs(K1[j * 9 + i] - K0[j * 9 + i] - want));
            }
        T_CHECK(err <= 1e-13 * k, "triangle %lld: foundation part off by %g", (long long)e, err);
    }
    double *K = dense_K(&m);
    int z = zero_count((int)m.nn * 3, K, 1e-10, NULL);
    T_CHECK(z == 3, "flat sheet on a foundation: %d zero modes, want 3", z);
    free(K);
    m.have |= AUG_HAVE_FNDN;
    aug_err e;
    int rc = record_trip(&m, &r, &e);
    T_CHECK(rc == 0 && (r.have & AUG_HAVE_FNDN) && r.mats[0].kf == k, "FNDN round trip: rc %d (%s)", rc, e.msg);
    aug_mesh_free(&r);
    m.mats[0].kf = -1;
    rc = record_trip(&m, &r, &e);
    T_CHECK(rc == AUG_EDATA && !strcmp(e.type, "FNDN"), "negative k: rc %d %s %s", rc, e.type, e.msg);
    aug_mesh_free(&r);
    m2.mats[0].kf = 1, m2.have |= AUG_HAVE_FNDN;
    rc = record_trip(&m2, &r, &e);
    T_CHECK(rc == AUG_EDATA && !strcmp(e.type, "FNDN") && strstr(e.msg, "membrane"), "FNDN on tri3: rc %d %s %s",
            rc, e.type, e.msg);
    aug_mesh_free(&r);
    aug_mesh_free(&m);
    aug_mesh_free(&m2);
}

/* aug_membrane_flex after a factorization: the curved sheet held on one
   edge (its corners' triangles aside, every node has a nonsingular block,
   but the free edges flex: K's null space over the free DOFs, counted by
   zero_count) is reported once its K is shifted by 1e-14 of its largest
   diagonal (so that CHOLMOD factors it); the dome clamped on its boundary
   passes */
static void test_flex_check(void)
{
    double Q[3][3];
    rotation(0.1, 0.2, 0.3, Q);
    aug_mesh m2, m;
    tm_rect(&m2, 4, 4, 1.0, 1.0, 70.0, 0.33, 0.2);
    unsigned char *sel = calloc((size_t)m2.nn, 1);
    for (int q = 0; q < 2; q++) {
        lift(&m, &m2, Q, origin, dome);
        if (q == 0) {
            for (int64_t i = 0; i < m.nn; i++) sel[i] = m2.x[i * 2 + 1] == 0;
        } else {
            aug_mesh_boundary_nodes(&m2, sel);
        }
        tm_fix_nodes(&m, sel, NULL);
        int32_t *map = malloc((size_t)m.nn * 3 * sizeof *map);
        int64_t nf = aug_dofmap(&m, map);
        aug_err e;
        cholmod_sparse *K = aug_assemble(&m, map, nf, AUG_MAT_K, &cm, &e);
        double *D = tm_dense(K), dmax = 0;
        int z = zero_count((int)nf, D, 1e-12, NULL);
        int *Kp = K->p, *Ki = K->i;
        double *Kx = K->x;
        for (int64_t j = 0; j < nf; j++) dmax = fmax(dmax, D[j * nf + j]);
        for (int64_t j = 0; j < nf; j++)
            for (int p = Kp[j]; p < Kp[j + 1]; p++)
                if (Ki[p] == j) Kx[p] += 1e-14 * dmax;
        cholmod_factor *L = cholmod_analyze(K, &cm);
        cholmod_factorize(K, L, &cm);
        int rc = aug_membrane_flex(K, L, &m, map, &cm, &e);
        if (q == 0)
            T_CHECK(z > 0 && rc == AUG_ESINGULAR && strstr(e.msg, "zero-stiffness mode"),
                    "sheet on one edge: %d zero modes, rc %d (%s)", z, rc, e.msg);
        else
            T_CHECK(z == 0 && rc == 0, "clamped dome: %d zero modes, rc %d (%s)", z, rc, e.msg);
        cholmod_free_factor(&L, &cm);
        cholmod_free_sparse(&K, &cm);
        free(D);
        free(map);
        aug_mesh_free(&m);
    }
    free(sel);
    aug_mesh_free(&m2);
}

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(test_element_is_rotated_plane_stress);
    T_RUN(test_patch_flat_sheet_any_orientation);
    T_RUN(test_zero_stiffness_modes);
    T_RUN(test_mass_totals);
    T_RUN(test_support_checks);
    T_RUN(test_mesh_record);
    T_RUN(test_foundation);
    T_RUN(test_flex_check);
    cholmod_finish(&cm);
    T_EXIT();
}
