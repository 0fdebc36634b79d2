/* Baseline: Jacobi-preconditioned conjugate gradients on the cut matrix
   ([Saad] ch. 9; Hestenes-Stiefel). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

/* y = K x for K stored by its upper triangle */
static void symv_upper(const cholmod_sparse *K, const double *x, double *y)
{
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    int64_t n = (int64_t)K->ncol;
    memset(y, 0, (size_t)n * sizeof *y);
    for (int64_t j = 0; j < n; j++) {
        double xj = x[j], s = 0;
        for (int k = Kp[j]; k < Kp[j + 1]; k++) {
            int i = Ki[k];
            if (i == j) {
                s += Kx[k] * xj;
            } else {
                y[i] += Kx[k] * xj;
                s += Kx[k] * x[i];
            }
        }
        y[j] += s;
    }
}

/* x := PCG on K x = f from the given x ([Saad] ch. 9), M = diag(K) (1 where
   K(j,j) <= 0): iterates while the recursive ||r|| > tol ||f|| (||f|| := 1 when
   f = 0), restarting from the true residual when it has drifted (at most 5
   passes); breakdown when p'Kp <= 0. relres = true ||f - K x|| / ||f||; converged:
   no breakdown and relres <= tol. Returns the iterations of all passes, -1 memory. */
int aug_pcg(const cholmod_sparse *K, const double *f, double *x, double tol, int maxit,
            int *converged, int *breakdown, double *relres, cholmod_common *cm)
{
    (void)cm;
    int64_t n = (int64_t)K->ncol;
    double *w = aug_malloc((size_t)(5 * n + 1) * sizeof *w);
    *converged = 0, *breakdown = 0, *relres = NAN;
    if (!w) return -1;
    double *r = w, *z = w + n, *p = w + 2 * n, *q = w + 3 * n, *dinv = w + 4 * n;
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    for (int64_t j = 0; j < n; j++) {
        dinv[j] = 1;
        for (int k = Kp[j]; k < Kp[j + 1]; k++)
            if (Ki[k] == j && Kx[k] > 0) dinv[j] = 1 / Kx[k];
    }
    double ff = 0;
    for (int64_t i = 0; i < n; i++) ff += f[i] * f[i];
    double fn = sqrt(ff) > 0 ? sqrt(ff) : 1;
    int it = 0;
    for (int restart = 0; restart < 5; restart++) {
    symv_upper(K, x, q);
    double rr = 0, rz = 0;
    for (int64_t i = 0; i < n; i++) {
        r[i] = f[i] - q[i];
        z[i] = dinv[i] * r[i];
        p[i] = z[i];
        rr += r[i] * r[i], rz += r[i] * z[i];
    }
    while (sqrt(rr) > tol * fn && it < maxit) {
        symv_upper(K, p, q);
        double pq = 0;
        for (int64_t i = 0; i < n; i++) pq += p[i] * q[i];
        if (!(pq > 0)) {
            *breakdown = 1;
            break;
        }
        double alpha = rz / pq, rz1 = 0;
        rr = 0;
        for (int64_t i = 0; i < n; i++) {
            x[i] += alpha * p[i];
            r[i] -= alpha * q[i];
            z[i] = dinv[i] * r[i];
            rz1 += r[i] * z[i], rr += r[i] * r[i];
        }
        double beta = rz1 / rz;
        rz = rz1;
        for (int64_t i = 0; i < n; i++) p[i] = z[i] + beta * p[i];
        it++;
    }
    /* the recursive residual drifts from the true one: restart from the true
       residual while that is above the tolerance */
    symv_upper(K, x, q);
    double tr0 = 0;
    for (int64_t i = 0; i < n; i++) tr0 += (f[i] - q[i]) * (f[i] - q[i]);
    if (*breakdown || sqrt(tr0) <= tol * fn || it >= maxit) break;
    }
    symv_upper(K, x, q);
    double tr = 0;
    for (int64_t i = 0; i < n; i++) tr += (f[i] - q[i]) * (f[i] - q[i]);
    *relres = sqrt(tr) / fn;
    *converged = !*breakdown && *relres <= tol * 1.0000001 + 1e-300;
    free(w);
    return it;
}
