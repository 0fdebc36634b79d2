/* Galerkin projection A_r = U' A U kept up to date along the incremental SVD
   (paper 004 eq. 3 and the split after eq. 8): G = U0' A U0 grows by one row
   and column per new U0 column and is rotated on compaction, never rebuilt. */
#include <cblas.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"
#include "aug_modal.h"

/* G(0:j, j) = G(j, 0:j) = U0(:, 0:j)' (A U0(:, j)): one sparse product and
   O(n j) */
static int grow(aug_galerkin *g, const aug_isvd *s, int j, cholmod_sparse *A, cholmod_common *cm,
                aug_err *e)
{
    int64_t n = s->n;
    int ld = g->qcap;
    if (aug_sym_mult(A, s->U0 + (size_t)j * n, g->Aw, cm))
        return aug_err_set(e, AUG_ENOMEM, -1, "", "galerkin: sparse product failed (CHOLMOD status %d)", cm->status);
    cblas_dgemv(CblasColMajor, CblasTrans, (int)n, j + 1, 1.0, s->U0, (int)n, g->Aw, 1, 0.0, g->G + (size_t)j * ld, 1);
    for (int i = 0; i < j; i++) g->G[j + (size_t)i * ld] = g->G[i + (size_t)j * ld];
    g->q = j + 1;
    return 0;
}

/* room for G (qcap x qcap) and the work arrays, after checking A */
static int alloc(aug_galerkin *g, const aug_isvd *s, const cholmod_sparse *A, aug_err *e)
{
    aug_err_clear(e);
    memset(g, 0, sizeof *g);
    if (!A || (int64_t)A->nrow != s->n || A->ncol != A->nrow || A->stype == 0)
        return aug_err_set(e, AUG_EUSAGE, -1, "", "galerkin: need a symmetric %lld x %lld matrix",
                           (long long)s->n, (long long)s->n);
    g->qcap = s->qcap;
    g->G = calloc((size_t)s->qcap * s->qcap, sizeof *g->G);
    g->Aw = malloc((size_t)s->n * sizeof *g->Aw);
    g->work = malloc((size_t)s->qcap * (s->rmax + 1) * sizeof *g->work);
    if (!g->G || !g->Aw || !g->work) {
        aug_galerkin_free(g);
        return aug_err_set(e, AUG_ENOMEM, -1, "", "galerkin: out of memory (qcap %d)", s->qcap);
    }
    return 0;
}

/* G = U0' A U0 for s's current U0 (q sparse products: the start and a
   re-wired sub-domain, not the frame-by-frame path) */
int aug_galerkin_init(aug_galerkin *g, const aug_isvd *s, cholmod_sparse *A, cholmod_common *cm,
                      aug_err *e)
{
    if (alloc(g, s, A, e)) return e->code;
    for (int j = 0; j < s->q; j++)
        if (grow(g, s, j, A, cm, e)) return e->code;
    return 0;
}

/* U0 = I: G = A, its stored triangle added to both (duplicates summed) */
int aug_galerkin_identity(aug_galerkin *g, const aug_isvd *s, const cholmod_sparse *A, aug_err *e)
{
    if (!s->unit_up || s->q != s->n) {
        memset(g, 0, sizeof *g);
        return aug_err_set(e, AUG_EUSAGE, -1, "", "galerkin: the basis of %d columns is not I_%lld", s->q,
                           (long long)s->n);
    }
    if (alloc(g, s, A, e)) return e->code;
    const int32_t *Ap = A->p, *Ai = A->i;
    const double *Ax = A->x;
    size_t ld = (size_t)g->qcap;
    for (int64_t j = 0; j < s->n; j++)
        for (int32_t k = Ap[j]; k < Ap[j + 1]; k++) {
            int64_t i = Ai[k];
            if ((A->stype > 0 && i > j) || (A->stype < 0 && i < j)) continue;
            g->G[i + j * ld] += Ax[k];
            if (i != j) g->G[j + i * ld] += Ax[k];
        }
    g->q = s->q;
    return 0;
}

void aug_galerkin_free(aug_galerkin *g)
{
    free(g->G);
    free(g->Aw);
    free(g->work);
    memset(g, 0, sizeof *g);
}

/* G <- Pc' G Pc on compaction (U0 <- U0 Pc), then the new column's row and
   column on growth */
int aug_galerkin_sync(aug_galerkin *g, const aug_isvd *s, cholmod_sparse *A, cholmod_common *cm,
                      aug_err *e)
{
    aug_err_clear(e);
    int ld = g->qcap;
    if (s->compacted) {
        if (g->q != s->qold)
            return aug_err_set(e, AUG_EUSAGE, -1, "", "galerkin: %d columns, the basis compacted %d", g->q, s->qold);
        int q = s->qold, r = s->rold;
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, q, r, q, 1.0, g->G, ld, s->Pc, ld, 0.0, g->work, ld);
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, r, q, 1.0, s->Pc, ld, g->work, ld, 0.0, g->G, ld);
        g->q = r;
    }
    if (g->q != s->q - s->grew)
        return aug_err_set(e, AUG_EUSAGE, -1, "", "galerkin: %d columns for a basis of %d (sync after every add)",
                           g->q, s->q);
    return s->grew ? grow(g, s, s->q - 1, A, cm, e) : 0;
}

/* Ar = Up' (G Up) (G itself when Up = I) */
void aug_galerkin_reduced(aug_galerkin *g, const aug_isvd *s, double *Ar)
{
    int ld = g->qcap, q = s->q, r = s->r;
    if (r == 0) return;
    if (s->unit_up) {
        for (int j = 0; j < r; j++) memcpy(Ar + (size_t)j * r, g->G + (size_t)j * ld, (size_t)r * sizeof *Ar);
        return;
    }
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, q, r, q, 1.0, g->G, ld, s->Up, ld, 0.0, g->work, ld);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, r, q, 1.0, s->Up, ld, g->work, ld, 0.0, Ar, r);
}
