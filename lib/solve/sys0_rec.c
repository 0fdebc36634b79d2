/* The original system of a stream for the update solvers: K0 (KMAT which 0),
   f0 (FVEC kind 0) and its factor (FACT), read through their codecs and
   checked against each other and the DOF numbering before a solver is made. */
#include <float.h>
#include <math.h>
#include <stdio.h>
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
        if (s->A0) cholmod_free_sparse(&s->A0, s->cm);
        for (int i = 0; i < 2; i++)
            if (s->Mk[i]) cholmod_free_sparse(&s->Mk[i], s->cm);
        cholmod_finish(s->cm);
    }
    free(s->cm);
    free(s->f0);
    memset(s, 0, sizeof *s);
}

/* KMAT (the first of each kind), FVEC (the first of kind 0), FACT, DYNP;
   others ignored */
int aug_sys0_add(aug_sys0 *s, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    if (!memcmp(rec->type, "KMAT", 4)) {
        int which = -1;
        cholmod_sparse *A = aug_read_sparse(rec, &which, s->cm, e);
        if (!A) return e->code;
        if (which == AUG_MAT_K && !s->K0) s->K0 = A, s->k_index = rec->index;
        else if (which == AUG_MAT_A && !s->A0) s->A0 = A, s->a_index = rec->index;
        else if ((which == AUG_MAT_M || which == AUG_MAT_ML) && !s->Mk[which - 1]) s->Mk[which - 1] = A;
        else cholmod_free_sparse(&A, s->cm);
    } else if (!memcmp(rec->type, "DYNP", 4)) {
        if (aug_read_dynp(rec, &s->dyn, e)) return e->code;
        s->dynamic = 1;
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

/* ||K L0^-1 f0 - f0|| / ||f0||: a factor of another K shows as a large residual
   (a factor of K reaches about cond(K) eps) */
static double factor_relres(aug_sys0 *s, cholmod_sparse *K)
{
    int64_t n = (int64_t)K->nrow;
    cholmod_dense *b = cholmod_allocate_dense((size_t)n, 1, (size_t)n, CHOLMOD_REAL, s->cm);
    if (!b) return NAN;
    memcpy(b->x, s->f0, (size_t)n * sizeof(double));
    cholmod_dense *x = cholmod_solve(CHOLMOD_A, s->L0, b, s->cm);
    double rr = NAN;
    if (x) {
        double one[2] = {1, 0}, mone[2] = {-1, 0};
        cholmod_dense *r = cholmod_copy_dense(b, s->cm);
        if (r && cholmod_sdmult(K, 0, one, mone, x, r, s->cm)) {
            double nr = cholmod_norm_dense(r, 2, s->cm), nf = cholmod_norm_dense(b, 2, s->cm);
            rr = nf > 0 ? nr / nf : nr;
        }
        cholmod_free_dense(&r, s->cm);
    }
    cholmod_free_dense(&x, s->cm);
    cholmod_free_dense(&b, s->cm);
    return rr;
}

/* ||A - (cM M + cK K)||_inf / (|cM| ||M||_inf + |cK| ||K||_inf): formats
   6.6, A assembled as cM M + cK K (a stream whose DYNP h was changed, cM and
   cK with it, integrated with the A of the old h); NaN when CHOLMOD fails */
static double a_off(cholmod_sparse *A, cholmod_sparse *M, cholmod_sparse *K, double cM, double cK,
                    cholmod_common *cm)
{
    double one[2] = {1, 0}, mone[2] = {-1, 0}, a[2] = {cM, 0}, b[2] = {cK, 0}, r = NAN;
    cholmod_sparse *C = cholmod_add(M, K, a, b, 1, 1, cm), *D = C ? cholmod_add(A, C, one, mone, 1, 1, cm) : NULL;
    if (D) {
        double den = fabs(cM) * cholmod_norm_sparse(M, 0, cm) + fabs(cK) * cholmod_norm_sparse(K, 0, cm);
        r = cholmod_norm_sparse(D, 0, cm) / (den > 0 ? den : 1);
    }
    if (C) cholmod_free_sparse(&C, cm);
    if (D) cholmod_free_sparse(&D, cm);
    return r;
}

/* the solver of the first update record rec: K0, f0, the factor and a DOF
   numbering of nfree free DOFs (-1: none seen) must all be there and agree */
int aug_sys0_solver(aug_sys0 *s, int64_t nfree, const aug_solver_opts *o, const aug_rec *rec,
                    aug_err *e)
{
    aug_err_clear(e);
    if (s->solver) return 0;
    if (s->K0 && nfree < 0) /* formats/stream.md 6.1: the mesh's own numbering is no DOFM */
        return aug_err_set(e, AUG_EDATA, s->k_index, "KMAT", "no DOFM gives the free DOFs it is over");
    if (!s->K0 || !s->f0 || !s->L0 || nfree < 0)
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type,
                           "DOFM, KMAT (which 0), FVEC and FACT must come first");
    if (s->dynamic && (!s->A0 || !s->Mk[s->dyn.mass - 1]))
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type,
                           "a dynamic stream (DYNP) needs KMAT which 3 (A) and which %d (M) first",
                           s->dyn.mass);
    if (!s->dynamic && s->A0)
        return aug_err_set(e, AUG_EDATA, s->a_index, "KMAT", "an effective matrix A without DYNP");
    cholmod_sparse *K = s->dynamic ? s->A0 : s->K0, *M = s->dynamic ? s->Mk[s->dyn.mass - 1] : NULL;
    long ki = s->dynamic ? s->a_index : s->k_index;
    if (s->nf0 != (int64_t)K->nrow || nfree != (int64_t)K->nrow || s->K0->nrow != K->nrow ||
        (M && M->nrow != K->nrow))
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "FVEC, DOFM and KMAT orders differ");
    if (M) {
        double d = a_off(s->A0, M, s->K0, s->dyn.cM, s->dyn.cK, s->cm);
        if (!(d <= 1e-10))
            return aug_err_set(e, AUG_EDATA, s->a_index, "KMAT",
                               "A is not cM M + cK K of DYNP (cM %.17g, cK %.17g): off by %.3g of its norm",
                               s->dyn.cM, s->dyn.cK, d);
    }
    if ((int64_t)s->L0->n != (int64_t)K->nrow)
        return aug_err_set(e, AUG_EDATA, s->l_index, "FACT", "order %lld, KMAT (record %ld) %lld",
                           (long long)s->L0->n, ki, (long long)K->nrow);
    /* a factor of another K leaves a relres of its order (2K: 0.5); a factor
       of K about cond(K) eps, which passes AUG_SYS0_TOL on stiff jumps (the
       cube, E 1e10 below 1: cond 2e12, relres 4.3e-4): above it, cond(K)
       is estimated (cond.c, through this factor) and the relres may reach
       AUG_SYS0_COND cond eps, at most 1e-2 (factor(1) refuses K past
       cond 4.5e13 anyway) */
    double rr = factor_relres(s, K), cond = NAN;
    if (!(rr <= AUG_SYS0_TOL) && isfinite(rr)) {
        aug_cond c;
        aug_err ce;
        if (!aug_cond_estimate(K, s->L0, 1e-2, &c, s->cm, &ce)) cond = c.cond;
    }
    double lim = fmax(AUG_SYS0_TOL, fmin(AUG_SYS0_COND * cond * DBL_EPSILON, 1e-2));
    if (!(rr <= lim)) {
        char allows[64] = "";
        if (!isnan(cond)) snprintf(allows, sizeof allows, "; cond %.3g allows %.3g", cond, lim);
        return aug_err_set(e, AUG_EDATA, s->l_index, "FACT",
                           "does not factor the KMAT of record %ld (relres %.3g of its solve of "
                           "FVEC record %ld%s)", ki, rr, s->f_index, allows);
    }
    aug_solver_opts so = *o;
    so.dynamic = s->dynamic;
    /* a direct step is failed above max(fail_tol, AUG_SYS0_COND x the base
       solve's relres), at most 1e-2, unless --fail-tol was given: the base's
       rounding says what the scene's conditioning allows (the cube, E 1e8
       below 1: base 2.9e-6) */
    if (!o->fail_tol_fixed) so.fail_tol = fmax(o->fail_tol, fmin(AUG_SYS0_COND * rr, 1e-2));
    s->solver = aug_solver_new(K, s->f0, s->L0, &so, s->cm, e);
    s->L0 = NULL; /* the solver owns it, also on failure */
    return s->solver ? 0 : e->code;
}
