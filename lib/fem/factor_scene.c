/* factor's job on the intact scene: assemble K (and M) over the free DOFs, order
   and factor K = L D L' with CHOLMOD (dynamics: the integrator's A = cM M + cK K),
   solve K a = f, estimate cond(K), and write DOFM, (DYNP,) KMAT, FVEC, FACT,
   cOND, the step-0 fELD and rEAC (dynamics: fRAM frame 0, at rest), sTAt and
   tIMe. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

void aug_factored_free(aug_factored *r, cholmod_common *cm)
{
    cholmod_free_sparse(&r->K, cm);
    cholmod_free_sparse(&r->M, cm);
    cholmod_free_sparse(&r->ML, cm);
    cholmod_free_sparse(&r->A, cm);
    cholmod_free_factor(&r->L, cm);
    free(r->map);
    free(r->f);
    free(r->a);
    memset(r, 0, sizeof *r);
}

/* K a = f of the intact mesh, timed per phase (paper 001 sec. 4: the base factor) */
int aug_factored_compute(aug_factored *r, const aug_mesh *m, const aug_factor_opts *o,
                         cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    memset(r, 0, sizeof *r);
    if (aug_mesh_validate(m, e) || (!o->dyn && aug_check_support(m, e))) return e->code;
    for (int32_t i = 0; o->dyn && i < m->nmat; i++)
        if (!(m->mats[i].rho > 0))
            return aug_err_set(e, AUG_EDATA, -1, "MATL", "material %d has density %g: no mass for "
                               "--dynamic", (int)i, m->mats[i].rho);
    r->map = aug_malloc((size_t)(m->nn * m->dim) * sizeof *r->map + 1);
    if (!r->map) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    r->nfree = aug_dofmap(m, r->map);
    if (r->nfree == 0) return aug_err_set(e, AUG_EDATA, -1, "", "every DOF is constrained: nothing to solve");
    double t0 = aug_now();
    if (!(r->K = aug_assemble(m, r->map, r->nfree, AUG_MAT_K, cm, e))) return e->code;
    r->f = aug_malloc((size_t)r->nfree * sizeof *r->f);
    r->a = aug_malloc((size_t)r->nfree * sizeof *r->a);
    if (!r->f || !r->a) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    if (aug_load_vector(m, r->map, r->nfree, r->f, e)) return e->code;
    int wantM = o->mass || (o->dyn && o->dyn->mass == AUG_MAT_M);
    int wantML = o->lumped || (o->dyn && o->dyn->mass == AUG_MAT_ML);
    if (wantM && !(r->M = aug_assemble(m, r->map, r->nfree, AUG_MAT_M, cm, e))) return e->code;
    if (wantML && !(r->ML = aug_assemble(m, r->map, r->nfree, AUG_MAT_ML, cm, e))) return e->code;
    cholmod_sparse *F = r->K;  /* the matrix factored */
    if (o->dyn) {
        double cM[2] = {o->dyn->cM, 0}, cK[2] = {o->dyn->cK, 0};
        r->A = cholmod_add(o->dyn->mass == AUG_MAT_M ? r->M : r->ML, r->K, cM, cK, 1, 1, cm);
        if (!r->A) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        F = r->A;
    }
    r->t_asm = aug_now() - t0;
    aug_factor_options(cm, o->ordering, o->simplicial);
    t0 = aug_now();
    if (!(r->L = aug_analyze_steps(F, o->ordering, cm, e))) return e->code;
    r->t_an = aug_now() - t0;
    r->lnz = cm->lnz;
    r->fl = cm->fl;
    t0 = aug_now();
    if (aug_factorize(F, r->L, m, r->map, cm, e) ||
        (!o->dyn && m->etype == AUG_MEM3 && aug_membrane_flex(F, r->L, m, r->map, cm, e)))
        return e->code;
    r->t_fac = aug_now() - t0;
    t0 = aug_now();
    if (aug_solve(F, r->L, r->f, r->a, &r->relres, cm, e)) return e->code;
    r->t_sol = aug_now() - t0;
    /* loads that overflow the solve (|f| ~ 1e306) give no field, not an infinite one */
    for (int64_t i = 0; i < r->nfree; i++)
        if (!isfinite(r->a[i]) || !isfinite(r->relres))
            return aug_err_set(e, AUG_EDATA, -1, "LOAD", "the solution of K a = f is not finite "
                               "(loads or material values out of range)");
    /* a factorization CHOLMOD calls positive definite whose solve leaves a
       relres above solve-aug's --fail-tol default may have met a
       numerically singular K: a mechanism the support checks do not see
       (two tets hinged on a shared edge: cond 7e16, relres 1.4, the field
       1e16). But a backward-stable solve leaves a relres up to about
       cond(K) eps, and a stiff jump is not singular (the cube, E 1e8 below
       1 loaded on top: cond 2e10, relres 2.9e-6): K is numerically singular
       when its condition number, estimated here (cond.c), passes
       1 / (100 eps) = 4.5e13 (fewer than two digits left in the field). */
    int suspect = !(r->relres <= 1e-6);
    if (!o->no_cond || suspect) {
        t0 = aug_now();
        if (aug_cond_estimate(F, r->L, o->no_cond ? 1e-2 : o->cond_tol, &r->cond, cm, e)) return e->code;
        r->t_cond = aug_now() - t0;
    }
    if (suspect && (!(r->cond.lambda_min > 0) || !(r->cond.cond < 0.01 / DBL_EPSILON)))
        return aug_err_set(e, AUG_EDATA, -1, "KMAT", "K is numerically singular: the solve of K a = f "
                           "leaves relres %.3g > 1e-6 and cond(K) is %.3g > 4.5e13 (a mechanism, "
                           "pieces hinged on an edge or a node, or a stiffness jump past double "
                           "precision?)", r->relres, r->cond.cond);
    if (o->modes) {
        cholmod_sparse *M = o->dyn ? (o->dyn->mass == AUG_MAT_M ? r->M : r->ML) : r->M ? r->M : r->ML;
        if (!M) return aug_err_set(e, AUG_EUSAGE, -1, "", "--modes needs a mass matrix");
        /* a dynamic scene need not be held: its free rigid motions are
           modes with lambda = 0, deflated (modes.c) */
        double *R = NULL;
        int64_t k = o->dyn ? aug_free_rigid_modes(m, r->map, r->nfree, o->modes, &R) : 0;
        if (k < 0) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        int mrc = o->dyn ? aug_modes_shifted(r->K, M, o->modes, o->cond_tol * 1e-4, R, (int)k, &r->modes, NULL, cm, e)
                         : aug_modes_lowest(M, r->L, 0.0, 1.0, o->modes, o->cond_tol * 1e-4, R, (int)k, &r->modes, cm, e);
        free(R);
        if (mrc) return e->code;
    }
    return 0;
}

/* rEAC of step 0: the reactions of the field u on the whole intact mesh */
static int write_reactions(aug_writer *w, const aug_mesh *m, const double *u, aug_err *e)
{
    int32_t *el;
    int64_t nel = aug_react_elements(m, &el);
    if (nel < 0) return aug_err_set(e, AUG_ENOMEM, aug_writer_count(w), "rEAC", "out of memory");
    aug_reaction q;
    memset(&q, 0, sizeof q);
    int rc = aug_reaction_compute(&q, m, el, nel, u, NULL, e) || aug_write_reaction(w, 0, &q, e);
    free(el);
    aug_reaction_free(&q);
    return rc ? e->code : 0;
}

int aug_factored_write(aug_writer *w, const aug_factored *r, const aug_mesh *m,
                       const aug_factor_opts *o, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    double t0 = aug_now();
    if (aug_write_dofmap(w, m, r->map, r->nfree, e) || (o->dyn && aug_write_dynp(w, o->dyn, e)) ||
        aug_write_sparse(w, AUG_MAT_K, r->K, e) ||
        (r->M && aug_write_sparse(w, AUG_MAT_M, r->M, e)) ||
        (r->ML && aug_write_sparse(w, AUG_MAT_ML, r->ML, e)) ||
        (r->A && aug_write_sparse(w, AUG_MAT_A, r->A, e)) ||
        aug_write_vector(w, "FVEC", AUG_NOSTEP, 0, r->f, r->nfree, e) ||
        (!o->no_factor && aug_write_factor(w, r->L, cm, e)))
        return e->code;
    aug_kv k;
    if (!o->no_cond) {
        aug_kv_init(&k, "arpack-lanczos");
        aug_kv_set(&k, "lambda_max", r->cond.lambda_max);
        aug_kv_set(&k, "lambda_min", r->cond.lambda_min);
        aug_kv_set(&k, "cond", r->cond.cond);
        aug_kv_set(&k, "iters", r->cond.iters_max + r->cond.iters_min);
        aug_kv_set(&k, "iters_max", r->cond.iters_max);
        aug_kv_set(&k, "iters_min", r->cond.iters_min);
        aug_kv_set(&k, "tol", o->cond_tol);
        aug_kv_set(&k, "converged", r->cond.converged);
        if (aug_write_kv(w, "cOND", AUG_NOSTEP, &k, e)) return e->code;
    }
    if (o->modes) { /* tag modes: the lowest eigenvalues of K x = lambda M x and their periods */
        aug_kv_init(&k, "modes");
        aug_kv_set(&k, "nev", r->modes.nev);
        aug_kv_set(&k, "converged", r->modes.converged);
        aug_kv_set(&k, "iters", r->modes.iters);
        char key[32]; /* "period_" and any int */
        for (int i = 0; i < r->modes.nev; i++) {
            double l = r->modes.lambda[i];
            snprintf(key, sizeof key, "lambda_%d", i + 1);
            aug_kv_set(&k, key, l);
            /* none for a free rigid motion (lambda 0: no finite period) or
               an unconverged lambda: left out, not written as inf or nan */
            snprintf(key, sizeof key, "period_%d", i + 1);
            if (l > 0) aug_kv_set(&k, key, 2 * M_PI / sqrt(l));
        }
        if (aug_write_kv(w, "cOND", AUG_NOSTEP, &k, e)) return e->code;
    }
    double *u = aug_malloc((size_t)(m->nn * m->dim) * sizeof *u + 1);
    if (!u) return aug_err_set(e, AUG_ENOMEM, aug_writer_count(w), "fELD", "out of memory");
    int rc;
    if (o->dyn) {
        /* at rest: u = the prescribed values (0 on the free DOFs), v = 0 */
        double *v = aug_calloc((size_t)(m->nn * m->dim) + 1, sizeof *v);
        if (!v) {
            free(u);
            return aug_err_set(e, AUG_ENOMEM, aug_writer_count(w), "fRAM", "out of memory");
        }
        aug_expand_field(m, r->map, v, u);
        aug_frame f = {0, 0.0, m->dim, m->nn, NULL, u, v};
        rc = aug_write_frame(w, 0, &f, e);
        free(v);
    } else {
        aug_expand_field(m, r->map, r->a, u);
        rc = aug_write_field(w, 0, 0, m->dim, m->nn, NULL, u, e);
        if (!rc && !o->no_reactions) rc = write_reactions(w, m, u, e);
    }
    free(u);
    if (rc) return rc;
    aug_kv_init(&k, "factor");
    aug_kv_set(&k, "n", (double)r->nfree);
    aug_kv_set(&k, "nnz_K", (double)cholmod_nnz(r->K, cm));
    aug_kv_set(&k, "nnz_L", r->lnz);
    aug_kv_set(&k, "flops", r->fl);
    aug_kv_set(&k, "ordering", r->L->ordering);
    aug_kv_set(&k, "is_super", r->L->is_super);
    aug_kv_set(&k, "relres", r->relres);
    if (o->dyn) aug_kv_set(&k, "nnz_A", (double)cholmod_nnz(r->A, cm));
    aug_kv_set(&k, "m", 0);
    aug_kv_set(&k, "k", 0);
    if (aug_write_kv(w, "sTAt", 0, &k, e)) return e->code;
    double t_write = aug_now() - t0;
    aug_kv_init(&k, "factor");
    aug_kv_set(&k, "assemble_ms", 1e3 * r->t_asm);
    aug_kv_set(&k, "analyze_ms", 1e3 * r->t_an);
    aug_kv_set(&k, "factor_ms", 1e3 * r->t_fac);
    aug_kv_set(&k, "solve_ms", 1e3 * r->t_sol);
    aug_kv_set(&k, "cond_ms", 1e3 * r->t_cond);
    aug_kv_set(&k, "write_ms", 1e3 * t_write);
    aug_kv_set(&k, "threads", o->threads);
    return aug_write_kv(w, "tIMe", 0, &k, e);
}
