/* The snapshots of a re-wired sub-domain (aug_isvd_remap, lib/modal/isvd_remap.c):
   after rows are copied (new nodes from their parents), dropped and zeroed, the
   state equals the thin SVD of P X computed by LAPACK from the snapshots
   themselves: singular values to 1e-10, subspace by principal angles, U'U = I;
   and snapshots added after the remap go on as if P X had been fed. */
#include "modal_gen.h"
#include "aug_msim.h"
#include "t.h"

static void remap_case(int64_t n, int m, int k, int64_t n2)
{
    aug_err e;
    aug_isvd s;
    double *X = g_snapshots(n, m, k, 1e-9);
    T_CHECK(aug_isvd_init(&s, n, m + 8, 0, 0, &e) == 0, "init: %s", e.msg);
    for (int j = 0; j < m; j++) T_CHECK(aug_isvd_add(&s, X + (size_t)j * n, &e) == 0, "add: %s", e.msg);
    /* P: rows in a shuffled order, every 7th row dropped, new rows copying a
       random old one (a parent), every 11th new row zero (no snapshot saw it) */
    int32_t *src = malloc((size_t)n2 * sizeof *src);
    for (int64_t i = 0; i < n2; i++) {
        int64_t r = (i * 7919 + 13) % n;
        src[i] = i % 11 == 10 ? -1 : (int32_t)(i < n ? r : (int64_t)(g_unif() * n));
    }
    double *PX = calloc((size_t)n2 * m, sizeof *PX);
    for (int j = 0; j < m; j++)
        for (int64_t i = 0; i < n2; i++) PX[i + (size_t)j * n2] = src[i] >= 0 ? X[src[i] + (size_t)j * n] : 0;
    T_CHECK(aug_isvd_remap(&s, n2, src, &e) == 0, "remap: %s", e.msg);
    T_CHECK(s.n == n2 && s.q == s.r, "n %lld, q %d, r %d", (long long)s.n, s.q, s.r);
    int p = m < n2 ? m : (int)n2;
    double *sv = malloc((size_t)p * sizeof *sv), *U = malloc((size_t)n2 * p * sizeof *U);
    g_svd(PX, n2, m, sv, U);
    int rank = 0;
    while (rank < p && sv[rank] > 1e-13 * sv[0]) rank++;
    T_CHECK(s.r == rank, "rank %d, LAPACK %d", s.r, rank);
    for (int i = 0; i < s.r && i < rank; i++)
        T_CHECK(fabs(s.S[i] - sv[i]) <= 1e-10 * sv[0], "sigma_%d %.17g, LAPACK %.17g", i, s.S[i], sv[i]);
    double *W = malloc((size_t)n2 * (s.r + 1) * sizeof *W);
    aug_isvd_basis(&s, W);
    for (int i = 0; i < s.r; i++)
        for (int j = 0; j < s.r; j++) {
            double d = 0;
            for (int64_t t = 0; t < n2; t++) d += W[t + (size_t)i * n2] * W[t + (size_t)j * n2];
            T_CHECK(fabs(d - (i == j)) <= 1e-12, "U'U - I (%d, %d) = %.2e", i, j, d - (i == j));
        }
    /* compare the dominant subspace where the spectrum has a gap (the k structured directions) */
    int kk = k < s.r ? k : s.r;
    if (kk > 0) T_CHECK(g_min_cos(W, U, n2, kk) >= 1 - 1e-10, "principal cosine %.17g", g_min_cos(W, U, n2, kk));
    /* one more snapshot after the remap: as if P X then u had been fed */
    double *u = malloc((size_t)n2 * sizeof *u), *Y = malloc((size_t)n2 * (m + 1) * sizeof *Y);
    for (int64_t i = 0; i < n2; i++) u[i] = g_normal();
    T_CHECK(aug_isvd_add(&s, u, &e) == 0, "add after remap: %s", e.msg);
    memcpy(Y, PX, (size_t)n2 * m * sizeof *Y);
    memcpy(Y + (size_t)n2 * m, u, (size_t)n2 * sizeof *u);
    double *sv2 = malloc((size_t)(p + 1) * sizeof *sv2), *U2 = malloc((size_t)n2 * (p + 1) * sizeof *U2);
    g_svd(Y, n2, m + 1, sv2, U2);
    for (int i = 0; i < s.r; i++)
        T_CHECK(fabs(s.S[i] - sv2[i]) <= 1e-9 * sv2[0], "after: sigma_%d %.17g, LAPACK %.17g", i, s.S[i], sv2[i]);
    aug_isvd_free(&s);
    free(X), free(src), free(PX), free(sv), free(U), free(W), free(u), free(Y), free(sv2), free(U2);
}

static void grown_rows(void) { remap_case(200, 12, 4, 260); }
static void fewer_rows(void) { remap_case(300, 20, 6, 180); }
static void full_rank(void) { remap_case(150, 10, 0, 170); }

/* an empty basis remaps to an empty one of the new length */
static void empty(void)
{
    aug_err e;
    aug_isvd s;
    T_CHECK(aug_isvd_init(&s, 10, 4, 0, 0, &e) == 0, "init");
    int32_t src[15];
    for (int i = 0; i < 15; i++) src[i] = i % 10;
    T_CHECK(aug_isvd_remap(&s, 15, src, &e) == 0 && s.n == 15 && s.r == 0, "empty remap: %s", e.msg);
    aug_isvd_free(&s);
}

int main(void)
{
    T_RUN(grown_rows);
    T_RUN(fewer_rows);
    T_RUN(full_rank);
    T_RUN(empty);
    T_EXIT();
}
