/* Lowest vibration modes with their vectors (aug_modes_lowest_vec): the
   residual of K x = lambda M x, M-orthonormality X'MX = I, and the eigenvalues
   against a dense generalized eigensolve (LAPACK dsygv), on a tet and a hex
   cantilever, by the factor of K (statics) and of A = cM M + cK K (dynamics);
   X NULL gives the same eigenvalues bit for bit. In dynamics a body held by
   nothing, or only along a line, has rigid motions left free
   (aug_free_rigid_modes: 6 and 1 in 3-D, 3 in 2-D), deflated: lambda = 0
   exactly and K x = 0 for each, the rest against dsygv (without the
   deflation the free tet box gave 2 zero eigenvalues of 6, converged). */
#include <lapacke.h>
#include "t.h"
#include "fem_mesh.h"

static cholmod_common cm;
static double worst_res, worst_orth, worst_lam;

enum { HELD, FREE, LINE };

static void check_modes(aug_mesh *m, double cM, double cK, int nev, int support, int nrigid)
{
    aug_err e;
    m->mats[0].rho = 7.8;
    if (support == HELD) tm_fix_plane(m, 0, 0.0, NULL);
    if (support == LINE) { /* the nodes on the edge y = z = 0: rotation about it stays free */
        unsigned char *sel = calloc((size_t)m->nn, 1);
        for (int64_t i = 0; i < m->nn; i++) sel[i] = fabs(m->x[i * 3 + 1]) < 1e-12 && fabs(m->x[i * 3 + 2]) < 1e-12;
        tm_fix_nodes(m, sel, NULL);
        free(sel);
    }
    int32_t *map = malloc((size_t)m->nn * m->dim * sizeof *map);
    int64_t n = aug_dofmap(m, map);
    cholmod_sparse *K = aug_assemble(m, map, n, AUG_MAT_K, &cm, &e);
    cholmod_sparse *M = aug_assemble(m, map, n, AUG_MAT_M, &cm, &e);
    T_CHECK(K && M, "assemble: %s", e.msg);
    double am[2] = {cM, 0}, ak[2] = {cK, 0};
    cholmod_sparse *F = cM == 0 && cK == 1 ? K : cholmod_add(M, K, am, ak, 1, 1, &cm);
    aug_factor_options(&cm, AUG_ORDER_AUTO, 0);
    cholmod_factor *L = aug_analyze(F, &cm, &e);
    T_CHECK(L && aug_factorize(F, L, m, map, &cm, &e) == 0, "factor: %s", e.msg);
    double *X = malloc((size_t)n * nev * sizeof *X), *R = NULL;
    int64_t k = aug_free_rigid_modes(m, map, n, nev, &R);
    T_CHECK(k == nrigid, "%lld free rigid motions, want %d", (long long)k, nrigid);
    aug_modes r, r0;
    T_CHECK(aug_modes_lowest_vec(M, L, cM, cK, nev, 1e-13, R, (int)k, &r, X, &cm, &e) == 0 && r.converged,
            "modes: %s", e.msg);
    T_CHECK(aug_modes_lowest(M, L, cM, cK, nev, 1e-13, R, (int)k, &r0, &cm, &e) == 0 && r0.converged, "modes: %s",
            e.msg);
    free(R);
    for (int j = 0; j < nev; j++)
        T_CHECK(r.lambda[j] == r0.lambda[j], "mode %d: %.17g with vectors, %.17g without", j, r.lambda[j], r0.lambda[j]);
    /* residuals and X'MX */
    double *kx = malloc((size_t)n * sizeof *kx), *mx = malloc((size_t)n * nev * sizeof *mx);
    for (int j = 0; j < nev; j++) {
        tm_symv(K, X + (size_t)j * n, kx);
        tm_symv(M, X + (size_t)j * n, mx + (size_t)j * n);
        double res = 0;
        for (int64_t i = 0; i < n; i++) {
            double d = kx[i] - r.lambda[j] * mx[(size_t)j * n + i];
            res += d * d;
        }
        /* a rigid motion: K x = 0, relative to ||K|| ||x|| (its ||K x|| is rounding) */
        double kn = 0;
        for (size_t t = 0; t < K->nzmax; t++) kn = fmax(kn, fabs(((double *)K->x)[t]));
        res = j < nrigid ? sqrt(res) / (kn * tm_norm(X + (size_t)j * n, n)) : sqrt(res) / tm_norm(kx, n);
        if (j < nrigid) T_CHECK(r.lambda[j] == 0, "mode %d: lambda %.3g, a free rigid motion", j, r.lambda[j]);
        if (res > worst_res) worst_res = res;
        T_CHECK(res <= 1e-8, "mode %d: relative residual %.2e", j, res);
    }
    for (int j = 0; j < nev; j++)
        for (int k = 0; k < nev; k++) {
            double g = 0;
            for (int64_t i = 0; i < n; i++) g += X[(size_t)j * n + i] * mx[(size_t)k * n + i];
            double d = fabs(g - (j == k));
            if (d > worst_orth) worst_orth = d;
            T_CHECK(d <= 1e-10, "X'MX (%d, %d) = %.15g", j, k, g);
        }
    /* dense generalized eigenvalues, ascending */
    double *DK = tm_dense(K), *DM = tm_dense(M), *w = malloc((size_t)n * sizeof *w);
    T_CHECK(LAPACKE_dsygv(LAPACK_COL_MAJOR, 1, 'N', 'U', (int)n, DK, (int)n, DM, (int)n, w) == 0, "dsygv");
    for (int j = 0; j < nev; j++) {
        /* dsygv's zero eigenvalues are rounding of the size eps ||K|| / ||M|| */
        double d = j < nrigid ? fabs(w[j]) / w[nev - 1] : t_reldiff(r.lambda[j], w[j]);
        if (d > worst_lam) worst_lam = d;
        T_CHECK(d <= 1e-8, "lambda %d: %.15g, dense %.15g", j, r.lambda[j], w[j]);
    }
    free(DK), free(DM), free(w), free(kx), free(mx), free(X), free(map);
    if (F != K) cholmod_free_sparse(&F, &cm);
    cholmod_free_sparse(&K, &cm);
    cholmod_free_sparse(&M, &cm);
    cholmod_free_factor(&L, &cm);
}

enum { TET, HEX, TRI };

/* the cantilever 3 x 1 x 1 (tri: 3 x 1), fixed at x = 0 */
static void run_case(int kind, double cM, double cK, int nev, int support, int nrigid)
{
    aug_mesh m;
    if (kind == TET) tm_box(&m, 6, 2, 2, 3, 1, 1, 2e3, 0.3);
    else if (kind == HEX) tm_hexbox(&m, 6, 2, 2, 3, 1, 1, 2e3, 0.3);
    else tm_rect(&m, 10, 3, 3, 1, 2e3, 0.3, 0.5);
    check_modes(&m, cM, cK, nev, support, nrigid);
    aug_mesh_free(&m);
}

static void tet_static(void) { run_case(TET, 0, 1, 8, HELD, 0); }
static void tet_dynamic(void) { run_case(TET, 4e2, 0.25, 6, HELD, 0); }
static void hex_static(void) { run_case(HEX, 0, 1, 8, HELD, 0); }
static void tri_dynamic(void) { run_case(TRI, 1e3, 1.0, 5, HELD, 0); }
/* cM / cK of Euler at dt = 0.01 (1 / dt^2): rigid motions at mu = cM, the
   elastic ones within 1e-4 of it */
static void tet_free(void) { run_case(TET, 1e4, 1.0, 10, FREE, 6); }
static void hex_free(void) { run_case(HEX, 1e4, 1.0, 8, FREE, 6); }
static void tet_line(void) { run_case(TET, 1e4, 1.0, 6, LINE, 1); }
static void tri_free(void) { run_case(TRI, 1e4, 1.0, 6, FREE, 3); }

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(tet_static);
    T_RUN(tet_dynamic);
    T_RUN(hex_static);
    T_RUN(tri_dynamic);
    T_RUN(tet_free);
    T_RUN(hex_free);
    T_RUN(tet_line);
    T_RUN(tri_free);
    printf("measured: residual %.2e, |X'MX - I| %.2e, lambda vs dsygv rel %.2e\n", worst_res,
           worst_orth, worst_lam);
    cholmod_finish(&cm);
    T_EXIT();
}
