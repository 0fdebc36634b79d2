/* One implicit time step of a reduced sub-domain (paper 004 eq. 2) with the
   integrators of the full model (aug_dyn.h; thesis 003 sec. 3.4.1). */
#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_modal.h"

/* (cM M_r + cK K_r) dq = h M_r q' + gamma h^2 (f_r - K_r q); q += dq;
   q' <- dq / h (Euler) or 2 dq / h - q' (Newmark), by Cholesky (dpotrf) */
int aug_reduced_step(const aug_dynp *p, int r, const double *Kr, const double *Mr, const double *fr, double *q,
                     double *qd, aug_err *e)
{
    aug_err_clear(e);
    if (r < 1) return aug_err_set(e, AUG_EUSAGE, -1, "", "reduced step: rank %d", r);
    size_t rr = (size_t)r * r;
    double *A = malloc((rr + 2 * (size_t)r) * sizeof *A);
    if (!A) return aug_err_set(e, AUG_ENOMEM, -1, "", "reduced step: out of memory (rank %d)", r);
    double *b = A + rr, *v1 = b + r;
    double h = p->h, g2 = aug_dynp_gamma(p) * h * h;
    for (size_t i = 0; i < rr; i++) A[i] = p->cM * Mr[i] + p->cK * Kr[i];
    for (int i = 0; i < r; i++) b[i] = g2 * fr[i];
    cblas_dgemv(CblasColMajor, CblasNoTrans, r, r, h, Mr, r, qd, 1, 1.0, b, 1);
    cblas_dgemv(CblasColMajor, CblasNoTrans, r, r, -g2, Kr, r, q, 1, 1.0, b, 1);
    int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', r, A, r);
    if (info == 0) info = LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', r, 1, A, r, b, r);
    if (info != 0) {
        free(A);
        return aug_err_set(e, AUG_ESINGULAR, -1, "", "reduced step: A_r (rank %d) not positive definite (pivot %d)",
                           r, info);
    }
    for (int i = 0; i < r; i++)
        if (!isfinite(b[i])) {
            free(A);
            return aug_err_set(e, AUG_EDATA, -1, "", "reduced step: the increment is not finite");
        }
    aug_dynp_velocity(p, b, qd, v1, r);
    for (int i = 0; i < r; i++) q[i] += b[i], qd[i] = v1[i];
    free(A);
    return 0;
}
