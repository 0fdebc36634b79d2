/* AMPS step 2: H'K^-1H = V'D^-1V memoized across steps, grown by trapezoidal
   augmentation (paper 001 eqs. 3.25-3.27). */
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"
#include "aug_par.h"

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

/* W (nu x QB) = D^-1 V(:, jb..jb+w-1) over U, row by row */
static void fill_w(const aug_memo *M, const aug_base *b, const int32_t *row, double *W, int64_t nu,
                   int64_t jb, int64_t w, int QB)
{
    memset(W, 0, (size_t)nu * QB * sizeof *W);
    for (int64_t j = jb; j < jb + w; j++)
        for (int64_t t = M->vp[j]; t < M->vp[j + 1]; t++) {
            int32_t r = M->vi[t];
            W[(int64_t)row[r] * QB + (j - jb)] = M->vx[t] / aug_base_d(b, r);
        }
}

/* G[i,j] and G[j,i] for the w new columns j = jb..jb+w-1 (w <= QB) and the
   columns i = i0..i1-1: one backward run over each column's suffix in U.
   QB is a literal at each call, so that the inner loop is a fixed width the
   compiler vectorizes; each entry's sum runs in the same order whatever QB
   is (the result does not depend on it). A pair of this pass's own columns
   i < j is written from column j's run only (the one a serial sweep over i
   writes last): columns split between threads then write each entry once,
   and the result is the serial one bit for bit. */
static inline __attribute__((always_inline)) void grow_rows(aug_memo *M, const int32_t *row, const double *W,
                                                            int64_t jb, int64_t w, const int QB, int64_t i0,
                                                            int64_t i1)
{
    int64_t ld = M->mcap;
    for (int64_t i = i0; i < i1; i++) {
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
        int64_t qend = i >= jb && i < jb + w ? i - jb + 1 : w;
        for (int64_t q = 0; q < qend; q++) {
            int64_t j = jb + q;
            M->G[i + j * ld] = M->G[j + i * ld] = tot[q] + acc[q];
        }
    }
}

/* one pass's rows i0..i1 at the pass's width; an AVX2 clone is chosen at
   load time where the CPU has it: the lanes are the independent sums q, each
   still added in the same order, and AVX2 without FMA does not contract
   v * W + acc, so every clone gives the same bits (the dumps of the brain's
   8-node steps are identical) */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
static void grow_range(aug_memo *M, const int32_t *row, const double *W, int64_t jb, int64_t w, int QB,
                       int64_t i0, int64_t i1)
{
    switch (QB) {
    case 32: grow_rows(M, row, W, jb, w, 32, i0, i1); break;
    case 16: grow_rows(M, row, W, jb, w, 16, i0, i1); break;
    case 8: grow_rows(M, row, W, jb, w, 8, i0, i1); break;
    default: grow_rows(M, row, W, jb, w, 4, i0, i1); break;
    }
}

/* a pass on the pool: thread t takes the columns cut[t] .. cut[t+1]-1 */
typedef struct grow_job {
    aug_memo *M;
    const int32_t *row;
    const double *W;
    int64_t jb, w;
    int QB;
    const int64_t *cut;
} grow_job;

static void grow_worker(void *arg, int t)
{
    const grow_job *g = arg;
    grow_range(g->M, g->row, g->W, g->jb, g->w, g->QB, g->cut[t], g->cut[t + 1]);
}

/* the new columns in passes of 32, 16, 8 or 4: each pass runs over every
   column's suffix once, so wide passes read V and W fewer times (brain, 16
   steps of 8 nodes: 36-87 new columns a step against up to 830). The q loops
   are unrolled so that the QB sums stay in registers. Brain, 16 steps of 8
   nodes: median memo 40 -> 22 ms a step, the AMPS step 122 -> 88 ms. With
   a pool (par, not NULL: solve-aug --threads 2) a pass's columns are split
   between its threads by their lengths (paper 001 sec. 3.6: the memo's
   entries are independent), when the pass reads at least PAR_MIN entries
   of V; G is the serial one bit for bit (grow_rows). */
#define PAR_MIN 20000
int aug_memo_grow(aug_memo *M, const aug_base *b, struct aug_par *par, aug_err *e)
{
    if (M->m_new == 0) return 0;
    enum { QMAX = 32, TMAX = 16 };
    int64_t n = b->n, j0 = M->m - M->m_new, cut[TMAX + 1];
    int nt = par ? aug_par_nthreads(par) : 1;
    if (nt > TMAX) nt = TMAX;
    int32_t *row = aug_malloc((size_t)n * sizeof *row);
    double *W = NULL;
    if (!row) goto nomem;
    for (int64_t t = 0; t < n; t++) row[t] = -1;
    int64_t nu = 0; /* |U|: rows numbered in order of first appearance */
    for (int64_t t = M->vp[j0]; t < M->vp[M->m]; t++)
        if (row[M->vi[t]] < 0) row[M->vi[t]] = (int32_t)nu++;
    W = aug_malloc((size_t)(nu ? nu : 1) * QMAX * sizeof *W);
    if (!W) goto nomem;
    /* the columns' split by their entries (an upper bound of their suffixes in U) */
    int64_t tot = M->vp[M->m] - M->vp[0];
    cut[0] = 0;
    for (int t = 1, i = 0; t < nt; t++) {
        while (i < M->m && (M->vp[i] - M->vp[0]) * nt < tot * t) i++;
        cut[t] = i;
    }
    cut[nt] = M->m;
    int pool = nt > 1 && tot >= PAR_MIN;
    for (int64_t jb = j0; jb < M->m;) {
        int64_t left = M->m - jb, w;
        int QB = left > 16 ? 32 : left > 8 ? 16 : left > 4 ? 8 : 4;
        w = left < QB ? left : QB;
        fill_w(M, b, row, W, nu, jb, w, QB);
        if (pool) {
            grow_job g = {M, row, W, jb, w, QB, cut};
            aug_par_run(par, grow_worker, &g);
        } else {
            grow_range(M, row, W, jb, w, QB, 0, M->m);
        }
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
