/* Condition estimate of K (cond = lambda_max / lambda_min, thesis 003 sec. 3.2.1):
   the extreme eigenvalues by implicitly restarted Lanczos ([ARPACK]) on K and,
   through the factor, on K^-1. */
#include <arpack/arpack.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

typedef struct op_ctx {
    cholmod_sparse *K;
    cholmod_factor *L;
    cholmod_common *cm;
    cholmod_dense *X, *Y, *E; /* cholmod_solve2 workspace */
} op_ctx;

/* y = K x; 0 or -1 */
static int op_K(void *ctx, double *x, double *y)
{
    op_ctx *c = ctx;
    return aug_sym_mult(c->K, x, y, c->cm) ? -1 : 0;
}

/* y = K^-1 x = P' L^-T D^-1 L^-1 P x; 0 or -1 */
static int op_Kinv(void *ctx, double *x, double *y)
{
    op_ctx *c = ctx;
    return aug_factor_apply_inv(c->L, x, y, &c->X, &c->Y, &c->E, c->cm) ? -1 : 0;
}

/* The extreme eigenvalue theta of the symmetric operator op (ARPACK dsaupd,
   mode 1, nev = 1, ncv <= 24, [ARPACK]; which = "LA": the largest, "LM": the
   largest in magnitude, with its sign) to ARPACK's relative Ritz residual tol,
   from a fixed start vector. Returns 1 when converged, 0 when not within maxit
   restarts, -1 on failure (op returned -1); nops = operator applications. */
int aug_lanczos_extreme(int n, aug_symop op, void *c, const char *which, double tol, int maxit,
                        double *theta, int *nops)
{
    int ncv = n < 24 ? n : 24, lworkl = ncv * (ncv + 8), ido = 0, info = 1;
    int iparam[11] = {0}, ipntr[14] = {0}, select[24] = {0}; /* dseupd_c copies select even when unused */
    double *resid = malloc((size_t)n * sizeof *resid);
    double *v = malloc((size_t)n * ncv * sizeof *v), *workd = malloc((size_t)3 * n * sizeof *workd);
    double *workl = malloc((size_t)lworkl * sizeof *workl), d[2] = {0, 0};
    int rc = -1;
    *nops = 0;
    if (!resid || !v || !workd || !workl) goto done;
    uint64_t s = 0x9e3779b97f4a7c15ull; /* fixed start vector: deterministic output */
    for (int i = 0; i < n; i++) {
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        resid[i] = (double)(s >> 11) / 9007199254740992.0 - 0.5;
    }
    iparam[0] = 1, iparam[2] = maxit, iparam[6] = 1;
    for (;;) {
        dsaupd_c(&ido, "I", n, which, 1, tol, resid, ncv, v, n, iparam, ipntr, workd, workl,
                 lworkl, &info);
        if (ido != 1 && ido != -1) break;
        if (op(c, workd + ipntr[0] - 1, workd + ipntr[1] - 1)) goto done;
    }
    *nops = iparam[8];
    if (info < 0) goto done;
    if (iparam[4] < 1) {
        rc = 0;
        goto done;
    }
    dseupd_c(0, "A", select, d, v, n, 0.0, "I", n, which, 1, tol, resid, ncv, v, n, iparam, ipntr,
             workd, workl, lworkl, &info);
    if (info != 0) goto done;
    *theta = d[0];
    rc = 1;
done:
    free(resid);
    free(v);
    free(workd);
    free(workl);
    return rc;
}

/* cond_2(K) = lambda_max / lambda_min (thesis 003 sec. 3.2.1). lambda_max: Lanczos
   on K to relative Ritz residual tol (a Ritz value theta of a symmetric matrix lies
   within its residual norm of an eigenvalue and never above lambda_max, [Parlett],
   so lambda_max is in [theta, theta (1 + tol)]);
   lambda_min = 1/theta, theta the largest eigenvalue of K^-1, by Lanczos with
   solves through the factor L, to the same tol. n <= 64: dense LAPACK dsyev.
   Unconverged iterations give NAN and converged = 0, never a number. */
int aug_cond_estimate(cholmod_sparse *K, cholmod_factor *L, double tol, aug_cond *r,
                      cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    memset(r, 0, sizeof *r);
    int n = (int)K->nrow;
    if (n == 0) return aug_err_set(e, AUG_EUSAGE, -1, "cOND", "empty matrix");
    if (n <= 64) {
        double *A = calloc((size_t)n * n, sizeof *A), *w = malloc((size_t)n * sizeof *w);
        if (!A || !w) {
            free(A);
            free(w);
            return aug_err_set(e, AUG_ENOMEM, -1, "cOND", "out of memory");
        }
        const int *Ap = K->p, *Ai = K->i;
        const double *Ax = K->x;
        for (int j = 0; j < n; j++)
            for (int p = Ap[j]; p < Ap[j + 1]; p++) A[(size_t)j * n + Ai[p]] = Ax[p];
        int info = LAPACKE_dsyev(LAPACK_COL_MAJOR, 'N', 'U', n, A, n, w);
        r->lambda_min = w[0], r->lambda_max = w[n - 1];
        free(A);
        free(w);
        if (info) return aug_err_set(e, AUG_ENOCONV, -1, "cOND", "LAPACK dsyev failed (%d)", info);
        r->converged = 1;
        r->cond = r->lambda_max / r->lambda_min;
        return 0;
    }
    op_ctx c = {K, L, cm, NULL, NULL, NULL};
    double tmax = 0, tinv = 0;
    int ok1 = aug_lanczos_extreme(n, op_K, &c, "LA", tol, 3000, &tmax, &r->iters_max);
    int ok2 = ok1 < 0 ? -1 : aug_lanczos_extreme(n, op_Kinv, &c, "LA", tol, 3000, &tinv, &r->iters_min);
    cholmod_free_dense(&c.X, cm);
    cholmod_free_dense(&c.Y, cm);
    cholmod_free_dense(&c.E, cm);
    if (ok1 < 0 || ok2 < 0)
        return aug_err_set(e, AUG_ENOMEM, -1, "cOND", "eigenvalue iteration failed");
    r->converged = ok1 == 1 && ok2 == 1;
    r->lambda_max = ok1 == 1 ? tmax : NAN;
    r->lambda_min = ok2 == 1 && tinv > 0 ? 1.0 / tinv : NAN;
    r->cond = r->lambda_max / r->lambda_min;
    return 0;
}
