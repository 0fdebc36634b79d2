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
int aug_memo_grow(aug_memo *M, const aug_base *b, aug_err *e)
{
    if (M->m_new == 0) return 0;
    enum { QB = 8 }; /* new columns per pass: the inner loop is a fixed 8 wide */
    int64_t n = b->n, j0 = M->m - M->m_new, ld = M->mcap;
    int32_t *row = aug_malloc((size_t)n * sizeof *row);
    double *W = NULL;
    if (!row) goto nomem;
    for (int64_t t = 0; t < n; t++) row[t] = -1;
    int64_t nu = 0; /* |U|: rows numbered in order of first appearance */
    for (int64_t t = M->vp[j0]; t < M->vp[M->m]; t++)
        if (row[M->vi[t]] < 0) row[M->vi[t]] = (int32_t)nu++;
    W = aug_malloc((size_t)(nu ? nu : 1) * QB * sizeof *W);
    if (!W) goto nomem;
    for (int64_t jb = j0; jb < M->m; jb += QB) {
        int64_t w = M->m - jb < QB ? M->m - jb : QB;
        memset(W, 0, (size_t)nu * QB * sizeof *W);
        for (int64_t j = jb; j < jb + w; j++)
            for (int64_t t = M->vp[j]; t < M->vp[j + 1]; t++) {
                int32_t r = M->vi[t];
                W[(int64_t)row[r] * QB + (j - jb)] = M->vx[t] / aug_base_d(b, r);
            }
        for (int64_t i = 0; i < M->m; i++) {
            double acc[QB] = {0}, tot[QB] = {0};
            int cnt = 0;
            for (int64_t t = M->vp[i + 1] - 1; t >= M->vp[i]; t--) {
                int32_t r = M->vi[t];
                if (row[r] < 0) break;
                const double *Wr = W + (int64_t)row[r] * QB;
                double v = M->vx[t];
                for (int q = 0; q < QB; q++) acc[q] += v * Wr[q];
                if (++cnt == CHUNK) {
                    cnt = 0;
                    for (int q = 0; q < QB; q++) tot[q] += acc[q], acc[q] = 0;
                }
            }
            for (int64_t q = 0; q < w; q++) {
                int64_t j = jb + q;
                M->G[i + j * ld] = M->G[j + i * ld] = tot[q] + acc[q];
            }
        }
    }
    free(row);
    free(W);
    return 0;
nomem:
    free(row);
    free(W);
    return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (G)");
}
