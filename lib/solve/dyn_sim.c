/* The time integration of a dynamic stream (thesis 003 sec. 3.4.1, paper 004
   eq. 1): the state u, v over every node of the step's mesh, K_t and M_t as
   K_0, M_0 plus the steps' UPKM updates (AMPS eq. 3.1 form), the right-hand
   side of the integrator's A du = h M v0 + gamma h^2 (f - K u0) with the
   prescribed motion of constrained DOFs lifted, and the state advanced from
   a solution du. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_solve.h"

void aug_dynsim_free(aug_dynsim *d)
{
    if (d->cm) {
        aug_cutmat_free(&d->Kc, d->cm);
        aug_cutmat_free(&d->Mc, d->cm);
    }
    free(d->u), free(d->v), free(d->acc), free(d->du);
    free(d->xu), free(d->xv), free(d->Mv), free(d->Ku), free(d->idof), free(d->cval);
    free(d->ep), free(d->ei), free(d->zero), free(d->elist), free(d->estamp);
    memset(d, 0, sizeof *d);
}

int aug_dynsim_init(aug_dynsim *d, const aug_dynp *p, const cholmod_sparse *K0,
                    const cholmod_sparse *M0, const double *f0, cholmod_common *cm, aug_err *e)
{
    memset(d, 0, sizeof *d);
    d->p = *p;
    d->cm = cm;
    double *z = aug_calloc(K0->nrow + 1, sizeof *z);
    if (!z) return aug_err_set(e, AUG_ENOMEM, -1, "KMAT", "out of memory");
    int rc = aug_cutmat_init(&d->Kc, K0, f0, cm, e);
    if (!rc) rc = aug_cutmat_init(&d->Mc, M0, z, cm, e);
    free(z);
    return rc;
}

#define NOMEM(e) aug_err_set((e), AUG_ENOMEM, -1, "fRAM", "out of memory")

/* the nodal arrays for nn nodes (new entries 0) and the matrix-numbered ones for n */
static int grow(aug_dynsim *d, int64_t nn, int dim, int64_t n)
{
    if (nn * dim > d->cap) {
        int64_t c = 2 * nn * dim;
        double **a[] = {&d->u, &d->v, &d->acc, &d->du, &d->cval};
        for (int i = 0; i < 5; i++) {
            double *q = aug_realloc(*a[i], (size_t)c * sizeof *q);
            if (!q) return -1;
            for (int64_t k = d->cap; k < c; k++) q[k] = 0;
            *a[i] = q;
        }
        d->cap = c;
    }
    if (n > d->ncap) {
        int64_t c = 2 * n;
        double **a[] = {&d->xu, &d->xv, &d->Mv, &d->Ku, &d->zero};
        for (int i = 0; i < 5; i++) {
            double *q = aug_realloc(*a[i], (size_t)c * sizeof *q);
            if (!q) return -1;
            *a[i] = q;
        }
        for (int64_t k = 0; k < c; k++) d->zero[k] = 0;
        int32_t *q = aug_realloc(d->idof, (size_t)c * sizeof *q);
        if (!q) return -1;
        d->idof = q;
        d->ncap = c;
    }
    return 0;
}

/* the step's numbering: idof[matrix index] = DOF; cval[DOF] = its prescribed
   value or NAN when free; node -> element incidence for the lifts */
static int renumber(aug_dynsim *d, const aug_replay *rp, aug_err *e)
{
    const aug_mesh *m = &rp->mesh;
    int dim = m->dim;
    d->n = aug_cutmat_n(&d->Kc);
    if (grow(d, m->nn, dim, d->n)) return NOMEM(e);
    for (int64_t i = 0; i < d->n; i++) d->idof[i] = -1;
    for (int64_t nd = 0; nd < m->nn; nd++)
        for (int c = 0; c < dim; c++) {
            int64_t g = aug_replay_index(rp, nd, c);
            if (g >= d->n)
                return aug_err_set(e, AUG_EDATA, -1, "UPDT", "node %lld: matrix index %lld beyond "
                                   "the order %lld of the updates", (long long)nd, (long long)g,
                                   (long long)d->n);
            if (g >= 0) d->idof[g] = (int32_t)(nd * dim + c);
        }
    for (int64_t i = 0; i < d->n; i++)
        if (d->idof[i] < 0)
            return aug_err_set(e, AUG_EDATA, -1, "UPDT", "matrix index %lld has no node of the mesh",
                               (long long)i);
    for (int64_t k = 0; k < m->nn * dim; k++) d->cval[k] = NAN;
    for (int64_t k = 0; k < m->nfix; k++) d->cval[m->fix_dof[k]] = m->fix_val[k];
    free(d->ep), free(d->ei), free(d->elist), free(d->estamp);
    d->ep = NULL, d->ei = NULL;
    d->elist = aug_malloc((size_t)(m->ne + 1) * sizeof *d->elist);
    d->estamp = aug_calloc((size_t)(m->ne + 1), sizeof *d->estamp);
    d->stamp = 0;
    if (!d->elist || !d->estamp || aug_node_elements(m, &d->ep, &d->ei)) return NOMEM(e);
    d->fresh = 0; /* the products of the state are of the old matrices */
    d->nn = m->nn;
    d->dim = dim;
    return 0;
}

int aug_dynsim_start(aug_dynsim *d, const aug_replay *rp, const aug_frame *init, aug_err *e)
{
    aug_err_clear(e);
    const aug_mesh *m = &rp->mesh;
    if (renumber(d, rp, e)) return e->code;
    int64_t nd = m->nn * m->dim;
    if (init && (init->nodes || init->count != m->nn || init->dim != m->dim))
        return aug_err_set(e, AUG_EDATA, -1, "fRAM", "the initial frame holds %lld nodes of the "
                           "%lld of the mesh", (long long)init->count, (long long)m->nn);
    for (int64_t k = 0; k < nd; k++) {
        d->u[k] = init ? init->u[k] : isnan(d->cval[k]) ? 0 : d->cval[k];
        d->v[k] = init ? init->v[k] : 0;
        d->acc[k] = 0;
    }
    return 0;
}

int aug_dynsim_step(aug_dynsim *d, const aug_update *u, const aug_replay *rp,
                    const int32_t *parent, int64_t nnew, aug_err *e)
{
    aug_err_clear(e);
    if (!u->EK || !u->EM)
        return aug_err_set(e, AUG_EDATA, -1, "UPDT", "step %d of a dynamic stream has no UPKM",
                           (int)u->step);
    aug_update k = *u, mm = *u;
    k.E = u->EK;
    mm.E = u->EM;
    int64_t s = (int64_t)u->m + u->k;
    if (grow(d, d->nn, rp->mesh.dim, s > d->n ? s : d->n)) return NOMEM(e);
    mm.df = d->zero; /* M carries no load */
    if (aug_cutmat_apply(&d->Kc, &k, e) || aug_cutmat_apply(&d->Mc, &mm, e)) return e->code;
    int64_t nn_old = d->nn, dim = rp->mesh.dim;
    if (rp->mesh.nn != nn_old + nnew)
        return aug_err_set(e, AUG_EDATA, -1, "MDLT", "the mesh has %lld nodes, the state %lld + %lld "
                           "new", (long long)rp->mesh.nn, (long long)nn_old, (long long)nnew);
    if (grow(d, rp->mesh.nn, (int)dim, 1)) return NOMEM(e);
    /* new nodes take the displacement and velocity of the node they were copied
       (or split) from */
    for (int64_t i = 0; i < nnew; i++) {
        int64_t q = parent[i], nd = nn_old + i;
        if (q < 0 || q >= nd) /* a parent may be an earlier new node of the step */
            return aug_err_set(e, AUG_EDATA, -1, "MDLT", "new node %lld: parent %lld", (long long)nd,
                               (long long)q);
        for (int c = 0; c < dim; c++) {
            d->u[nd * dim + c] = d->u[q * dim + c];
            d->v[nd * dim + c] = d->v[q * dim + c];
            d->acc[nd * dim + c] = d->acc[q * dim + c];
        }
    }
    return renumber(d, rp, e);
}

/* c += h M_e v0_C - A_e du_C + gamma h^2 K_e du_C on the free rows of the
   elements holding a moving constrained DOF (du_C = its value - u0, or v0
   non-zero): the coupling that the matrices' identity rows left out */
static void lift_moving(aug_dynsim *d, const aug_replay *rp, double *b)
{
    const aug_mesh *m = &rp->mesh;
    int dim = d->dim, nv = m->nv, nd = nv * dim;
    double h = d->p.h, g2 = aug_dynp_gamma(&d->p) * h * h;
    /* the elements of the nodes of moving constrained DOFs, once each, in
       increasing order (the summation order of a sweep over all elements) */
    int64_t nel = 0;
    d->stamp++;
    for (int64_t k = 0; k < m->nfix; k++) {
        int32_t dof = m->fix_dof[k];
        if (d->cval[dof] == d->u[dof] && d->v[dof] == 0) continue;
        for (int64_t t = d->ep[dof / dim]; t < d->ep[dof / dim + 1]; t++)
            if (d->estamp[d->ei[t]] != d->stamp) d->estamp[d->ei[t]] = d->stamp, d->elist[nel++] = d->ei[t];
    }
    if (!nel) return;
    qsort(d->elist, (size_t)nel, sizeof *d->elist, aug_cmp_i32);
    for (int64_t q = 0; q < nel; q++) {
        int64_t el = d->elist[q];
        const int32_t *cn = m->conn + el * nv;
        double Ke[AUG_MAX_EMAT], Me[AUG_MAX_EMAT];
        aug_elem_stiffness(m, el, Ke);
        aug_elem_mass(m, el, d->p.mass == 2, Me);
        for (int j = 0; j < nd; j++) {
            int64_t dj = (int64_t)cn[j / dim] * dim + j % dim;
            if (isnan(d->cval[dj])) continue;
            double du = d->cval[dj] - d->u[dj], v0 = d->v[dj];
            if (du == 0 && v0 == 0) continue;
            for (int a = 0; a < nd; a++) {
                int64_t da = (int64_t)cn[a / dim] * dim + a % dim;
                if (!isnan(d->cval[da])) continue;
                int64_t g = aug_replay_index(rp, da / dim, (int)(da % dim));
                if (g < 0) continue;
                double Ka = Ke[a + j * nd], Ma = Me[a + j * nd];
                double Aa = d->p.cM * Ma + d->p.cK * Ka;
                b[g] += h * Ma * v0 - Aa * du + g2 * Ka * du;
            }
        }
    }
}

int aug_dynsim_rhs(aug_dynsim *d, const aug_replay *rp, double *b, aug_err *e)
{
    aug_err_clear(e);
    int64_t n = d->n;
    double h = d->p.h, g2 = aug_dynp_gamma(&d->p) * h * h;
    if (!d->fresh) { /* M v0, K u0: from the last advance, unless a step came since */
        for (int64_t i = 0; i < n; i++) d->xu[i] = d->u[d->idof[i]], d->xv[i] = d->v[d->idof[i]];
        aug_cutmat_mult(&d->Mc, d->xv, d->Mv);
        aug_cutmat_mult(&d->Kc, d->xu, d->Ku);
    }
    aug_cutmat_rhs(&d->Kc, d->du); /* f_t into du (scratch, nodal capacity >= n) */
    for (int64_t i = 0; i < n; i++) {
        int32_t k = d->idof[i];
        b[i] = isnan(d->cval[k]) ? h * d->Mv[i] + g2 * (d->du[i] - d->Ku[i]) : d->cval[k] - d->u[k];
    }
    lift_moving(d, rp, b);
    for (int64_t i = 0; i < n; i++)
        if (!isfinite(b[i]))
            return aug_err_set(e, AUG_EDATA, -1, "fRAM", "frame %d: the right-hand side is not finite",
                               (int)d->frame + 1);
    return 0;
}

int aug_dynsim_advance(aug_dynsim *d, const aug_replay *rp, const double *dx, aug_err *e)
{
    aug_err_clear(e);
    const aug_mesh *m = &rp->mesh;
    int64_t nd = m->nn * m->dim, n = d->n;
    double h = d->p.h;
    for (int64_t k = 0; k < nd; k++) d->du[k] = isnan(d->cval[k]) ? 0 : d->cval[k] - d->u[k];
    for (int64_t i = 0; i < n; i++) {
        int32_t k = d->idof[i];
        if (isnan(d->cval[k])) d->du[k] = dx[i];
    }
    for (int64_t k = 0; k < nd; k++) {
        double v0 = d->v[k], v1 = d->p.integrator == AUG_INT_EULER ? d->du[k] / h
                                                                   : 2 * d->du[k] / h - v0;
        d->u[k] = isnan(d->cval[k]) ? d->u[k] + d->du[k] : d->cval[k];
        d->v[k] = v1;
        d->acc[k] = (v1 - v0) / h;
        if (!isfinite(d->u[k]) || !isfinite(v1))
            return aug_err_set(e, AUG_EDATA, -1, "fRAM", "frame %d: DOF %lld is not finite",
                               (int)d->frame + 1, (long long)k);
    }
    d->frame++;
    d->time = d->frame * h;
    /* energies over the free DOFs of the matrix: 1/2 v'Mv, 1/2 u'Ku, f'u; the
       products are the next frame's right-hand side's too */
    for (int64_t i = 0; i < n; i++) d->xu[i] = d->u[d->idof[i]], d->xv[i] = d->v[d->idof[i]];
    aug_cutmat_mult(&d->Mc, d->xv, d->Mv);
    aug_cutmat_mult(&d->Kc, d->xu, d->Ku);
    aug_cutmat_rhs(&d->Kc, d->du);
    double ke = 0, pe = 0, w = 0;
    for (int64_t i = 0; i < n; i++)
        if (isnan(d->cval[d->idof[i]]))
            ke += d->xv[i] * d->Mv[i], pe += d->xu[i] * d->Ku[i], w += d->du[i] * d->xu[i];
    d->kinetic = 0.5 * ke, d->potential = 0.5 * pe, d->work = w;
    d->fresh = 1;
    return 0;
}
