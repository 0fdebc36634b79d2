/* The incremental SVD (paper 004 eqs. 4-11) against LAPACK's SVD of the whole
   snapshot matrix: singular values, subspaces by principal angles, the
   orthonormal basis, the sum ratio of eq. 12, truncation within the dropped
   mass (Weyl), and bad input. */
#include "t.h"
#include "modal_gen.h"

static double worst_sv, worst_cos, worst_orth, worst_trunc;

/* feed X's columns; compare with the dense SVD of all of them */
static void run_full(int64_t n, int m, int k, double noise, int qcap)
{
    double *X = g_snapshots(n, m, k, noise);
    aug_isvd s;
    aug_err e;
    T_CHECK(aug_isvd_init(&s, n, m, qcap, 0, &e) == 0, "init: %s", e.msg);
    for (int j = 0; j < m; j++) T_CHECK(aug_isvd_add(&s, X + (size_t)j * n, &e) == 0, "add %d: %s", j, e.msg);
    double *sv = malloc(m * sizeof *sv), *Ux = malloc((size_t)n * m * sizeof *Ux), *U = malloc((size_t)n * m * sizeof *U);
    g_svd(X, n, m, sv, Ux);
    int rank = 0;
    while (rank < m && sv[rank] > 1e-13 * sv[0]) rank++;
    T_CHECK(s.r == rank, "rank %d, LAPACK %d", s.r, rank);
    for (int i = 0; i < s.r && i < rank; i++) {
        double d = t_reldiff(s.S[i], sv[i]);
        if (d > worst_sv) worst_sv = d;
        T_CHECK(d <= 1e-10, "sigma_%d %.17g, LAPACK %.17g (rel %.2e)", i, s.S[i], sv[i], d);
    }
    aug_isvd_basis(&s, U);
    for (int i = 0; i < s.r; i++)
        for (int j = 0; j <= i; j++) {
            double d = 0;
            for (int64_t t = 0; t < n; t++) d += U[t + i * n] * U[t + j * n];
            d = fabs(d - (i == j));
            if (d > worst_orth) worst_orth = d;
            T_CHECK(d <= 1e-12, "U'U - I (%d, %d) = %.2e", i, j, d);
        }
    double c = g_min_cos(U, Ux, n, s.r);
    if (1 - c > worst_cos) worst_cos = 1 - c;
    T_CHECK(c >= 1 - 1e-10, "smallest principal cosine %.17g", c);
    aug_isvd_free(&s);
    free(X), free(sv), free(Ux), free(U);
}

static void random_snapshots(void)
{
    run_full(80, 30, 0, 0, 0);
    run_full(300, 50, 0, 0, 0);
}

/* compaction at every add (qcap = rmax + 1) gives the same */
static void random_compacting(void) { run_full(120, 40, 0, 0, 41); }

/* rank 6 with singular values down to 2^-5 plus noise 1e-3 */
static void structured_snapshots(void)
{
    run_full(200, 40, 6, 1e-3, 0);
    run_full(200, 40, 6, 1e-3, 41);
}

/* exactly rank 5: the numerically zero directions are not kept */
static void exact_low_rank(void) { run_full(150, 30, 5, 0, 0); }

/* eq. 12's ratio after each add = sum sigma(X_{j-1}) / sum sigma(X_j) */
static void sum_ratio(void)
{
    int64_t n = 60;
    int m = 12;
    double *X = g_snapshots(n, m, 0, 0), sv[12], *Ux = malloc((size_t)n * m * sizeof *Ux);
    aug_isvd s;
    aug_err e;
    aug_isvd_init(&s, n, m, 0, 0, &e);
    double prev = 0;
    for (int j = 0; j < m; j++) {
        aug_isvd_add(&s, X + (size_t)j * n, &e);
        g_svd(X, n, j + 1, sv, Ux);
        double sum = 0;
        for (int i = 0; i <= j; i++) sum += sv[i];
        T_CHECK(fabs(s.ratio - prev / sum) <= 1e-12, "add %d: ratio %.17g, oracle %.17g", j, s.ratio, prev / sum);
        prev = sum;
    }
    aug_isvd_free(&s);
    free(X), free(Ux);
}

/* rank cap and relative threshold: |S_i - sigma_i| <= sum of the largest
   values dropped per add (Weyl: the kept factorisation is X minus the sum of
   the dropped rank-one pieces) */
static void truncated(void)
{
    int64_t n = 150;
    int m = 60;
    int caps[2] = {8, 60};
    double rtols[2] = {0, 1e-2};
    for (int c = 0; c < 2; c++) {
        double *X = g_snapshots(n, m, 6, 1e-4);
        aug_isvd s;
        aug_err e;
        aug_isvd_init(&s, n, caps[c], 0, rtols[c], &e);
        for (int j = 0; j < m; j++) aug_isvd_add(&s, X + (size_t)j * n, &e);
        double sv[60], *Ux = malloc((size_t)n * m * sizeof *Ux);
        g_svd(X, n, m, sv, Ux);
        T_CHECK(s.r == (c == 0 ? 8 : 6), "case %d: rank %d", c, s.r);
        T_CHECK(s.dropped2 > 0 && s.dropped2 < 0.05 * sv[0], "case %d: dropped %.3g", c, s.dropped2);
        for (int i = 0; i < s.r; i++) {
            double d = fabs(s.S[i] - sv[i]);
            if (d / s.dropped2 > worst_trunc) worst_trunc = d / s.dropped2;
            T_CHECK(d <= s.dropped2, "case %d sigma_%d: %.10g vs %.10g, dropped bound %.3g", c, i, s.S[i], sv[i],
                    s.dropped2);
        }
        aug_isvd_free(&s);
        free(X), free(Ux);
    }
}

static void bad_input(void)
{
    aug_isvd s;
    aug_err e;
    T_CHECK(aug_isvd_init(&s, 10, 0, 0, 0, &e) == AUG_EUSAGE, "rank cap 0 accepted");
    T_CHECK(aug_isvd_init(&s, 10, 4, 4, 0, &e) == AUG_EUSAGE, "qcap 4 with cap 4 accepted");
    T_CHECK(aug_isvd_init(&s, 10, 4, 0, 1, &e) == AUG_EUSAGE, "rtol 1 accepted");
    T_CHECK(aug_isvd_init(&s, 10, 4, 0, 0, &e) == 0, "init: %s", e.msg);
    double u[10] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 0};
    u[3] = NAN;
    T_CHECK(aug_isvd_add(&s, u, &e) == AUG_EDATA && strstr(e.msg, "entry 3"), "NaN: %s", e.msg);
    double z[10] = {0};
    T_CHECK(aug_isvd_add(&s, z, &e) == 0 && s.r == 0, "zero snapshot: rank %d", s.r);
    aug_isvd_free(&s);
}

int main(void)
{
    T_RUN(random_snapshots);
    T_RUN(random_compacting);
    T_RUN(structured_snapshots);
    T_RUN(exact_low_rank);
    T_RUN(sum_ratio);
    T_RUN(truncated);
    T_RUN(bad_input);
    printf("measured: sigma rel %.2e, 1 - cos %.2e, orthonormality %.2e, truncation |dS|/bound %.3f\n", worst_sv,
           worst_cos, worst_orth, worst_trunc);
    T_EXIT();
}
