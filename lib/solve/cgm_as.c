/* AS-CGM (thesis 003 sec. 3.5.2): the square root of a symmetric positive
   definite matrix by the coupled Newton-Schulz iteration (eq. 3.27), dense. */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

/* P ~ (Y/c)^(1/2), c = ||Y||_F: P_0 = Y/c, Q_0 = I,
     Z_k = 3I - Q_k P_k,  P_k+1 = P_k Z_k / 2,  Q_k+1 = Z_k Q_k / 2
   (thesis 003 eq. 3.27; [Higham 2008] eq. 6.35, l = 0, m = 1). The iteration
   converges when ||I - Y/c|| < 1, which the thesis states but does not
   arrange: the scaling by c >= lambda_max(Y) puts the spectrum of Y/c in
   (0, 1], so ||I - Y/c||_2 < 1 for Y positive definite. Each eigenvalue y of
   Y/c gives q p -> 1 (a small y needs about log(1/y) / log(9/4) steps before
   the quadratic phase), so the test is on all modes alike: it stops when
   ||I - Q_k P_k||_F <= tol (converged, 1), when that stops decreasing below
   1e-6 (rounding level reached, converged), or after maxit steps (0).
   P_k -> (Y/c)^(1/2), Q_k -> (Y/c)^(-1/2); -1: out of memory. */
int aug_cgm_newton_schulz(const double *Y, int n, double tol, int maxit, double *P, int *iters,
                          double *scale)
{
    size_t nn = (size_t)n * n;
    double *X = aug_malloc(nn * sizeof *X), *Q = aug_malloc(nn * sizeof *Q);
    double *Z = aug_malloc(nn * sizeof *Z), *W = aug_malloc(nn * sizeof *W);
    *iters = 0;
    if (!X || !Q || !Z || !W) {
        free(X), free(Q), free(Z), free(W);
        return -1;
    }
    double c = 0;
    for (size_t i = 0; i < nn; i++) c += Y[i] * Y[i];
    c = sqrt(c);
    *scale = c;
    double s = c > 0 ? 1 / c : 0, prev = INFINITY;
    for (size_t i = 0; i < nn; i++) X[i] = s * Y[i], Q[i] = 0;
    for (int i = 0; i < n; i++) Q[(size_t)i * n + i] = 1;
    int ok = 0;
    for (;;) {
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, n, n, -1.0, Q, n, X, n, 0.0, Z, n);
        double r = 0; /* ||I - Q P||_F, Z = -Q P */
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                double t = Z[(size_t)j * n + i] + (i == j);
                r += t * t;
            }
        r = sqrt(r);
        if (r <= tol || (prev < 1e-6 && r >= prev)) {
            ok = 1;
            break;
        }
        if (*iters >= maxit) break;
        prev = r;
        for (int i = 0; i < n; i++) Z[(size_t)i * n + i] += 3;
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, n, n, 0.5, X, n, Z, n, 0.0, W, n);
        /* Q_k+1 into X's storage, then X = P_k+1 = W */
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, n, n, 0.5, Z, n, Q, n, 0.0, X, n);
        double *t = Q;
        Q = X, X = W, W = t;
        ++*iters;
    }
    memcpy(P, X, nn * sizeof *P);
    free(X), free(Q), free(Z), free(W);
    return ok;
}
