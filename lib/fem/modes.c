/* The lowest vibration modes K x = lambda M x by implicitly restarted Lanczos
   in shift-invert mode ([ARPACK] dsaupd mode 3, sigma = 0) on the CHOLMOD
   factor of F = cM M + cK K (statics: F = K; dynamics: the integrator's A,
   aug_dyn.h): F x = mu M x with mu = cM + cK lambda, so the largest
   eigenvalues 1/mu of F^-1 M give the smallest lambda = (mu - cM) / cK. */
#include <arpack/arpack.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

typedef struct mctx {
    cholmod_sparse *M;
    cholmod_factor *L;
    cholmod_common *cm;
    cholmod_dense *X, *Y, *E;
    double *t;
    int failed;
} mctx;

static void mult_M(mctx *c, double *x, double *y)
{
    if (aug_sym_mult(c->M, x, y, c->cm)) c->failed = 1;
}

static void solve_F(mctx *c, double *x, double *y)
{
    if (aug_factor_apply_inv(c->L, x, y, &c->X, &c->Y, &c->E, c->cm)) c->failed = 1;
}

/* dseupd with rvec = 1 when X is given: the Ritz vectors of mode 3 are
   M-orthonormal, X'MX = I, in the order of lambda */
int aug_modes_lowest_vec(cholmod_sparse *M, cholmod_factor *L, double cM, double cK, int nev,
                         double tol, aug_modes *r, double *X, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    memset(r, 0, sizeof *r);
    int n = (int)M->nrow;
    if (nev < 1 || nev > AUG_MODES_MAX || nev >= n)
        return aug_err_set(e, AUG_EUSAGE, -1, "cOND", "%d modes of a matrix of order %d", nev, n);
    int ncv = 2 * nev + 20 < n ? 2 * nev + 20 : n, lworkl = ncv * (ncv + 8), ido = 0, info = 1;
    int iparam[11] = {0}, ipntr[14] = {0}, *select = calloc((size_t)ncv, sizeof *select);
    double *resid = malloc((size_t)n * sizeof *resid), *v = malloc((size_t)n * ncv * sizeof *v);
    double *workd = malloc((size_t)3 * n * sizeof *workd), *workl = malloc((size_t)lworkl * sizeof *workl);
    double *d = malloc((size_t)ncv * sizeof *d);
    mctx c = {M, L, cm, NULL, NULL, NULL, malloc((size_t)n * sizeof(double)), 0};
    int rc = AUG_ENOMEM;
    if (!select || !resid || !v || !workd || !workl || !d || !c.t) goto done;
    uint64_t s = 0x9e3779b97f4a7c15ull; /* fixed start vector: deterministic output */
    for (int i = 0; i < n; i++) {
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        resid[i] = (double)(s >> 11) / 9007199254740992.0 - 0.5;
    }
    iparam[0] = 1, iparam[2] = 3000, iparam[6] = 3;
    for (;;) {
        dsaupd_c(&ido, "G", n, "LM", nev, tol, resid, ncv, v, n, iparam, ipntr, workd, workl,
                 lworkl, &info);
        double *x = workd + ipntr[0] - 1, *y = workd + ipntr[1] - 1;
        if (ido == -1) { /* y = F^-1 M x */
            mult_M(&c, x, c.t);
            solve_F(&c, c.t, y);
        } else if (ido == 1) { /* y = F^-1 (M x), M x given */
            solve_F(&c, workd + ipntr[2] - 1, y);
        } else if (ido == 2) {
            mult_M(&c, x, y);
        } else {
            break;
        }
        if (c.failed) goto done;
    }
    r->iters = iparam[8];
    if (info < 0) {
        rc = aug_err_set(e, AUG_ENOCONV, -1, "cOND", "ARPACK dsaupd failed (%d)", info);
        goto done;
    }
    r->nev = nev;
    if (iparam[4] < nev) { /* not converged: no numbers */
        for (int i = 0; i < nev; i++) r->lambda[i] = NAN;
        for (size_t i = 0; X && i < (size_t)n * nev; i++) X[i] = NAN;
        rc = 0;
        goto done;
    }
    dseupd_c(X != NULL, "A", select, d, X ? X : v, n, 0.0, "G", n, "LM", nev, tol, resid, ncv, v, n, iparam, ipntr,
             workd, workl, lworkl, &info);
    if (info != 0) {
        rc = aug_err_set(e, AUG_ENOCONV, -1, "cOND", "ARPACK dseupd failed (%d)", info);
        goto done;
    }
    /* d: eigenvalues mu of (F, M), ascending */
    for (int i = 0; i < nev; i++) r->lambda[i] = (d[i] - cM) / cK;
    r->converged = 1;
    rc = 0;
done:
    if (rc == AUG_ENOMEM) aug_err_set(e, AUG_ENOMEM, -1, "cOND", "out of memory");
    cholmod_free_dense(&c.X, cm);
    cholmod_free_dense(&c.Y, cm);
    cholmod_free_dense(&c.E, cm);
    free(c.t), free(select), free(resid), free(v), free(workd), free(workl), free(d);
    return rc;
}

int aug_modes_lowest(cholmod_sparse *M, cholmod_factor *L, double cM, double cK, int nev,
                     double tol, aug_modes *r, cholmod_common *cm, aug_err *e)
{
    return aug_modes_lowest_vec(M, L, cM, cK, nev, tol, r, NULL, cm, e);
}
