/* The original system of a stream for the update solvers: K0 (KMAT which 0),
   f0 (FVEC kind 0) and its factor (FACT), read through their codecs and
   checked against each other and the DOF numbering before a solver is made. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"
#include "aug_solve.h"

int aug_sys0_init(aug_sys0 *s, aug_err *e)
{
    aug_err_clear(e);
    memset(s, 0, sizeof *s);
    s->cm = aug_malloc(sizeof *s->cm);
    if (!s->cm) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    aug_cholmod_start(s->cm);
    return 0;
}

void aug_sys0_free(aug_sys0 *s)
{
    aug_solver_free(s->solver);
    if (s->cm) {
        if (s->L0) cholmod_free_factor(&s->L0, s->cm);
        if (s->K0) cholmod_free_sparse(&s->K0, s->cm);
        cholmod_finish(s->cm);
    }
    free(s->cm);
    free(s->f0);
    memset(s, 0, sizeof *s);
}

/* KMAT (the first of kind K), FVEC (the first of kind 0), FACT; others ignored */
int aug_sys0_add(aug_sys0 *s, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    if (!memcmp(rec->type, "KMAT", 4)) {
        int which = -1;
        cholmod_sparse *A = aug_read_sparse(rec, &which, s->cm, e);
        if (!A) return e->code;
        if (which == AUG_MAT_K && !s->K0) s->K0 = A, s->k_index = rec->index;
        else cholmod_free_sparse(&A, s->cm);
    } else if (!memcmp(rec->type, "FVEC", 4)) {
        int32_t kind;
        int64_t n;
        double *v;
        if (aug_read_vector(rec, &kind, &n, &v, e)) return e->code;
        if (kind == 0 && !s->f0) s->f0 = v, s->nf0 = n, s->f_index = rec->index;
        else free(v);
    } else if (!memcmp(rec->type, "FACT", 4)) {
        if (s->L0) cholmod_free_factor(&s->L0, s->cm);
        s->L0 = aug_read_factor(rec, s->cm, e);
        if (!s->L0) return e->code;
        s->l_index = rec->index;
    }
    return 0;
}

/* ||K0 L0^-1 f0 - f0|| / ||f0||: a factor of another K shows as a large residual
   (a factor of K0 reaches about cond(K0) eps) */
static double factor_relres(aug_sys0 *s)
{
    int64_t n = (int64_t)s->K0->nrow;
    cholmod_dense *b = cholmod_allocate_dense((size_t)n, 1, (size_t)n, CHOLMOD_REAL, s->cm);
    if (!b) return NAN;
    memcpy(b->x, s->f0, (size_t)n * sizeof(double));
    cholmod_dense *x = cholmod_solve(CHOLMOD_A, s->L0, b, s->cm);
    double rr = NAN;
    if (x) {
        double one[2] = {1, 0}, mone[2] = {-1, 0};
        cholmod_dense *r = cholmod_copy_dense(b, s->cm);
        if (r && cholmod_sdmult(s->K0, 0, one, mone, x, r, s->cm)) {
            double nr = cholmod_norm_dense(r, 2, s->cm), nf = cholmod_norm_dense(b, 2, s->cm);
            rr = nf > 0 ? nr / nf : nr;
        }
        cholmod_free_dense(&r, s->cm);
    }
    cholmod_free_dense(&x, s->cm);
    cholmod_free_dense(&b, s->cm);
    return rr;
}

/* the solver of the first update record rec: K0, f0, the factor and a DOF
   numbering of nfree free DOFs (-1: none seen) must all be there and agree */
int aug_sys0_solver(aug_sys0 *s, int64_t nfree, const aug_solver_opts *o, const aug_rec *rec,
                    aug_err *e)
{
    aug_err_clear(e);
    if (s->solver) return 0;
    if (!s->K0 || !s->f0 || !s->L0 || nfree < 0)
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type,
                           "DOFM, KMAT (which 0), FVEC and FACT must come first");
    if (s->nf0 != (int64_t)s->K0->nrow || nfree != (int64_t)s->K0->nrow)
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "FVEC, DOFM and KMAT orders differ");
    if ((int64_t)s->L0->n != (int64_t)s->K0->nrow)
        return aug_err_set(e, AUG_EDATA, s->l_index, "FACT", "order %lld, KMAT (record %ld) %lld",
                           (long long)s->L0->n, s->k_index, (long long)s->K0->nrow);
    double rr = factor_relres(s);
    if (!(rr <= AUG_SYS0_TOL))
        return aug_err_set(e, AUG_EDATA, s->l_index, "FACT",
                           "does not factor the KMAT of record %ld (relres %.3g of its solve of "
                           "FVEC record %ld)", s->k_index, rr, s->f_index);
    s->solver = aug_solver_new(s->K0, s->f0, s->L0, o, s->cm, e);
    s->L0 = NULL; /* the solver owns it, also on failure */
    return s->solver ? 0 : e->code;
}
