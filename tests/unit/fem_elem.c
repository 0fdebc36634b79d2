/* Element and global matrices (tri3, tet4, hex8): symmetry, rigid-body null
   space, patch test, mass totals, multi-material additivity, assembly against
   an independent triplet assembly, the lifted load against the full matrix;
   hex8: the element against an independent Voigt-form integration, the
   scaled Jacobian, and hex vs tet convergence on a cantilever. */
#include <gsl/gsl_linalg.h>
#include <lapacke.h>
#include "t.h"
#include "fem_mesh.h"

static cholmod_common cm;

/* rigid mode j (translations, then rotations about the axes) at point x */
static void rigid(int dim, int j, const double *x, double *u)
{
    if (dim == 3) {
        u[0] = u[1] = u[2] = 0;
        if (j < 3) u[j] = 1;
        else if (j == 3) u[1] = -x[2], u[2] = x[1];
        else if (j == 4) u[0] = x[2], u[2] = -x[0];
        else u[0] = -x[1], u[1] = x[0];
    } else {
        u[0] = u[1] = 0;
        if (j < 2) u[j] = 1;
        else u[0] = -x[1], u[1] = x[0];
    }
}

/* dense eigenvalues of an n x n symmetric (column-major) matrix, ascending */
static void eig(int n, const double *A, double *w)
{
    double *B = malloc((size_t)n * n * sizeof *B);
    memcpy(B, A, (size_t)n * n * sizeof *B);
    LAPACKE_dsyev(LAPACK_COL_MAJOR, 'N', 'U', n, B, n, w);
    free(B);
}

/* move interior nodes of a structured mesh by up to frac of a cell, deterministically */
static void distort(aug_mesh *m, double frac, double h)
{
    unsigned char *bd = calloc((size_t)m->nn, 1);
    aug_mesh_boundary_nodes(m, bd);
    for (int64_t i = 0; i < m->nn; i++)
        if (!bd[i])
            for (int c = 0; c < m->dim; c++) m->x[i * m->dim + c] += frac * h * sin(3.7 * i + 1.3 * c + 0.5);
    free(bd);
    for (int64_t e = 0; e < m->ne; e++) /* the test's own precondition */
        if (!(aug_elem_measure(m, e) > 0) || (m->nv == 8 && !(aug_hex_scaled_jacobian(m, e, NULL) > 0.3)))
            abort();
}

static void test_element_symmetry_and_null_space(void)
{
    aug_mesh m3, m2, mh;
    tm_box(&m3, 2, 2, 2, 1.0, 1.3, 0.7, 210.0, 0.27);
    tm_rect(&m2, 3, 2, 1.0, 0.8, 70.0, 0.33, 0.2);
    tm_hexbox(&mh, 2, 2, 2, 1.0, 1.3, 0.7, 210.0, 0.27);
    distort(&m3, 0.2, 0.35);
    distort(&m2, 0.2, 0.3);
    distort(&mh, 0.2, 0.35);
    aug_mesh *ms[3] = {&m3, &m2, &mh};
    for (int q = 0; q < 3; q++) {
        aug_mesh *m = ms[q];
        int n = m->dim * m->nv, nr = m->dim == 3 ? 6 : 3;
        for (int64_t e = 0; e < m->ne; e++) {
            double K[AUG_MAX_EMAT], w[AUG_MAX_EDOF], u[AUG_MAX_EDOF];
            aug_elem_stiffness(m, e, K);
            double kmax = 0, asym = 0;
            for (int i = 0; i < n * n; i++) kmax = fmax(kmax, fabs(K[i]));
            for (int i = 0; i < n; i++)
                for (int j = 0; j < n; j++) asym = fmax(asym, fabs(K[i * n + j] - K[j * n + i]));
            T_CHECK(asym <= 1e-14 * kmax, "dim %d element %lld: asymmetry %g", m->dim, (long long)e, asym / kmax);
            /* K r = 0 for each rigid mode */
            for (int j = 0; j < nr; j++) {
                for (int a = 0; a < m->nv; a++)
                    rigid(m->dim, j, m->x + (size_t)m->conn[e * m->nv + a] * m->dim, u + a * m->dim);
                for (int i = 0; i < n; i++) {
                    double s = 0;
                    for (int k = 0; k < n; k++) s += K[k * n + i] * u[k];
                    T_CHECK(fabs(s) <= 1e-12 * kmax, "dim %d element %lld: K r_%d = %g", m->dim, (long long)e, j, s);
                }
            }
            /* exactly nr zero eigenvalues, the rest positive */
            eig(n, K, w);
            int zero = 0;
            for (int i = 0; i < n; i++) {
                T_CHECK(w[i] > -1e-12 * w[n - 1], "negative eigenvalue %g", w[i]);
                zero += fabs(w[i]) <= 1e-10 * w[n - 1];
            }
            T_CHECK(zero == nr, "dim %d nv %d element %lld: %d zero eigenvalues, expected %d", m->dim, m->nv,
                    (long long)e, zero, nr);
        }
    }
    aug_mesh_free(&m3);
    aug_mesh_free(&m2);
    aug_mesh_free(&mh);
}

/* unconstrained global K: symmetric PSD with a null space of dimension 6 (3-D)
   / 3 (2-D) spanned by the rigid modes */
static void global_null_space(aug_mesh *m)
{
    int d = m->dim, nr = d == 3 ? 6 : 3;
    int32_t *map = malloc((size_t)m->nn * d * sizeof *map);
    int64_t n = aug_dofmap(m, map);
    aug_err e;
    cholmod_sparse *K = aug_assemble(m, map, n, AUG_MAT_K, &cm, &e);
    T_CHECK(K && n == m->nn * d, "assemble: %s", e.msg);
    if (!K) return;
    double *D = tm_dense(K), *w = malloc((size_t)n * sizeof *w);
    eig((int)n, D, w);
    int zero = 0;
    for (int64_t i = 0; i < n; i++) zero += fabs(w[i]) <= 1e-10 * w[n - 1];
    T_CHECK(zero == nr, "%d-D: null space of dimension %d, expected %d", d, zero, nr);
    T_CHECK(w[0] > -1e-10 * w[n - 1], "%d-D: negative eigenvalue %g", d, w[0]);
    double *r = malloc((size_t)n * sizeof *r), *Kr = malloc((size_t)n * sizeof *Kr);
    for (int j = 0; j < nr; j++) {
        for (int64_t i = 0; i < m->nn; i++) rigid(d, j, m->x + i * d, r + i * d);
        tm_symv(K, r, Kr);
        T_CHECK(tm_norm(Kr, n) <= 1e-12 * w[n - 1] * tm_norm(r, n), "%d-D: |K r_%d| = %g", d, j,
                tm_norm(Kr, n));
    }
    free(r);
    free(Kr);
    free(D);
    free(w);
    free(map);
    cholmod_free_sparse(&K, &cm);
}

static void test_global_null_space(void)
{
    aug_mesh m;
    tm_box(&m, 3, 2, 2, 1.5, 1, 1, 3.0, 0.3);
    distort(&m, 0.15, 0.33);
    global_null_space(&m);
    aug_mesh_free(&m);
    tm_rect(&m, 5, 4, 2, 1.5, 3.0, 0.3, 0.5);
    distort(&m, 0.15, 0.35);
    global_null_space(&m);
    aug_mesh_free(&m);
    tm_hexbox(&m, 3, 2, 2, 1.5, 1, 1, 3.0, 0.3);
    distort(&m, 0.15, 0.33);
    global_null_space(&m);
    /* and the support check names the free piece */
    aug_err e;
    T_CHECK(aug_check_support(&m, &e) == AUG_ESINGULAR, "unsupported hex box passes the support check");
    tm_fix_plane(&m, 2, 0.0, NULL);
    T_CHECK(aug_check_support(&m, &e) == 0, "hex box fixed at z = 0: %s", e.msg);
    aug_mesh_free(&m);
}

/* the patch test: u = A x + b prescribed on the boundary, interior nodes of a
   distorted mesh reproduce it to round-off (no loads) */
static const double PA[3][3] = {{1e-3, 2e-3, -1.5e-3}, {-0.7e-3, 0.4e-3, 1.1e-3}, {0.9e-3, -1.2e-3, 0.6e-3}};
static const double Pb[3] = {0.01, -0.02, 0.005};
static double patch_field3(const double *x, int c)
{
    return Pb[c] + PA[c][0] * x[0] + PA[c][1] * x[1] + PA[c][2] * x[2];
}
static double patch_field2(const double *x, int c)
{
    return Pb[c] + PA[c][0] * x[0] + PA[c][1] * x[1];
}

/* u[nn*dim] := the static solution of m (K a = f, constrained DOFs at their values) */
static void solve_static(const aug_mesh *m, double *u)
{
    int d = m->dim;
    int32_t *map = malloc((size_t)m->nn * d * sizeof *map);
    int64_t n = aug_dofmap(m, map);
    aug_err e;
    cholmod_sparse *K = aug_assemble(m, map, n, AUG_MAT_K, &cm, &e);
    double *f = malloc((size_t)n * sizeof *f), *a = malloc((size_t)n * sizeof *a);
    T_CHECK(K && aug_load_vector(m, map, n, f, &e) == 0, "assemble/load: %s", e.msg);
    aug_factor_options(&cm, AUG_ORDER_AUTO, 0);
    cholmod_factor *L = aug_analyze(K, &cm, &e);
    T_CHECK(L && aug_factorize(K, L, m, map, &cm, &e) == 0, "factor: %s", e.msg);
    double rr;
    T_CHECK(aug_solve(K, L, f, a, &rr, &cm, &e) == 0, "solve: %s", e.msg);
    aug_expand_field(m, map, a, u);
    cholmod_free_factor(&L, &cm);
    cholmod_free_sparse(&K, &cm);
    free(map);
    free(f);
    free(a);
}

static void patch(aug_mesh *m, tm_field fld)
{
    int d = m->dim;
    unsigned char *bd = calloc((size_t)m->nn, 1);
    aug_mesh_boundary_nodes(m, bd);
    tm_fix_nodes(m, bd, fld);
    double *u = malloc((size_t)m->nn * d * sizeof *u);
    solve_static(m, u);
    double err = 0;
    int64_t interior = 0;
    for (int64_t i = 0; i < m->nn; i++) {
        interior += !bd[i];
        for (int c = 0; c < d; c++) err = fmax(err, fabs(u[i * d + c] - fld(m->x + i * d, c)));
    }
    T_CHECK(interior > 0 && err <= 1e-10 * 0.02, "%d-D nv %d patch test: max error %g on %lld interior nodes",
            d, m->nv, err, (long long)interior);
    free(bd);
    free(u);
}

/* tet4, and hex8: Q1 is isoparametric and fully integrated, so the patch
   test holds on distorted hexes too (Hughes, The Finite Element Method,
   sec. 3.7) */
static void test_patch_3d(void)
{
    for (int hex = 0; hex < 2; hex++) {
        aug_mesh m;
        (hex ? tm_hexbox : tm_box)(&m, 4, 3, 3, 1.0, 0.9, 0.8, 5.0, 0.35);
        distort(&m, 0.2, 0.25);
        patch(&m, patch_field3);
        aug_mesh_free(&m);
    }
}

static void test_patch_tri3(void)
{
    aug_mesh m;
    tm_rect(&m, 5, 4, 1.0, 0.9, 5.0, 0.35, 0.3);
    distort(&m, 0.2, 0.2);
    patch(&m, patch_field2);
    aug_mesh_free(&m);
}

/* uniform tension sigma along x of a plate (plane stress, thickness t): a
   state linear elements represent exactly, so u_x(L) = sigma L / E and
   u_y(H) = -nu sigma H / E at every node (plane strain would give
   -nu (1 + nu) sigma H / E); u_x = 0 on x = 0, u_y = 0 at the origin; the end
   traction as consistent nodal forces sigma t H / ny (half at the corners) */
static void test_plane_stress_tension(void)
{
    int nx = 4, ny = 3;
    double L = 2.0, H = 0.9, E = 7.0, nu = 0.3, t = 0.25, sigma = 0.5;
    aug_mesh m;
    tm_rect(&m, nx, ny, L, H, E, nu, t);
    m.fix_dof = malloc((size_t)(ny + 2) * sizeof(int32_t));
    m.fix_val = calloc((size_t)(ny + 2), sizeof(double));
    m.fix_dof[m.nfix++] = 0, m.fix_dof[m.nfix++] = 1;            /* node 0: x and y */
    for (int j = 1; j <= ny; j++) m.fix_dof[m.nfix++] = 2 * (j * (nx + 1));
    m.have |= AUG_HAVE_FIXD;
    m.load_dof = malloc((size_t)(ny + 1) * sizeof(int32_t));
    m.load_val = malloc((size_t)(ny + 1) * sizeof(double));
    for (int j = 0; j <= ny; j++) {
        m.load_dof[m.nload] = 2 * (nx + j * (nx + 1));
        m.load_val[m.nload++] = sigma * t * H / ny * (j == 0 || j == ny ? 0.5 : 1.0);
    }
    m.have |= AUG_HAVE_LOAD;
    int32_t *map = malloc((size_t)m.nn * 2 * sizeof *map);
    int64_t n = aug_dofmap(&m, map);
    aug_err e;
    cholmod_sparse *K = aug_assemble(&m, map, n, AUG_MAT_K, &cm, &e);
    double *f = malloc((size_t)n * sizeof *f), *a = malloc((size_t)n * sizeof *a);
    double *u = malloc((size_t)m.nn * 2 * sizeof *u), rr;
    T_CHECK(K && aug_load_vector(&m, map, n, f, &e) == 0, "assemble/load: %s", e.msg);
    aug_factor_options(&cm, AUG_ORDER_AUTO, 0);
    cholmod_factor *Lf = aug_analyze(K, &cm, &e);
    T_CHECK(Lf && aug_factorize(K, Lf, &m, map, &cm, &e) == 0 && aug_solve(K, Lf, f, a, &rr, &cm, &e) == 0,
            "solve: %s", e.msg);
    aug_expand_field(&m, map, a, u);
    double err = 0;
    for (int64_t i = 0; i < m.nn; i++) {
        const double *x = m.x + 2 * i;
        err = fmax(err, fabs(u[2 * i] - sigma * x[0] / E));
        err = fmax(err, fabs(u[2 * i + 1] + nu * sigma * x[1] / E));
    }
    T_CHECK(err <= 1e-12 * sigma * L / E, "plane-stress tension: max error %g", err);
    cholmod_free_factor(&Lf, &cm);
    cholmod_free_sparse(&K, &cm);
    free(map), free(f), free(a), free(u);
    aug_mesh_free(&m);
}

/* global symmetric matrix: max |A - A'| relative (upper storage makes this a
   check of the stored pattern: only i <= j entries, sorted, unique) */
static void check_upper_sorted(const cholmod_sparse *A, const char *what)
{
    const int *Ap = A->p, *Ai = A->i;
    int ok = A->stype == 1 && A->sorted && A->packed;
    for (size_t j = 0; j < A->ncol && ok; j++)
        for (int p = Ap[j]; p < Ap[j + 1]; p++)
            if (Ai[p] > (int)j || (p > Ap[j] && Ai[p] <= Ai[p - 1])) ok = 0;
    T_CHECK(ok, "%s: not upper triangular with sorted unique rows", what);
}

/* consistent and lumped mass: r' M r = rho * volume (* t) for every translation
   r; lumped M = row sums of consistent M */
static void mass_totals(aug_mesh *m);

static void test_mass(void)
{
    for (int hex = 0; hex < 2; hex++) {
        aug_mesh m;
        (hex ? tm_hexbox : tm_box)(&m, 3, 2, 2, 1.2, 1, 0.9, 1.0, 0.3);
        distort(&m, 0.2, 0.3);
        mass_totals(&m);
        aug_mesh_free(&m);
    }
}

/* the box's volume is 1.2 x 1 x 0.9 whatever its interior nodes do */
static void mass_totals(aug_mesh *mp)
{
    aug_mesh m = *mp;
    m.mats[0].rho = 7.8;
    int32_t *map = malloc((size_t)m.nn * 3 * sizeof *map);
    int64_t n = aug_dofmap(&m, map);
    aug_err e;
    cholmod_sparse *M = aug_assemble(&m, map, n, AUG_MAT_M, &cm, &e);
    cholmod_sparse *ML = aug_assemble(&m, map, n, AUG_MAT_ML, &cm, &e);
    check_upper_sorted(M, "M");
    check_upper_sorted(ML, "ML");
    double vol = 0;
    for (int64_t el = 0; el < m.ne; el++) vol += aug_elem_measure(&m, el);
    T_CHECK(t_reldiff(vol, 1.2 * 0.9) < 1e-13, "nv %d: volume %.17g, the box's 1.08", m.nv, vol);
    double *r = calloc((size_t)n, sizeof *r), *y = malloc((size_t)n * sizeof *y);
    for (int c = 0; c < 3; c++) {
        memset(r, 0, (size_t)n * sizeof *r);
        for (int64_t i = 0; i < m.nn; i++) r[i * 3 + c] = 1;
        tm_symv(M, r, y);
        double s = 0, sl = 0;
        for (int64_t i = 0; i < n; i++) s += r[i] * y[i];
        tm_symv(ML, r, y);
        for (int64_t i = 0; i < n; i++) sl += r[i] * y[i];
        T_CHECK(t_reldiff(s, 7.8 * vol) < 1e-12 && t_reldiff(sl, 7.8 * vol) < 1e-12,
                "total mass %g / %g, expected %g", s, sl, 7.8 * vol);
    }
    /* lumped = row sums of consistent */
    double *D = tm_dense(M);
    const double *lx = ML->x;
    for (int64_t i = 0; i < n; i++) {
        double rs = 0;
        for (int64_t j = 0; j < n; j++) rs += D[j * n + i];
        T_CHECK(t_reldiff(lx[i], rs) < 1e-12, "lumped %g vs row sum %g", lx[i], rs);
    }
    /* positive definite: consistent M has positive eigenvalues */
    double *w = malloc((size_t)n * sizeof *w);
    eig((int)n, D, w);
    T_CHECK(w[0] > 0, "consistent M not positive definite: %g", w[0]);
    free(w);
    free(D);
    free(r);
    free(y);
    free(map);
    cholmod_free_sparse(&M, &cm);
    cholmod_free_sparse(&ML, &cm);
}

/* copy of m keeping only the elements of material k (same nodes) */
static void only_material(const aug_mesh *m, int k, aug_mesh *s)
{
    *s = *m;
    s->conn = malloc((size_t)m->ne * m->nv * sizeof(int32_t));
    s->mat = malloc((size_t)m->ne * sizeof(int32_t));
    s->ne = 0;
    for (int64_t e = 0; e < m->ne; e++)
        if (m->mat[e] == k) {
            memcpy(s->conn + s->ne * m->nv, m->conn + e * m->nv, (size_t)m->nv * sizeof(int32_t));
            s->mat[s->ne++] = k;
        }
}

static void test_multimaterial_sum(void)
{
    aug_mesh m;
    tm_box(&m, 4, 2, 2, 2, 1, 1, 1.0, 0.3);
    free(m.mats);
    tm_material(&m, 2, 1.0, 0.3, 1.0, 1.0);
    m.mats[1].E = 1e3, m.mats[1].nu = 0.45, m.mats[1].rho = 3.0;
    for (int64_t e = 0; e < m.ne; e++) {
        double cx = 0;
        for (int a = 0; a < 4; a++) cx += m.x[(size_t)m.conn[e * 4 + a] * 3] / 4;
        m.mat[e] = cx > 1.0;
    }
    tm_fix_plane(&m, 0, 0.0, NULL);
    int32_t *map = malloc((size_t)m.nn * 3 * sizeof *map);
    int64_t n = aug_dofmap(&m, map);
    aug_err e;
    for (int which = AUG_MAT_K; which <= AUG_MAT_M; which++) {
        aug_mesh a, b;
        only_material(&m, 0, &a);
        only_material(&m, 1, &b);
        T_CHECK(a.ne > 0 && b.ne > 0 && a.ne + b.ne == m.ne, "material split");
        cholmod_sparse *K = aug_assemble(&m, map, n, which, &cm, &e);
        cholmod_sparse *Ka = aug_assemble(&a, map, n, which, &cm, &e);
        cholmod_sparse *Kb = aug_assemble(&b, map, n, which, &cm, &e);
        double one[2] = {1, 0}, mone[2] = {-1, 0};
        cholmod_sparse *S = cholmod_add(Ka, Kb, one, one, 1, 1, &cm);
        cholmod_sparse *D = cholmod_add(K, S, one, mone, 1, 1, &cm);
        double dn = cholmod_norm_sparse(D, 0, &cm), kn = cholmod_norm_sparse(K, 0, &cm);
        T_CHECK(dn <= 1e-14 * kn, "which %d: |K - (K_0 + K_1)| = %g of %g", which, dn, kn);
        cholmod_free_sparse(&K, &cm);
        cholmod_free_sparse(&Ka, &cm);
        cholmod_free_sparse(&Kb, &cm);
        cholmod_free_sparse(&S, &cm);
        cholmod_free_sparse(&D, &cm);
        free(a.conn);
        free(a.mat);
        free(b.conn);
        free(b.mat);
    }
    free(map);
    aug_mesh_free(&m);
}

/* K from the symbolic+scatter assembly equals K from element triplets summed
   by CHOLMOD (cholmod_triplet_to_sparse), with constraints */
static void assembly_vs_triplets(int hex)
{
    aug_mesh m;
    (hex ? tm_hexbox : tm_box)(&m, 3, 3, 2, 1, 1, 0.7, 2.0, 0.25);
    distort(&m, 0.2, 0.3);
    int nv = m.nv, nd = 3 * nv;
    tm_fix_plane(&m, 2, 0.0, NULL);
    int32_t *map = malloc((size_t)m.nn * 3 * sizeof *map);
    int64_t n = aug_dofmap(&m, map);
    aug_err e;
    cholmod_sparse *K = aug_assemble(&m, map, n, AUG_MAT_K, &cm, &e);
    check_upper_sorted(K, "K");
    cholmod_triplet *T = cholmod_allocate_triplet(n, n, (size_t)(m.ne * nd * nd), 1, CHOLMOD_REAL, &cm);
    int *Ti = T->i, *Tj = T->j;
    double *Tx = T->x, Ke[AUG_MAX_EMAT];
    for (int64_t el = 0; el < m.ne; el++) {
        aug_elem_stiffness(&m, el, Ke);
        for (int a = 0; a < nd; a++)
            for (int b = 0; b < nd; b++) {
                int ra = map[m.conn[el * nv + a / 3] * 3 + a % 3], cb = map[m.conn[el * nv + b / 3] * 3 + b % 3];
                if (ra < 0 || cb < 0 || ra > cb) continue;
                Ti[T->nnz] = ra, Tj[T->nnz] = cb, Tx[T->nnz++] = Ke[b * nd + a];
            }
    }
    cholmod_sparse *K2 = cholmod_triplet_to_sparse(T, 0, &cm);
    double one[2] = {1, 0}, mone[2] = {-1, 0};
    cholmod_sparse *D = cholmod_add(K, K2, one, mone, 1, 1, &cm);
    double dn = cholmod_norm_sparse(D, 0, &cm), kn = cholmod_norm_sparse(K, 0, &cm);
    T_CHECK(dn <= 1e-14 * kn, "|K - K_triplets| = %g of %g", dn, kn);
    T_CHECK(cholmod_nnz(K, &cm) >= cholmod_nnz(K2, &cm), "pattern misses entries");
    /* global symmetry: the lower triangle, assembled from the lower entries of
       the element matrices and transposed, equals the stored upper one */
    T->nnz = 0;
    for (int64_t el = 0; el < m.ne; el++) {
        aug_elem_stiffness(&m, el, Ke);
        for (int a = 0; a < nd; a++)
            for (int b = 0; b < nd; b++) {
                int ra = map[m.conn[el * nv + a / 3] * 3 + a % 3], cb = map[m.conn[el * nv + b / 3] * 3 + b % 3];
                if (ra < 0 || cb < 0 || ra < cb) continue;
                Ti[T->nnz] = cb, Tj[T->nnz] = ra, Tx[T->nnz++] = Ke[b * nd + a];
            }
    }
    cholmod_sparse *KL = cholmod_triplet_to_sparse(T, 0, &cm);
    cholmod_sparse *DL = cholmod_add(K, KL, one, mone, 1, 1, &cm);
    double dl = cholmod_norm_sparse(DL, 0, &cm);
    T_CHECK(dl <= 1e-14 * kn, "|K_upper - K_lower'| = %g of %g", dl, kn);
    cholmod_free_sparse(&KL, &cm);
    cholmod_free_sparse(&DL, &cm);
    cholmod_free_triplet(&T, &cm);
    cholmod_free_sparse(&K, &cm);
    cholmod_free_sparse(&K2, &cm);
    cholmod_free_sparse(&D, &cm);
    free(map);
    aug_mesh_free(&m);
}

static void test_assembly_vs_triplets(void)
{
    assembly_vs_triplets(0);
    assembly_vs_triplets(1);
}

/* f_F = l_F - K_FD a_D against the full (unconstrained) K times a_D */
static double lift_field(const double *x, int c) { return 1e-3 * (c + 1) * (1 + x[0] - 2 * x[1]); }

static void test_load_lifting(void)
{
    aug_mesh m;
    tm_box(&m, 3, 2, 3, 1, 1, 1.2, 4.0, 0.3);
    tm_fix_plane(&m, 2, 0.0, lift_field);
    /* loads on the top face, some on constrained DOFs (ignored) */
    int64_t nl = 0;
    m.load_dof = malloc((size_t)m.nn * 3 * sizeof(int32_t));
    m.load_val = malloc((size_t)m.nn * 3 * sizeof(double));
    for (int64_t i = 0; i < m.nn; i++)
        if (fabs(m.x[i * 3 + 2] - 1.2) < 1e-12 || i == 0) {
            m.load_dof[nl] = (int32_t)(i * 3 + 1);
            m.load_val[nl++] = 0.5 + 0.1 * i;
        }
    m.nload = nl;
    m.have |= AUG_HAVE_LOAD;
    int32_t *map = malloc((size_t)m.nn * 3 * sizeof *map), *all = malloc((size_t)m.nn * 3 * sizeof *all);
    int64_t n = aug_dofmap(&m, map), nd = m.nn * 3;
    for (int64_t i = 0; i < nd; i++) all[i] = (int32_t)i;
    aug_err e;
    double *f = malloc((size_t)n * sizeof *f);
    T_CHECK(aug_load_vector(&m, map, n, f, &e) == 0, "%s", e.msg);
    cholmod_sparse *Kf = aug_assemble(&m, all, nd, AUG_MAT_K, &cm, &e);
    double *aD = calloc((size_t)nd, sizeof *aD), *KaD = malloc((size_t)nd * sizeof *KaD);
    double *l = calloc((size_t)nd, sizeof *l);
    for (int64_t t = 0; t < m.nfix; t++) aD[m.fix_dof[t]] = m.fix_val[t];
    for (int64_t t = 0; t < m.nload; t++) l[m.load_dof[t]] += m.load_val[t];
    tm_symv(Kf, aD, KaD);
    double err = 0, sc = 0;
    for (int64_t i = 0; i < nd; i++)
        if (map[i] >= 0) {
            double ref = l[i] - KaD[i];
            err = fmax(err, fabs(f[map[i]] - ref));
            sc = fmax(sc, fabs(ref));
        }
    T_CHECK(sc > 0 && err <= 1e-13 * sc, "lifted load differs by %g (scale %g)", err, sc);
    cholmod_free_sparse(&Kf, &cm);
    free(aD);
    free(KaD);
    free(l);
    free(f);
    free(map);
    free(all);
    aug_mesh_free(&m);
}

/* ---- hex8 against independent code ---- */

/* shape values and natural derivatives of the trilinear hex, corner a at
   (sx, sy, sz) = signs of the bits x=1, y=2, z=4 of gmsh's 0 1 3 2 4 5 7 6 */
static void q1_shape(const double *xi, double *N, double dN[8][3])
{
    static const int bits[8] = {0, 1, 3, 2, 4, 5, 7, 6};
    for (int a = 0; a < 8; a++) {
        double c[3], f[3];
        for (int k = 0; k < 3; k++) c[k] = (bits[a] >> k & 1) ? 1 : -1, f[k] = 1 + c[k] * xi[k];
        N[a] = f[0] * f[1] * f[2] / 8;
        dN[a][0] = c[0] * f[1] * f[2] / 8;
        dN[a][1] = f[0] * c[1] * f[2] / 8;
        dN[a][2] = f[0] * f[1] * c[2] / 8;
    }
}

/* K = sum_q w_q det J B' D B in Voigt form (B 6 x 24, strains xx yy zz yz xz xy,
   engineering shears; D the isotropic 6 x 6) and M = rho sum_q w_q det J N N'
   (per component), by the npt-point Gauss rule per direction (2 or 3) */
static void q1_voigt(const double *P, double E, double nu, double rho, int npt, double *K, double *M)
{
    static const double g2[2] = {-0.57735026918962576, 0.57735026918962576}, w2[2] = {1, 1};
    static const double g3[3] = {-0.77459666924148338, 0, 0.77459666924148338}, w3[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    const double *g = npt == 2 ? g2 : g3, *wt = npt == 2 ? w2 : w3;
    double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu)), D[6][6] = {{0}};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) D[i][j] = lam;
        D[i][i] += 2 * mu;
        D[i + 3][i + 3] = mu;
    }
    memset(K, 0, 576 * sizeof *K);
    memset(M, 0, 64 * sizeof *M);
    for (int p = 0; p < npt; p++)
        for (int q = 0; q < npt; q++)
            for (int r = 0; r < npt; r++) {
                double xi[3] = {g[p], g[q], g[r]}, w = wt[p] * wt[q] * wt[r], N[8], dN[8][3], J[3][3];
                q1_shape(xi, N, dN);
                for (int i = 0; i < 3; i++)
                    for (int k = 0; k < 3; k++) {
                        J[i][k] = 0; /* dx_i / dxi_k */
                        for (int a = 0; a < 8; a++) J[i][k] += P[a * 3 + i] * dN[a][k];
                    }
                gsl_matrix_view Jv = gsl_matrix_view_array(&J[0][0], 3, 3);
                gsl_permutation *pm = gsl_permutation_alloc(3);
                gsl_matrix *Ji = gsl_matrix_alloc(3, 3);
                int sg;
                gsl_linalg_LU_decomp(&Jv.matrix, pm, &sg);
                double det = gsl_linalg_LU_det(&Jv.matrix, sg);
                gsl_linalg_LU_invert(&Jv.matrix, pm, Ji);
                double G[8][3], B[6][24] = {{0}};
                for (int a = 0; a < 8; a++)
                    for (int c = 0; c < 3; c++) {
                        G[a][c] = 0;
                        for (int k = 0; k < 3; k++) G[a][c] += dN[a][k] * gsl_matrix_get(Ji, (size_t)k, (size_t)c);
                    }
                gsl_matrix_free(Ji);
                gsl_permutation_free(pm);
                for (int a = 0; a < 8; a++) {
                    B[0][a * 3] = G[a][0], B[1][a * 3 + 1] = G[a][1], B[2][a * 3 + 2] = G[a][2];
                    B[3][a * 3 + 1] = G[a][2], B[3][a * 3 + 2] = G[a][1];
                    B[4][a * 3] = G[a][2], B[4][a * 3 + 2] = G[a][0];
                    B[5][a * 3] = G[a][1], B[5][a * 3 + 1] = G[a][0];
                }
                for (int i = 0; i < 24; i++)
                    for (int j = 0; j < 24; j++) {
                        double v = 0;
                        for (int k = 0; k < 6; k++)
                            for (int l = 0; l < 6; l++) v += B[k][i] * D[k][l] * B[l][j];
                        K[j * 24 + i] += w * det * v;
                    }
                for (int a = 0; a < 8; a++)
                    for (int b = 0; b < 8; b++) M[b * 8 + a] += rho * w * det * N[a] * N[b];
            }
}

static double maxabs(const double *v, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++) s = fmax(s, fabs(v[i]));
    return s;
}

/* aug_elem_stiffness / aug_elem_mass of one hex against q1_voigt: a distorted
   hex to round-off (the same 2x2x2 rule); a parallelepiped also against the
   3x3x3 rule (2x2x2 is exact there: the integrands are polynomials of degree
   <= 2 in each direction) */
static void test_hex_element_independent(void)
{
    aug_mesh m;
    tm_hexbox(&m, 1, 1, 1, 1.0, 1.0, 1.0, 3.5, 0.28);
    m.mats[0].rho = 2.5;
    static const double distorted[8][3] = {{0, 0, 0}, {1.2, 0.1, -0.05}, {1.1, 0.9, 0.1}, {-0.1, 1.0, 0.05},
                                           {0.05, -0.1, 1.1}, {1.0, 0.05, 0.9}, {1.3, 1.2, 1.3}, {0.1, 0.95, 1.0}};
    double A[3][3] = {{1.3, 0.2, -0.1}, {0.1, 0.8, 0.3}, {-0.2, 0.15, 1.1}}, base[3] = {0.3, -0.2, 0.5};
    for (int shape = 0; shape < 2; shape++) {
        for (int a = 0; a < 8; a++) {
            int b = m.conn[a];
            double y[3] = {b & 1, (b >> 1) & 1, (b >> 2) & 1}; /* tm_box node (i,j,k) of a 1x1x1 box */
            for (int i = 0; i < 3; i++) {
                double v = base[i];
                for (int k = 0; k < 3; k++) v += A[i][k] * y[k];
                m.x[b * 3 + i] = shape ? v : distorted[a][i];
            }
        }
        double P[24], K[576], M[64], Kr[576], Mr[64], Kl[AUG_MAX_EMAT], Ml[AUG_MAX_EMAT], Mlump[AUG_MAX_EMAT];
        for (int a = 0; a < 8; a++) memcpy(P + a * 3, m.x + m.conn[a] * 3, 3 * sizeof(double));
        aug_elem_stiffness(&m, 0, Kl);
        aug_elem_mass(&m, 0, 0, Ml);
        aug_elem_mass(&m, 0, 1, Mlump);
        for (int npt = 2; npt <= 2 + shape; npt++) {
            q1_voigt(P, 3.5, 0.28, 2.5, npt, K, M);
            for (int i = 0; i < 576; i++) Kr[i] = Kl[i] - K[i];
            T_CHECK(maxabs(Kr, 576) <= 1e-13 * maxabs(K, 576), "shape %d, %d-point rule: |Ke - K_voigt| = %g of %g",
                    shape, npt, maxabs(Kr, 576), maxabs(K, 576));
            for (int a = 0; a < 8; a++)
                for (int b = 0; b < 8; b++) {
                    double rs = 0;
                    for (int c = 0; c < 8; c++) rs += M[c * 8 + a];
                    for (int i = 0; i < 3; i++)
                        for (int j = 0; j < 3; j++) {
                            double want = i == j ? M[b * 8 + a] : 0, lump = i == j && a == b ? rs : 0;
                            Mr[b * 8 + a] = fmax(fabs(Ml[(b * 3 + j) * 24 + a * 3 + i] - want),
                                                 fabs(Mlump[(b * 3 + j) * 24 + a * 3 + i] - lump));
                            T_CHECK(Mr[b * 8 + a] <= 1e-14 * maxabs(M, 64), "shape %d: mass (%d,%d) off by %g",
                                    shape, a * 3 + i, b * 3 + j, Mr[b * 8 + a]);
                        }
                }
        }
        double V = aug_elem_measure(&m, 0), sum = 0;
        for (int i = 0; i < 64; i++) sum += M[i];
        T_CHECK(t_reldiff(sum, 2.5 * V) < 1e-13, "shape %d: mass %.17g, rho V %.17g", shape, sum, 2.5 * V);
        if (shape) {
            double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                         A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                         A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
            T_CHECK(t_reldiff(V, det) < 1e-14, "parallelepiped volume %.17g, det A %.17g", V, det);
        }
    }
    aug_mesh_free(&m);
}

/* the scaled Jacobian (least corner det[e1,e2,e3]/(|e1||e2||e3|)): 1 for a
   cube, 1/sqrt(1+s^2) for the shear x += s y of it (every corner alike),
   negative for the mirror image, <= 0 with a corner folded in; the quality's
   least edge angle acos(s / sqrt(1+s^2)) */
static void test_hex_scaled_jacobian(void)
{
    aug_mesh m;
    tm_hexbox(&m, 1, 1, 1, 2.0, 2.0, 2.0, 1.0, 0.3);
    int corner;
    T_CHECK(fabs(aug_hex_scaled_jacobian(&m, 0, &corner) - 1) < 1e-15, "cube: %g", aug_hex_scaled_jacobian(&m, 0, NULL));
    aug_quality q;
    aug_elem_quality(&m, 0, &q);
    T_CHECK(fabs(q.min_angle - 90) < 1e-12 && fabs(q.aspect - 1) < 1e-15 && fabs(q.measure - 8) < 1e-13 &&
                fabs(q.sjac - 1) < 1e-15, "cube quality: angle %g aspect %g volume %g sjac %g", q.min_angle,
            q.aspect, q.measure, q.sjac);
    double s = 0.75;
    for (int64_t i = 0; i < m.nn; i++) m.x[i * 3] += s * m.x[i * 3 + 1];
    double want = 1 / sqrt(1 + s * s);
    T_CHECK(fabs(aug_hex_scaled_jacobian(&m, 0, NULL) - want) < 1e-15, "sheared: %.17g, want %.17g",
            aug_hex_scaled_jacobian(&m, 0, NULL), want);
    aug_elem_quality(&m, 0, &q);
    T_CHECK(fabs(q.min_angle - acos(s / sqrt(1 + s * s)) * 180 / M_PI) < 1e-12, "sheared: least angle %g", q.min_angle);
    T_CHECK(fabs(q.measure - 8) < 1e-13, "shear keeps the volume: %g", q.measure);
    for (int a = 0; a < 4; a++) {
        int32_t t = m.conn[a];
        m.conn[a] = m.conn[a + 4], m.conn[a + 4] = t;
    }
    T_CHECK(fabs(aug_hex_scaled_jacobian(&m, 0, NULL) + want) < 1e-15, "mirrored: %g", aug_hex_scaled_jacobian(&m, 0, NULL));
    T_CHECK(aug_elem_measure(&m, 0) < 0, "mirrored: volume %g", aug_elem_measure(&m, 0));
    for (int a = 0; a < 4; a++) {
        int32_t t = m.conn[a];
        m.conn[a] = m.conn[a + 4], m.conn[a + 4] = t;
    }
    double *p6 = m.x + m.conn[6] * 3; /* top corner (1,1,1) pushed through the opposite corner */
    p6[0] = p6[1] = p6[2] = -0.5;
    double sj = aug_hex_scaled_jacobian(&m, 0, &corner);
    T_CHECK(sj <= 0, "folded corner: scaled Jacobian %g at %d", sj, corner);
    aug_mesh_free(&m);
}

/* A cantilever 1 x 1 x 4 (z), clamped at z = 0, a transverse force P (x)
   shared by the tip nodes: the mean tip deflection of hex8 and tet4 meshes
   on the same n x n x 4n grids, n = 1 2 3 5 7 (so equal node counts). Both
   converge to one value: their gap shrinks with n (under 10% at n = 7), both
   grow monotonically, and the Richardson limits (error ~ n^-2) of the two
   finest grids of each agree to 3%; hex8 is closer to the limit than tet4
   on every grid (the tets lock in bending), and the limit is within 10% of
   Timoshenko's P L^3 / (3 E I) + P L / (kappa G A), kappa = 5/6. */
static double tip_deflection(int hex, int n)
{
    aug_mesh m;
    double E = 1000, nu = 0.3, L = 4, P = 1;
    (hex ? tm_hexbox : tm_box)(&m, n, n, 4 * n, 1, 1, L, E, nu);
    tm_fix_plane(&m, 2, 0.0, NULL);
    int64_t nt = 0;
    m.load_dof = malloc((size_t)m.nn * sizeof(int32_t));
    m.load_val = malloc((size_t)m.nn * sizeof(double));
    for (int64_t i = 0; i < m.nn; i++)
        if (fabs(m.x[i * 3 + 2] - L) < 1e-12) m.load_dof[nt++] = (int32_t)(i * 3);
    for (int64_t k = 0; k < nt; k++) m.load_val[k] = P / (double)nt;
    m.nload = nt;
    m.have |= AUG_HAVE_LOAD;
    double *u = malloc((size_t)m.nn * 3 * sizeof *u), tip = 0;
    solve_static(&m, u);
    for (int64_t k = 0; k < nt; k++) tip += u[m.load_dof[k]] / (double)nt;
    free(u);
    aug_mesh_free(&m);
    return tip;
}

static void test_cantilever_hex_vs_tet(void)
{
    enum { NG = 5 };
    static const int ns[NG] = {1, 2, 3, 5, 7};
    double h[NG], t[NG], E = 1000, nu = 0.3, L = 4, Iy = 1.0 / 12, G = E / (2 * (1 + nu));
    double timo = L * L * L / (3 * E * Iy) + L / (5.0 / 6 * G);
    for (int i = 0; i < NG; i++) {
        h[i] = tip_deflection(1, ns[i]);
        t[i] = tip_deflection(0, ns[i]);
    }
    /* the limit: Richardson's from the two finest hex grids, error ~ n^-2 */
    double n1 = ns[NG - 2], n2 = ns[NG - 1], lim = (n2 * n2 * h[NG - 1] - n1 * n1 * h[NG - 2]) / (n2 * n2 - n1 * n1);
    for (int i = 0; i < NG; i++) {
        T_CHECK(h[i] > 0 && t[i] > 0 && h[i] < lim && t[i] < lim, "n %d: deflections hex %g tet %g, limit %g",
                ns[i], h[i], t[i], lim);
        T_CHECK(fabs(h[i] - lim) < fabs(t[i] - lim), "n %d: hex %g is farther than tet %g from %g", ns[i], h[i],
                t[i], lim);
        if (i) {
            T_CHECK(fabs(h[i] - t[i]) < fabs(h[i - 1] - t[i - 1]), "n %d: the gap grows: %g, was %g", ns[i],
                    fabs(h[i] - t[i]), fabs(h[i - 1] - t[i - 1]));
            T_CHECK(h[i] > h[i - 1] && t[i] > t[i - 1], "n %d: not monotone (hex %g, tet %g)", ns[i], h[i], t[i]);
        }
    }
    T_CHECK(fabs(h[NG - 1] - t[NG - 1]) < 0.1 * lim, "finest grid: hex %g, tet %g", h[NG - 1], t[NG - 1]);
    double tlim = (n2 * n2 * t[NG - 1] - n1 * n1 * t[NG - 2]) / (n2 * n2 - n1 * n1);
    T_CHECK(fabs(tlim - lim) < 0.03 * lim, "the tet limit %g is not the hex limit %g", tlim, lim);
    T_CHECK(fabs(lim - timo) < 0.1 * timo, "limit %g, Timoshenko %g", lim, timo);
    if (getenv("AUG_VERBOSE"))
        for (int i = 0; i < NG; i++)
            printf("n %d: hex %.6g tet %.6g (limit %.6g, Timoshenko %.6g)\n", ns[i], h[i], t[i], lim, timo);
}

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(test_element_symmetry_and_null_space);
    T_RUN(test_global_null_space);
    T_RUN(test_patch_3d);
    T_RUN(test_patch_tri3);
    T_RUN(test_plane_stress_tension);
    T_RUN(test_mass);
    T_RUN(test_multimaterial_sum);
    T_RUN(test_assembly_vs_triplets);
    T_RUN(test_load_lifting);
    T_RUN(test_hex_element_independent);
    T_RUN(test_hex_scaled_jacobian);
    T_RUN(test_cantilever_hex_vs_tet);
    cholmod_finish(&cm);
    T_EXIT();
}
