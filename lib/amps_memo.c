/* AMPS step 2: H'K^-1H = V'D^-1V memoized across steps, grown by trapezoidal
   augmentation (paper 001 eqs. 3.25-3.27). */
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

/* G[i,j] = V(:,i)' D^-1 V(:,j) for the m_new last columns j and every i <= j.
   Two etree paths share exactly the path from their lowest common ancestor to
   the root, which is a suffix of both ascending lists: each product runs
   backwards over that suffix only (eq. 3.27, table 1 step 2). */
int aug_memo_grow(aug_memo *M, const aug_base *b, aug_err *e)
{
    if (M->m_new == 0) return 0;
    int64_t n = b->n, j0 = M->m - M->m_new, ld = M->mcap;
    double *w = aug_malloc((size_t)n * sizeof *w);
    int32_t *stamp = aug_calloc((size_t)n, sizeof *stamp);
    if (!w || !stamp) {
        free(w), free(stamp);
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (G)");
    }
    for (int64_t j = j0; j < M->m; j++) {
        int32_t tag = (int32_t)(j - j0 + 1);
        for (int64_t t = M->vp[j]; t < M->vp[j + 1]; t++) {
            int32_t r = M->vi[t];
            w[r] = M->vx[t] / aug_base_d(b, r);
            stamp[r] = tag;
        }
        double *Gj = M->G + j * ld;
        for (int64_t i = 0; i <= j; i++) {
            double s = 0;
            for (int64_t t = M->vp[i + 1] - 1; t >= M->vp[i]; t--) {
                int32_t r = M->vi[t];
                if (stamp[r] != tag) break;
                s += M->vx[t] * w[r];
            }
            Gj[i] = s;
            M->G[j + i * ld] = s;
        }
    }
    free(w);
    free(stamp);
    return 0;
}
