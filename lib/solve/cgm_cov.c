/* The covariance matrix of the rows of the cut stiffness matrix (thesis 003
   sec. 3.5.1, eq. 3.21), dense. */
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

/* COV = 1/(n-1) sum_i (x_i - xbar)' (x_i - xbar), x_i the i-th row of K,
   xbar = 1/n sum_i x_i (thesis 003 eq. 3.21); with K symmetric this is
   (K K - n xbar' xbar) / (n-1), K K accumulated column by column from the
   full pattern of K: C(:, j) = sum_k K(:, k) K(k, j). n = 1: C = 0. */
int aug_cgm_cov(const cholmod_sparse *K, double *C, cholmod_common *cm, aug_err *e)
{
    int n = (int)K->nrow;
    cholmod_sparse *A = cholmod_copy((cholmod_sparse *)K, 0, 1, cm); /* both triangles */
    double *xbar = aug_calloc((size_t)n + 1, sizeof *xbar);
    if (!A || !xbar) {
        if (A) cholmod_free_sparse(&A, cm);
        free(xbar);
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (COV of order %d)", n);
    }
    const int *Ap = A->p, *Ai = A->i;
    const double *Ax = A->x;
    memset(C, 0, (size_t)n * n * sizeof *C);
    for (int j = 0; j < n; j++) {
        double *c = C + (size_t)j * n;
        for (int q = Ap[j]; q < Ap[j + 1]; q++) {
            int k = Ai[q];
            double akj = Ax[q];
            xbar[j] += akj; /* column sum = row sum (K symmetric) */
            for (int r = Ap[k]; r < Ap[k + 1]; r++) c[Ai[r]] += Ax[r] * akj;
        }
    }
    double s = n > 1 ? 1.0 / (n - 1) : 0;
    for (int j = 0; j < n; j++) xbar[j] /= n;
    for (int j = 0; j < n; j++) {
        double *c = C + (size_t)j * n;
        for (int i = 0; i < n; i++) c[i] = s * (c[i] - n * xbar[i] * xbar[j]);
    }
    cholmod_free_sparse(&A, cm);
    free(xbar);
    return 0;
}
