/* Baseline: CHOLMOD re-factorization of the cut matrix every step, as an
   expert configures it: the fill-reducing ordering of K0 extended to the new
   DOFs (no re-ordering), the factor's memory kept across steps, numeric-only
   re-factorization whenever the pattern holds. */
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

void aug_refactor_init(aug_refactor *r) { memset(r, 0, sizeof *r); }

void aug_refactor_free(aug_refactor *r, cholmod_common *cm)
{
    if (r->L) cholmod_free_factor(&r->L, cm);
    free(r->Kp);
    free(r->Ki);
    free(r->perm);
    cholmod_dense **w[] = {&r->X, &r->Y, &r->E};
    for (int i = 0; i < 3; i++)
        if (*w[i]) cholmod_free_dense(w[i], cm);
    memset(r, 0, sizeof *r);
}

int aug_refactor_order(aug_refactor *r, const int32_t *perm, int64_t n)
{
    int *p = aug_malloc((size_t)(n + 1) * sizeof *p);
    if (!p) return -1;
    for (int64_t k = 0; k < n; k++) p[k] = perm[k];
    free(r->perm);
    r->perm = p, r->nperm = n;
    return 0;
}

/* 1 when K has the pattern of the last analysis (its symbolic factor is reused) */
static int same_pattern(const aug_refactor *r, const cholmod_sparse *K)
{
    const int *Kp = K->p;
    if (!r->L || r->n != (int64_t)K->ncol || r->nnz != Kp[K->ncol]) return 0;
    return !memcmp(r->Kp, Kp, (size_t)(r->n + 1) * sizeof *Kp) &&
           !memcmp(r->Ki, K->i, (size_t)r->nnz * sizeof(int));
}

/* the pattern of K kept for same_pattern, in buffers that only grow */
static int keep_pattern(aug_refactor *r, const cholmod_sparse *K)
{
    const int *Kp = K->p;
    int64_t n = (int64_t)K->ncol, nnz = Kp[K->ncol];
    if (n + 1 > r->pcap) {
        free(r->Kp);
        r->pcap = 2 * (n + 1);
        if (!(r->Kp = aug_malloc((size_t)r->pcap * sizeof *r->Kp))) return r->pcap = 0, -1;
    }
    if (nnz + 1 > r->icap) {
        free(r->Ki);
        r->icap = 2 * (nnz + 1);
        if (!(r->Ki = aug_malloc((size_t)r->icap * sizeof *r->Ki))) return r->icap = 0, -1;
    }
    r->n = n, r->nnz = nnz;
    memcpy(r->Kp, Kp, (size_t)(n + 1) * sizeof *Kp);
    memcpy(r->Ki, K->i, (size_t)nnz * sizeof(int));
    return 0;
}

static int cmp_key(const void *a, const void *b)
{
    const int64_t *x = a, *y = b;
    return (x[0] > y[0]) - (x[0] < y[0]);
}

/* The ordering of the last analysis (r->perm, n_prev entries, postordered)
   extended to the DOFs added since: each new DOF i takes the place just
   after its latest-ordered neighbour in K (upper triangle: its neighbours of
   lower index, the old DOFs and the new ones already placed), so that it is
   eliminated after all its neighbours but before the rest of the separators
   above them; a new DOF without neighbours goes last. On the brick N=12, 64
   one-node steps: nnz(L) +4.5% (new DOFs last: +6.1%, just before the
   earliest neighbour: +17%). Keys: 4 * position for old DOFs, the latest
   neighbour's key + 1 for a new one, ties by index. */
static int extend_order(aug_refactor *r, const cholmod_sparse *K)
{
    int64_t n = (int64_t)K->ncol, n0 = r->nperm;
    if (n <= n0) return 0;
    int64_t *key = aug_malloc((size_t)(n + 1) * sizeof *key);
    int *p = aug_malloc((size_t)(n + 1) * sizeof *p);
    if (!key || !p) {
        free(key), free(p);
        return -1;
    }
    for (int64_t k = 0; k < n0; k++) key[r->perm[k]] = 4 * k;
    const int *Kp = K->p, *Ki = K->i;
    for (int64_t i = n0; i < n; i++) {
        int64_t best = -1;
        for (int t = Kp[i]; t < Kp[i + 1]; t++)
            if (Ki[t] < i && key[Ki[t]] + 1 > best) best = key[Ki[t]] + 1;
        key[i] = best < 0 ? 4 * n : best;
    }
    /* sorted on (key, index), packed into one integer */
    int64_t (*pr)[2] = aug_malloc((size_t)(n + 1) * sizeof *pr);
    if (!pr) {
        free(key), free(p);
        return -1;
    }
    for (int64_t i = 0; i < n; i++) pr[i][0] = key[i] * (n + 1) + i, pr[i][1] = i;
    qsort(pr, (size_t)n, sizeof *pr, cmp_key);
    for (int64_t k = 0; k < n; k++) p[k] = (int)pr[k][1];
    free(pr), free(key);
    free(r->perm);
    r->perm = p, r->nperm = n;
    return 0;
}

/* P K P' analysed with the ordering r->perm as given (CHOLMOD_GIVEN,
   postordered); NULL on failure */
static cholmod_factor *analyze_given(aug_refactor *r, cholmod_sparse *K, cholmod_common *cm)
{
    int nm = cm->nmethods, ord = cm->method[0].ordering;
    cm->nmethods = 1, cm->method[0].ordering = CHOLMOD_GIVEN;
    cholmod_factor *L = cholmod_analyze_p(K, r->perm, NULL, 0, cm);
    cm->nmethods = nm, cm->method[0].ordering = ord;
    return L;
}

/* The symbolic factor of K: with an ordering (aug_refactor_order) the
   extended one (extend_order), re-ordered by CHOLMOD (cholmod_analyze, its
   ordering then extended in turn) only when the fill nnz(L) exceeds
   AUG_REFACTOR_FILL times that of the last ordering CHOLMOD chose; without
   one, cholmod_analyze every time (a fresh analysis). A re-ordering for a
   base of the augmented methods (r->step_cost: auto's re-factorization)
   picks AMD or METIS by the cost of an AMPS step (aug_analyze_steps), the
   refactor baseline CHOLMOD's least fill. */
static cholmod_factor *analyze(aug_refactor *r, cholmod_sparse *K, cholmod_common *cm)
{
    r->reordered = 0;
    if (r->perm) {
        if (extend_order(r, K)) return NULL;
        cholmod_factor *L = analyze_given(r, K, cm);
        if (!L) return NULL;
        if (r->lnz_ref == 0) r->lnz_ref = cm->lnz;
        r->lnz = cm->lnz;
        if (!(cm->lnz > AUG_REFACTOR_FILL * r->lnz_ref)) return L;
        cholmod_free_factor(&L, cm);
    }
    aug_err e;
    cholmod_factor *L = r->step_cost ? aug_analyze_steps(K, AUG_ORDER_AUTO, cm, &e) : cholmod_analyze(K, cm);
    if (!L) return NULL;
    r->lnz = r->lnz_ref = cm->lnz;
    if (r->perm) {
        r->reordered = 1;
        const int *P = L->Perm;
        for (int64_t k = 0; k < (int64_t)L->n; k++) r->perm[k] = P[k];
    }
    return L;
}

/* The numeric storage of the last factor handed to the new symbolic one L
   when it fits, else a new one with AUG_REFACTOR_SLACK times the room (the
   memory kept across steps: no allocation, no first-touch page faults of a
   fresh factor on the steps after). CHOLMOD takes a supernodal symbolic
   factor with xtype REAL and x of xsize >= Px[nsuper] entries as numeric and
   refactors it in place (cholmod_super_numeric); simplicial factors are left
   to CHOLMOD. Returns 1 when the old storage was kept, 0 otherwise. */
#define AUG_REFACTOR_SLACK 1.25
static int reuse_values(cholmod_factor *L, cholmod_factor *old, cholmod_common *cm)
{
    if (!L->is_super) return 0;
    if (old && old->is_super && old->xtype == CHOLMOD_REAL && old->x && old->xsize >= L->xsize) {
        L->x = old->x, L->xsize = old->xsize;
        old->x = NULL, old->xtype = CHOLMOD_PATTERN, old->xsize = 0;
    } else {
        size_t xs = (size_t)(AUG_REFACTOR_SLACK * (double)L->xsize) + 1;
        double *x = cholmod_malloc(xs, sizeof *x, cm);
        if (!x) return 0; /* CHOLMOD allocates its own */
        L->x = x, L->xsize = xs;
        old = NULL;
    }
    L->xtype = CHOLMOD_REAL, L->dtype = CHOLMOD_DOUBLE;
    L->is_ll = 1; /* CHOLMOD's supernodal factors are L L' */
    return old != NULL;
}

/* The numeric factor of K in r->L: a new symbolic analysis (analyze) only
   when the pattern changed, its storage kept (reuse_values),
   cholmod_factorize every step; 1 when K is not positive definite (the
   symbolic analysis kept, the values garbage), 0, or an error code. times[1]
   analyze, times[2] factor. */
static int factor_step(aug_refactor *r, cholmod_sparse *K, double times[4], cholmod_common *cm,
                       aug_err *e)
{
    double t1 = 1e3 * aug_now();
    r->analyzed = r->reordered = 0, r->kept = 1;
    if (!same_pattern(r, K)) {
        cholmod_factor *L = analyze(r, K, cm);
        if (!L || keep_pattern(r, K)) {
            if (L) cholmod_free_factor(&L, cm);
            r->n = 0;
            return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_analyze failed");
        }
        r->kept = reuse_values(L, r->L, cm);
        if (r->L) cholmod_free_factor(&r->L, cm);
        r->L = L;
        r->analyzed = 1;
    }
    double t2 = 1e3 * aug_now();
    int nb = r->nblas > 1 ? aug_blas_threads(r->nblas) : 0;
    int ok = cholmod_factorize(K, r->L, cm);
    if (nb) aug_blas_threads(nb);
    times[1] = t2 - t1, times[2] = 1e3 * aug_now() - t2;
    if (!ok && cm->status != CHOLMOD_NOT_POSDEF)
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_factorize failed (%d)", cm->status);
    return cm->status == CHOLMOD_NOT_POSDEF || r->L->minor < r->L->n;
}

/* P K_t P' = L D L' (or L L') by CHOLMOD ([CHOLMOD]) through factor_step,
   x = K_t^-1 f_t; not positive definite: singular = 1 and x untouched */
int aug_refactor_step(aug_refactor *r, const aug_cutmat *m, double *u, double times[4],
                      cholmod_common *cm, aug_err *e)
{
    double t0 = 1e3 * aug_now();
    r->singular = 0;
    times[3] = 0;
    cholmod_sparse *K = aug_cutmat_sparse(m, 0, cm);
    if (!K) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (K_t)");
    times[0] = 1e3 * aug_now() - t0;
    int rc = factor_step(r, K, times, cm, e);
    cholmod_free_sparse(&K, cm);
    if (rc < 0 || rc > 1) return rc;
    if (rc == 1) { /* the symbolic analysis kept, the numeric values garbage */
        r->singular = 1;
        return 0;
    }
    double t3 = 1e3 * aug_now();
    double *f = aug_malloc((size_t)m->cum.n * sizeof *f);
    if (!f) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    aug_cutmat_rhs(m, f);
    rc = aug_refactor_solve(r, f, u, cm, e);
    free(f);
    times[3] = 1e3 * aug_now() - t3;
    return rc;
}

/* x = K_t^-1 rhs with the last factor (cholmod_solve2, its workspaces kept) */
int aug_refactor_solve(aug_refactor *r, const double *rhs, double *x, cholmod_common *cm,
                       aug_err *e)
{
    cholmod_dense B = {0};
    B.nrow = (size_t)r->n, B.ncol = 1, B.d = B.nzmax = (size_t)r->n;
    B.x = (void *)rhs, B.xtype = CHOLMOD_REAL, B.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_solve2(CHOLMOD_A, r->L, &B, NULL, &r->X, NULL, &r->Y, &r->E, cm))
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_solve failed");
    memcpy(x, r->X->x, (size_t)r->n * sizeof *x);
    return 0;
}

/* The step of aug_refactor_step (factor_step: the extended ordering, the
   memory kept, numeric-only when the pattern holds) whose factor is then
   moved into a new base (aug_base_new: L as its supernodal Ls, the simplicial
   LDL' built beside it, a_b = K_t^-1 f_t): the synchronous re-factorization
   of --method auto (paper 000 sec. 3.6 done in the foreground), as dear as a
   refactor step. The base being replaced (old, when only the caller holds
   it) hands its supernodal factor back first: its symbolic analysis when r
   made it (the pattern check of factor_step holds), else its storage; old
   keeps its simplicial LDL' and solves without Ls from then on (it is
   released on success, and stays the base only when K_t is singular). */
aug_base *aug_refactor_take_base(aug_refactor *r, const aug_cutmat *m, int32_t step, aug_base *old,
                                 double times[4], cholmod_common *cm, aug_err *e)
{
    double t0 = 1e3 * aug_now();
    r->singular = 0;
    if (old && old->refs == 1 && old->Ls && !r->L) {
        if (old != r->given) r->n = 0; /* not r's analysis: only its storage */
        r->L = old->Ls, old->Ls = NULL;
        free(old->sqrtd), free(old->super_of);
        old->sqrtd = NULL, old->super_of = NULL;
    }
    r->given = NULL;
    cholmod_sparse *K = aug_cutmat_sparse(m, 0, cm);
    double *f = aug_malloc((size_t)(m->cum.n + 1) * sizeof *f);
    if (!K || !f) {
        if (K) cholmod_free_sparse(&K, cm);
        free(f);
        aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (K_t)");
        return NULL;
    }
    aug_cutmat_rhs(m, f);
    times[0] = 1e3 * aug_now() - t0;
    int rc = factor_step(r, K, times, cm, e);
    double t3 = 1e3 * aug_now();
    aug_base *b = NULL;
    if (rc == 1) {
        r->singular = 1;
    } else if (rc == 0) {
        cholmod_factor *L = r->L;
        r->L = NULL; /* moved: aug_base_new takes it, or frees it on failure */
        if ((b = aug_base_new(L, K, f, step, cm, e))) r->given = b;
        else if (e->code == AUG_ESINGULAR) r->singular = 1;
        if (!b) r->n = 0;
    }
    cholmod_free_sparse(&K, cm);
    free(f);
    times[3] = 1e3 * aug_now() - t3;
    return b;
}
