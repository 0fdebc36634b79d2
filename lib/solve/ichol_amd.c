/* IC(0) on a fill-reducing ordering: AMD [Amestoy-Davis-Duff 1996] of K's
   pattern, applied symmetrically, then ichol.c on P'KP. */
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

/* A = P'KP upper-stored in (Ap, Ai, Ax): K(i,j), i <= j stored, goes to
   (min(pinv i, pinv j), max(pinv i, pinv j)), pinv the inverse of the
   ordering (rows unsorted; aug_ichol_factor sorts them). Ap, cur: n + 1
   ints; Ai, Ax: K's upper nnz. */
static void permute_upper(const cholmod_sparse *K, const int *pinv, int *Ap, int *cur, int *Ai, double *Ax)
{
    int n = (int)K->ncol;
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    memset(Ap, 0, (size_t)(n + 1) * sizeof *Ap);
    for (int j = 0; j < n; j++)
        for (int q = Kp[j]; q < Kp[j + 1]; q++)
            if (Ki[q] <= j) {
                int a = pinv[Ki[q]], b = pinv[j];
                Ap[(a > b ? a : b) + 1]++;
            }
    for (int j = 0; j < n; j++) Ap[j + 1] += Ap[j];
    memcpy(cur, Ap, (size_t)(n + 1) * sizeof *cur);
    for (int j = 0; j < n; j++)
        for (int q = Kp[j]; q < Kp[j + 1]; q++)
            if (Ki[q] <= j) {
                int a = pinv[Ki[q]], b = pinv[j], c = cur[a > b ? a : b]++;
                Ai[c] = a < b ? a : b, Ax[c] = Kx[q];
            }
}

/* R'R ~ P'(K + a diag(K))P with P = amd(pattern of K + K'), R->perm = P
   (row k of P'KP is row P[k] of K) and R->w the workspace of its apply.
   0; -1 out of memory, AMD failed or its result is not a permutation; 1 no
   shift worked (aug_ichol_factor). */
int aug_ichol_factor_amd(const cholmod_sparse *K, aug_ichol *R, cholmod_common *cm)
{
    memset(R, 0, sizeof *R);
    int n = (int)K->ncol, nz = 0;
    const int *Kp = K->p, *Ki = K->i;
    for (int j = 0; j < n; j++)
        for (int q = Kp[j]; q < Kp[j + 1]; q++) nz += Ki[q] <= j;
    int *perm = aug_malloc((size_t)(n + 1) * sizeof *perm), *pinv = aug_malloc((size_t)(n + 1) * sizeof *pinv);
    int *Ap = aug_malloc((size_t)(n + 1) * sizeof *Ap), *cur = aug_malloc((size_t)(n + 1) * sizeof *cur);
    int *Ai = aug_malloc((size_t)(nz + 1) * sizeof *Ai);
    double *Ax = aug_malloc((size_t)(nz + 1) * sizeof *Ax), *w = aug_malloc((size_t)(n + 1) * sizeof *w);
    cholmod_sparse Kc = *K, A = *K; /* shallow: cholmod_amd takes a non-const pointer */
    int rc = -1;
    Kc.stype = 1;
    if (!perm || !pinv || !Ap || !cur || !Ai || !Ax || !w || !cholmod_amd(&Kc, NULL, 0, perm, cm)) goto done;
    for (int k = 0; k < n; k++) pinv[k] = -1;
    for (int k = 0; k < n; k++) {
        if (perm[k] < 0 || perm[k] >= n || pinv[perm[k]] >= 0) goto done;
        pinv[perm[k]] = k;
    }
    permute_upper(K, pinv, Ap, cur, Ai, Ax);
    A.nzmax = (size_t)nz, A.p = Ap, A.i = Ai, A.x = Ax, A.nz = NULL, A.z = NULL;
    A.stype = 1, A.packed = 1, A.sorted = 0;
    if ((rc = aug_ichol_factor(&A, R)) >= 0) R->perm = perm, R->w = w, perm = NULL, w = NULL;
done:
    free(perm), free(pinv), free(Ap), free(cur), free(Ai), free(Ax), free(w);
    return rc;
}
