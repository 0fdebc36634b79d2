/* Projected PCG for the coupled system (paper 004 sec. 5.3, algorithms 1-3)
   with the Schilders constraint preconditioner, G11 = 0 on the slaves. */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_saddle.h"

#define ERR(e, code, ...) aug_err_set(e, code, -1, "MODE", __VA_ARGS__)
/* restarts from the true residual when the recurred one drifted off */
#define MAX_RESTART 4

/* Solve P [z; v] = [a; w] (w == NULL: 0) with the constraint preconditioner
   P = [G C_c'; C_c 0] permuted by the slaves (paper 004 eq. 19-20) as
   [0 0 C1'; 0 G22 C2'; C1 C2 0]: G11 = 0, G22 = diag(A) off the slaves. The
   paper's printed algorithm 2 is garbled; by block elimination (Dollar,
   Gould, Schilders & Wathen, SIMAX 28 (2006), the Schilders factorisation
   with G11 = 0), row by row:
       C1' v = a1                 (v = C1^-T a1)
       G22 z2 = a2 - C2' v        (z2 = G22^-1 (a2 - C2' v))
       C1 z1 = w - C2 z2          (z1 = C1^-1 (w - C2 z2)).
   C1 = C_c(:, slaves) = [D X; 0 R] by construction (D diagonal: private
   rows and their slave columns; X: private rows on dense slave columns;
   R = Q R11 from the column-pivoted QR of the compressed rows), so
   C1' v = a1 is v_P = D^-1 a1_P, v_k = Q R11^-T (a1_k - X' v_P), and
   C1 z1 = t is z1_k = R11^-1 Q' t_k, z1_P = D^-1 (t_P - X z1_k).
   P is nonsingular with Z'GZ = G22 SPD on the null space Z of C_c, which
   makes it a valid constraint preconditioner. O(nnz(C_P) + k nd + k^2 + N). */
static void schilders(aug_saddle *s, const double *a, const double *w, double *z, double *v)
{
    int mp = s->mp, k = s->k;
    int64_t N = s->N;
    double *t = s->u[3], *y = s->u[4], *ctv = s->w[4];
    for (int i = 0; i < mp; i++) v[i] = a[s->pslave[i]] / s->pdiag[i];
    if (k) {
        for (int j = 0; j < k; j++) y[j] = a[s->dslave[j]];
        for (int q = 0; q < s->nx; q++) y[s->xj[q]] -= s->xv[q] * v[s->xi[q]];
        cblas_dtrsv(CblasColMajor, CblasUpper, CblasTrans, CblasNonUnit, k, s->Rr, k, y, 1);
        cblas_dgemv(CblasColMajor, CblasNoTrans, k, k, 1.0, s->Rq, k, y, 1, 0.0, v + mp, 1);
    }
    memset(ctv, 0, (size_t)N * sizeof *ctv);
    aug_saddle_cct(s, v, ctv);
    for (int64_t j = 0; j < N; j++) z[j] = s->ginv[j] * (a[j] - ctv[j]);
    aug_saddle_cc(s, z, t);  /* C2 z2: the slave entries of z are still 0 */
    for (int i = 0; i < s->mc; i++) t[i] = (w ? w[i] : 0) - t[i];
    if (k) {
        cblas_dgemv(CblasColMajor, CblasTrans, k, k, 1.0, s->Rq, k, t + mp, 1, 0.0, y, 1);
        cblas_dtrsv(CblasColMajor, CblasUpper, CblasNoTrans, CblasNonUnit, k, s->Rr, k, y, 1);
        for (int q = 0; q < s->nx; q++) t[s->xi[q]] -= s->xv[q] * y[s->xj[q]];
        for (int j = 0; j < k; j++) z[s->dslave[j]] = y[j];
    }
    for (int i = 0; i < mp; i++) z[s->pslave[i]] = t[i] / s->pdiag[i];
}

static double dot(const double *a, const double *b, int64_t n)
{
    return n > 0 ? cblas_ddot((int)n, a, 1, b, 1) : 0;
}

/* z, v from res, then the residual update res -= C_c' v, mu -= v (Gould,
   Hribar & Nocedal 2001 sec. 3; paper 004 algorithm 3): afterwards res =
   G z, so ||res|| is the residual of the first block row with the current mu
   and no component of res along range(C_c') is carried into the iteration */
static void precondition(aug_saddle *s, double *res, double *z, double *mu)
{
    const double *v = s->u[2], *ctv = s->w[4];  /* schilders leaves C_c' v in w[4] */
    schilders(s, res, NULL, z, s->u[2]);
    for (int64_t j = 0; j < s->N; j++) res[j] -= ctv[j];
    for (int i = 0; i < s->mc; i++) mu[i] -= v[i];
}

/* Projected CG on the null space of C_c (Gould, Hribar & Nocedal 2001,
   algorithm II with the residual update; paper 004 algorithm 1):
   x0 feasible by one preconditioner solve with [0; g_c - C_c x], then
   res = A x + C_c' mu - r, z = P res, p = -z,
   alpha = res'z / p'Ap, x += alpha p, res += alpha A p, z = P res (+update),
   beta = res'z_new / res'z_old, p = -z + beta p.
   Every z and p lies in null(C_c), so x stays feasible up to round-off. */
int aug_saddle_ppcg(aug_saddle *s, const double *r, const double *g, double *x, double *lambda,
                    double tol, int maxit, int warm, aug_saddle_stats *st, aug_err *e)
{
    aug_err_clear(e);
    aug_saddle_stats zst = {0};
    if (!st) st = &zst;
    memset(st, 0, sizeof *st);
    if (!s->c_ok) return ERR(e, AUG_EUSAGE, "saddle: no system set");
    if (!(tol > 0) || maxit < 0) return ERR(e, AUG_EUSAGE, "saddle: ppcg needs tol > 0, maxit >= 0");
    double t0 = aug_now();
    int64_t N = s->N;
    int mc = s->mc;
    double *res = s->w[0], *z = s->w[1], *p = s->w[2], *q = s->w[3];
    double *gc = s->u[0], *mu = s->u[1], *t = s->u[5];
    aug_saddle_compress(s, g, gc);
    if (!warm) memset(x, 0, (size_t)N * sizeof *x);
    if (warm && lambda) aug_saddle_compress(s, lambda, mu);
    else memset(mu, 0, ((size_t)mc + 1) * sizeof *mu);
    double nrm = hypot(cblas_dnrm2((int)N, r, 1), mc ? cblas_dnrm2(mc, gc, 1) : 0);
    if (nrm == 0) nrm = 1;
    /* feasible start: x += z with C_c z = g_c - C_c x, z on the slaves only */
    aug_saddle_cc(s, x, t);
    for (int i = 0; i < mc; i++) t[i] = gc[i] - t[i];
    memset(res, 0, (size_t)N * sizeof *res);
    schilders(s, res, t, z, s->u[2]);
    for (int64_t j = 0; j < N; j++) x[j] += z[j];
    int it = 0, restarts = 0, conv = 0, rc = 0;
    double rz = 0;
    for (;;) {
        /* (re)start from the true residual */
        if (aug_saddle_apply_A(s, x, res, e)) return e->code;
        aug_saddle_cct(s, mu, res);
        for (int64_t j = 0; j < N; j++) res[j] -= r[j];
        precondition(s, res, z, mu);
        rz = dot(res, z, N);
        for (int64_t j = 0; j < N; j++) p[j] = -z[j];
        while (cblas_dnrm2((int)N, res, 1) > tol * nrm && it < maxit) {
            if (aug_saddle_apply_A(s, p, q, e)) return e->code;
            double pq = dot(p, q, N);
            if (!(pq > 0)) {
                rc = ERR(e, AUG_ESINGULAR, "saddle: ppcg: A is not positive definite on the "
                         "constraint null space (p'Ap = %g at iteration %d)", pq, it);
                goto done;
            }
            double alpha = rz / pq;
            for (int64_t j = 0; j < N; j++) {
                x[j] += alpha * p[j];
                res[j] += alpha * q[j];
            }
            precondition(s, res, z, mu);
            double rz1 = dot(res, z, N), beta = rz1 / rz;
            rz = rz1;
            for (int64_t j = 0; j < N; j++) p[j] = beta * p[j] - z[j];
            it++;
        }
        if (aug_saddle_residuals(s, r, g, gc, x, mu, st, e)) return e->code;
        if (st->relres <= tol) {
            conv = 1;
            break;
        }
        if (it >= maxit || ++restarts > MAX_RESTART) break;
    }
done:
    if (lambda) aug_saddle_expand(s, mu, lambda);
    if (!rc && aug_saddle_residuals(s, r, g, gc, x, mu, st, e)) return e->code;
    st->iters = it;
    st->converged = conv;
    st->prep_ms = 0;
    st->solve_ms = 1e3 * (aug_now() - t0);
    if (!rc && !conv)
        rc = ERR(e, AUG_ENOCONV, "saddle: ppcg: relres %.3g > tol %.3g after %d iterations",
                 st->relres, tol, it);
    return rc;
}
