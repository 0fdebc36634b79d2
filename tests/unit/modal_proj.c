/* Projection error onto the incremental basis (paper 004 eqs. 13-14): the
   exact error against a least-squares distance by LAPACK, the Wallis factors
   against eq. 14's products, and the Kenney-Laub estimate's spread on many
   random states with a fixed seed. */
#include "t.h"
#include "modal_gen.h"

/* distance of u to range(X) by least squares (dgels) over ||u|| */
static double ls_dist(const double *X, int64_t n, int m, const double *u)
{
    double *A = malloc((size_t)n * m * sizeof *A), *b = malloc((size_t)n * sizeof *b);
    memcpy(A, X, (size_t)n * m * sizeof *A);
    memcpy(b, u, (size_t)n * sizeof *b);
    LAPACKE_dgels(LAPACK_COL_MAJOR, 'N', (int)n, m, 1, A, (int)n, b, (int)n);
    double r = 0, un = 0;
    for (int64_t i = m; i < n; i++) r += b[i] * b[i];
    for (int64_t i = 0; i < n; i++) un += u[i] * u[i];
    free(A), free(b);
    return sqrt(r / un);
}

static double worst_exact;

/* states u = X c + t w at distances t over 1e-8..1 */
static void exact_error(void)
{
    int64_t n = 120;
    int m = 15;
    double *X = g_snapshots(n, m, 0, 0), *u = malloc(n * sizeof *u), *w = malloc((n + 2 * m + m) * sizeof *w);
    aug_isvd s;
    aug_err e;
    aug_isvd_init(&s, n, m, 0, 0, &e);
    for (int j = 0; j < m; j++) aug_isvd_add(&s, X + (size_t)j * n, &e);
    for (int trial = 0; trial < 40; trial++) {
        double t = pow(10, -8 + 8.0 * trial / 39);
        for (int64_t i = 0; i < n; i++) u[i] = t * g_normal();
        for (int j = 0; j < m; j++) {
            double c = g_normal();
            for (int64_t i = 0; i < n; i++) u[i] += c * X[i + (size_t)j * n];
        }
        double got = aug_proj_err(&s, u, w), want = ls_dist(X, n, m, u);
        double d = t_reldiff(got, want);
        if (d > worst_exact) worst_exact = d;
        T_CHECK(d <= 1e-6 || fabs(got - want) <= 1e-14, "t %.1e: %.17g vs %.17g", t, got, want);
    }
    for (int64_t i = 0; i < n; i++) u[i] = 0;
    T_CHECK(aug_proj_err(&s, u, w) == 0, "zero state");
    aug_isvd_free(&s);
    free(X), free(u), free(w);
}

/* W_m = Gamma(m/2) / (sqrt(pi) Gamma((m+1)/2)) equals eq. 14's products */
static void wallis(void)
{
    for (int m = 1; m <= 60; m++) {
        double p;
        if (m % 2 == 0) {
            p = 2 / M_PI;
            for (int j = 2; j <= m - 2; j += 2) p *= j;
            for (int j = 1; j <= m - 1; j += 2) p /= j;
        } else {
            p = 1;
            for (int j = 1; j <= m - 2; j += 2) p *= j;
            for (int j = 2; j <= m - 1; j += 2) p /= j;
        }
        T_CHECK(t_reldiff(aug_wallis(m), p) <= 1e-13, "W_%d = %.17g, product %.17g", m, aug_wallis(m), p);
    }
    T_CHECK(fabs(aug_wallis(2) - 2 / M_PI) < 1e-15 && fabs(aug_wallis(3) - 0.5) < 1e-15, "W_2, W_3");
}

/* k = n probes: the estimate is the exact error */
static void all_probes(void)
{
    int64_t n = 30;
    int m = 5;
    double *X = g_snapshots(n, m, 0, 0), u[30], w[30 + 15];
    aug_isvd s;
    aug_err e;
    aug_isvd_init(&s, n, m, 0, 0, &e);
    for (int j = 0; j < m; j++) aug_isvd_add(&s, X + (size_t)j * n, &e);
    for (int i = 0; i < n; i++) u[i] = g_normal();
    uint64_t seed = 7;
    double est = aug_proj_err_estimate(&s, u, (int)n, &seed, &e), ex = aug_proj_err(&s, u, w);
    T_CHECK(t_reldiff(est, ex) <= 1e-12, "k = n: %.17g vs %.17g", est, ex);
    T_CHECK(aug_proj_err_estimate(&s, u, 0, &seed, &e) == -1 && e.code == AUG_EUSAGE, "k = 0 accepted");
    T_CHECK(aug_proj_err_estimate(&s, u, 31, &seed, &e) == -1 && e.code == AUG_EUSAGE, "k > n accepted");
    aug_isvd_free(&s);
    free(X);
}

/* k = 4 on 2000 random states (n = 400, rank 12). nu / ||e|| = (W_4 / W_n)
   ||y||, ||y||^2 ~ Beta(2, (n-4)/2), so for large n nu / ||e|| ~ 0.532 chi_4:
   P(nu < ||e|| / 3) = P(chi2_4 < 0.393) = 0.0169, P(nu > 3 ||e||) = 2e-6,
   P(nu < ||e|| / 30) = 2e-6. The test asserts: the mean ratio is 1 within
   0.04 (5 standard errors), the fraction outside [1/3, 3] is 0.0169 within
   0.0115 (4 binomial standard deviations), none outside [1/30, 30]. */
static void estimate_brackets(void)
{
    int64_t n = 400;
    int m = 12, N = 2000, out = 0, far = 0;
    double *X = g_snapshots(n, m, 0, 0), *u = malloc(n * sizeof *u), *w = malloc((n + 3 * m) * sizeof *w);
    aug_isvd s;
    aug_err e;
    aug_isvd_init(&s, n, m, 0, 0, &e);
    for (int j = 0; j < m; j++) aug_isvd_add(&s, X + (size_t)j * n, &e);
    uint64_t seed = 2016;
    double mean = 0;
    for (int t = 0; t < N; t++) {
        double a = pow(10, -6 + 6 * g_unif());
        for (int64_t i = 0; i < n; i++) u[i] = a * g_normal();
        for (int j = 0; j < m; j++) {
            double c = g_normal();
            for (int64_t i = 0; i < n; i++) u[i] += c * X[i + (size_t)j * n];
        }
        double est = aug_proj_err_estimate(&s, u, 4, &seed, &e), ex = aug_proj_err(&s, u, w);
        T_CHECK(est >= 0, "estimate: %s", e.msg);
        double q = est / ex;
        mean += q / N;
        out += q < 1.0 / 3 || q > 3;
        far += q < 1.0 / 30 || q > 30;
    }
    double frac = (double)out / N;
    printf("estimate k=4: mean nu/err %.4f, outside [1/3,3] %.4f (theory 0.0169)\n", mean, frac);
    T_CHECK(fabs(mean - 1) <= 0.04, "mean ratio %.4f", mean);
    T_CHECK(fabs(frac - 0.0169) <= 0.0115, "fraction outside [1/3, 3]: %.4f", frac);
    T_CHECK(far == 0, "%d estimates off by more than 30x", far);
    aug_isvd_free(&s);
    free(X), free(u), free(w);
}

int main(void)
{
    T_RUN(exact_error);
    T_RUN(wallis);
    T_RUN(all_probes);
    T_RUN(estimate_brackets);
    printf("measured: exact error vs least squares rel %.2e\n", worst_exact);
    T_EXIT();
}
