/* The incremental SVD of a sub-domain whose DOFs a cut re-wired (paper 004
   sec. 4.2, "Cutting": the snapshots padded for the new nodes). */
#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_msim.h"

/* P U S = Q R (dgeqrf, dorgqr), R = U2 S2 V2' (dgesvd): P X = (Q U2) S2 (V2' V')
   is again a thin SVD, so U0 = Q U2, Up = I, S = S2 */
int aug_isvd_remap(aug_isvd *s, int64_t n, const int32_t *src, aug_err *e)
{
    aug_err_clear(e);
    aug_isvd t;
    if (aug_isvd_init(&t, n, s->rmax, s->qcap, s->rtol, e)) return e->code;
    int r = s->r < n ? s->r : (int)n;
    t.nsnap = s->nsnap, t.dropped2 = s->dropped2;
    if (r == 0) {
        aug_isvd_free(s);
        *s = t;
        return 0;
    }
    int64_t no = s->n;
    double *U = malloc((size_t)no * s->r * sizeof *U), *B = malloc((size_t)n * r * sizeof *B);
    double *tau = malloc((size_t)r * sizeof *tau), *R = calloc((size_t)r * r, sizeof *R);
    double *U2 = malloc((size_t)r * r * sizeof *U2), *sv = malloc((size_t)r * sizeof *sv);
    double *sb = malloc((size_t)r * sizeof *sb);
    int rc = 0;
    if (!U || !B || !tau || !R || !U2 || !sv || !sb) {
        rc = aug_err_set(e, AUG_ENOMEM, -1, "MODE", "out of memory");
        goto done;
    }
    aug_isvd_basis(s, U);
    for (int j = 0; j < r; j++)
        for (int64_t i = 0; i < n; i++) B[i + (size_t)j * n] = src[i] >= 0 ? U[src[i] + (size_t)j * no] * s->S[j] : 0;
    int info = LAPACKE_dgeqrf(LAPACK_COL_MAJOR, (int)n, r, B, (int)n, tau);
    for (int j = 0; j < r && !info; j++)
        for (int i = 0; i <= j; i++) R[i + (size_t)j * r] = B[i + (size_t)j * n];
    if (!info) info = LAPACKE_dorgqr(LAPACK_COL_MAJOR, (int)n, r, r, B, (int)n, tau);
    if (!info) info = LAPACKE_dgesvd(LAPACK_COL_MAJOR, 'A', 'N', r, r, R, r, sv, U2, r, NULL, 1, sb);
    if (info) {
        rc = aug_err_set(e, AUG_ENOCONV, -1, "MODE", "re-wired basis: LAPACK failed (%d)", info);
        goto done;
    }
    int k = 0;
    double cut = fmax(s->rtol, 1e-13) * sv[0];
    while (k < r && sv[k] > cut) k++;
    if (k > 0)
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, (int)n, k, r, 1.0, B, (int)n, U2, r, 0.0, t.U0, (int)n);
    for (int j = 0; j < k; j++) t.S[j] = sv[j], t.Up[j + (size_t)j * t.qcap] = 1;
    t.q = t.r = k;
    t.unit_up = 1;
    aug_isvd_free(s);
    *s = t;
done:
    if (rc) aug_isvd_free(&t);
    free(U), free(B), free(tau), free(R), free(U2), free(sv), free(sb);
    return rc;
}
