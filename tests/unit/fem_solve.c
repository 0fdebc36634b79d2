/* Solves through the factor: cantilever convergence to beam theory, agreement
   with an independent Jacobi PCG, singular scenes, a not positive definite
   pivot named, the condition estimate against dense eigenvalues. */
#include <lapacke.h>
#include "t.h"
#include "fem_mesh.h"

static cholmod_common cm;

typedef struct solved {
    int32_t *map;
    int64_t n;
    cholmod_sparse *K;
    cholmod_factor *L;
    double *f, *a, *u, relres;
} solved;

static int solve_mesh(aug_mesh *m, solved *s, aug_err *e)
{
    memset(s, 0, sizeof *s);
    s->map = malloc((size_t)m->nn * m->dim * sizeof *s->map);
    s->n = aug_dofmap(m, s->map);
    if (aug_check_support(m, e)) return e->code;
    s->K = aug_assemble(m, s->map, s->n, AUG_MAT_K, &cm, e);
    s->f = malloc((size_t)s->n * sizeof *s->f);
    s->a = malloc((size_t)s->n * sizeof *s->a);
    s->u = malloc((size_t)m->nn * m->dim * sizeof *s->u);
    if (!s->K || aug_load_vector(m, s->map, s->n, s->f, e)) return e->code;
    aug_factor_options(&cm, AUG_ORDER_AUTO, 0);
    if (!(s->L = aug_analyze(s->K, &cm, e))) return e->code;
    if (aug_factorize(s->K, s->L, m, s->map, &cm, e)) return e->code;
    if (aug_solve(s->K, s->L, s->f, s->a, &s->relres, &cm, e)) return e->code;
    aug_expand_field(m, s->map, s->a, s->u);
    return 0;
}

static void solved_free(solved *s)
{
    cholmod_free_sparse(&s->K, &cm);
    cholmod_free_factor(&s->L, &cm);
    free(s->map);
    free(s->f);
    free(s->a);
    free(s->u);
}

/* total force F (component c) on the nodes with x[axis] = value, distributed
   by the nodes' share of the end face (trapezoidal weights per grid line) */
static void end_load(aug_mesh *m, int axis, double value, int c, double F)
{
    int d = m->dim;
    m->load_dof = malloc((size_t)m->nn * sizeof(int32_t));
    m->load_val = malloc((size_t)m->nn * sizeof(double));
    m->nload = 0;
    double wsum = 0;
    for (int64_t i = 0; i < m->nn; i++) {
        if (fabs(m->x[i * d + axis] - value) > 1e-12) continue;
        double w = 1;
        for (int q = 0; q < d; q++) {
            if (q == axis) continue;
            double lo = 0, hi = 0;
            for (int64_t j = 0; j < m->nn; j++) {
                lo = fmin(lo, m->x[j * d + q]);
                hi = fmax(hi, m->x[j * d + q]);
            }
            double y = m->x[i * d + q];
            if (fabs(y - lo) < 1e-12 || fabs(y - hi) < 1e-12) w *= 0.5;
        }
        m->load_dof[m->nload] = (int32_t)(i * d + c);
        m->load_val[m->nload++] = w;
        wsum += w;
    }
    for (int64_t t = 0; t < m->nload; t++) m->load_val[t] *= F / wsum;
    m->have |= AUG_HAVE_LOAD;
}

/* mean tip deflection (component c) over the nodes at x[axis] = value */
static double tip(const aug_mesh *m, const double *u, int axis, double value, int c)
{
    double s = 0;
    int n = 0;
    for (int64_t i = 0; i < m->nn; i++)
        if (fabs(m->x[i * m->dim + axis] - value) < 1e-12) s += u[i * m->dim + c], n++;
    return s / n;
}

/* Cantilever of length Lx, square section h (3-D, tet4) or depth h and
   thickness t (2-D, tri3 plane stress), clamped at x = 0, end shear F.
   Timoshenko: delta = F L^3 / (3 E I) + F L / (kappa G A), kappa = 5/6; the
   Euler-Bernoulli part dominates (slenderness 20, nu = 0). The error must fall
   under refinement; the observed rate is printed. */
static void cantilever(int dim, int levels, const int *nx, double tol_final)
{
    const double Lx = 20, h = 1, E = 1000, nu = 0, F = -0.05, t = 0.5;
    double Iz = dim == 3 ? h * h * h * h / 12 : t * h * h * h / 12, A = dim == 3 ? h * h : t * h;
    double G = E / (2 * (1 + nu));
    double eb = F * Lx * Lx * Lx / (3 * E * Iz), timo = eb + F * Lx / (5.0 / 6.0 * G * A);
    double err[8], hs[8];
    for (int lv = 0; lv < levels; lv++) {
        aug_mesh m;
        int ny = nx[lv] / 20 > 0 ? nx[lv] / 20 : 1;
        if (dim == 3) tm_box(&m, nx[lv], ny, ny, Lx, h, h, E, nu);
        else tm_rect(&m, nx[lv], ny, Lx, h, E, nu, t);
        tm_fix_plane(&m, 0, 0.0, NULL);
        end_load(&m, 0, Lx, 1, F);
        solved s;
        aug_err e;
        int rc = solve_mesh(&m, &s, &e);
        T_CHECK(rc == 0, "solve: %s", e.msg);
        double d = rc ? NAN : tip(&m, s.u, 0, Lx, 1);
        err[lv] = fabs(d - timo) / fabs(timo);
        hs[lv] = Lx / nx[lv];
        printf("  %d-D cantilever %dx%d%s: n %lld, tip %.6g, Timoshenko %.6g (EB %.6g), rel. error %.3e",
               dim, nx[lv], ny, dim == 3 ? "x(same)" : "", (long long)s.n, d, timo, eb, err[lv]);
        if (lv > 0) printf(", observed rate %.2f", log(err[lv - 1] / err[lv]) / log(hs[lv - 1] / hs[lv]));
        printf("\n");
        /* bending makes K ill-conditioned: check the normwise backward error */
        double eta = rc ? NAN : s.relres * tm_norm(s.f, s.n) /
                                    (cholmod_norm_sparse(s.K, 1, &cm) * tm_norm(s.a, s.n) + tm_norm(s.f, s.n));
        T_CHECK(eta < 1e-14, "backward error %g (relres %g)", eta, s.relres);
        T_CHECK(lv == 0 || err[lv] < err[lv - 1], "error did not decrease: %g -> %g", err[lv - 1], err[lv]);
        solved_free(&s);
        aug_mesh_free(&m);
    }
    double rate = log(err[levels - 2] / err[levels - 1]) / log(hs[levels - 2] / hs[levels - 1]);
    T_CHECK(rate > 1.5, "%d-D: observed convergence rate %.2f (expected about 2)", dim, rate);
    T_CHECK(err[levels - 1] < tol_final, "%d-D: final error %g", dim, err[levels - 1]);
}

static void test_cantilever_tri3(void)
{
    int nx[5] = {20, 40, 80, 160, 320};
    cantilever(2, 5, nx, 0.02);
}

static void test_cantilever_tet4(void)
{
    int nx[4] = {20, 40, 80, 160};
    cantilever(3, 4, nx, 0.08);
}

/* Jacobi-preconditioned CG on K x = f to ||r|| <= tol ||f||; returns iterations */
static int pcg(const cholmod_sparse *K, const double *f, double *x, double tol, int maxit)
{
    int64_t n = (int64_t)K->nrow;
    double *r = malloc(n * sizeof *r), *z = malloc(n * sizeof *z), *p = malloc(n * sizeof *p);
    double *q = malloc(n * sizeof *q), *dinv = malloc(n * sizeof *dinv);
    const int *Ap = K->p, *Ai = K->i;
    const double *Ax = K->x;
    for (int64_t j = 0; j < n; j++)
        for (int k = Ap[j]; k < Ap[j + 1]; k++)
            if (Ai[k] == j) dinv[j] = 1 / Ax[k];
    memset(x, 0, n * sizeof *x);
    memcpy(r, f, n * sizeof *r);
    double fn = tm_norm(f, n), rz = 0;
    for (int64_t i = 0; i < n; i++) z[i] = dinv[i] * r[i], p[i] = z[i], rz += r[i] * z[i];
    int it = 0;
    while (tm_norm(r, n) > tol * fn && it < maxit) {
        tm_symv(K, p, q);
        double pq = 0;
        for (int64_t i = 0; i < n; i++) pq += p[i] * q[i];
        double al = rz / pq, rz2 = 0;
        for (int64_t i = 0; i < n; i++) x[i] += al * p[i], r[i] -= al * q[i];
        for (int64_t i = 0; i < n; i++) z[i] = dinv[i] * r[i], rz2 += r[i] * z[i];
        for (int64_t i = 0; i < n; i++) p[i] = z[i] + rz2 / rz * p[i];
        rz = rz2;
        it++;
    }
    free(r);
    free(z);
    free(p);
    free(q);
    free(dinv);
    return it;
}

/* ||x_chol - x_pcg|| / ||x_chol|| <= cond(K) * tol: the bound the residual
   criterion of PCG guarantees */
static void test_factor_matches_pcg(void)
{
    aug_mesh m;
    tm_box(&m, 6, 3, 3, 2, 1, 1, 50.0, 0.3);
    tm_fix_plane(&m, 0, 0.0, NULL);
    end_load(&m, 0, 2.0, 2, 1.0);
    solved s;
    aug_err e;
    T_CHECK(solve_mesh(&m, &s, &e) == 0, "%s", e.msg);
    aug_cond c;
    T_CHECK(aug_cond_estimate(s.K, s.L, 1e-8, &c, &cm, &e) == 0 && c.converged, "cond: %s", e.msg);
    double tol = 1e-10, *x = malloc((size_t)s.n * sizeof *x);
    int it = pcg(s.K, s.f, x, tol, 100000);
    double d = 0;
    for (int64_t i = 0; i < s.n; i++) d += (x[i] - s.a[i]) * (x[i] - s.a[i]);
    d = sqrt(d) / tm_norm(s.a, s.n);
    printf("  PCG: %d iterations to %g, cond(K) %.3g, relative difference %.3g (bound %.3g)\n", it,
           tol, c.cond, d, c.cond * tol);
    T_CHECK(it < 100000, "PCG did not converge");
    T_CHECK(d <= c.cond * tol, "factor and PCG differ by %g > cond * tol = %g", d, c.cond * tol);
    T_CHECK(s.relres < 1e-12, "factor relres %g", s.relres);
    free(x);
    solved_free(&s);
    aug_mesh_free(&m);
}

/* condition estimate (ARPACK) against dense LAPACK eigenvalues, n > 64 */
static void test_cond_vs_dense(void)
{
    aug_mesh m;
    tm_box(&m, 8, 2, 2, 4, 1, 1, 10.0, 0.3);
    tm_fix_plane(&m, 0, 0.0, NULL);
    solved s;
    aug_err e;
    T_CHECK(solve_mesh(&m, &s, &e) == 0, "%s", e.msg);
    T_CHECK(s.n > 64, "mesh too small for the iterative path");
    aug_cond c;
    T_CHECK(aug_cond_estimate(s.K, s.L, 1e-8, &c, &cm, &e) == 0 && c.converged, "cond: %s", e.msg);
    double *D = tm_dense(s.K), *w = malloc((size_t)s.n * sizeof *w);
    LAPACKE_dsyev(LAPACK_COL_MAJOR, 'N', 'U', (int)s.n, D, (int)s.n, w);
    double lmin = w[0], lmax = w[s.n - 1];
    T_CHECK(t_reldiff(c.lambda_max, lmax) < 1e-7, "lambda_max %.10g vs %.10g", c.lambda_max, lmax);
    T_CHECK(t_reldiff(c.lambda_min, lmin) < 1e-7, "lambda_min %.10g vs %.10g", c.lambda_min, lmin);
    T_CHECK(t_reldiff(c.cond, lmax / lmin) < 1e-6, "cond %g vs %g", c.cond, lmax / lmin);
    T_CHECK(c.iters_max > 0 && c.iters_min > 0, "iteration counts");
    printf("  cond: %.6g (dense %.6g), %d + %d operator applications\n", c.cond, lmax / lmin,
           c.iters_max, c.iters_min);
    free(D);
    free(w);
    solved_free(&s);
    aug_mesh_free(&m);
}

static int singular_message(aug_mesh *m, const char *want, char *got)
{
    aug_err e;
    int rc = aug_check_support(m, &e);
    snprintf(got, 256, "%s", e.msg);
    return rc == AUG_ESINGULAR && strstr(e.msg, want) != NULL;
}

static void test_singular_scenes(void)
{
    aug_mesh m;
    char got[256];
    aug_err e;
    /* no Dirichlet set at all */
    tm_box(&m, 2, 2, 2, 1, 1, 1, 1.0, 0.3);
    T_CHECK(singular_message(&m, "singular scene: component of 27 nodes (node 0, material mat0) has no Dirichlet support", got),
            "no Dirichlet: '%s'", got);
    /* one node fixed: rotations free */
    unsigned char *sel = calloc((size_t)m.nn, 1);
    sel[13] = 1;
    tm_fix_nodes(&m, sel, NULL);
    T_CHECK(singular_message(&m, "leave 3 of 6 rigid-body modes free", got), "one node: '%s'", got);
    /* a line of nodes (x axis, y = z = 0) fixed: rotation about it free */
    memset(sel, 0, (size_t)m.nn);
    for (int64_t i = 0; i < m.nn; i++) sel[i] = m.x[i * 3 + 1] == 0 && m.x[i * 3 + 2] == 0;
    tm_fix_nodes(&m, sel, NULL);
    T_CHECK(singular_message(&m, "leave 1 of 6", got), "line: '%s'", got);
    /* three non-collinear nodes fixed: held */
    sel[m.nn - 1] = 1;
    tm_fix_nodes(&m, sel, NULL);
    T_CHECK(aug_check_support(&m, &e) == 0, "three nodes refused: %s", e.msg);
    /* only z fixed on the bottom face: x, y translation and z rotation free */
    tm_fix_plane(&m, 2, 0.0, NULL);
    {
        int64_t k = 0;
        for (int64_t t = 0; t < m.nfix; t++)
            if (m.fix_dof[t] % 3 == 2) m.fix_dof[k] = m.fix_dof[t], m.fix_val[k++] = 0;
        m.nfix = k;
    }
    T_CHECK(singular_message(&m, "leave 3 of 6", got), "z only: '%s'", got);
    free(sel);
    aug_mesh_free(&m);

    /* a floating second component: two boxes side by side, only the first fixed */
    aug_mesh a, b;
    tm_box(&a, 2, 1, 1, 1, 1, 1, 1.0, 0.3);
    tm_box(&b, 1, 1, 1, 1, 1, 1, 1.0, 0.3);
    aug_mesh_init(&m);
    m.dim = 3, m.etype = AUG_TET4, m.nv = 4;
    m.nn = a.nn + b.nn;
    m.x = malloc((size_t)m.nn * 3 * sizeof(double));
    memcpy(m.x, a.x, (size_t)a.nn * 3 * sizeof(double));
    for (int64_t i = 0; i < b.nn; i++)
        for (int c = 0; c < 3; c++) m.x[(a.nn + i) * 3 + c] = b.x[i * 3 + c] + (c == 0 ? 5.0 : 0);
    m.ne = a.ne + b.ne;
    m.conn = malloc((size_t)m.ne * 4 * sizeof(int32_t));
    m.mat = malloc((size_t)m.ne * sizeof(int32_t));
    for (int64_t i = 0; i < a.ne * 4; i++) m.conn[i] = a.conn[i];
    for (int64_t i = 0; i < b.ne * 4; i++) m.conn[a.ne * 4 + i] = b.conn[i] + (int32_t)a.nn;
    for (int64_t i = 0; i < m.ne; i++) m.mat[i] = i >= a.ne;
    m.have = AUG_HAVE_NODE | AUG_HAVE_ELEM;
    tm_material(&m, 2, 1.0, 0.3, 1.0, 1.0);
    snprintf(m.mats[1].name, AUG_NAME, "%s", "loose");
    tm_fix_plane(&m, 0, 0.0, NULL);
    int32_t comp[64];
    T_CHECK(aug_mesh_components(&m, comp) == 2 && comp[0] == 0 && comp[a.nn] == 1, "components");
    char want[128];
    snprintf(want, sizeof want, "component of %lld nodes (node %lld, material loose) has no Dirichlet support",
             (long long)b.nn, (long long)a.nn);
    T_CHECK(singular_message(&m, want, got), "floating piece: '%s'", got);
    aug_mesh_free(&m);
    aug_mesh_free(&a);
    aug_mesh_free(&b);

    /* 2-D: only x fixed on the left edge: y translation free */
    tm_rect(&m, 3, 2, 1, 1, 1.0, 0.3, 1.0);
    tm_fix_plane(&m, 0, 0.0, NULL);
    T_CHECK(aug_check_support(&m, &e) == 0, "2-D clamped edge refused: %s", e.msg);
    {
        int64_t k = 0;
        for (int64_t t = 0; t < m.nfix; t++)
            if (m.fix_dof[t] % 2 == 0) m.fix_dof[k] = m.fix_dof[t], m.fix_val[k++] = 0;
        m.nfix = k;
    }
    T_CHECK(singular_message(&m, "leave 1 of 3", got), "2-D roller edge: '%s'", got);
    aug_mesh_free(&m);
}

/* an indefinite matrix: the failing pivot is named down to its node */
static void test_not_posdef_named(void)
{
    aug_mesh m;
    tm_box(&m, 2, 2, 2, 1, 1, 1, 1.0, 0.3);
    tm_fix_plane(&m, 2, 0.0, NULL);
    int32_t *map = malloc((size_t)m.nn * 3 * sizeof *map);
    int64_t n = aug_dofmap(&m, map);
    aug_err e;
    for (int simplicial = 0; simplicial < 2; simplicial++) {
        cholmod_sparse *K = aug_assemble(&m, map, n, AUG_MAT_K, &cm, &e);
        /* make the diagonal of node 22's y DOF negative */
        int f = map[22 * 3 + 1];
        int *Ap = K->p;
        ((double *)K->x)[Ap[f + 1] - 1] = -1.0;
        aug_factor_options(&cm, AUG_ORDER_AMD, simplicial);
        cholmod_factor *L = aug_analyze(K, &cm, &e);
        int rc = aug_factorize(K, L, &m, map, &cm, &e);
        T_CHECK(rc == AUG_ESINGULAR && strstr(e.msg, "not positive definite") && strstr(e.msg, "node"),
                "%s: rc %d '%s'", simplicial ? "simplicial" : "supernodal", rc, e.msg);
        cholmod_free_factor(&L, &cm);
        cholmod_free_sparse(&K, &cm);
    }
    printf("  e.g. %s\n", e.msg);
    free(map);
    aug_mesh_free(&m);
}

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(test_cantilever_tri3);
    T_RUN(test_cantilever_tet4);
    T_RUN(test_factor_matches_pcg);
    T_RUN(test_cond_vs_dense);
    T_RUN(test_singular_scenes);
    T_RUN(test_not_posdef_named);
    cholmod_finish(&cm);
    T_EXIT();
}
