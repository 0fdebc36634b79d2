/* Products with a basis W = U0 Up held in factored form (paper 004 eq. 3):
   W'x, W y, and the projection residual x - W W'x without forming W W'. */
#include <cblas.h>
#include <string.h>
#include "aug_modal.h"

/* y = Up' (U0' x) */
void aug_basis_project(const aug_basis *W, const double *x, double *y, double *work)
{
    if (W->q == 0) return;
    double *t = W->Up ? work : y;
    cblas_dgemv(CblasColMajor, CblasTrans, (int)W->n, W->q, 1.0, W->U0, (int)W->n, x, 1, 0.0, t, 1);
    if (W->Up && W->r > 0) cblas_dgemv(CblasColMajor, CblasTrans, W->q, W->r, 1.0, W->Up, W->ldp, t, 1, 0.0, y, 1);
}

/* x = U0 (Up y) */
void aug_basis_expand(const aug_basis *W, const double *y, double *x, double *work)
{
    if (W->q == 0 || W->r == 0) {
        memset(x, 0, (size_t)W->n * sizeof *x);
        return;
    }
    const double *t = y;
    if (W->Up) {
        cblas_dgemv(CblasColMajor, CblasNoTrans, W->q, W->r, 1.0, W->Up, W->ldp, y, 1, 0.0, work, 1);
        t = work;
    }
    cblas_dgemv(CblasColMajor, CblasNoTrans, (int)W->n, W->q, 1.0, W->U0, (int)W->n, t, 1, 0.0, x, 1);
}

/* e = u - W (W'u) (work: 2 q + r) */
void aug_basis_residual(const aug_basis *W, const double *u, double *res, double *work)
{
    double *y = work + W->q, *t = y + W->r;
    aug_basis_project(W, u, y, work);
    aug_basis_expand(W, y, res, t);
    for (int64_t i = 0; i < W->n; i++) res[i] = u[i] - res[i];
}
