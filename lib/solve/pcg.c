/* Baseline: preconditioned conjugate gradients on the cut matrix ([Saad]
   ch. 9; Hestenes-Stiefel): no, Jacobi or IC(0) preconditioner, IC(0) on
   the natural or the AMD ordering. */
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

/* z = M^-1 r: M = I (R and dinv NULL), diag (dinv) or R'R (R) */
static void prec_apply(const aug_ichol *R, const double *dinv, const double *r, double *z, int64_t n)
{
    if (R) {
        aug_ichol_apply(R, r, z);
        return;
    }
    for (int64_t i = 0; i < n; i++) z[i] = dinv ? dinv[i] * r[i] : r[i];
}

/* x := PCG on K x = f from the given x ([Saad] ch. 9), M = I, diag(K) (1
   where K(j,j) <= 0), the IC(0) R'R of K (ichol.c; its shift in *shift) or
   P R'R P', IC(0) of P'KP on the AMD ordering P (ichol_amd.c):
   iterates while the recursive ||r|| > tol ||f|| (||f|| := 1 when f = 0),
   restarting from the true residual when it has drifted (at most 5 passes);
   breakdown when p'Kp <= 0. relres = true ||f - K x|| / ||f||; converged: no
   breakdown and relres <= tol; *prec_ms the time of the IC(0) factorization.
   Unit rows (unit[i], i < nunit: K's row and column i are e_i) start at
   x_i = f_i, where r_i = p_i = 0 stays in exact arithmetic; ||f|| and the
   true residual are over the other rows. In a dynamic frame a unit row holds
   a displacement jump, the others forces times h^2: with them in ||f||, a
   dropped piece's jump (3.3e-3 against 7.5e-6 on the square) let the free
   rows stop at 3.8e-6 of their own right-hand side at tol 1e-8.
   Returns the iterations of all passes, -1 memory or no IC(0). */
int aug_pcg_prec(const cholmod_sparse *K, const double *f, const unsigned char *unit, int64_t nunit,
                 double *x, int prec, double tol,
                 int maxit, int *converged, int *breakdown, double *relres, double *shift,
                 double *prec_ms, cholmod_common *cm)
{
    int64_t n = (int64_t)K->ncol;
    double *w = aug_malloc((size_t)(5 * n + 1) * sizeof *w);
    aug_ichol ic, *R = NULL;
    *converged = 0, *breakdown = 0, *relres = NAN;
    if (shift) *shift = 0;
    if (prec_ms) *prec_ms = 0;
    if (!w) return -1;
    double *r = w, *z = w + n, *p = w + 2 * n, *q = w + 3 * n, *dinv = prec == AUG_PCG_JACOBI ? w + 4 * n : NULL;
    if (prec == AUG_PCG_IC || prec == AUG_PCG_IC_AMD) {
        double t0 = aug_now();
        int bad = prec == AUG_PCG_IC ? aug_ichol_factor(K, &ic) : aug_ichol_factor_amd(K, &ic, cm);
        if (prec_ms) *prec_ms = 1e3 * (aug_now() - t0);
        if (bad) {
            if (ic.p) aug_ichol_free(&ic);
            free(w);
            return -1;
        }
        R = &ic;
        if (shift) *shift = ic.shift;
    }
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    for (int64_t j = 0; dinv && j < n; j++) {
        dinv[j] = 1;
        for (int k = Kp[j]; k < Kp[j + 1]; k++)
            if (Ki[k] == j && Kx[k] > 0) dinv[j] = 1 / Kx[k];
    }
    if (nunit > n) nunit = n;
    if (!unit) nunit = 0;
    double ff = 0;
    for (int64_t i = 0; i < nunit; i++)
        if (unit[i]) x[i] = f[i];
    for (int64_t i = 0; i < n; i++)
        if (i >= nunit || !unit[i]) ff += f[i] * f[i];
    double fn = sqrt(ff) > 0 ? sqrt(ff) : 1;
    int it = 0;
    for (int restart = 0; restart < 5; restart++) {
    symv_upper(K, x, q);
    double rr = 0, rz = 0;
    for (int64_t i = 0; i < n; i++) r[i] = f[i] - q[i];
    prec_apply(R, dinv, r, z, n);
    for (int64_t i = 0; i < n; i++) {
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
            rr += r[i] * r[i];
        }
        prec_apply(R, dinv, r, z, n);
        for (int64_t i = 0; i < n; i++) rz1 += r[i] * z[i];
        double beta = rz1 / rz;
        rz = rz1;
        for (int64_t i = 0; i < n; i++) p[i] = z[i] + beta * p[i];
        it++;
    }
    /* the recursive residual drifts from the true one: restart from the true
       residual while that is above the tolerance */
    symv_upper(K, x, q);
    double tr0 = 0;
    for (int64_t i = 0; i < n; i++)
        if (i >= nunit || !unit[i]) tr0 += (f[i] - q[i]) * (f[i] - q[i]);
    if (*breakdown || sqrt(tr0) <= tol * fn || it >= maxit) break;
    }
    symv_upper(K, x, q);
    double tr = 0;
    for (int64_t i = 0; i < n; i++)
        if (i >= nunit || !unit[i]) tr += (f[i] - q[i]) * (f[i] - q[i]);
    *relres = sqrt(tr) / fn;
    *converged = !*breakdown && *relres <= tol * 1.0000001 + 1e-300;
    if (R) aug_ichol_free(R);
    free(w);
    return it;
}

/* x := Jacobi PCG on K x = f (aug_pcg_prec with M = diag(K)) */
int aug_pcg(const cholmod_sparse *K, const double *f, double *x, double tol, int maxit,
            int *converged, int *breakdown, double *relres, cholmod_common *cm)
{
    return aug_pcg_prec(K, f, NULL, 0, x, AUG_PCG_JACOBI, tol, maxit, converged, breakdown, relres, NULL, NULL, cm);
}
