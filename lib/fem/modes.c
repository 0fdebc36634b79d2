/* The lowest vibration modes K x = lambda M x by implicitly restarted Lanczos
   in shift-invert mode ([ARPACK] dsaupd mode 3, sigma = 0) on the CHOLMOD
   factor of F = cM M + cK K (statics: F = K; dynamics: the integrator's A,
   aug_dyn.h): F x = mu M x with mu = cM + cK lambda, so the largest
   eigenvalues 1/mu of F^-1 M give the smallest lambda = (mu - cM) / cK.
   Rigid motions left free (a dynamic scene need not be held) are deflated:
   they are exact eigenvectors with lambda = 0, and in dynamics they sit at
   mu = cM with the elastic modes at cM + cK lambda, 1/mu clustered within
   cK lambda / cM (1e-4 at dt = 0.01): Lanczos from one start vector found
   2 of the 6 of a free brick and went on to elastic modes, converged. The
   iteration runs in their M-orthogonal complement instead (the operator
   followed by the projector I - R R'M, the start vector projected), and
   they are reported as lambda = 0 first ([ARPACK] sec. 4.4 on deflation). */
#include <arpack/arpack.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

typedef struct mctx {
    const double *R, *MR; /* deflated: M-orthonormal R (n x k) and M R */
    int k;
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

/* y := (I - R R'M) y: the M-orthogonal complement of the deflated modes */
static void project(const mctx *c, double *y, int64_t n)
{
    for (int j = 0; j < c->k; j++) {
        const double *r = c->R + (int64_t)j * n, *mr = c->MR + (int64_t)j * n;
        double a = 0;
        for (int64_t i = 0; i < n; i++) a += mr[i] * y[i];
        for (int64_t i = 0; i < n; i++) y[i] -= a * r[i];
    }
}

static void solve_F(mctx *c, double *x, double *y)
{
    if (aug_factor_apply_inv(c->L, x, y, &c->X, &c->Y, &c->E, c->cm)) c->failed = 1;
    project(c, y, (int64_t)c->M->nrow);
}

/* R (n x k) M-orthonormalized in place by modified Gram-Schmidt (columns
   whose M-norm falls below 1e-8 of their own before are dropped), MR = M R;
   returns the columns kept, -1 when M's product failed */
static int m_orthonormal(mctx *c, double *R, double *MR, int k, int64_t n)
{
    int kept = 0;
    for (int j = 0; j < k; j++) {
        double *r = R + (int64_t)kept * n, *mr = MR + (int64_t)kept * n;
        if (kept != j) memcpy(r, R + (int64_t)j * n, (size_t)n * sizeof *r);
        mult_M(c, r, mr);
        if (c->failed) return -1;
        double n0 = 0;
        for (int64_t i = 0; i < n; i++) n0 += r[i] * mr[i];
        for (int q = 0; q < kept; q++) {
            const double *mq = MR + (int64_t)q * n, *rq = R + (int64_t)q * n;
            double a = 0;
            for (int64_t i = 0; i < n; i++) a += mq[i] * r[i];
            for (int64_t i = 0; i < n; i++) r[i] -= a * rq[i], mr[i] -= a * mq[i];
        }
        double nn = 0;
        for (int64_t i = 0; i < n; i++) nn += r[i] * mr[i];
        if (!(nn > 1e-16 * n0) || !(n0 > 0)) continue;
        double s = 1 / sqrt(nn);
        for (int64_t i = 0; i < n; i++) r[i] *= s, mr[i] *= s;
        kept++;
    }
    return kept;
}

/* ARPACK (dsaupd mode 3, dseupd with vectors) for the nv lowest lambda in
   the M-orthogonal complement of c->R: lam ascending, V (n x nv) their
   M-orthonormal vectors. 0, 1 not converged (lam NAN), -1 with e set. */
static int arpack_run(mctx *c, int n, int nv, double cM, double cK, double tol, double *lam, double *V,
                      int *iters, aug_err *e)
{
    int ncv = 2 * nv + 20 < n - c->k ? 2 * nv + 20 : n - c->k, lworkl = ncv * (ncv + 8), ido = 0, info = 1;
    int iparam[11] = {0}, ipntr[14] = {0}, *select = calloc((size_t)ncv, sizeof *select);
    double *resid = malloc((size_t)n * sizeof *resid), *v = malloc((size_t)n * ncv * sizeof *v);
    double *workd = malloc((size_t)3 * n * sizeof *workd), *workl = malloc((size_t)lworkl * sizeof *workl);
    double *d = malloc((size_t)ncv * sizeof *d);
    int rc = -1;
    if (!select || !resid || !v || !workd || !workl || !d) {
        aug_err_set(e, AUG_ENOMEM, -1, "cOND", "out of memory");
        goto done;
    }
    uint64_t s = 0x9e3779b97f4a7c15ull; /* fixed start vector: deterministic output */
    for (int i = 0; i < n; i++) {
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        resid[i] = (double)(s >> 11) / 9007199254740992.0 - 0.5;
    }
    project(c, resid, n);
    iparam[0] = 1, iparam[2] = 3000, iparam[6] = 3;
    for (;;) {
        dsaupd_c(&ido, "G", n, "LM", nv, tol, resid, ncv, v, n, iparam, ipntr, workd, workl, lworkl, &info);
        double *x = workd + ipntr[0] - 1, *y = workd + ipntr[1] - 1;
        if (ido == -1) { /* y = F^-1 M x */
            mult_M(c, x, c->t);
            solve_F(c, c->t, y);
        } else if (ido == 1) { /* y = F^-1 (M x), M x given */
            solve_F(c, workd + ipntr[2] - 1, y);
        } else if (ido == 2) {
            mult_M(c, x, y);
        } else {
            break;
        }
        if (c->failed) {
            aug_err_set(e, AUG_ENOMEM, -1, "cOND", "out of memory");
            goto done;
        }
    }
    *iters += iparam[8];
    if (info < 0) {
        aug_err_set(e, AUG_ENOCONV, -1, "cOND", "ARPACK dsaupd failed (%d)", info);
        goto done;
    }
    if (iparam[4] < nv) { /* not converged: no numbers */
        for (int i = 0; i < nv; i++) lam[i] = NAN;
        rc = 1;
        goto done;
    }
    dseupd_c(1, "A", select, d, V, n, 0.0, "G", n, "LM", nv, tol, resid, ncv, v, n, iparam, ipntr, workd, workl,
             lworkl, &info);
    if (info != 0) {
        aug_err_set(e, AUG_ENOCONV, -1, "cOND", "ARPACK dseupd failed (%d)", info);
        goto done;
    }
    /* d: eigenvalues mu of (F, M), ascending */
    for (int i = 0; i < nv; i++) lam[i] = (d[i] - cM) / cK;
    rc = 0;
done:
    free(select), free(resid), free(v), free(workd), free(workl), free(d);
    return rc;
}

/* the deflated columns of c extended by the q columns of V (M-orthonormal
   and M-orthogonal to them): R, MR grown to k + q (cap columns) */
static int deflate_more(mctx *c, double **R, double **MR, int n, const double *V, int q)
{
    int k = c->k;
    double *r2 = realloc(*R, (size_t)n * (k + q) * sizeof *r2);
    if (!r2) return -1;
    *R = r2;
    double *m2 = realloc(*MR, (size_t)n * (k + q) * sizeof *m2);
    if (!m2) return -1;
    *MR = m2;
    memcpy(r2 + (size_t)n * k, V, (size_t)n * q * sizeof *r2);
    for (int j = 0; j < q; j++) {
        mult_M(c, r2 + (size_t)n * (k + j), m2 + (size_t)n * (k + j));
        if (c->failed) return -1;
    }
    c->R = r2, c->MR = m2, c->k = k + q;
    return 0;
}

/* Lanczos from one start vector finds one copy of a repeated eigenvalue in
   exact arithmetic and others only as rounding feeds them: the bending
   pairs of a square beam, the rigid motions above. So the nv found are
   checked: a second run in the complement of the modes known and found
   asks for the lowest min(nv, 4) left, and any below the largest found
   (the copies the first run missed) replace the largest, until a check
   finds none (at most 4 checks). The 3 x 1 x 1 hex beam, free: lambda_8
   110.6 (the second bending mode's copy missed) against dsygv's 94.2;
   checked, exact. [ARPACK] sec. 4.6 names the limitation. */
int aug_modes_lowest_vec(cholmod_sparse *M, cholmod_factor *L, double cM, double cK, int nev,
                         double tol, const double *R0, int k0, aug_modes *r, double *X,
                         cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    memset(r, 0, sizeof *r);
    int n = (int)M->nrow;
    if (nev < 1 || nev > AUG_MODES_MAX || nev >= n)
        return aug_err_set(e, AUG_EUSAGE, -1, "cOND", "%d modes of a matrix of order %d", nev, n);
    mctx c = {NULL, NULL, 0, M, L, cm, NULL, NULL, NULL, malloc((size_t)n * sizeof(double)), 0};
    double *R = NULL, *MR = NULL, *V = NULL, *W = NULL, lam[AUG_MODES_MAX], chk[AUG_MODES_MAX];
    int k = 0, rc = -1;
    if (!c.t) goto nomem;
    /* the deflated modes: lambda = 0, the first ones */
    if (R0 && k0 > 0) {
        R = malloc((size_t)n * k0 * sizeof *R), MR = malloc((size_t)n * k0 * sizeof *MR);
        if (!R || !MR) goto nomem;
        memcpy(R, R0, (size_t)n * k0 * sizeof *R);
        if ((k = m_orthonormal(&c, R, MR, k0, n)) < 0) goto nomem;
        if (k > nev) k = nev;
        c.R = R, c.MR = MR, c.k = k;
    }
    for (int i = 0; i < k; i++) r->lambda[i] = 0;
    if (X && k > 0) memcpy(X, R, (size_t)n * k * sizeof *X);
    r->nev = nev;
    int nv = nev - k; /* the modes ARPACK finds, in the complement */
    if (nv == 0 || nv >= n - k) { /* nothing left to iterate for, or too little room */
        r->converged = nv == 0;
        for (int i = k; i < nev; i++) r->lambda[i] = NAN;
        rc = 0;
        goto done;
    }
    V = malloc((size_t)n * nv * sizeof *V);
    W = malloc((size_t)n * nv * sizeof *W);
    if (!V || !W) goto nomem;
    int st = arpack_run(&c, n, nv, cM, cK, tol, lam, V, &r->iters, e);
    for (int round = 0; st == 0 && round < 4; round++) {
        int p = nv < 4 ? nv : 4;
        if (p >= n - c.k - nv) break;
        if (deflate_more(&c, &R, &MR, n, V, nv)) goto nomem;
        st = arpack_run(&c, n, p, cM, cK, tol, chk, W, &r->iters, e);
        c.k -= nv; /* back to the deflated modes only */
        if (st) break;
        int nb = 0; /* found below the largest: merge (both lists ascending) */
        while (nb < p && chk[nb] < lam[nv - 1] * (1 - 1e-9)) nb++;
        if (nb == 0) break;
        for (int j = 0; j < nb; j++) { /* insert chk[j] with its vector, dropping the largest */
            int at = nv - 1;
            while (at > 0 && lam[at - 1] > chk[j]) {
                lam[at] = lam[at - 1];
                memcpy(V + (size_t)n * at, V + (size_t)n * (at - 1), (size_t)n * sizeof *V);
                at--;
            }
            lam[at] = chk[j];
            memcpy(V + (size_t)n * at, W + (size_t)n * j, (size_t)n * sizeof *V);
        }
    }
    if (st < 0) goto done;
    if (st > 0) { /* not converged: no numbers */
        for (int i = 0; i < nev; i++) r->lambda[i] = NAN;
        for (size_t i = 0; X && i < (size_t)n * nev; i++) X[i] = NAN;
        rc = 0;
        goto done;
    }
    for (int i = 0; i < nv; i++) r->lambda[k + i] = lam[i];
    if (X) memcpy(X + (size_t)n * k, V, (size_t)n * nv * sizeof *X);
    r->converged = 1;
    rc = 0;
    goto done;
nomem:
    aug_err_set(e, AUG_ENOMEM, -1, "cOND", "out of memory");
done:
    cholmod_free_dense(&c.X, cm);
    cholmod_free_dense(&c.Y, cm);
    cholmod_free_dense(&c.E, cm);
    free(c.t), free(R), free(MR), free(V), free(W);
    return rc ? (e->code ? e->code : AUG_ENOMEM) : 0;
}

int aug_modes_lowest(cholmod_sparse *M, cholmod_factor *L, double cM, double cK, int nev,
                     double tol, const double *R, int k, aug_modes *r, cholmod_common *cm, aug_err *e)
{
    return aug_modes_lowest_vec(M, L, cM, cK, nev, tol, R, k, r, NULL, cm, e);
}

/* diagonal entry j of a symmetric matrix stored as one triangle */
static double diag_at(const cholmod_sparse *A, int64_t j)
{
    const int *Ap = A->p, *Ai = A->i;
    const double *Ax = A->x;
    for (int p = Ap[j]; p < Ap[j + 1]; p++)
        if (Ai[p] == j) return Ax[p];
    return 0;
}

/* The lowest modes of K x = lambda M x where K may be singular (a dynamic
   scene need not be held; a sub-domain of modal floats): shift-invert on
   G = K + alpha M, alpha = 1e-8 max_j K_jj / M_jj (a lower bound of
   lambda_max, so cond(G) stays near 1e8 and alpha below lambda_1 unless
   cond(K) exceeds that), mu = alpha + lambda. The factor of A = cM M + cK K
   the scene has is the shift sigma = -cM / cK instead, -1e4 at dt = 0.01:
   the 1/mu of the lowest modes then lie within cK lambda / cM of each
   other and of the rigid motions, and Lanczos converged on the armadillo
   (6 modes) in none of its 3,000 restarts (45 s). K and M: the same
   triangle stored. */
int aug_modes_shifted(cholmod_sparse *K, cholmod_sparse *M, int nev, double tol, const double *R, int k,
                      aug_modes *r, double *X, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    double lmax = 0;
    for (int64_t j = 0; j < (int64_t)K->ncol; j++) {
        double kd = diag_at(K, j), md = diag_at(M, j);
        if (md > 0 && kd / md > lmax) lmax = kd / md;
    }
    if (!(lmax > 0 && lmax < INFINITY))
        return aug_err_set(e, AUG_EDATA, -1, "cOND", "modes: no positive K_jj / M_jj (K or M empty?)");
    double alpha = 1e-8 * lmax, one[2] = {1, 0}, al[2] = {alpha, 0};
    cholmod_sparse *G = cholmod_add(K, M, one, al, 1, 1, cm);
    if (!G) return aug_err_set(e, AUG_ENOMEM, -1, "cOND", "out of memory");
    cholmod_factor *L = aug_analyze(G, cm, e);
    int rc = !L ? e->code : aug_factorize(G, L, NULL, NULL, cm, e);
    if (!rc) rc = aug_modes_lowest_vec(M, L, alpha, 1.0, nev, tol, R, k, r, X, cm, e);
    cholmod_free_factor(&L, cm);
    cholmod_free_sparse(&G, cm);
    return rc;
}
