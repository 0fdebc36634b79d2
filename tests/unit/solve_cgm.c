/* The thesis 003 sec. 3.5 transforms against dense references: COV from its
   definition (eq. 3.21), the blocked L D L' against the textbook one and its
   recomposition, Newton-Schulz against the square root known by construction,
   and every variant's cond, lambda_max and error against an independent dense
   computation on a small square with a sliver element. */
#include <lapacke.h>
#include "t.h"
#include "fem_mesh.h"
#include "aug_solve.h"

static cholmod_common cm;

static double urand(unsigned long *s)
{
    *s = *s * 6364136223846793005ul + 1442695040888963407ul;
    return (double)(*s >> 11) / 9007199254740992.0 - 0.5;
}

/* K (upper) of a 6 x 6 square fixed at x = 0, the node at (1/2, 1/2) moved
   next to its neighbour at (1/3, 1/2) (a sliver, as a cut makes) */
static cholmod_sparse *square_K(void)
{
    aug_mesh m;
    aug_err e;
    tm_rect(&m, 6, 6, 1, 1, 1000, 0.3, 1);
    m.x[2 * (3 + 7 * 3)] = 1.0 / 3 + 0.01; /* node (3, 3) */
    tm_fix_plane(&m, 0, 0, NULL);
    int32_t *map = malloc((size_t)m.nn * 2 * sizeof *map);
    int64_t n = aug_dofmap(&m, map);
    cholmod_sparse *K = aug_assemble(&m, map, n, AUG_MAT_K, &cm, &e);
    free(map);
    aug_mesh_free(&m);
    return K;
}

/* COV = 1/(n-1) sum_i (x_i - xbar)'(x_i - xbar), the rows x_i of A (eq. 3.21) */
static void naive_cov(const double *A, int n, double *C)
{
    double *xbar = calloc((size_t)n, sizeof *xbar);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) xbar[j] += A[(size_t)j * n + i] / n;
    memset(C, 0, (size_t)n * n * sizeof *C);
    for (int i = 0; i < n; i++)
        for (int a = 0; a < n; a++)
            for (int b = 0; b < n; b++)
                C[(size_t)b * n + a] += (A[(size_t)a * n + i] - xbar[a]) * (A[(size_t)b * n + i] - xbar[b]) / (n - 1);
    free(xbar);
}

/* textbook L D L' (column by column); pivots <= tiny are 0 with a zero column */
static void naive_ldl(const double *M, int n, double *L, double *d, double tiny)
{
    memset(L, 0, (size_t)n * n * sizeof *L);
    for (int j = 0; j < n; j++) {
        double s = M[(size_t)j * n + j];
        for (int k = 0; k < j; k++) s -= L[(size_t)k * n + j] * L[(size_t)k * n + j] * d[k];
        L[(size_t)j * n + j] = 1;
        if (!(s > tiny)) {
            d[j] = 0;
            continue;
        }
        d[j] = s;
        for (int i = j + 1; i < n; i++) {
            double t = M[(size_t)j * n + i];
            for (int k = 0; k < j; k++) t -= L[(size_t)k * n + i] * L[(size_t)k * n + j] * d[k];
            L[(size_t)j * n + i] = t / s;
        }
    }
}

/* T = L diag(F) L' by its definition */
static void naive_recompose(const double *L, const double *F, int n, double *T)
{
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double s = 0;
            for (int k = 0; k < n; k++) s += L[(size_t)k * n + i] * F[k] * L[(size_t)k * n + j];
            T[(size_t)j * n + i] = s;
        }
}

static double fro_diff(const double *A, const double *B, size_t nn, double *nb)
{
    double d = 0, b = 0;
    for (size_t i = 0; i < nn; i++) d += (A[i] - B[i]) * (A[i] - B[i]), b += B[i] * B[i];
    *nb = sqrt(b);
    return sqrt(d);
}

static void t_cov(void)
{
    cholmod_sparse *K = square_K();
    int n = (int)K->nrow;
    double *A = tm_dense(K), *C = malloc((size_t)n * n * sizeof *C), *R = malloc((size_t)n * n * sizeof *R), nb;
    aug_err e;
    T_CHECK(!aug_cgm_cov(K, C, &cm, &e), "cov failed: %s", e.msg);
    naive_cov(A, n, R);
    double d = fro_diff(C, R, (size_t)n * n, &nb);
    T_CHECK(d <= 1e-13 * nb, "COV differs from eq. 3.21 by %g of %g", d, nb);
    free(A), free(C), free(R);
    cholmod_free_sparse(&K, &cm);
}

static void t_ldl(void)
{
    int n = 150; /* more than two blocks of 64 */
    size_t nn = (size_t)n * n;
    double *G = malloc(nn * sizeof *G), *M = malloc(nn * sizeof *M), *W = malloc(nn * sizeof *W);
    double *L = malloc(nn * sizeof *L), *T = malloc(nn * sizeof *T), *d = malloc(n * sizeof *d), *d2 = malloc(n * sizeof *d2), nb;
    unsigned long s = 7;
    for (size_t i = 0; i < nn; i++) G[i] = urand(&s);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double t = i == j ? 0.1 : 0;
            for (int k = 0; k < n; k++) t += G[(size_t)k * n + i] * G[(size_t)k * n + j];
            M[(size_t)j * n + i] = t;
        }
    memcpy(W, M, nn * sizeof *W);
    T_CHECK(aug_cgm_ldl(W, n, d) == 0, "zero pivots in an SPD matrix");
    naive_ldl(M, n, L, d2, 0);
    double dd = 0, dn = 0;
    for (int i = 0; i < n; i++) dd = fmax(dd, fabs(d[i] - d2[i]) / d2[i]);
    T_CHECK(dd <= 1e-10, "pivots differ from the textbook L D L' by %g", dd);
    for (int j = 0; j < n; j++)
        for (int i = j + 1; i < n; i++) dn = fmax(dn, fabs(W[(size_t)j * n + i] - L[(size_t)j * n + i]));
    T_CHECK(dn <= 1e-9, "L differs from the textbook L by %g", dn);
    aug_cgm_recompose(W, d, n, T);
    double r = fro_diff(T, M, nn, &nb);
    T_CHECK(r <= 1e-12 * nb, "L D L' differs from M by %g of %g", r, nb);
    /* the singular COV of the square: one zero pivot, L D L' = COV */
    cholmod_sparse *K = square_K();
    int m = (int)K->nrow;
    aug_err e;
    aug_cgm_cov(K, M, &cm, &e);
    memcpy(W, M, (size_t)m * m * sizeof *W);
    int z = aug_cgm_ldl(W, m, d);
    T_CHECK(z == 1, "COV (rank n-1) gave %d zero pivots", z);
    aug_cgm_recompose(W, d, m, T);
    r = fro_diff(T, M, (size_t)m * m, &nb);
    T_CHECK(r <= 1e-10 * nb, "L D L' differs from COV by %g of %g", r, nb);
    cholmod_free_sparse(&K, &cm);
    free(G), free(M), free(W), free(L), free(T), free(d), free(d2);
}

/* Y = V diag(lambda) V' with lambda from 1e-6 to 1 and V orthogonal (QR of a
   random matrix): P = (Y/c)^(1/2) = V diag(sqrt(lambda/c)) V' */
static void t_newton_schulz(void)
{
    int n = 80;
    size_t nn = (size_t)n * n;
    double *V = malloc(nn * sizeof *V), *Y = calloc(nn, sizeof *Y), *S = calloc(nn, sizeof *S), *P = malloc(nn * sizeof *P);
    double *tau = malloc(n * sizeof *tau), lam[80], nb;
    unsigned long s = 11;
    for (size_t i = 0; i < nn; i++) V[i] = urand(&s);
    LAPACKE_dgeqrf(LAPACK_COL_MAJOR, n, n, V, n, tau);
    LAPACKE_dorgqr(LAPACK_COL_MAJOR, n, n, n, V, n, tau);
    for (int k = 0; k < n; k++) lam[k] = pow(10.0, -6.0 * k / (n - 1));
    double c = 0;
    for (int k = 0; k < n; k++) c += lam[k] * lam[k];
    c = sqrt(c); /* ||Y||_F */
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            for (int k = 0; k < n; k++) {
                Y[(size_t)j * n + i] += V[(size_t)k * n + i] * lam[k] * V[(size_t)k * n + j];
                S[(size_t)j * n + i] += V[(size_t)k * n + i] * sqrt(lam[k] / c) * V[(size_t)k * n + j];
            }
    int it;
    double scale;
    int ok = aug_cgm_newton_schulz(Y, n, 1e-12, 100, P, &it, &scale);
    T_CHECK(ok == 1, "did not converge in %d iterations", it);
    T_CHECK(fabs(scale - c) <= 1e-12 * c, "scale %.17g, ||Y||_F %.17g", scale, c);
    double d = fro_diff(P, S, nn, &nb);
    T_CHECK(d <= 1e-12 * nb, "||P - (Y/c)^1/2||_F = %g of %g after %d iterations", d, nb, it);
    free(V), free(Y), free(S), free(P), free(tau);
}

/* every variant on the square: T built by the definitions above (AS: the
   square root of COV + eps I by dsyev), its eigenvalues by dsyev, the error
   against a dense LAPACK solve of K */
static void t_variants(void)
{
    cholmod_sparse *K = square_K();
    int n = (int)K->nrow;
    size_t nn = (size_t)n * n;
    double *A = tm_dense(K), *C = malloc(nn * sizeof *C), *L = malloc(nn * sizeof *L), *T = malloc(nn * sizeof *T);
    double *V = malloc(nn * sizeof *V), *d = malloc(n * sizeof *d), *F = malloc(n * sizeof *F), *w = malloc(n * sizeof *w);
    double *f = malloc(n * sizeof *f), *u = malloc(n * sizeof *u), *x = malloc(n * sizeof *x), *xr = malloc(n * sizeof *xr);
    unsigned long s = 3;
    for (int i = 0; i < n; i++) f[i] = urand(&s);
    memcpy(u, f, n * sizeof *u);
    memcpy(V, A, nn * sizeof *V);
    LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', n, 1, V, n, u, n);
    aug_cgm_opts o;
    aug_cgm_opts_default(&o);
    naive_cov(A, n, C);
    double dmax = 0;
    for (int j = 0; j < n; j++) dmax = fmax(dmax, C[(size_t)j * n + j]);
    naive_ldl(C, n, L, d, n * 2.220446049250313e-16 * dmax);
    for (int v = 0; v < AUG_CGM_COUNT; v++) {
        aug_cgm_res r;
        aug_err e;
        int rc = aug_cgm_solve(v, K, f, &o, 1e-12, 20000, x, &r, &cm, &e);
        T_CHECK(!rc, "variant %d failed: %s", v, e.msg);
        if (v == AUG_CGM_AS) {
            memcpy(V, C, nn * sizeof *V);
            for (int i = 0; i < n; i++) V[(size_t)i * n + i] += o.eps;
            LAPACKE_dsyev(LAPACK_COL_MAJOR, 'V', 'L', n, V, n, w);
            for (int i = 0; i < n; i++) F[i] = sqrt(w[i]);
            naive_recompose(V, F, n, T); /* V orthogonal: T = V sqrt(W) V' */
            T_CHECK(r.ns_converged && r.ns_resid <= 1e-10, "Newton-Schulz: converged %d, ||P^2 - Y/c|| %g",
                    r.ns_converged, r.ns_resid);
        } else {
            for (int i = 0; i < n; i++)
                F[i] = v == AUG_CGM_COV ? d[i] : v == AUG_CGM_ES ? pow(d[i] + o.eps, o.p) : log(d[i] + o.eps);
            naive_recompose(L, F, n, T);
        }
        memcpy(V, T, nn * sizeof *V);
        LAPACKE_dsyev(LAPACK_COL_MAJOR, 'N', 'L', n, V, n, w);
        int imax = 0, imin = 0;
        for (int i = 1; i < n; i++) {
            if (fabs(w[i]) > fabs(w[imax])) imax = i;
            if (fabs(w[i]) < fabs(w[imin])) imin = i;
        }
        T_CHECK(t_reldiff(r.lambda_max, w[imax]) <= 1e-6, "variant %d: lambda_max %g, dsyev %g", v, r.lambda_max, w[imax]);
        if (v == AUG_CGM_COV) {
            T_CHECK(isinf(r.cond) && r.spd == 0 && r.zero_pivots == 1, "COV: cond %g, spd %d (rank n-1)", r.cond, r.spd);
        } else {
            /* AS: lambda_min = (eps + lambda_0(COV))^(1/2), lambda_0 = 0 known
               only to macheps ||COV|| (3e-9 here, against eps = 1e-6) */
            double cref = fabs(w[imax] / w[imin]), tol = v == AUG_CGM_AS ? 1e-3 : 1e-5;
            T_CHECK(t_reldiff(r.cond, cref) <= tol, "variant %d: cond %g, dsyev %g", v, r.cond, cref);
            T_CHECK(r.spd == (w[0] > 0), "variant %d: spd %d, lambda_1 %g", v, r.spd, w[0]);
        }
        /* the reported error is ||x - K^-1 f|| / ||K^-1 f|| of the x returned */
        double dx = 0, uu = 0, xx = 0, xu = 0;
        for (int i = 0; i < n; i++) dx += (x[i] - u[i]) * (x[i] - u[i]), uu += u[i] * u[i], xx += x[i] * x[i], xu += x[i] * u[i];
        T_CHECK(t_reldiff(r.err, sqrt(dx / uu)) <= 1e-9, "variant %d: err %.17g, dense %.17g", v, r.err, sqrt(dx / uu));
        T_CHECK(fabs(r.err_scaled - sqrt(fmax(0, 1 - xu * xu / (xx * uu)))) <= 1e-7, "variant %d: err_scaled %g", v, r.err_scaled);
        /* x solves T x = f where CG converged: against a dense solve of T */
        if (r.converged) {
            memcpy(V, T, nn * sizeof *V);
            memcpy(xr, f, n * sizeof *xr);
            lapack_int *ip = malloc(n * sizeof *ip);
            LAPACKE_dsysv(LAPACK_COL_MAJOR, 'L', n, 1, V, n, ip, xr, n);
            free(ip);
            double ex = 0, xn = 0;
            for (int i = 0; i < n; i++) ex += (x[i] - xr[i]) * (x[i] - xr[i]), xn += xr[i] * xr[i];
            T_CHECK(sqrt(ex / xn) <= 1e-10 * r.cond, "variant %d: x off T^-1 f by %g (cond %g)", v, sqrt(ex / xn), r.cond);
        }
        T_CHECK(v != AUG_CGM_LOG || !r.spd, "log variant positive definite");
    }
    /* above the dense limit: refused */
    o.max_n = n - 1;
    aug_cgm_res r;
    aug_err e;
    T_CHECK(aug_cgm_solve(AUG_CGM_ES, K, f, &o, 1e-8, 100, x, &r, &cm, &e) == AUG_EUSAGE, "order above max_n accepted");
    T_CHECK(strstr(e.msg, "--cgm-max-n") != NULL, "message: %s", e.msg);
    free(A), free(C), free(L), free(T), free(V), free(d), free(F), free(w), free(f), free(u), free(x), free(xr);
    cholmod_free_sparse(&K, &cm);
}

int main(void)
{
    cholmod_start(&cm);
    T_RUN(t_cov);
    T_RUN(t_ldl);
    T_RUN(t_newton_schulz);
    T_RUN(t_variants);
    cholmod_finish(&cm);
    T_EXIT();
}
