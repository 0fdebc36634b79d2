/* The frame-by-frame simulation of paper 004: sub-domains (sec. 3), their
   snapshots and switches (sec. 4.2, eqs. 4-14), the interface coupling
   (sec. 4.3, eq. 15) and the cut steps (sec. 5.2). */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_msim.h"
#include "aug_saddle.h"

#define NOMEM(e) aug_err_set((e), AUG_ENOMEM, -1, "MODE", "out of memory")

void aug_msim_opts_default(aug_msim_opts *o)
{
    memset(o, 0, sizeof *o);
    o->split = 1;
    o->reduce_all = 1;
    o->rank = 32;
    o->svd_tol = 1e-8;
    o->tau_svd = 0.95;
    o->err_tol = 0.01;
    o->acc_tol = 0.01;
    o->min_snap = 4;
    o->sync = 10;
    o->probes = 4;
    o->coupling = AUG_COUPLE_DIRECT;
    o->tol = 1e-10;
    o->maxit = 20000;
    o->seed = 1;
}

static int may_reduce(const aug_msim *s, int d)
{
    if (s->o.reduce_none) return 0;
    if (s->o.reduce_all) return 1;
    for (int i = 0; i < s->o.nreduce; i++)
        if (s->o.reduce[i] == d) return 1;
    return 0;
}

/* owner[node] = the lowest domain holding it, ownloc its local index there */
static int owners(aug_msim *s, const aug_mesh *m, aug_err *e)
{
    free(s->owner);
    free(s->ownloc);
    s->owner = malloc((size_t)(m->nn + 1) * sizeof *s->owner);
    s->ownloc = malloc((size_t)(m->nn + 1) * sizeof *s->ownloc);
    if (!s->owner || !s->ownloc) return NOMEM(e);
    for (int64_t i = 0; i < m->nn; i++) s->owner[i] = -1;
    for (int64_t el = 0; el < m->ne; el++)
        for (int j = 0; j < m->nv; j++) {
            int32_t nd = m->conn[el * m->nv + j];
            if (s->owner[nd] < 0 || s->edom[el] < s->owner[nd]) s->owner[nd] = s->edom[el];
        }
    return 0;
}

static void locate_owners(aug_msim *s)
{
    for (int64_t i = 0; i < s->nn; i++) s->ownloc[i] = -1;
    for (int di = s->nd - 1; di >= 0; di--)
        for (int64_t l = 0; l < s->d[di].nn; l++) {
            int32_t g = s->d[di].nodes[l];
            if (s->owner[g] == di) s->ownloc[g] = (int32_t)l;
        }
}

/* interface rows (eq. 15 with C selecting pairs): for every free component
   of a node held by several domains, each copy but the master minus the
   master; the master is the first reduced copy, else the first copy */
static int rows(aug_msim *s, aug_err *e)
{
    int dim = s->dim;
    int64_t nn = s->nn;
    int64_t *cnt = calloc((size_t)nn + 1, sizeof *cnt);
    if (!cnt) return NOMEM(e);
    for (int di = 0; di < s->nd; di++)
        for (int64_t l = 0; l < s->d[di].nn; l++) cnt[s->d[di].nodes[l] + 1]++;
    for (int64_t i = 0; i < nn; i++) cnt[i + 1] += cnt[i];
    int64_t tot = cnt[nn];
    int32_t *cd = malloc((size_t)(tot + 1) * sizeof *cd), *cl = malloc((size_t)(tot + 1) * sizeof *cl);
    int64_t *fill = malloc((size_t)(nn + 1) * sizeof *fill);
    if (!cd || !cl || !fill) {
        free(cnt), free(cd), free(cl), free(fill);
        return NOMEM(e);
    }
    memcpy(fill, cnt, (size_t)nn * sizeof *fill);
    for (int di = 0; di < s->nd; di++)
        for (int64_t l = 0; l < s->d[di].nn; l++) {
            int32_t g = s->d[di].nodes[l];
            cd[fill[g]] = di, cl[fill[g]++] = (int32_t)l;
        }
    s->m = 0;
    for (int pass = 0; pass < 2; pass++) {
        int64_t m = 0;
        for (int64_t g = 0; g < nn; g++) {
            int64_t a = cnt[g], b = cnt[g + 1];
            if (b - a < 2) continue;
            int64_t mst = a;
            for (int64_t q = a; q < b; q++)
                if (s->d[cd[q]].mode == AUG_MD_RED) {
                    mst = q;
                    break;
                }
            for (int c = 0; c < dim; c++) {
                const aug_mdomain *M = &s->d[cd[mst]];
                int32_t im = M->map[(int64_t)cl[mst] * dim + c];
                if (im < 0) continue; /* constrained: every copy at the same value */
                for (int64_t q = a; q < b; q++) {
                    if (q == mst) continue;
                    if (pass) {
                        const aug_mdomain *S = &s->d[cd[q]];
                        s->ca[m] = cd[q], s->cb[m] = cd[mst];
                        s->cia[m] = S->map[(int64_t)cl[q] * dim + c], s->cib[m] = im;
                        s->cdof[m] = (int32_t)(g * dim + c);
                    }
                    m++;
                }
            }
        }
        if (!pass && m > s->mcap) {
            s->mcap = 2 * m + 16;
            int32_t **v[] = {&s->ca, &s->cb, &s->cdof, &s->cia, &s->cib};
            for (int i = 0; i < 5; i++) {
                free(*v[i]);
                if (!(*v[i] = malloc((size_t)s->mcap * sizeof(int32_t)))) {
                    free(cnt), free(cd), free(cl), free(fill);
                    return NOMEM(e);
                }
            }
        }
        s->m = m;
    }
    free(cnt), free(cd), free(cl), free(fill);
    return 0;
}

/* per domain: its free DOFs on an interface row (the residual monitor leaves
   them out: the coupling forces act there) */
static int mark_iface(aug_msim *s, aug_err *e)
{
    for (int di = 0; di < s->nd; di++) {
        aug_mdomain *d = &s->d[di];
        free(d->iface);
        if (!(d->iface = calloc((size_t)d->nf + 1, 1))) return NOMEM(e);
    }
    for (int64_t k = 0; k < s->m; k++) s->d[s->ca[k]].iface[s->cia[k]] = 1, s->d[s->cb[k]].iface[s->cib[k]] = 1;
    return 0;
}

/* a reducible domain's empty snapshot basis, or with --basis identity
   W = I over its free DOFs (aug_isvd_identity, G_K = K, G_M = M: O(n^2)) */
static int basis_start(aug_msim *s, aug_mdomain *d, aug_err *e)
{
    if (!may_reduce(s, d->id) || d->nf == 0) return 0;
    if (s->o.basis == AUG_BASIS_IDENTITY) {
        if (d->nf > 3000)
            return aug_err_set(e, AUG_EUSAGE, -1, "MODE",
                               "--basis identity: domain %d has %lld free DOFs (at most 3000)", d->id,
                               (long long)d->nf);
        if (aug_isvd_identity(&d->svd, d->nf, e)) return e->code;
        d->have_svd = 1;
        if (aug_galerkin_identity(&d->gK, &d->svd, d->K, e) || aug_galerkin_identity(&d->gM, &d->svd, d->M, e))
            return e->code;
        return 0;
    }
    int cap = s->o.rank < d->nf ? s->o.rank : (int)d->nf;
    if (aug_isvd_init(&d->svd, d->nf, cap, 0, s->o.svd_tol, e)) return e->code;
    d->have_svd = 1;
    if (aug_galerkin_init(&d->gK, &d->svd, d->K, s->cm, e) || aug_galerkin_init(&d->gM, &d->svd, d->M, s->cm, e))
        return e->code;
    return 0;
}

static int add_snapshot(aug_msim *s, aug_mdomain *d, const double *x, aug_err *e)
{
    if (aug_isvd_add(&d->svd, x, e)) return e->code;
    if (aug_galerkin_sync(&d->gK, &d->svd, d->K, s->cm, e)) return e->code;
    return aug_galerkin_sync(&d->gM, &d->svd, d->M, s->cm, e);
}

/* resolve a new node to the node of the mesh before the step it descends from */
static int64_t root(int64_t g, int64_t nn_old, const int32_t *parent)
{
    while (g >= nn_old) g = parent[g - nn_old];
    return g;
}

/* the old element (index < s->ne) whose corners before the step hold the
   roots of every node of the added element el (a split's pieces descend from
   the corners of the element they split, cut_split.c): among the step's
   re-wired elements chg first, -1 when none */
static int64_t parent_element(const aug_msim *s, const aug_mesh *m, int64_t el, int64_t nn_old, const int32_t *parent,
                              const int32_t *chg, int64_t nchg)
{
    int nv = m->nv;
    for (int64_t k = 0; k < nchg; k++) {
        int64_t c = chg[k];
        if (c < 0 || c >= s->ne) continue;
        int all = 1;
        for (int j = 0; j < nv && all; j++) {
            int64_t r = root(m->conn[el * nv + j], nn_old, parent), hit = 0;
            for (int i = 0; i < nv && !hit; i++) hit = s->conn[c * nv + i] == r;
            all = (int)hit;
        }
        if (all) return c;
    }
    return -1;
}

/* element -> domain (paper 004 sec. 3 with --split slabs): at the start by the
   element's centroid (partition.c); at a cut step an old element keeps its
   domain (a re-wired one too: its centroid may cross into the next slab, and
   its old domain would keep it with its old nodes), an added one takes its
   parent element's, else its centroid's (modal(1): "elements a cut makes fall
   in their parent's slab") */
static int partition(aug_msim *s, const aug_mesh *m, int64_t nn_old, const int32_t *parent, const int32_t *chg,
                     int64_t nchg, aug_err *e)
{
    int32_t *ed = malloc((size_t)(m->ne + 1) * sizeof *ed);
    int32_t *cn = malloc((size_t)(m->ne * m->nv + 1) * sizeof *cn);
    if (!ed || !cn) return free(ed), free(cn), NOMEM(e);
    for (int64_t el = 0; el < m->ne; el++) {
        int64_t pe = el < s->ne ? el : parent_element(s, m, el, nn_old, parent, chg, nchg);
        ed[el] = pe >= 0 ? s->edom[pe] : aug_mpart_domain(&s->part, m, el);
    }
    memcpy(cn, m->conn, (size_t)(m->ne * m->nv) * sizeof *cn);
    free(s->edom), free(s->conn);
    s->edom = ed, s->conn = cn, s->ne = m->ne;
    return owners(s, m, e);
}

static int grow_global(aug_msim *s, int64_t nn, int dim)
{
    double **v[] = {&s->u, &s->v, &s->uw, &s->rsum, &s->dsum};
    for (int i = 0; i < 5; i++) {
        double *p = realloc(*v[i], (size_t)(nn * dim + 1) * sizeof *p);
        if (!p) return -1;
        for (int64_t k = s->nn * dim; k < nn * dim; k++) p[k] = 0;
        *v[i] = p;
    }
    return 0;
}

/* the global nodal state from the owners' copies */
static void gather(aug_msim *s)
{
    int dim = s->dim;
    for (int64_t g = 0; g < s->nn; g++) {
        if (s->owner[g] < 0) continue;
        const aug_mdomain *d = &s->d[s->owner[g]];
        int32_t l = s->ownloc[g];
        for (int c = 0; c < dim; c++) s->u[g * dim + c] = d->u[l * dim + c], s->v[g * dim + c] = d->v[l * dim + c];
    }
}

int aug_msim_init(aug_msim *s, const aug_msim_opts *o, const aug_dynp *p, const aug_mesh *m,
                  const double *u0, const double *v0, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    memset(s, 0, sizeof *s);
    s->o = *o, s->p = *p, s->cm = cm, s->dim = m->dim;
    s->rng = o->seed ? o->seed : 1;
    if (aug_mpart_init(&s->part, m, o->domains, o->split, e)) return e->code;
    s->nd = s->part.nd;
    for (int i = 0; i < o->nreduce; i++)
        if (o->reduce[i] < 0 || o->reduce[i] >= s->nd)
            return aug_err_set(e, AUG_EUSAGE, -1, "", "--reduce: no domain %d (domains 0..%d)", (int)o->reduce[i],
                               s->nd - 1);
    s->d = calloc((size_t)s->nd, sizeof *s->d);
    if (!s->d || partition(s, m, 0, NULL, NULL, 0, e)) return e->code ? e->code : NOMEM(e);
    if (grow_global(s, m->nn, m->dim)) return NOMEM(e);
    s->nn = m->nn;
    for (int64_t k = 0; k < m->nn * m->dim; k++) s->u[k] = u0 ? u0[k] : 0, s->v[k] = v0 ? v0[k] : 0;
    for (int64_t t = 0; t < m->nfix && !u0; t++) s->u[m->fix_dof[t]] = m->fix_val[t];
    for (int di = 0; di < s->nd; di++) {
        aug_mdomain *d = &s->d[di];
        if (aug_mdomain_build(d, di, m, s->edom, s->owner, p, cm, e)) return e->code;
        for (int64_t l = 0; l < d->nn; l++)
            for (int c = 0; c < m->dim; c++) {
                d->u[l * m->dim + c] = s->u[(int64_t)d->nodes[l] * m->dim + c];
                d->v[l * m->dim + c] = s->v[(int64_t)d->nodes[l] * m->dim + c];
            }
        if (basis_start(s, d, e)) return e->code;
    }
    locate_owners(s);
    if (rows(s, e)) return e->code;
    /* W = I: every reducible domain reduced from the start (a check of the
       machinery: it must reproduce FE exactly) */
    for (int di = 0; di < s->nd && o->basis == AUG_BASIS_IDENTITY; di++)
        if (s->d[di].have_svd && aug_mdomain_reduce(&s->d[di], &s->p, cm, e)) return e->code;
    if (aug_direct_new(&s->dir, e)) return e->code;
    s->dirty = 1;
    return 0;
}

void aug_msim_free(aug_msim *s)
{
    for (int di = 0; di < s->nd && s->d; di++) aug_mdomain_free(&s->d[di], s->cm);
    free(s->d);
    aug_direct_free(s->dir, s->cm);
    if (s->sad) {
        aug_saddle_free(s->sad);
        free(s->sad);
    }
    if (s->C) cholmod_free_sparse(&s->C, s->cm);
    free(s->blk), free(s->off), free(s->g), free(s->lam), free(s->x), free(s->rhs);
    free(s->edom), free(s->conn), free(s->owner), free(s->ownloc), free(s->u), free(s->v), free(s->uw), free(s->rsum), free(s->dsum);
    free(s->ca), free(s->cb), free(s->cdof), free(s->cia), free(s->cib);
    aug_mpart_free(&s->part);
    memset(s, 0, sizeof *s);
}

/* ---- the saddle-point form for schur / ppcg (aug_saddle.h) ---- */

/* blocks (FE: A over the free DOFs; reduced: A_r) and C = e_slave - e_master
   over the blocks' unknowns (reduced copies through their basis rows) */
static int saddle_build(aug_msim *s, aug_err *e)
{
    cholmod_common *cm = s->cm;
    free(s->blk), free(s->off);
    s->blk = calloc((size_t)s->nd + 1, sizeof *s->blk);
    s->off = calloc((size_t)s->nd + 1, sizeof *s->off);
    if (!s->blk || !s->off) return NOMEM(e);
    int64_t N = 0;
    size_t nz = 0;
    for (int di = 0; di < s->nd; di++) {
        aug_mdomain *d = &s->d[di];
        s->off[di] = N;
        aug_sblock *b = &s->blk[di];
        b->version = d->version;
        if (d->mode == AUG_MD_FE) {
            b->n = d->nf, b->A = d->A;
        } else {
            b->n = d->r, b->Ad = d->Ar;
        }
        N += b->n;
    }
    s->off[s->nd] = N;
    s->N = N;
    for (int64_t k = 0; k < s->m; k++)
        nz += (s->d[s->ca[k]].mode == AUG_MD_RED ? s->d[s->ca[k]].r : 1) +
              (s->d[s->cb[k]].mode == AUG_MD_RED ? s->d[s->cb[k]].r : 1);
    cholmod_triplet *T = cholmod_allocate_triplet(s->m, N, nz + 1, 0, CHOLMOD_REAL, cm);
    if (!T) return NOMEM(e);
    int32_t *Ti = T->i, *Tj = T->j;
    double *Tx = T->x;
    size_t q = 0;
    for (int64_t k = 0; k < s->m; k++)
        for (int side = 0; side < 2; side++) {
            const aug_mdomain *d = &s->d[side ? s->cb[k] : s->ca[k]];
            int32_t i = side ? s->cib[k] : s->cia[k];
            double sg = side ? -1 : 1;
            if (d->mode == AUG_MD_FE) {
                Ti[q] = (int32_t)k, Tj[q] = (int32_t)(s->off[d->id] + i), Tx[q++] = sg;
            } else {
                for (int j = 0; j < d->r; j++)
                    Ti[q] = (int32_t)k, Tj[q] = (int32_t)(s->off[d->id] + j), Tx[q++] = sg * d->W[i + (size_t)j * d->nf];
            }
        }
    T->nnz = q;
    if (s->C) cholmod_free_sparse(&s->C, cm);
    s->C = cholmod_triplet_to_sparse(T, q, cm);
    cholmod_free_triplet(&T, cm);
    if (!s->C) return NOMEM(e);
    if (N + s->m > s->xcap) {
        s->xcap = 2 * (N + s->m) + 16;
        free(s->g), free(s->lam), free(s->x), free(s->rhs);
        s->g = calloc((size_t)s->xcap, sizeof *s->g);
        s->lam = calloc((size_t)s->xcap, sizeof *s->lam);
        s->x = calloc((size_t)s->xcap, sizeof *s->x);
        s->rhs = calloc((size_t)s->xcap, sizeof *s->rhs);
        if (!s->g || !s->lam || !s->x || !s->rhs) return NOMEM(e);
    }
    if (!s->sad) {
        s->sad = calloc(1, sizeof *s->sad);
        if (!s->sad || aug_saddle_init(s->sad, cm, e)) return e->code ? e->code : NOMEM(e);
    }
    /* the blocks of domains with free DOFs: a domain held whole (a clamped
       material, a slab of --split with every node fixed) has no unknowns
       and no interface row, and the saddle solvers take no empty block
       ("block 2 has size 0": --coupling schur and ppcg refused what direct
       solves) */
    aug_sblock *nb = malloc((size_t)(s->nd + 1) * sizeof *nb);
    if (!nb) return NOMEM(e);
    int k = 0;
    for (int di = 0; di < s->nd; di++)
        if (s->blk[di].n > 0) nb[k++] = s->blk[di];
    int rc = k > 0 ? aug_saddle_set(s->sad, k, nb, s->C, 1, e)
                   : aug_err_set(e, AUG_ESINGULAR, -1, "MODE", "no domain has a free DOF");
    free(nb);
    return rc;
}

static int saddle_solve(aug_msim *s, aug_err *e)
{
    for (int di = 0; di < s->nd; di++) {
        const aug_mdomain *d = &s->d[di];
        memcpy(s->rhs + s->off[di], d->mode == AUG_MD_FE ? d->b : d->br, (size_t)s->blk[di].n * sizeof *s->rhs);
    }
    for (int64_t k = 0; k < s->m; k++)
        s->g[k] = aug_msim_row_gap(s, k);
    aug_saddle_stats st;
    memset(&st, 0, sizeof st);
    int rc = s->o.coupling == AUG_COUPLE_SCHUR
                 ? aug_saddle_schur(s->sad, s->rhs, s->g, s->x, s->lam, &st, e)
                 : aug_saddle_ppcg(s->sad, s->rhs, s->g, s->x, s->lam, s->o.tol, s->o.maxit, 0, &st, e);
    if (rc) return rc;
    s->iters = st.iters, s->converged = st.converged, s->relres = st.relres, s->rank_c = st.rank;
    for (int di = 0; di < s->nd; di++) {
        aug_mdomain *d = &s->d[di];
        memcpy(d->mode == AUG_MD_FE ? d->du : d->dq, s->x + s->off[di], (size_t)s->blk[di].n * sizeof(double));
    }
    return 0;
}

/* ---- the frame ---- */

double aug_msim_row_gap(const aug_msim *s, int64_t k)
{
    return aug_mdomain_value(&s->d[s->cb[k]], s->cib[k]) - aug_mdomain_value(&s->d[s->ca[k]], s->cia[k]);
}

static double frame_gap(const aug_msim *s)
{
    double g2 = 0;
    for (int64_t k = 0; k < s->m; k++) {
        double g = aug_msim_row_gap(s, k);
        g2 += g * g;
    }
    return sqrt(g2);
}

/* The error a reduced frame adds to its domain's state, a posteriori
   (paper 004 sec. 4.2, after eq. 14: the integration error, which the paper
   assumes grows linearly, measured instead). The full-order residual of the
   integrator at the reduced increment, res = b - A W dq (aug_mdomain_advance),
   leaves the error delta = A^-1 res in u, estimated by the Jacobi step
   diag(A)^-1 res (measured 1.1-1.5x below A^-1 res on the cube and the
   3-layer sphere), and the error delta / h (Euler; Newmark 2 delta / h) in
   the velocity, which carries about as much again into u in the next frames
   until the stiffness turns it: a frame adds (1 + h |v(delta)| / delta)
   delta, 2 delta (Euler) or 3 delta (Newmark), relative to ||u|| over the
   domain, to acc, accumulated over the whole run (the error stays in the
   state). Measured (the cube and the sphere as one domain, backward Euler):
   the error against FE reaches 1.4-2.7x the sum of the exact A^-1 res over a
   stretch.
   At an interface DOF the coupling forces C'lambda act on every copy of the
   node; they cancel in the sum over the copies (FE copies: b - A du), which
   is the residual of the whole body there, scaled by the sum of the copies'
   diagonals. Without it a thin layer whose every DOF lies on an interface
   (the middle shell of the 3-layer sphere) measured no error at all. */
static int estimate(aug_msim *s, aug_err *e)
{
    int nred = 0, dim = s->dim;
    double one = 1, zero = 0, v1;
    aug_dynp_velocity(&s->p, &one, &zero, &v1, 1); /* the velocity error of a unit error in u */
    double carry = 1 + s->p.h * fabs(v1);
    for (int di = 0; di < s->nd; di++) nred += s->d[di].mode == AUG_MD_RED;
    if (!nred) return 0;
    for (int di = 0; di < s->nd; di++)
        if (aug_mdomain_fe_residual(&s->d[di], s->cm, e)) return e->code;
    for (int64_t k = 0; k < s->m; k++) s->rsum[s->cdof[k]] = 0, s->dsum[s->cdof[k]] = 0;
    for (int64_t k = 0; k < s->m; k++) { /* a node's rows for one component are consecutive */
        int32_t g = s->cdof[k];
        const aug_mdomain *a = &s->d[s->ca[k]], *b = &s->d[s->cb[k]];
        s->rsum[g] += a->res[s->cia[k]];
        s->dsum[g] += a->dinv[s->cia[k]] > 0 ? 1 / a->dinv[s->cia[k]] : 0;
        if (k > 0 && s->cdof[k - 1] == g) continue;
        s->rsum[g] += b->res[s->cib[k]];
        s->dsum[g] += b->dinv[s->cib[k]] > 0 ? 1 / b->dinv[s->cib[k]] : 0;
    }
    for (int di = 0; di < s->nd; di++) {
        aug_mdomain *d = &s->d[di];
        if (d->mode != AUG_MD_RED) continue;
        double e2 = 0, u2 = 0;
        for (int64_t i = 0; i < d->nf; i++) {
            int32_t k = d->free_dof[i];
            int64_t g = (int64_t)d->nodes[k / dim] * dim + k % dim;
            double x = d->iface[i] ? (s->dsum[g] > 0 ? s->rsum[g] / s->dsum[g] : 0) : d->res[i] * d->dinv[i];
            e2 += x * x, u2 += s->u[g] * s->u[g];
        }
        d->last_res = u2 > 0 ? carry * sqrt(e2 / u2) : 0;
        d->acc += d->last_res;
    }
    return 0;
}

/* eqs. 12-14 after the frame: an FE domain's state u is measured against the
   basis before its snapshot (exact: Brand's residual, eq. 13; estimate: eq. 14
   by random probes), then added; it switches when the singular-value ratio
   passes tau_svd and the gated error is below err_tol.
   How long it stays reduced: paper 004 (sec. 4.2, after eq. 14) assumes the
   error grows linearly and allows s = floor(tau_acc / ||Error_disp||) frames.
   That does not hold: the switch error measures how well the basis spans the
   states seen so far (1e-8 on the 3-layer sphere), not how fast the FE
   trajectory leaves the subspace (its best approximation in the basis grows
   to 2e-2 in 70 frames, the reduced solution staying within 1.1x of it), and
   any a-priori rate from the snapshots (the drift ||du - UU'du|| / ||u|| of
   the last increment, which is the switch error itself) is as small. So the
   error is measured a posteriori instead: every reduced frame adds the
   estimate of the error its full-order residual leaves (estimate()) to acc,
   accumulated over the whole run (an error made in a reduced stretch stays
   in the state), and a stretch ends when err + acc passes acc_tol (err: the
   projection error at the switch). The domain's budget is then spent: it
   takes no more snapshots and does not switch again (no switching back and
   forth on a few frames of budget each). */
static int switching(aug_msim *s, aug_mdomain *d, aug_err *e)
{
    d->last_est = NAN; /* computed below only where the switch may happen (a reduced frame repeated the last) */
    if (d->mode == AUG_MD_RED) {
        if (d->err_switch + d->acc > s->o.acc_tol) {
            aug_mdomain_unreduce(d);
            d->since = 0, d->spent = 1;
            s->dirty = 1, s->events++;
            s->returned = 1;
        }
        return 0;
    }
    d->ready = 0;
    if (!d->have_svd || d->spent) return 0; /* a spent budget: no switch, no snapshots */
    if (s->o.basis == AUG_BASIS_IDENTITY) { /* W = I spans every state: no snapshot, back at once */
        d->last_err = 0, d->last_est = NAN, d->last_ratio = 1;
        d->ready = 1;
        return 0;
    }
    for (int64_t i = 0; i < d->nf; i++) d->uf[i] = d->u[d->free_dof[i]];
    double un = cblas_dnrm2((int)d->nf, d->uf, 1);
    d->last_est = NAN;
    /* the estimate only where the switch may happen this frame (the paper
       computes eq. 12 only once the ratio test passes) */
    int may = d->since + 1 >= s->o.min_snap && d->last_ratio > s->o.tau_svd;
    if (may && d->svd.r > 0 && un > 0 && s->o.probes > 0) {
        d->last_est = aug_proj_err_estimate(&d->svd, d->uf, s->o.probes < d->nf ? s->o.probes : (int)d->nf,
                                            &s->rng, e);
        if (d->last_est < 0) return e->code;
    }
    if (add_snapshot(s, d, d->uf, e)) return e->code;
    d->since++;
    d->last_err = un > 0 ? d->svd.resid / un : 0;
    d->last_ratio = d->svd.ratio;
    double gate = s->o.gate_estimate ? d->last_est : d->last_err;
    if (d->since < s->o.min_snap || !(un > 0) || d->svd.r < 1 || !(d->last_ratio > s->o.tau_svd) ||
        !(gate < s->o.err_tol) || !(d->last_err + d->acc < s->o.acc_tol))
        return 0;
    d->ready = 1;
    return 0;
}

/* The domains ready to switch switch together: a switch that leaves other
   FE domains behind re-factors their FE part (0.3-0.5 s on the cube, some ten
   FE frames), so a ready domain waits up to --sync N frames for the other
   FE domains that may reduce to be ready too, then switches anyway. */
static int switch_ready(aug_msim *s, aug_err *e)
{
    /* a domain back in FE with the others reduced would have its FE part
       factored (0.3-0.5 s on the cube); with the external FE solver every
       domain comes back instead (no factorization) and they leave together */
    if (s->returned && s->ext)
        for (int di = 0; di < s->nd; di++) {
            aug_mdomain *d = &s->d[di];
            if (d->mode != AUG_MD_RED) continue;
            aug_mdomain_unreduce(d);
            d->since = 0, d->ready = 0;
            s->events++;
        }
    s->returned = 0;
    int ready = 0, pending = 0, waited = 0;
    for (int di = 0; di < s->nd; di++) {
        const aug_mdomain *d = &s->d[di];
        if (d->mode != AUG_MD_FE || !d->have_svd || d->spent) continue;
        if (d->ready) ready++, waited |= d->wait >= s->o.sync;
        else pending++;
    }
    if (!ready) return 0;
    if (pending && !waited) {
        for (int di = 0; di < s->nd; di++) s->d[di].wait += s->d[di].ready;
        return 0;
    }
    for (int di = 0; di < s->nd; di++) {
        aug_mdomain *d = &s->d[di];
        if (!d->ready || d->mode != AUG_MD_FE) continue;
        d->err_switch = d->last_err;
        if (aug_mdomain_reduce(d, &s->p, s->cm, e)) return e->code;
        d->ready = 0, d->wait = 0;
        s->dirty = 1, s->events++;
    }
    return 0;
}

/* The state a reduced frame may be taken back from (aug_msim_frame): per
   domain u, v (local) and, reduced, q, q', acc and its last increment. */
typedef struct saved {
    double *u, *v, *q, *qd, acc, last_res;
} saved;

static void saved_free(saved *sv, int nd)
{
    for (int di = 0; sv && di < nd; di++) free(sv[di].u), free(sv[di].v), free(sv[di].q), free(sv[di].qd);
    free(sv);
}

static saved *save_state(const aug_msim *s)
{
    saved *sv = calloc((size_t)s->nd, sizeof *sv);
    if (!sv) return NULL;
    for (int di = 0; di < s->nd; di++) {
        const aug_mdomain *d = &s->d[di];
        size_t nu = (size_t)(d->nn * d->sub.dim + 1), nr = (size_t)(d->mode == AUG_MD_RED ? d->r : 0) + 1;
        saved *x = &sv[di];
        x->u = malloc(nu * sizeof *x->u), x->v = malloc(nu * sizeof *x->v);
        x->q = malloc(nr * sizeof *x->q), x->qd = malloc(nr * sizeof *x->qd);
        if (!x->u || !x->v || !x->q || !x->qd) return saved_free(sv, s->nd), NULL;
        memcpy(x->u, d->u, (nu - 1) * sizeof *x->u), memcpy(x->v, d->v, (nu - 1) * sizeof *x->v);
        if (d->mode == AUG_MD_RED)
            memcpy(x->q, d->q, (nr - 1) * sizeof *x->q), memcpy(x->qd, d->qd, (nr - 1) * sizeof *x->qd);
        x->acc = d->acc, x->last_res = d->last_res;
    }
    return sv;
}

static void restore_state(aug_msim *s, const saved *sv)
{
    for (int di = 0; di < s->nd; di++) {
        aug_mdomain *d = &s->d[di];
        const saved *x = &sv[di];
        size_t nu = (size_t)(d->nn * d->sub.dim);
        memcpy(d->u, x->u, nu * sizeof *d->u), memcpy(d->v, x->v, nu * sizeof *d->v);
        if (d->mode == AUG_MD_RED)
            memcpy(d->q, x->q, (size_t)d->r * sizeof *d->q), memcpy(d->qd, x->qd, (size_t)d->r * sizeof *d->qd);
        d->acc = x->acc, d->last_res = x->last_res;
    }
}

/* One frame (paper 004 eq. 2 per domain, coupled at the interfaces). A
   reduced domain whose error estimate this frame takes past its budget
   (err at the switch + acc > acc_tol) returns to FE, as switching() does
   after a frame, but the frame itself is not kept: the state is taken back
   and the frame solved again with it in FE (redo). Kept, the frame's error
   stayed in the state: four slabs of the liver reduced at --rank 4, whose
   coupled subspaces satisfy the interface constraints only at q = 0, set
   u to 0 in one frame (l2_err 1.0, acc 4.4 against 0.01) and the run
   ended at l2_err 13. */
int aug_msim_frame(aug_msim *s, aug_err *e)
{
    aug_err_clear(e);
    int nred0 = 0;
    for (int di = 0; di < s->nd; di++) nred0 += s->d[di].mode == AUG_MD_RED;
    saved *sv = NULL;
    s->redo = 0;
    if (nred0 && s->o.basis != AUG_BASIS_IDENTITY && !(sv = save_state(s)))
        return aug_err_set(e, AUG_ENOMEM, -1, "fRAM", "out of memory");
    int rc = 0;
    s->events = s->step_events;
    s->step_events = 0;
    for (int di = 0; di < s->nd; di++) {
        if (!s->d[di].rebuilt && !s->d[di].hold) s->d[di].switched = 0;
        s->d[di].hold = 0;
    }
again:;
    double t0 = aug_now();
    for (int di = 0; di < s->nd; di++)
        if ((rc = aug_mdomain_rhs(&s->d[di], &s->p, s->cm, e))) goto out;
    double t1 = aug_now();
    s->t_build = 0;
    if (s->dirty) {
        if ((rc = rows(s, e)) || (rc = mark_iface(s, e))) goto out;
        rc = s->o.coupling == AUG_COUPLE_DIRECT ? aug_direct_build(s->dir, s, e) : saddle_build(s, e);
        if (rc) goto out;
        s->dirty = 0;
        s->t_build = aug_now() - t1;
    }
    double t2 = aug_now();
    s->iters = 0, s->converged = 1, s->relres = NAN, s->rank_c = -1;
    if (s->o.coupling == AUG_COUPLE_DIRECT) {
        if ((rc = aug_direct_solve(s->dir, s, e))) goto out;
        s->nsys = aug_direct_size(s->dir);
    } else {
        if ((rc = saddle_solve(s, e))) goto out;
        s->nsys = s->N;
    }
    double t3 = aug_now();
    for (int di = 0; di < s->nd; di++) aug_mdomain_advance(&s->d[di], &s->p);
    if ((rc = estimate(s, e))) goto out;
    if (sv) { /* a domain past its budget: the frame again, it in FE */
        int over = 0;
        for (int di = 0; di < s->nd; di++) {
            aug_mdomain *d = &s->d[di];
            d->over = d->mode == AUG_MD_RED && d->err_switch + d->acc > s->o.acc_tol;
            over |= d->over;
        }
        if (over) {
            restore_state(s, sv);
            for (int di = 0; di < s->nd; di++) {
                aug_mdomain *d = &s->d[di];
                /* with the external FE solver every reduced domain comes back
                   with it (switch_ready: no FE part of its own to factor) */
                if (!d->over && !(s->ext && d->mode == AUG_MD_RED)) continue;
                /* taken back: its state is u, v as they were (expanded from q) */
                aug_mdomain_unreduce(d);
                d->since = 0, d->ready = 0;
                if (d->over) d->spent = 1;
                s->dirty = 1, s->events++;
            }
            s->redo++;
            goto again;
        }
    }
    gather(s);
    s->gap = frame_gap(s);
    double t4 = aug_now();
    for (int di = 0; di < s->nd; di++)
        if ((rc = switching(s, &s->d[di], e))) goto out;
    if ((rc = switch_ready(s, e))) goto out;
    if (s->events) gather(s); /* a projected state */
    for (int di = 0; di < s->nd; di++) s->d[di].rebuilt = 0;
    s->frame++;
    s->time = s->frame * s->p.h;
    double t5 = aug_now();
    s->t_rhs = t1 - t0, s->t_solve = t3 - t2, s->t_adv = t4 - t3, s->t_svd = t5 - t4;
out:
    saved_free(sv, s->nd);
    return rc;
}

/* ---- cut steps ---- */

/* the constraints (local DOF, value) and owner loads of domain d on m equal
   those of its sub-mesh? */
static int same_bc(const aug_mdomain *d, const aug_mesh *m, const int32_t *owner, const int32_t *loc)
{
    int dim = m->dim;
    int64_t nf = 0, nl = 0;
    for (int64_t t = 0; t < m->nfix; t++) {
        int32_t l = loc[m->fix_dof[t] / dim];
        if (l < 0) continue;
        if (nf >= d->sub.nfix || d->sub.fix_dof[nf] != l * dim + m->fix_dof[t] % dim ||
            d->sub.fix_val[nf] != m->fix_val[t])
            return 0;
        nf++;
    }
    for (int64_t t = 0; t < m->nload; t++) {
        int32_t nd = m->load_dof[t] / dim;
        if (owner[nd] != d->id) continue;
        if (nl >= d->sub.nload || d->sub.load_dof[nl] != loc[nd] * dim + m->load_dof[t] % dim ||
            d->sub.load_val[nl] != m->load_val[t])
            return 0;
        nl++;
    }
    return nf == d->sub.nfix && nl == d->sub.nload;
}

/* rebuild domain di on m: state and snapshots carried over (new nodes from
   their parents), FE */
static int rewire(aug_msim *s, int di, const aug_mesh *m, int64_t nn_old, const int32_t *parent, aug_err *e)
{
    aug_mdomain old = s->d[di], *d = &s->d[di];
    int dim = m->dim;
    if (aug_mdomain_build(d, di, m, s->edom, s->owner, &s->p, s->cm, e)) {
        aug_mdomain_free(&old, s->cm);
        return e->code;
    }
    int32_t *src = malloc((size_t)(d->nf + 1) * sizeof *src);
    if (!src) return aug_mdomain_free(&old, s->cm), NOMEM(e);
    for (int64_t l = 0; l < d->nn; l++) {
        int64_t g = d->nodes[l], r = root(g, nn_old, parent);
        /* the copy in the old domain of g itself, else of its root */
        int64_t lo = -1;
        const int32_t *hit = bsearch(&(int32_t){(int32_t)g}, old.nodes, (size_t)old.nn, sizeof *old.nodes, aug_cmp_i32);
        if (!hit && r != g) hit = bsearch(&(int32_t){(int32_t)r}, old.nodes, (size_t)old.nn, sizeof *old.nodes, aug_cmp_i32);
        if (hit) lo = hit - old.nodes;
        for (int c = 0; c < dim; c++) {
            int64_t k = l * dim + c;
            d->u[k] = lo >= 0 ? old.u[lo * dim + c] : s->u[g * dim + c];
            d->v[k] = lo >= 0 ? old.v[lo * dim + c] : s->v[g * dim + c];
            if (d->map[k] >= 0) src[d->map[k]] = lo >= 0 ? old.map[lo * dim + c] : -1;
        }
    }
    int rc = 0;
    if (old.have_svd && d->nf > 0 && s->o.basis == AUG_BASIS_IDENTITY) {
        rc = basis_start(s, d, e); /* W = I over the new free DOFs, not the old I padded */
    } else if (old.have_svd && d->nf > 0) {
        d->svd = old.svd, d->have_svd = 1;
        old.have_svd = 0;
        aug_galerkin_free(&old.gK), aug_galerkin_free(&old.gM);
        rc = aug_isvd_remap(&d->svd, d->nf, src, e);
        if (!rc) rc = aug_galerkin_init(&d->gK, &d->svd, d->K, s->cm, e);
        if (!rc) rc = aug_galerkin_init(&d->gM, &d->svd, d->M, s->cm, e);
    } else if (!old.have_svd) {
        rc = basis_start(s, d, e);
    }
    d->version = old.version + 1;
    d->acc = old.acc;
    d->last_err = old.last_err; /* its last snapshot's error until it takes another (it read 0) */
    d->spent = old.spent;
    d->switched = old.mode == AUG_MD_RED ? -1 : 0;
    d->rebuilt = 1;
    free(src);
    aug_mdomain_free(&old, s->cm);
    return rc;
}

int aug_msim_step(aug_msim *s, const aug_mesh *m, int64_t nn_old, const int32_t *parent,
                  const int32_t *chg, int64_t nchg, aug_err *e)
{
    aug_err_clear(e);
    if (m->nn < s->nn || nn_old != s->nn)
        return aug_err_set(e, AUG_EDATA, -1, "MDLT", "the mesh has %lld nodes, the simulation %lld", (long long)m->nn,
                           (long long)s->nn);
    if (grow_global(s, m->nn, m->dim)) return NOMEM(e);
    for (int64_t g = nn_old; g < m->nn; g++) {
        int64_t r = root(g, nn_old, parent);
        for (int c = 0; c < m->dim; c++) s->u[g * m->dim + c] = s->u[r * m->dim + c], s->v[g * m->dim + c] = s->v[r * m->dim + c];
    }
    s->nn = m->nn;
    if (partition(s, m, nn_old, parent, chg, nchg, e)) return e->code;
    unsigned char *hit = calloc((size_t)s->nd, 1);
    int32_t *loc = malloc((size_t)(m->nn + 1) * sizeof *loc);
    if (!hit || !loc) return free(hit), free(loc), NOMEM(e);
    for (int64_t k = 0; k < nchg; k++)
        if (chg[k] >= 0 && chg[k] < m->ne) hit[s->edom[chg[k]]] = 1;
    for (int di = 0; di < s->nd; di++) {
        if (hit[di]) continue;
        aug_mdomain *d = &s->d[di];
        for (int64_t i = 0; i < m->nn; i++) loc[i] = -1;
        for (int64_t l = 0; l < d->nn; l++) loc[d->nodes[l]] = (int32_t)l;
        hit[di] = !same_bc(d, m, s->owner, loc);
    }
    free(loc);
    /* which reduced domains a cut sends back to FE besides those it re-wires
       (--after-cut): every one (default: in one elastic body a cut changes
       the response everywhere), the neighbours (an interface row with a
       re-wired domain before the step: their subspace saw the old interface
       only), or none (paper 004's rule) */
    unsigned char *nb = calloc((size_t)s->nd, 1);
    if (!nb) return free(hit), NOMEM(e);
    int any = 0;
    for (int di = 0; di < s->nd; di++) any |= hit[di];
    for (int di = 0; di < s->nd && any && s->o.after_cut == AUG_AFTER_CUT_ALL; di++) nb[di] = 1;
    for (int64_t k = 0; k < s->m && s->o.after_cut == AUG_AFTER_CUT_NEIGHBOURS; k++) {
        if (hit[s->ca[k]]) nb[s->cb[k]] = 1;
        if (hit[s->cb[k]]) nb[s->ca[k]] = 1;
    }
    int rc = 0;
    for (int di = 0; di < s->nd && !rc; di++)
        if (hit[di]) {
            rc = rewire(s, di, m, nn_old, parent, e), s->step_events++;
        } else if (nb[di] && s->d[di].mode == AUG_MD_RED) {
            aug_mdomain_unreduce(&s->d[di]);
            s->d[di].since = 0, s->d[di].hold = 1, s->step_events++;
        }
    free(nb);
    free(hit);
    if (rc) return rc;
    locate_owners(s);
    gather(s);
    s->dirty = 1;
    return 0;
}

/* ---- figures ---- */

/* a figure that is not a number (an estimate not computed this frame) is
   left out, not written */
static void set_finite(aug_kv *kv, const char *key, double v)
{
    if (isfinite(v)) aug_kv_set(kv, key, v);
}

void aug_msim_stats(const aug_msim *s, aug_kv *st, aug_kv *tm)
{
    aug_kv_init(st, "modal");
    aug_kv_set(st, "frame", s->frame);
    aug_kv_set(st, "time", s->time);
    aug_kv_set(st, "domains", s->nd);
    aug_kv_set(st, "n_sys", (double)s->nsys);
    aug_kv_set(st, "rows", (double)s->m);
    int nred = 0;
    for (int di = 0; di < s->nd; di++) nred += s->d[di].mode == AUG_MD_RED;
    aug_kv_set(st, "reduced", nred);
    aug_kv_set(st, "events", s->events);
    aug_kv_set(st, "redo", s->redo);
    set_finite(st, "gap", s->gap);
    if (s->o.coupling == AUG_COUPLE_PPCG) {
        aug_kv_set(st, "iters", s->iters);
        aug_kv_set(st, "converged", s->converged);
    }
    if (s->o.coupling != AUG_COUPLE_DIRECT) {
        set_finite(st, "relres", s->relres);
        aug_kv_set(st, "rank_c", s->rank_c);
    }
    /* per domain (as many as fit): state, size, rank, errors */
    for (int di = 0; di < s->nd && st->n + 7 <= AUG_KV_MAX - 2; di++) {
        const aug_mdomain *d = &s->d[di];
        char k[32];
        snprintf(k, sizeof k, "d%d_state", di), aug_kv_set(st, k, d->mode);
        snprintf(k, sizeof k, "d%d_n", di), aug_kv_set(st, k, d->mode == AUG_MD_RED ? d->r : (double)d->nf);
        snprintf(k, sizeof k, "d%d_rank", di), aug_kv_set(st, k, d->have_svd ? d->svd.r : 0);
        snprintf(k, sizeof k, "d%d_err", di), set_finite(st, k, d->mode == AUG_MD_RED ? d->err_switch + d->acc : d->last_err);
        snprintf(k, sizeof k, "d%d_est", di), set_finite(st, k, d->last_est);
        snprintf(k, sizeof k, "d%d_acc", di), set_finite(st, k, d->acc);
        snprintf(k, sizeof k, "d%d_switch", di), aug_kv_set(st, k, d->switched);
    }
    aug_kv_init(tm, "modal");
    aug_kv_set(tm, "frame", s->frame);
    aug_kv_set(tm, "time_ms", 1e3 * (s->t_rhs + s->t_build + s->t_solve + s->t_adv + s->t_svd));
    aug_kv_set(tm, "rhs_ms", 1e3 * s->t_rhs);
    aug_kv_set(tm, "build_ms", 1e3 * s->t_build);
    aug_kv_set(tm, "solve_ms", 1e3 * s->t_solve);
    aug_kv_set(tm, "advance_ms", 1e3 * s->t_adv);
    aug_kv_set(tm, "svd_ms", 1e3 * s->t_svd);
}
