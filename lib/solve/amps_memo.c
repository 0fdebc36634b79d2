/* AMPS step 2: H'K^-1H = V'D^-1V memoized across steps, grown by trapezoidal
   augmentation (paper 001 eqs. 3.25-3.27). */
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

/* G[i,j] = V(:,i)' D^-1 V(:,j) for the m_new last columns j and every i.
   The new columns' paths form U, a set closed under etree ancestors, so U
   meets any column's path in a suffix of it (eq. 3.27, table 1 step 2).
   W = D^-1 V_new is gathered densely over U, row by row (m_new wide), and
   each column i runs backwards over its suffix in U, adding v * W(r, :).
   The sums run over paths of thousands of rows with cancellation, so they
   are taken in blocks of CHUNK rows whose partial sums are added apart: the
   rounding error grows with CHUNK + len/CHUNK instead of len, which is what
   brings the AMPS residual on the bricks from ~6e-12 to below 1e-12 (H'K^-1H
   is what S2 and the back-substitution must agree on). */
#define CHUNK 32

/* G[i,j] and G[j,i] for the w new columns j = jb..jb+w-1 (w <= QB) and
   every i: W (nu x QB) = D^-1 V(:, jb..) over U, then one backward run over
   each column's suffix in U. QB is a literal at each call, so that the inner
   loop is a fixed width the compiler vectorizes; each entry's sum runs in
   the same order whatever QB is (the result does not depend on it). */
static inline __attribute__((always_inline)) void grow_pass(aug_memo *M, const aug_base *b,
                                                            const int32_t *row, double *W,
                                                            int64_t nu, int64_t jb, int64_t w,
                                                            const int QB)
{
    int64_t ld = M->mcap;
    memset(W, 0, (size_t)nu * QB * sizeof *W);
    for (int64_t j = jb; j < jb + w; j++)
        for (int64_t t = M->vp[j]; t < M->vp[j + 1]; t++) {
            int32_t r = M->vi[t];
            W[(int64_t)row[r] * QB + (j - jb)] = M->vx[t] / aug_base_d(b, r);
        }
    for (int64_t i = 0; i < M->m; i++) {
        double acc[QB], tot[QB];
#pragma GCC unroll 32
        for (int q = 0; q < QB; q++) acc[q] = tot[q] = 0;
        int cnt = 0;
        for (int64_t t = M->vp[i + 1] - 1; t >= M->vp[i]; t--) {
            int32_t r = M->vi[t];
            if (row[r] < 0) break;
            const double *Wr = W + (int64_t)row[r] * QB;
            double v = M->vx[t];
#pragma GCC unroll 32
            for (int q = 0; q < QB; q++) acc[q] += v * Wr[q];
            if (++cnt == CHUNK) {
                cnt = 0;
#pragma GCC unroll 32
                for (int q = 0; q < QB; q++) tot[q] += acc[q], acc[q] = 0;
            }
        }
        for (int64_t q = 0; q < w; q++) {
            int64_t j = jb + q;
            M->G[i + j * ld] = M->G[j + i * ld] = tot[q] + acc[q];
        }
    }
}

/* the new columns in passes of 32, 16, 8 or 4: each pass runs over every
   column's suffix once, so wide passes read V and W fewer times (brain, 16
   steps of 8 nodes: 36-87 new columns a step against up to 830). The q loops
   are unrolled so that the QB sums stay in registers, and an AVX2 clone is
   chosen at load time where the CPU has it: the lanes are the independent
   sums q, each still added in the same order, and AVX2 without FMA does not
   contract v * W + acc, so every clone gives the same bits (the dumps of
   the brain's 8-node steps are identical). Brain, 16 steps of 8 nodes:
   median memo 40 -> 22 ms a step, the AMPS step 122 -> 88 ms. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
int aug_memo_grow(aug_memo *M, const aug_base *b, aug_err *e)
{
    if (M->m_new == 0) return 0;
    enum { QMAX = 32 };
    int64_t n = b->n, j0 = M->m - M->m_new;
    int32_t *row = aug_malloc((size_t)n * sizeof *row);
    double *W = NULL;
    if (!row) goto nomem;
    for (int64_t t = 0; t < n; t++) row[t] = -1;
    int64_t nu = 0; /* |U|: rows numbered in order of first appearance */
    for (int64_t t = M->vp[j0]; t < M->vp[M->m]; t++)
        if (row[M->vi[t]] < 0) row[M->vi[t]] = (int32_t)nu++;
    W = aug_malloc((size_t)(nu ? nu : 1) * QMAX * sizeof *W);
    if (!W) goto nomem;
    for (int64_t jb = j0; jb < M->m;) {
        int64_t left = M->m - jb, w;
        if (left > 16) w = left < 32 ? left : 32, grow_pass(M, b, row, W, nu, jb, w, 32);
        else if (left > 8) w = left, grow_pass(M, b, row, W, nu, jb, w, 16);
        else if (left > 4) w = left, grow_pass(M, b, row, W, nu, jb, w, 8);
        else w = left, grow_pass(M, b, row, W, nu, jb, w, 4);
        jb += w;
    }
    free(row);
    free(W);
    return 0;
nomem:
    free(row);
    free(W);
    return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (G)");
}
