/* The thesis's conditioning transforms as solvers (thesis 003 sec. 3.5):
   build T from K_t, CG on T x = f_t, and what that x is worth against the
   true cut system (cond of T, error against a fresh CHOLMOD solve). */
#include <float.h>
#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

void aug_cgm_opts_default(aug_cgm_opts *o)
{
    o->eps = 1e-6;
    o->p = 0.5;
    o->ns_tol = 1e-10;
    o->ns_maxit = 100;
    o->max_n = 8400;
    o->cond_tol = 1e-6;
}

static double ms(void) { return 1e3 * aug_now(); }

/* y = T x, T dense symmetric (lower triangle read) */
static void symv(const double *T, int n, const double *x, double *y)
{
    cblas_dsymv(CblasColMajor, CblasLower, n, 1.0, T, n, x, 1, 0.0, y, 1);
}

/* x := Jacobi PCG on T x = f from x ([Saad] ch. 9, as aug_pcg): M = diag(T)
   (1 where T_jj <= 0), ||r|| <= tol ||f|| on the recursive residual, at most 5
   restarts from the true residual; breakdown when p'Tp <= 0. Returns the
   iterations, -1 out of memory; relres = true ||f - T x|| / ||f||. */
static int dense_pcg(const double *T, int n, const double *f, double *x, double tol, int maxit,
                     int *conv, int *brk, double *relres)
{
    double *w = aug_malloc((size_t)(5 * n + 1) * sizeof *w);
    *conv = 0, *brk = 0, *relres = NAN;
    if (!w) return -1;
    double *r = w, *z = w + n, *p = w + 2 * n, *q = w + 3 * n, *dinv = w + 4 * n;
    for (int j = 0; j < n; j++) dinv[j] = T[(size_t)j * n + j] > 0 ? 1 / T[(size_t)j * n + j] : 1;
    double fn = cblas_dnrm2(n, f, 1);
    if (!(fn > 0)) fn = 1;
    int it = 0;
    for (int pass = 0; pass < 5; pass++) {
        symv(T, n, x, q);
        double rr = 0, rz = 0;
        for (int i = 0; i < n; i++) {
            r[i] = f[i] - q[i], z[i] = dinv[i] * r[i], p[i] = z[i];
            rr += r[i] * r[i], rz += r[i] * z[i];
        }
        while (sqrt(rr) > tol * fn && it < maxit) {
            symv(T, n, p, q);
            double pq = cblas_ddot(n, p, 1, q, 1);
            if (!(pq > 0)) {
                *brk = 1;
                break;
            }
            double alpha = rz / pq, rz1 = 0;
            rr = 0;
            for (int i = 0; i < n; i++) {
                x[i] += alpha * p[i], r[i] -= alpha * q[i], z[i] = dinv[i] * r[i];
                rz1 += r[i] * z[i], rr += r[i] * r[i];
            }
            double beta = rz1 / rz;
            rz = rz1;
            for (int i = 0; i < n; i++) p[i] = z[i] + beta * p[i];
            it++;
        }
        symv(T, n, x, q);
        for (int i = 0; i < n; i++) q[i] = f[i] - q[i];
        *relres = cblas_dnrm2(n, q, 1) / fn;
        if (*brk || *relres <= tol || it >= maxit) break;
    }
    *conv = !*brk && *relres <= tol * 1.0000001;
    free(w);
    return it;
}

/* the operators of the condition estimate */
typedef struct cond_ctx {
    const double *T, *L, *F; /* T; T = L diag(F) L' when L (unit lower) */
    double *B;               /* AS: Bunch-Kaufman factor of T (dsytrf) */
    lapack_int *ipiv;
    int n;
} cond_ctx;

static int op_T(void *c, double *x, double *y)
{
    cond_ctx *k = c;
    symv(k->T, k->n, x, y);
    return 0;
}

/* y = T^-1 x: L^-T F^-1 L^-1 x (two dtrsv), or by the dsytrf factor */
static int op_Tinv(void *c, double *x, double *y)
{
    cond_ctx *k = c;
    memcpy(y, x, (size_t)k->n * sizeof *y);
    if (k->B)
        return LAPACKE_dsytrs(LAPACK_COL_MAJOR, 'L', k->n, 1, k->B, k->n, k->ipiv, y, k->n) ? -1 : 0;
    cblas_dtrsv(CblasColMajor, CblasLower, CblasNoTrans, CblasUnit, k->n, k->L, k->n, y, 1);
    for (int i = 0; i < k->n; i++) y[i] /= k->F[i];
    cblas_dtrsv(CblasColMajor, CblasLower, CblasTrans, CblasUnit, k->n, k->L, k->n, y, 1);
    return 0;
}

/* cond(T) = |lambda|_max / |lambda|_min with the signed extreme eigenvalues:
   n <= 64 dense dsyev, else ARPACK "LM" on T and on T^-1 (cond.c); a zero
   F_i: T singular, cond = inf. AS (L NULL): T^-1 and the inertia (spd) from
   the Bunch-Kaufman factor. Returns 0 or -1 (memory, LAPACK). */
static int cond_of(const double *T, const double *L, const double *F, int n, double tol,
                   aug_cgm_res *r)
{
    cond_ctx k = {T, L, F, NULL, NULL, n};
    r->cond = r->lambda_max = r->lambda_min = NAN;
    r->cond_converged = 0;
    int rc = -1, nops;
    if (n <= 64) {
        double *A = aug_malloc((size_t)n * n * sizeof *A + 1), *w = aug_malloc((size_t)n * sizeof *w + 1);
        if (A && w) {
            memcpy(A, T, (size_t)n * n * sizeof *A);
            if (!LAPACKE_dsyev(LAPACK_COL_MAJOR, 'N', 'L', n, A, n, w)) {
                int imax = 0, imin = 0;
                for (int i = 1; i < n; i++) {
                    if (fabs(w[i]) > fabs(w[imax])) imax = i;
                    if (fabs(w[i]) < fabs(w[imin])) imin = i;
                }
                r->lambda_max = w[imax], r->lambda_min = w[imin];
                r->cond = fabs(w[imax]) / fabs(w[imin]);
                /* singular to working precision (LAPACK's rank rule, |lambda|
                   <= n eps lambda_max: COV of rank n - 1 gave lambda_min
                   -2.9e-16, cond 6e16) is singular, as an exactly zero
                   pivot is on the Lanczos path below: cond inf */
                int sing = !(fabs(w[imin]) > n * DBL_EPSILON * fabs(w[imax]));
                if (sing) r->lambda_min = 0, r->cond = INFINITY;
                r->cond_converged = 1;
                if (!L) r->spd = w[0] > 0 && !sing;
                rc = 0;
            }
        }
        free(A), free(w);
        return rc;
    }
    if (!L) {
        k.B = aug_malloc((size_t)n * n * sizeof *k.B);
        k.ipiv = aug_malloc((size_t)n * sizeof *k.ipiv);
        if (!k.B || !k.ipiv) goto done;
        memcpy(k.B, T, (size_t)n * n * sizeof *k.B);
        lapack_int info = LAPACKE_dsytrf(LAPACK_COL_MAJOR, 'L', n, k.B, n, k.ipiv);
        if (info < 0) goto done;
        r->spd = info == 0;
        for (int i = 0; i < n && r->spd; i++) /* a 2x2 block (ipiv < 0) or a pivot <= 0 */
            if (k.ipiv[i] < 0 || !(k.B[(size_t)i * n + i] > 0)) r->spd = 0;
        if (info > 0) { /* an exactly zero pivot */
            double tmax;
            int ok = aug_lanczos_extreme(n, op_T, &k, "LM", tol, 3000, &tmax, &nops);
            if (ok < 0) goto done;
            r->lambda_max = ok ? tmax : NAN, r->lambda_min = 0, r->cond = INFINITY;
            r->cond_converged = ok;
            rc = 0;
            goto done;
        }
    } else {
        for (int i = 0; i < n; i++)
            if (F[i] == 0) {
                double tmax;
                int ok = aug_lanczos_extreme(n, op_T, &k, "LM", tol, 3000, &tmax, &nops);
                if (ok < 0) return -1;
                r->lambda_max = ok ? tmax : NAN, r->lambda_min = 0, r->cond = INFINITY;
                r->cond_converged = ok;
                return 0;
            }
    }
    double tmax, tinv;
    int ok1 = aug_lanczos_extreme(n, op_T, &k, "LM", tol, 3000, &tmax, &nops);
    int ok2 = ok1 < 0 ? -1 : aug_lanczos_extreme(n, op_Tinv, &k, "LM", tol, 3000, &tinv, &nops);
    if (ok1 < 0 || ok2 < 0) goto done;
    r->lambda_max = ok1 ? tmax : NAN;
    r->lambda_min = ok2 ? 1 / tinv : NAN;
    r->cond = fabs(r->lambda_max / r->lambda_min);
    r->cond_converged = ok1 && ok2;
    rc = 0;
done:
    free(k.B), free(k.ipiv);
    return rc;
}

/* u = K^-1 f by a fresh CHOLMOD factorization, cond(K) (ARPACK, cond.c), and
   err = ||x - u|| / ||u||, err_scaled = min_a ||a x - u|| / ||u|| =
   sqrt(1 - (x'u)^2 / (x'x u'u)); K not positive definite: NAN, ref_spd 0 */
static int against_cholmod(const cholmod_sparse *K, const double *f, const double *x, double tol,
                           aug_cgm_res *r, cholmod_common *cm, aug_err *e)
{
    int n = (int)K->nrow;
    cholmod_sparse *A = (cholmod_sparse *)K;
    r->ref_spd = 0, r->err = r->err_scaled = r->cond_k = NAN;
    cholmod_factor *L = cholmod_analyze(A, cm);
    if (!L) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_analyze failed");
    if (!cholmod_factorize(A, L, cm) && cm->status != CHOLMOD_NOT_POSDEF) {
        cholmod_free_factor(&L, cm);
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_factorize failed");
    }
    if (cm->status == CHOLMOD_NOT_POSDEF || L->minor < L->n) {
        cholmod_free_factor(&L, cm);
        return 0;
    }
    cholmod_dense B = aug_dense_view((double *)f, (size_t)n);
    cholmod_dense *U = cholmod_solve(CHOLMOD_A, L, &B, cm);
    if (!U) {
        cholmod_free_factor(&L, cm);
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_solve failed");
    }
    const double *u = U->x;
    double d = 0, uu = 0, xx = 0, xu = 0;
    for (int i = 0; i < n; i++)
        d += (x[i] - u[i]) * (x[i] - u[i]), uu += u[i] * u[i], xx += x[i] * x[i], xu += x[i] * u[i];
    r->ref_spd = 1;
    r->err = uu > 0 ? sqrt(d / uu) : sqrt(d);
    double c = xx > 0 && uu > 0 ? 1 - xu * xu / (xx * uu) : 1;
    r->err_scaled = sqrt(c > 0 ? c : 0);
    aug_cond ck;
    aug_err e2;
    if (!aug_cond_estimate(A, L, tol, &ck, cm, &e2)) r->cond_k = ck.cond;
    cholmod_free_dense(&U, cm);
    cholmod_free_factor(&L, cm);
    return 0;
}

static const char *const names[AUG_CGM_COUNT] = {"cgm-cov", "cgm-es", "cgm-log", "cgm-as"};

/* T by variant into T (n x n), C = COV of K (destroyed: L of ES): the thesis
   003 sec. 3.5 pipeline with its phase times; F = the diagonal of T = L F L'
   (COV, ES, log) */
static int transform(int v, const aug_cgm_opts *o, int n, double *C, double *T, double *F,
                     aug_cgm_res *r)
{
    size_t nn = (size_t)n * n;
    double t0 = ms();
    if (v == AUG_CGM_AS) { /* Y = COV + eps I, P ~ (Y/c)^(1/2), T = c^(1/2) P */
        for (int i = 0; i < n; i++) C[(size_t)i * n + i] += o->eps;
        r->t_decomp = 0;
        int ok = aug_cgm_newton_schulz(C, n, o->ns_tol, o->ns_maxit, T, &r->ns_iters, &r->ns_scale);
        if (ok < 0) return -1;
        r->ns_converged = ok;
        double t1 = ms();
        r->t_norm = t1 - t0;
        double s = sqrt(r->ns_scale);
        for (size_t i = 0; i < nn; i++) T[i] *= s;
        r->t_recomp = ms() - t1;
        return 0;
    }
    if (v == AUG_CGM_COV) memcpy(T, C, nn * sizeof *T); /* T = COV; C becomes its L */
    r->zero_pivots = aug_cgm_ldl(C, n, F);
    double t1 = ms();
    r->t_decomp = t1 - t0;
    if (v == AUG_CGM_COV) {
        r->spd = r->zero_pivots == 0;
        r->t_norm = r->t_recomp = 0;
        return 0;
    }
    r->spd = 1;
    for (int i = 0; i < n; i++) {
        double di = F[i] + o->eps; /* D' = D + eps I (eq. 3.22) */
        F[i] = v == AUG_CGM_ES ? pow(di, o->p) : log(di); /* eq. 3.25, eq. 3.24 */
        if (!(F[i] > 0)) r->spd = 0;
    }
    double t2 = ms();
    r->t_norm = t2 - t1;
    aug_cgm_recompose(C, F, n, T);
    r->t_recomp = ms() - t2;
    return 0;
}

int aug_cgm_solve(int v, const cholmod_sparse *K, const double *f, const aug_cgm_opts *o,
                  double tol, int maxit, double *x, aug_cgm_res *r, cholmod_common *cm,
                  aug_err *e)
{
    memset(r, 0, sizeof *r);
    int64_t n64 = (int64_t)K->nrow;
    if (n64 > o->max_n)
        return aug_err_set(e, AUG_EUSAGE, -1, "UPDT",
                           "%s: K_t of order %lld is above the dense limit %lld (--cgm-max-n)",
                           names[v], (long long)n64, (long long)o->max_n);
    int n = (int)n64;
    size_t nn = (size_t)n * n;
    double *C = aug_malloc(nn * sizeof *C + 1), *T = aug_malloc(nn * sizeof *T + 1);
    double *F = aug_malloc((size_t)n * sizeof *F + 1);
    int rc = 0;
    if (!C || !T || !F) {
        rc = aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "%s: out of memory (dense order %d)", names[v], n);
        goto done;
    }
    double t0 = ms();
    if ((rc = aug_cgm_cov(K, C, cm, e))) goto done;
    r->t_cov = ms() - t0;
    if (transform(v, o, n, C, T, F, r)) {
        rc = aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "%s: out of memory (dense order %d)", names[v], n);
        goto done;
    }
    double t1 = ms();
    memset(x, 0, (size_t)n * sizeof *x);
    r->iters = dense_pcg(T, n, f, x, tol, maxit, &r->converged, &r->breakdown, &r->relres_t);
    if (r->iters < 0) {
        rc = aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "%s: out of memory", names[v]);
        goto done;
    }
    double t2 = ms();
    r->t_cg = t2 - t1;
    /* the diagnostics, timed apart: ||P^2 - Y/c|| (AS), cond(T), the reference */
    if (v == AUG_CGM_AS) { /* C still holds Y; W = T T / c = P^2 (lower) */
        double s = r->ns_scale > 0 ? 1 / r->ns_scale : 0, num = 0, den = 0;
        double *W = aug_malloc(nn * sizeof *W + 1);
        if (!W) {
            rc = aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "%s: out of memory", names[v]);
            goto done;
        }
        cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, n, n, s, T, n, 0.0, W, n);
        for (int j = 0; j < n; j++)
            for (int i = j; i < n; i++) {
                double y = C[(size_t)j * n + i] * s, d = W[(size_t)j * n + i] - y, w = i == j ? 1 : 2;
                num += w * d * d, den += w * y * y;
            }
        free(W);
        r->ns_resid = den > 0 ? sqrt(num / den) : 0;
    }
    if (cond_of(T, v == AUG_CGM_AS ? NULL : C, F, n, o->cond_tol, r)) {
        rc = aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "%s: condition estimate failed", names[v]);
        goto done;
    }
    rc = against_cholmod(K, f, x, o->cond_tol, r, cm, e);
    r->t_diag = ms() - t2;
done:
    free(C), free(T), free(F);
    return rc;
}

/* sTAt: cond, lambda_max, lambda_min (of T), cond_converged, spd, cond_k
   (of K_t), relres_t, breakdown, err_chol, err_scaled, ref_spd, eps and p /
   zero_pivots / ns_iters, ns_converged, ns_scale, ns_resid; tIMe: cov,
   decomp, normalise, recomp, cg, diag */
void aug_cgm_put(int v, const aug_cgm_res *r, const aug_cgm_opts *o, aug_kv *st, aug_kv *tm)
{
    aug_kv_set(st, "cond", r->cond);
    aug_kv_set(st, "lambda_max", r->lambda_max);
    aug_kv_set(st, "lambda_min", r->lambda_min);
    aug_kv_set(st, "cond_converged", r->cond_converged);
    aug_kv_set(st, "spd", r->spd);
    aug_kv_set(st, "cond_k", r->cond_k);
    aug_kv_set(st, "relres_t", r->relres_t);
    aug_kv_set(st, "breakdown", r->breakdown);
    aug_kv_set(st, "err_chol", r->err);
    aug_kv_set(st, "err_scaled", r->err_scaled);
    aug_kv_set(st, "ref_spd", r->ref_spd);
    if (v != AUG_CGM_COV) aug_kv_set(st, "eps", o->eps);
    if (v == AUG_CGM_ES) aug_kv_set(st, "p", o->p);
    if (v != AUG_CGM_AS) aug_kv_set(st, "zero_pivots", r->zero_pivots);
    if (v == AUG_CGM_AS) {
        aug_kv_set(st, "ns_iters", r->ns_iters);
        aug_kv_set(st, "ns_converged", r->ns_converged);
        aug_kv_set(st, "ns_scale", r->ns_scale);
        aug_kv_set(st, "ns_resid", r->ns_resid);
    }
    aug_kv_set(tm, "cov", r->t_cov);
    aug_kv_set(tm, "decomp", r->t_decomp);
    aug_kv_set(tm, "normalise", r->t_norm);
    aug_kv_set(tm, "recomp", r->t_recomp);
    aug_kv_set(tm, "cg", r->t_cg);
    aug_kv_set(tm, "diag", r->t_diag);
}
