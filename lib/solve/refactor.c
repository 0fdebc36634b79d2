/* Baseline: CHOLMOD re-factorization of the cut matrix every step (symbolic
   analysis only when the pattern changed). */
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

void aug_refactor_init(aug_refactor *r) { memset(r, 0, sizeof *r); }

void aug_refactor_free(aug_refactor *r, cholmod_common *cm)
{
    if (r->L) cholmod_free_factor(&r->L, cm);
    free(r->Kp);
    free(r->Ki);
    memset(r, 0, sizeof *r);
}

/* 1 when K has the pattern of the last analysis (its symbolic factor is reused) */
static int same_pattern(const aug_refactor *r, const cholmod_sparse *K)
{
    const int *Kp = K->p;
    if (!r->L || r->n != (int64_t)K->ncol || r->nnz != Kp[K->ncol]) return 0;
    return !memcmp(r->Kp, Kp, (size_t)(r->n + 1) * sizeof *Kp) &&
           !memcmp(r->Ki, K->i, (size_t)r->nnz * sizeof(int));
}

static int keep_pattern(aug_refactor *r, const cholmod_sparse *K)
{
    const int *Kp = K->p;
    free(r->Kp), free(r->Ki);
    r->n = (int64_t)K->ncol, r->nnz = Kp[K->ncol];
    r->Kp = aug_malloc((size_t)(r->n + 1) * sizeof *r->Kp);
    r->Ki = aug_malloc((size_t)(r->nnz + 1) * sizeof *r->Ki);
    if (!r->Kp || !r->Ki) return -1;
    memcpy(r->Kp, Kp, (size_t)(r->n + 1) * sizeof *Kp);
    memcpy(r->Ki, K->i, (size_t)r->nnz * sizeof(int));
    return 0;
}

/* P K_t P' = L D L' (or L L') by CHOLMOD ([CHOLMOD]: cholmod_analyze only when the
   pattern changed, cholmod_factorize every step), x = K_t^-1 f_t; not positive
   definite: singular = 1 and x untouched */
int aug_refactor_step(aug_refactor *r, const aug_cutmat *m, double *u, double times[4],
                      cholmod_common *cm, aug_err *e)
{
    double t0 = 1e3 * aug_now();
    r->singular = 0;
    cholmod_sparse *K = aug_cutmat_sparse(m, 0, cm);
    if (!K) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (K_t)");
    double t1 = 1e3 * aug_now();
    r->analyzed = 0;
    if (!same_pattern(r, K)) {
        if (r->L) cholmod_free_factor(&r->L, cm);
        r->L = cholmod_analyze(K, cm);
        if (!r->L || keep_pattern(r, K)) {
            cholmod_free_sparse(&K, cm);
            return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_analyze failed");
        }
        r->analyzed = 1;
    }
    double t2 = 1e3 * aug_now();
    int ok = cholmod_factorize(K, r->L, cm);
    cholmod_free_sparse(&K, cm);
    double t3 = 1e3 * aug_now();
    times[0] = t1 - t0, times[1] = t2 - t1, times[2] = t3 - t2, times[3] = 0;
    if (!ok && cm->status != CHOLMOD_NOT_POSDEF)
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_factorize failed (%d)", cm->status);
    if (cm->status == CHOLMOD_NOT_POSDEF || r->L->minor < r->L->n) {
        r->singular = 1;
        /* keep the symbolic analysis; the numeric values are garbage */
        return 0;
    }
    double *f = aug_malloc((size_t)m->cum.n * sizeof *f);
    if (!f) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    aug_cutmat_rhs(m, f);
    int rc = aug_refactor_solve(r, f, u, cm, e);
    free(f);
    times[3] = 1e3 * aug_now() - t3;
    return rc;
}

/* x = K_t^-1 rhs with the last factor (cholmod_solve) */
int aug_refactor_solve(aug_refactor *r, const double *rhs, double *x, cholmod_common *cm,
                       aug_err *e)
{
    cholmod_dense B = {0};
    B.nrow = (size_t)r->n, B.ncol = 1, B.d = B.nzmax = (size_t)r->n;
    B.x = (void *)rhs, B.xtype = CHOLMOD_REAL, B.dtype = CHOLMOD_DOUBLE;
    cholmod_dense *X = cholmod_solve(CHOLMOD_A, r->L, &B, cm);
    if (!X) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_solve failed");
    memcpy(x, X->x, (size_t)r->n * sizeof *x);
    cholmod_free_dense(&X, cm);
    return 0;
}
