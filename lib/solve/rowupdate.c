/* Baseline: CHOLMOD row deletions and additions (cholmod_rowdel/rowadd,
   [Davis-Hager 2005]) on a simplicial LDL' of blkdiag(K_t, I_spare); new DOFs
   take spare identity rows. */
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

struct aug_rowupd {
    cholmod_factor *L;   /* of order N = n + spare, Perm keeps spares last */
    int64_t N;
    int *pinv;
    int32_t *idx;
    double *val, *scr;
    int64_t ccap;
    unsigned char *pending;
    int64_t spare;
    cholmod_dense *B, *X, *Y, *E; /* solve workspaces, kept across steps */
};

static int set_pinv(aug_rowupd *r)
{
    free(r->pinv);
    free(r->pending);
    r->N = (int64_t)r->L->n;
    r->pinv = aug_malloc((size_t)r->N * sizeof *r->pinv);
    r->pending = aug_calloc((size_t)r->N, 1);
    if (!r->pinv || !r->pending) return -1;
    const int *P = r->L->Perm;
    for (int64_t k = 0; k < r->N; k++) r->pinv[P[k]] = (int)k;
    return 0;
}

/* a simplicial LDL' of blkdiag(K_t, I_spare) by CHOLMOD, with the ordering
   perm of the first np indices (the rest, spares among them, last in index
   order) or CHOLMOD's own when perm is NULL */
static cholmod_factor *padded_factor(const aug_cutmat *m, int64_t spare, const int32_t *perm,
                                     int64_t np, cholmod_common *cm)
{
    cholmod_sparse *K = aug_cutmat_sparse(m, spare, cm);
    if (!K) return NULL;
    int64_t N = (int64_t)K->nrow;
    int *P = NULL;
    if (perm) {
        P = aug_malloc((size_t)N * sizeof *P);
        if (!P) {
            cholmod_free_sparse(&K, cm);
            return NULL;
        }
        for (int64_t k = 0; k < N; k++) P[k] = k < np ? perm[k] : (int)k;
    }
    int nm = cm->nmethods, sn = cm->supernodal, ord = cm->method[0].ordering, post = cm->postorder;
    if (P) cm->nmethods = 1, cm->method[0].ordering = CHOLMOD_GIVEN, cm->postorder = 0;
    cm->supernodal = CHOLMOD_SIMPLICIAL;
    cholmod_factor *L = cholmod_analyze_p(K, P, NULL, 0, cm);
    int ok = L && cholmod_factorize(K, L, cm) && L->minor == L->n;
    cm->nmethods = nm, cm->supernodal = sn, cm->method[0].ordering = ord, cm->postorder = post;
    free(P);
    cholmod_free_sparse(&K, cm);
    if (!ok && L) cholmod_free_factor(&L, cm);
    return L;
}

/* the simplicial LDL' of blkdiag(K_t, I_spare) in the base's ordering (spares
   last), by padded_factor */
aug_rowupd *aug_rowupd_new(const aug_cutmat *m, const aug_base *b0, int64_t spare,
                           cholmod_common *cm, aug_err *e)
{
    aug_rowupd *r = aug_calloc(1, sizeof *r);
    if (!r) goto nomem;
    r->spare = spare > 0 ? spare : 1;
    r->L = padded_factor(m, r->spare, b0->perm, m->n0, cm);
    if (!r->L || set_pinv(r)) goto nomem;
    return r;
nomem:
    aug_rowupd_free(r, cm);
    aug_err_set(e, AUG_ENOMEM, -1, "FACT", "out of memory (rowupdate factor)");
    return NULL;
}

void aug_rowupd_free(aug_rowupd *r, cholmod_common *cm)
{
    if (!r) return;
    if (r->L) cholmod_free_factor(&r->L, cm);
    free(r->pinv), free(r->idx), free(r->val), free(r->scr), free(r->pending);
    cholmod_dense **w[] = {&r->B, &r->X, &r->Y, &r->E};
    for (int i = 0; i < 4; i++)
        if (*w[i]) cholmod_free_dense(w[i], cm);
    free(r);
}

/* out of spare rows: factor blkdiag(K_t, I) afresh, simplicial LDL', in the
   current ordering extended (the DOFs added since in their spare positions,
   new spares last: no re-ordering, as refactor) */
static int rebuild(aug_rowupd *r, const aug_cutmat *m, cholmod_common *cm)
{
    int64_t n = m->cum.n;
    int32_t *perm = aug_malloc((size_t)(n + 1) * sizeof *perm);
    if (!perm) return -1;
    /* the order of the current factor restricted to the DOFs of K_t, those
       beyond its spares last */
    int64_t k = 0;
    const int *P = r->L->Perm;
    for (int64_t q = 0; q < r->N; q++)
        if (P[q] < n) perm[k++] = P[q];
    for (int64_t i = r->N; i < n; i++) perm[k++] = (int32_t)i; /* beyond the spares */
    cholmod_factor *L = padded_factor(m, r->spare * 2, perm, n, cm);
    free(perm);
    if (!L) return -2;
    cholmod_free_factor(&r->L, cm);
    r->L = L;
    r->spare *= 2;
    return set_pinv(r) ? -1 : 1;
}

/* Row modifications of the step ([Davis-Hager 2005]): every row i of Hbar deleted
   (cholmod_rowdel: row and column of L D L' become e_i), then added back one by
   one as column i of K_t on the rows already present (cholmod_rowadd), so each
   intermediate matrix is K_t with identity rows; x = K_t^-1 f_t. Out of spare
   rows: re-factored with twice the spares. singular: a pivot D(k,k) <= 0. */
int aug_rowupd_step(aug_rowupd *r, const aug_cutmat *m, const aug_update *u, double *x,
                    double times[2], int64_t *rows, int *rebuilt, int *singular,
                    cholmod_common *cm, aug_err *e)
{
    double t0 = 1e3 * aug_now();
    int64_t n = m->cum.n, s = (int64_t)u->m + u->k, nold = n - u->k;
    *rebuilt = 0, *singular = 0, *rows = s;
    int64_t cmax = aug_cutmat_colmax(m);
    if (r->ccap < cmax || r->ccap < n) {
        int64_t c = cmax > n ? cmax : n;
        free(r->idx), free(r->val), free(r->scr);
        r->idx = aug_malloc((size_t)c * sizeof *r->idx);
        r->val = aug_malloc((size_t)c * sizeof *r->val);
        r->scr = aug_calloc((size_t)c, sizeof *r->scr);
        r->ccap = r->idx && r->val && r->scr ? c : 0;
        if (!r->ccap) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    }
    if (n > r->N) {
        int rc = rebuild(r, m, cm);
        if (rc == -2) {
            *singular = 1;
            times[0] = 1e3 * aug_now() - t0, times[1] = 0;
            return 0;
        }
        if (rc < 0) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (rebuild)");
        *rebuilt = 1;
    } else {
        /* delete every changed row, then add them back one by one, each with
           its couplings to the rows already present (the matrix stays
           K_t on the present rows plus identity: positive definite) */
        for (int64_t a = 0; a < s; a++) {
            int64_t i = a < u->m ? u->H[a] : nold + (a - u->m);
            r->pending[i] = 1;
            if (!cholmod_rowdel((size_t)r->pinv[i], NULL, r->L, cm))
                return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_rowdel failed (%d)", cm->status);
        }
        cholmod_sparse *R = cholmod_allocate_sparse((size_t)r->N, 1, (size_t)cmax, 1, 1, 0, CHOLMOD_REAL, cm);
        if (!R) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
        for (int64_t a = 0; a < s && !*singular; a++) {
            int64_t i = a < u->m ? u->H[a] : nold + (a - u->m);
            int64_t nz = aug_cutmat_column(m, i, r->idx, r->val, r->scr), k = 0;
            int *Ri = R->i;
            double *Rx = R->x;
            for (int64_t t = 0; t < nz; t++) {
                int64_t row = r->idx[t];
                if (row != i && r->pending[row]) continue;
                Ri[k] = r->pinv[row], Rx[k++] = r->val[t];
            }
            for (int64_t q = 1; q < k; q++) { /* sort by permuted row */
                int ti = Ri[q];
                double tv = Rx[q];
                int64_t z = q - 1;
                while (z >= 0 && Ri[z] > ti) Ri[z + 1] = Ri[z], Rx[z + 1] = Rx[z], z--;
                Ri[z + 1] = ti, Rx[z + 1] = tv;
            }
            ((int *)R->p)[1] = (int)k;
            r->pending[i] = 0;
            if (!cholmod_rowadd((size_t)r->pinv[i], R, r->L, cm) || cm->status == CHOLMOD_NOT_POSDEF ||
                r->L->minor < r->L->n ||
                !(((double *)r->L->x)[((int *)r->L->p)[r->pinv[i]]] > 0))
                *singular = 1; /* D(k,k) <= 0: K_t is not positive definite */
        }
        for (int64_t a = 0; a < s; a++) r->pending[a < u->m ? u->H[a] : nold + (a - u->m)] = 0;
        cholmod_free_sparse(&R, cm);
    }
    double t1 = 1e3 * aug_now();
    times[0] = t1 - t0, times[1] = 0;
    if (*singular) return 0;
    double *f = aug_malloc((size_t)n * sizeof *f);
    if (!f) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    aug_cutmat_rhs(m, f);
    int rc = aug_rowupd_solve(r, n, f, x, cm, e);
    free(f);
    times[1] = 1e3 * aug_now() - t1;
    return rc;
}

/* x = K_t^-1 rhs through blkdiag(K_t, I_spare) (the spare rows of rhs are 0),
   cholmod_solve2 with its workspaces kept */
int aug_rowupd_solve(aug_rowupd *r, int64_t n, const double *rhs, double *x, cholmod_common *cm,
                     aug_err *e)
{
    if (r->B && r->B->nrow != (size_t)r->N) cholmod_free_dense(&r->B, cm);
    if (!r->B && !(r->B = cholmod_zeros((size_t)r->N, 1, CHOLMOD_REAL, cm)))
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    double *b = r->B->x;
    memcpy(b, rhs, (size_t)n * sizeof *rhs);
    memset(b + n, 0, (size_t)(r->N - n) * sizeof *b); /* spare rows: 0 */
    if (!cholmod_solve2(CHOLMOD_A, r->L, r->B, NULL, &r->X, NULL, &r->Y, &r->E, cm))
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_solve failed");
    memcpy(x, r->X->x, (size_t)n * sizeof *x);
    return 0;
}
