/* One sub-domain of paper 004 (sec. 4.1-4.2): its own mesh, matrices, state,
   snapshots, and its two regimes, full FE (eq. 1) and reduced (eq. 2). */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_msim.h"

#define NOMEM(e) aug_err_set((e), AUG_ENOMEM, -1, "MODE", "out of memory")

void aug_mdomain_free(aug_mdomain *d, cholmod_common *cm)
{
    free(d->elems), free(d->nodes), free(d->map), free(d->free_dof), free(d->fext);
    free(d->u), free(d->v), free(d->uf), free(d->b), free(d->du), free(d->tmp), free(d->tmp2);
    free(d->W), free(d->Kr), free(d->Mr), free(d->Ar), free(d->fr), free(d->q), free(d->qd);
    free(d->br), free(d->dq), free(d->lmaX), free(d->MW), free(d->KW), free(d->flift), free(d->dinv);
    free(d->mvc);
    free(d->iface);
    cholmod_sparse **s[] = {&d->Kall, &d->Mall, &d->Aall, &d->K, &d->M, &d->A, &d->Afull};
    for (int i = 0; i < 7; i++)
        if (*s[i]) cholmod_free_sparse(s[i], cm);
    if (d->have_svd) {
        aug_isvd_free(&d->svd);
        aug_galerkin_free(&d->gK);
        aug_galerkin_free(&d->gM);
    }
    aug_mesh_free(&d->sub);
    memset(d, 0, sizeof *d);
}

cholmod_sparse *aug_sym_restrict(const cholmod_sparse *A, const int32_t *map, int64_t nf,
                                 cholmod_common *cm)
{
    const int32_t *Ap = A->p, *Ai = A->i;
    const double *Ax = A->x;
    size_t nz = 0;
    for (size_t j = 0; j < A->ncol; j++)
        if (map[j] >= 0)
            for (int32_t k = Ap[j]; k < Ap[j + 1]; k++) nz += map[Ai[k]] >= 0;
    cholmod_sparse *B = cholmod_allocate_sparse(nf, nf, nz ? nz : 1, 1, 1, 1, CHOLMOD_REAL, cm);
    if (!B) return NULL;
    int32_t *Bp = B->p, *Bi = B->i;
    double *Bx = B->x;
    size_t q = 0;
    for (size_t j = 0; j < A->ncol; j++) {
        if (map[j] < 0) continue;
        Bp[map[j]] = (int32_t)q;
        for (int32_t k = Ap[j]; k < Ap[j + 1]; k++)
            if (map[Ai[k]] >= 0) Bi[q] = map[Ai[k]], Bx[q++] = Ax[k];
    }
    Bp[nf] = (int32_t)q;
    return B;
}

/* the domain's elements over local nodes; its constraints; the loads of the
   nodes it owns (a nodal force acts once, on the owner's copy); GRAV */
static int submesh(aug_mdomain *d, const aug_mesh *m, const int32_t *owner, int32_t *loc)
{
    aug_mesh *s = &d->sub;
    aug_mesh_init(s);
    int dim = m->dim, nv = m->nv;
    s->dim = dim, s->etype = m->etype, s->nv = nv;
    s->nn = d->nn, s->ne = d->nel;
    s->x = malloc((size_t)(d->nn * dim + 1) * sizeof *s->x);
    s->conn = malloc((size_t)(d->nel * nv + 1) * sizeof *s->conn);
    s->mat = malloc((size_t)(d->nel + 1) * sizeof *s->mat);
    s->mats = malloc((size_t)(m->nmat + 1) * sizeof *s->mats);
    if (!s->x || !s->conn || !s->mat || !s->mats) return -1;
    for (int64_t i = 0; i < d->nn; i++)
        memcpy(s->x + i * dim, m->x + (int64_t)d->nodes[i] * dim, dim * sizeof *s->x);
    for (int64_t k = 0; k < d->nel; k++) {
        int64_t el = d->elems[k];
        for (int j = 0; j < nv; j++) s->conn[k * nv + j] = loc[m->conn[el * nv + j]];
        s->mat[k] = m->mat[el];
    }
    s->nmat = m->nmat;
    memcpy(s->mats, m->mats, (size_t)m->nmat * sizeof *s->mats);
    int64_t nf = 0, nl = 0;
    for (int64_t t = 0; t < m->nfix; t++) nf += loc[m->fix_dof[t] / dim] >= 0;
    for (int64_t t = 0; t < m->nload; t++) nl += owner[m->load_dof[t] / dim] == d->id;
    s->fix_dof = malloc((size_t)(nf + 1) * sizeof *s->fix_dof);
    s->fix_val = malloc((size_t)(nf + 1) * sizeof *s->fix_val);
    s->load_dof = malloc((size_t)(nl + 1) * sizeof *s->load_dof);
    s->load_val = malloc((size_t)(nl + 1) * sizeof *s->load_val);
    if (!s->fix_dof || !s->fix_val || !s->load_dof || !s->load_val) return -1;
    for (int64_t t = 0; t < m->nfix; t++) {
        int32_t ln = loc[m->fix_dof[t] / dim];
        if (ln < 0) continue;
        s->fix_dof[s->nfix] = ln * dim + m->fix_dof[t] % dim;
        s->fix_val[s->nfix++] = m->fix_val[t];
    }
    for (int64_t t = 0; t < m->nload; t++) {
        int32_t nd = m->load_dof[t] / dim;
        if (owner[nd] != d->id) continue;
        s->load_dof[s->nload] = loc[nd] * dim + m->load_dof[t] % dim;
        s->load_val[s->nload++] = m->load_val[t];
    }
    /* node order is increasing, so DOF order is kept: constraints stay sorted */
    memcpy(s->grav, m->grav, sizeof s->grav);
    s->have = m->have & (AUG_HAVE_NODE | AUG_HAVE_ELEM | AUG_HAVE_MATL | AUG_HAVE_FIXD |
                         AUG_HAVE_LOAD | AUG_HAVE_GRAV);
    return 0;
}

/* dinv = 1 / diag(A) over the free DOFs (0 where not positive) */
static void diag_inv(aug_mdomain *d)
{
    const int32_t *Ap = d->A->p, *Ai = d->A->i;
    const double *Ax = d->A->x;
    for (int64_t j = 0; j < d->nf; j++) {
        d->dinv[j] = 0;
        for (int32_t k = Ap[j]; k < Ap[j + 1]; k++)
            if (Ai[k] == j) d->dinv[j] = Ax[k] > 0 ? 1 / Ax[k] : 0;
    }
}

int aug_mdomain_build(aug_mdomain *d, int id, const aug_mesh *m, const int32_t *edom,
                      const int32_t *owner, const aug_dynp *p, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    memset(d, 0, sizeof *d);
    d->id = id;
    int dim = m->dim, nv = m->nv;
    int32_t *loc = malloc((size_t)(m->nn + 1) * sizeof *loc);
    if (!loc) return NOMEM(e);
    for (int64_t i = 0; i < m->nn; i++) loc[i] = -1;
    for (int64_t el = 0; el < m->ne; el++) d->nel += edom[el] == id;
    d->elems = malloc((size_t)(d->nel + 1) * sizeof *d->elems);
    if (!d->elems) goto nomem;
    d->nel = 0;
    for (int64_t el = 0; el < m->ne; el++)
        if (edom[el] == id) {
            d->elems[d->nel++] = (int32_t)el;
            for (int j = 0; j < nv; j++) loc[m->conn[el * nv + j]] = 0;
        }
    for (int64_t i = 0; i < m->nn; i++) d->nn += loc[i] == 0;
    d->nodes = malloc((size_t)(d->nn + 1) * sizeof *d->nodes);
    if (!d->nodes) goto nomem;
    d->nn = 0;
    for (int64_t i = 0; i < m->nn; i++)
        if (loc[i] == 0) loc[i] = (int32_t)d->nn, d->nodes[d->nn++] = (int32_t)i;
    if (submesh(d, m, owner, loc)) goto nomem;
    int64_t nd = d->nn * dim;
    d->map = malloc((size_t)(nd + 1) * sizeof *d->map);
    int32_t *ident = malloc((size_t)(nd + 1) * sizeof *ident);
    if (!d->map || !ident) {
        free(ident);
        goto nomem;
    }
    d->nf = aug_dofmap(&d->sub, d->map);
    for (int64_t k = 0; k < nd; k++) ident[k] = (int32_t)k;
    d->free_dof = malloc((size_t)(d->nf + 1) * sizeof *d->free_dof);
    d->fext = calloc((size_t)(nd + 1), sizeof *d->fext);
    d->u = calloc((size_t)(nd + 1), sizeof *d->u);
    d->v = calloc((size_t)(nd + 1), sizeof *d->v);
    double **w[] = {&d->uf, &d->b, &d->du, &d->tmp, &d->tmp2};
    int bad = !d->free_dof || !d->fext || !d->u || !d->v;
    for (int i = 0; i < 5; i++) bad |= !(*w[i] = calloc((size_t)(nd + 1), sizeof(double)));
    if (bad) {
        free(ident);
        goto nomem;
    }
    for (int64_t k = 0; k < nd; k++)
        if (d->map[k] >= 0) d->free_dof[d->map[k]] = (int32_t)k;
    if (d->nel > 0) {
        d->Kall = aug_assemble(&d->sub, ident, nd, AUG_MAT_K, cm, e);
        if (d->Kall) d->Mall = aug_assemble(&d->sub, ident, nd, p->mass, cm, e);
        if (d->Mall) {
            double a[2] = {p->cM, 0}, b[2] = {p->cK, 0};
            d->Aall = cholmod_add(d->Mall, d->Kall, a, b, 1, 1, cm);
            if (!d->Aall) aug_err_set(e, AUG_ENOMEM, -1, "MODE", "out of memory");
        }
        if (d->Aall && aug_load_vector(&d->sub, ident, nd, d->fext, e) == 0) {
            d->K = aug_sym_restrict(d->Kall, d->map, d->nf, cm);
            d->M = aug_sym_restrict(d->Mall, d->map, d->nf, cm);
            d->A = aug_sym_restrict(d->Aall, d->map, d->nf, cm);
            d->dinv = malloc((size_t)(d->nf + 1) * sizeof *d->dinv);
            if (!d->K || !d->M || !d->A || !d->dinv) aug_err_set(e, AUG_ENOMEM, -1, "MODE", "out of memory");
            else diag_inv(d);
        }
    }
    free(ident);
    free(loc);
    for (int64_t t = 0; t < d->sub.nfix; t++) d->u[d->sub.fix_dof[t]] = d->sub.fix_val[t];
    d->mode = AUG_MD_FE;
    d->version = 1;
    return e->code;
nomem:
    free(loc);
    return NOMEM(e);
}

double aug_mdomain_value(const aug_mdomain *d, int64_t i)
{
    return d->u[d->free_dof[i]];
}

/* The FE right-hand side's h M v0 holds h M[F,C] v_C: constrained DOFs
   that moved to a new target keep a velocity (Euler: one frame, dc / h;
   Newmark: v1 = -v0 for ever after). A domain reduced after such a step
   (modal --lead, then cut --constrain / --drag) took h W'M_FF W q' alone and
   drifted from FE (W = I: l2_err 0.49 and 0.99 in its two reduced frames).
   When some v_C != 0: mvc = M[F,C] v_C (one product with M, the size of
   the residual's O(n r)), br += h W'mvc; the residual takes h mvc too. */
static int red_moving(aug_mdomain *d, double h, cholmod_common *cm, aug_err *e)
{
    d->vc = 0;
    for (int64_t t = 0; t < d->sub.nfix && !d->vc; t++) d->vc = d->v[d->sub.fix_dof[t]] != 0;
    if (!d->vc || d->nf == 0) return 0;
    int64_t n = d->nf, nd = d->nn * d->sub.dim;
    if (!d->mvc && !(d->mvc = malloc((size_t)n * sizeof *d->mvc))) return NOMEM(e);
    memset(d->tmp, 0, (size_t)nd * sizeof *d->tmp);
    for (int64_t t = 0; t < d->sub.nfix; t++) d->tmp[d->sub.fix_dof[t]] = d->v[d->sub.fix_dof[t]];
    if (aug_sym_mult(d->Mall, d->tmp, d->tmp2, cm))
        return aug_err_set(e, AUG_ENOMEM, -1, "MODE", "sparse product failed (CHOLMOD status %d)", cm->status);
    for (int64_t i = 0; i < n; i++) d->mvc[i] = d->tmp2[d->free_dof[i]];
    cblas_dgemv(CblasColMajor, CblasTrans, (int)n, d->r, h, d->W, (int)n, d->mvc, 1, 1.0, d->br, 1);
    return 0;
}

int aug_mdomain_rhs(aug_mdomain *d, const aug_dynp *p, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    double h = p->h, gh2 = aug_dynp_gamma(p) * h * h;
    d->moved = 0;
    if (d->mode == AUG_MD_RED) {
        int r = d->r;
        for (int i = 0; i < r; i++) d->br[i] = gh2 * d->fr[i];
        cblas_dgemv(CblasColMajor, CblasNoTrans, r, r, h, d->Mr, r, d->qd, 1, 1.0, d->br, 1);
        cblas_dgemv(CblasColMajor, CblasNoTrans, r, r, -gh2, d->Kr, r, d->q, 1, 1.0, d->br, 1);
        return red_moving(d, h, cm, e);
    }
    if (d->nf == 0) return 0;
    int64_t nd = d->nn * d->sub.dim;
    if (aug_sym_mult(d->Mall, d->v, d->tmp, cm) || aug_sym_mult(d->Kall, d->u, d->tmp2, cm))
        return aug_err_set(e, AUG_ENOMEM, -1, "MODE", "sparse product failed (CHOLMOD status %d)", cm->status);
    for (int64_t i = 0; i < d->nf; i++) {
        int32_t k = d->free_dof[i];
        d->b[i] = h * d->tmp[k] + gh2 * (d->fext[k] - d->tmp2[k]);
    }
    /* prescribed motion: du_c = target - u_c, lifted as -A[F,C] du_c */
    memset(d->tmp, 0, (size_t)nd * sizeof *d->tmp);
    for (int64_t t = 0; t < d->sub.nfix; t++) {
        int32_t k = d->sub.fix_dof[t];
        double dc = d->sub.fix_val[t] - d->u[k];
        if (dc != 0) d->tmp[k] = dc, d->moved = 1;
    }
    if (d->moved) {
        if (aug_sym_mult(d->Aall, d->tmp, d->tmp2, cm))
            return aug_err_set(e, AUG_ENOMEM, -1, "MODE", "sparse product failed");
        for (int64_t i = 0; i < d->nf; i++) d->b[i] -= d->tmp2[d->free_dof[i]];
    }
    return 0;
}

/* free-DOF velocity rule on gathered values (aug_dynp_velocity) */
static void advance_free(aug_mdomain *d, const aug_dynp *p)
{
    for (int64_t i = 0; i < d->nf; i++) d->tmp[i] = d->v[d->free_dof[i]];
    aug_dynp_velocity(p, d->du, d->tmp, d->tmp2, d->nf);
    for (int64_t i = 0; i < d->nf; i++) {
        int32_t k = d->free_dof[i];
        d->u[k] += d->du[i];
        d->v[k] = d->tmp2[i];
    }
}

/* u_f = W q, v_f = W q' */
static void expand(aug_mdomain *d)
{
    int64_t n = d->nf;
    cblas_dgemv(CblasColMajor, CblasNoTrans, (int)n, d->r, 1.0, d->W, (int)n, d->q, 1, 0.0, d->tmp, 1);
    cblas_dgemv(CblasColMajor, CblasNoTrans, (int)n, d->r, 1.0, d->W, (int)n, d->qd, 1, 0.0, d->tmp2, 1);
    for (int64_t i = 0; i < n; i++) d->u[d->free_dof[i]] = d->tmp[i], d->v[d->free_dof[i]] = d->tmp2[i];
}

/* The full-order residual of the integrator at a reduced frame's increment,
   res = b - A W dq over the free DOFs (b at the frame's start state),
     res = M W (h q' - cM dq) - K W (gamma h^2 q + cK dq) + gamma h^2 (f - K[F,C] u_C),
   O(n r) with M W and K W kept from the switch; in du (unused while
   reduced), before q advances. */
static void residual(aug_mdomain *d, const aug_dynp *p)
{
    int64_t n = d->nf;
    int r = d->r;
    double h = p->h, gh2 = aug_dynp_gamma(p) * h * h;
    double *a = d->tmp, *b = d->tmp2;
    for (int i = 0; i < r; i++) a[i] = h * d->qd[i] - p->cM * d->dq[i], b[i] = -(gh2 * d->q[i] + p->cK * d->dq[i]);
    double *res = d->du;
    for (int64_t i = 0; i < n; i++) res[i] = gh2 * d->flift[i] + (d->vc ? h * d->mvc[i] : 0);
    cblas_dgemv(CblasColMajor, CblasNoTrans, (int)n, r, 1.0, d->MW, (int)n, a, 1, 1.0, res, 1);
    cblas_dgemv(CblasColMajor, CblasNoTrans, (int)n, r, 1.0, d->KW, (int)n, b, 1, 1.0, res, 1);
    d->res = res;
}

int aug_mdomain_fe_residual(aug_mdomain *d, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    if (d->mode != AUG_MD_FE) return 0;
    d->res = NULL;
    if (d->nf == 0) return 0;
    if (d->iface) {
        /* the interface rows alone: one row of A each (a column of A with
           both triangles, copied once: A changes only with a rebuild), not
           the whole A du */
        if (!d->Afull && !(d->Afull = cholmod_copy(d->A, 0, 1, cm))) return NOMEM(e);
        const int32_t *Ap = d->Afull->p, *Ai = d->Afull->i;
        const double *Ax = d->Afull->x;
        for (int64_t i = 0; i < d->nf; i++) {
            if (!d->iface[i]) continue;
            double acc = 0;
            for (int32_t q = Ap[i]; q < Ap[i + 1]; q++) acc += Ax[q] * d->du[Ai[q]];
            d->tmp[i] = d->b[i] - acc;
        }
        d->res = d->tmp;
        return 0;
    }
    if (aug_sym_mult(d->A, d->du, d->tmp, cm))
        return aug_err_set(e, AUG_ENOMEM, -1, "MODE", "sparse product failed (CHOLMOD status %d)", cm->status);
    for (int64_t i = 0; i < d->nf; i++) d->tmp[i] = d->b[i] - d->tmp[i];
    d->res = d->tmp;
    return 0;
}

void aug_mdomain_advance(aug_mdomain *d, const aug_dynp *p)
{
    if (d->mode == AUG_MD_RED) {
        int r = d->r;
        residual(d, p);
        for (int i = 0; i < r; i++) d->q[i] += d->dq[i];
        double *qd1 = d->tmp;
        aug_dynp_velocity(p, d->dq, d->qd, qd1, r);
        memcpy(d->qd, qd1, (size_t)r * sizeof *d->qd);
        expand(d);
    } else {
        advance_free(d, p);
    }
    /* constrained DOFs at their target, moving at the integrator's rate */
    for (int64_t t = 0; t < d->sub.nfix; t++) {
        int32_t k = d->sub.fix_dof[t];
        double dc = d->sub.fix_val[t] - d->u[k], v1;
        if (dc == 0 && d->v[k] == 0) continue;
        aug_dynp_velocity(p, &dc, &d->v[k], &v1, 1);
        d->u[k] = d->sub.fix_val[t];
        d->v[k] = v1;
    }
}

/* Paper 004 eq. 3 with the split after eq. 8: W = U0 after the deferred
   rotation (eq. 9), K_r = G_K and M_r = G_M (kept along the snapshots, not
   recomputed), f_r = W'(f - K[F,C] u_C); the state projected, q = W'u_F,
   q' = W'v_F. */
int aug_mdomain_reduce(aug_mdomain *d, const aug_dynp *p, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    if (!d->have_svd || d->svd.r < 1) return aug_err_set(e, AUG_EUSAGE, -1, "MODE", "domain %d: no basis", d->id);
    if (aug_isvd_compact(&d->svd, e) || aug_galerkin_sync(&d->gK, &d->svd, d->K, cm, e)) return e->code;
    if (aug_galerkin_sync(&d->gM, &d->svd, d->M, cm, e)) return e->code;
    int r = d->svd.r;
    int64_t n = d->nf;
    free(d->W), free(d->Kr), free(d->Mr), free(d->Ar), free(d->fr), free(d->q), free(d->qd);
    free(d->br), free(d->dq), free(d->MW), free(d->KW), free(d->flift);
    d->W = malloc((size_t)n * r * sizeof *d->W);
    d->MW = malloc((size_t)n * r * sizeof *d->MW);
    d->KW = malloc((size_t)n * r * sizeof *d->KW);
    d->flift = malloc((size_t)(n + 1) * sizeof *d->flift);
    d->Kr = malloc((size_t)r * r * sizeof *d->Kr);
    d->Mr = malloc((size_t)r * r * sizeof *d->Mr);
    d->Ar = malloc((size_t)r * r * sizeof *d->Ar);
    double **v[] = {&d->fr, &d->q, &d->qd, &d->br, &d->dq};
    int bad = !d->W || !d->Kr || !d->Mr || !d->Ar || !d->MW || !d->KW || !d->flift;
    for (int i = 0; i < 5; i++) bad |= !(*v[i] = calloc((size_t)r, sizeof(double)));
    if (bad) return NOMEM(e);
    d->r = r;
    aug_isvd_basis(&d->svd, d->W);
    aug_galerkin_reduced(&d->gK, &d->svd, d->Kr);
    aug_galerkin_reduced(&d->gM, &d->svd, d->Mr);
    for (int k = 0; k < r * r; k++) d->Ar[k] = p->cM * d->Mr[k] + p->cK * d->Kr[k];
    /* f_F - K[F,C] u_C over the free DOFs, projected */
    int64_t nd = d->nn * d->sub.dim;
    memset(d->tmp, 0, (size_t)nd * sizeof *d->tmp);
    for (int64_t t = 0; t < d->sub.nfix; t++) d->tmp[d->sub.fix_dof[t]] = d->sub.fix_val[t];
    if (aug_sym_mult(d->Kall, d->tmp, d->tmp2, cm))
        return aug_err_set(e, AUG_ENOMEM, -1, "MODE", "sparse product failed");
    for (int64_t i = 0; i < n; i++) d->flift[i] = d->fext[d->free_dof[i]] - d->tmp2[d->free_dof[i]];
    cblas_dgemv(CblasColMajor, CblasTrans, (int)n, r, 1.0, d->W, (int)n, d->flift, 1, 0.0, d->fr, 1);
    /* M W, K W for the residual of the reduced frames (r sparse products each) */
    cholmod_dense Wd = {(size_t)n, (size_t)r, (size_t)n * r, (size_t)n, d->W, NULL, CHOLMOD_REAL, CHOLMOD_DOUBLE};
    cholmod_dense MWd = Wd, KWd = Wd;
    MWd.x = d->MW, KWd.x = d->KW;
    double one[2] = {1, 0}, zero[2] = {0, 0};
    if (!cholmod_sdmult(d->M, 0, one, zero, &Wd, &MWd, cm) || !cholmod_sdmult(d->K, 0, one, zero, &Wd, &KWd, cm))
        return aug_err_set(e, AUG_ENOMEM, -1, "MODE", "sparse product failed");
    for (int64_t i = 0; i < n; i++) d->tmp[i] = d->u[d->free_dof[i]], d->tmp2[i] = d->v[d->free_dof[i]];
    cblas_dgemv(CblasColMajor, CblasTrans, (int)n, r, 1.0, d->W, (int)n, d->tmp, 1, 0.0, d->q, 1);
    cblas_dgemv(CblasColMajor, CblasTrans, (int)n, r, 1.0, d->W, (int)n, d->tmp2, 1, 0.0, d->qd, 1);
    expand(d);
    d->mode = AUG_MD_RED;
    d->version++;
    d->switched = 1;
    return 0;
}

void aug_mdomain_unreduce(aug_mdomain *d)
{
    d->mode = AUG_MD_FE;
    d->version++;
    d->switched = -1;
}
