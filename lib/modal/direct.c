/* The coupled frame of paper 004 eq. 15 solved directly by eliminating the
   slave DOFs: the FE union (nodes shared by FE domains one unknown) factored
   by CHOLMOD, its FE copies of reduced masters expressed through the
   masters' bases, the reduced coordinates by a dense Schur complement with the
   reduced-reduced rows as constraints on their row space. */
#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_msim.h"
#include "aug_saddle.h"

struct aug_direct {
    int64_t nI, nG, nU;         /* union: kept, slave, all */
    int32_t **dmap;             /* per domain (FE): free index -> union index */
    int ndmap;
    int32_t *gsrc;              /* per slave k (nG): the row of its master */
    cholmod_sparse *AU, *AII;
    cholmod_factor *L;
    int R, k;                   /* reduced coordinates, constraints kept */
    int *roff;                  /* per domain: offset of its q (reduced) */
    double *T, *P, *Z, *KKT, *V, *Ug, *sig; /* nG x R, nU x R, nI x R, (R+k)^2, R x k, mrr x k, k */
    int *ipiv;
    int64_t mrr;
    int32_t *rr;                /* the reduced-reduced rows of s */
    double *bU, *gG, *t, *y, *z, *grr; /* work */
    cholmod_dense *X, *Y, *E;
    int ext;                    /* every domain FE: the external solver */
    int64_t *xmap, xn;          /* union index -> its unknown there */
    double *xb, *xx;
};

int aug_direct_new(aug_direct **dp, aug_err *e)
{
    *dp = calloc(1, sizeof **dp);
    return *dp ? 0 : aug_err_set(e, AUG_ENOMEM, -1, "MODE", "out of memory");
}

static void clear(aug_direct *dr, cholmod_common *cm)
{
    for (int i = 0; i < dr->ndmap; i++) free(dr->dmap[i]);
    free(dr->dmap), free(dr->gsrc), free(dr->roff), free(dr->T), free(dr->P), free(dr->Z);
    free(dr->KKT), free(dr->V), free(dr->Ug), free(dr->sig), free(dr->ipiv), free(dr->rr);
    free(dr->bU), free(dr->gG), free(dr->t), free(dr->y), free(dr->z), free(dr->grr);
    free(dr->xmap), free(dr->xb), free(dr->xx);
    if (dr->AU) cholmod_free_sparse(&dr->AU, cm);
    if (dr->AII) cholmod_free_sparse(&dr->AII, cm);
    if (dr->L) cholmod_free_factor(&dr->L, cm);
    cholmod_free_dense(&dr->X, cm);
    cholmod_free_dense(&dr->Y, cm);
    cholmod_free_dense(&dr->E, cm);
    memset(dr, 0, sizeof *dr);
}

void aug_direct_free(aug_direct *dr, cholmod_common *cm)
{
    if (!dr) return;
    clear(dr, cm);
    free(dr);
}

int64_t aug_direct_size(const aug_direct *dr)
{
    return dr->nU + dr->R;
}

#define NOMEM(e) aug_err_set((e), AUG_ENOMEM, -1, "MODE", "out of memory")

/* union numbering: kept DOFs (FE, not slaved to a reduced master) first,
   then the slaves; gl[global DOF] -> union index */
static int number(aug_direct *dr, aug_msim *s, int32_t *gl, aug_err *e)
{
    int dim = s->dim;
    int64_t ng = s->nn * dim;
    unsigned char *slave = calloc((size_t)ng + 1, 1);
    if (!slave) return NOMEM(e);
    for (int64_t k = 0; k < s->m; k++)
        if (s->d[s->ca[k]].mode == AUG_MD_FE && s->d[s->cb[k]].mode == AUG_MD_RED) slave[s->cdof[k]] = 1;
    for (int64_t g = 0; g < ng; g++) gl[g] = -1;
    dr->ndmap = s->nd;
    dr->dmap = calloc((size_t)s->nd, sizeof *dr->dmap);
    if (!dr->dmap) return free(slave), NOMEM(e);
    for (int pass = 0; pass < 2; pass++)
        for (int di = 0; di < s->nd; di++) {
            aug_mdomain *d = &s->d[di];
            if (d->mode != AUG_MD_FE) continue;
            for (int64_t i = 0; i < d->nf; i++) {
                int32_t l = d->free_dof[i];
                int64_t g = (int64_t)d->nodes[l / dim] * dim + l % dim;
                if (slave[g] == pass && gl[g] < 0) gl[g] = (int32_t)(pass ? dr->nI + dr->nG++ : dr->nI++);
            }
        }
    free(slave);
    dr->nU = dr->nI + dr->nG;
    for (int di = 0; di < s->nd; di++) {
        aug_mdomain *d = &s->d[di];
        if (d->mode != AUG_MD_FE) continue;
        if (!(dr->dmap[di] = malloc((size_t)(d->nf + 1) * sizeof **dr->dmap))) return NOMEM(e);
        for (int64_t i = 0; i < d->nf; i++) {
            int32_t l = d->free_dof[i];
            dr->dmap[di][i] = gl[(int64_t)d->nodes[l / dim] * dim + l % dim];
        }
    }
    return 0;
}

/* the union matrix: every FE domain's A over the union numbering (duplicates
   summed: the shared-node assembly) */
static int union_matrix(aug_direct *dr, aug_msim *s, aug_err *e)
{
    cholmod_common *cm = s->cm;
    size_t nz = 0;
    for (int di = 0; di < s->nd; di++)
        if (s->d[di].mode == AUG_MD_FE && s->d[di].A) nz += ((int32_t *)s->d[di].A->p)[s->d[di].A->ncol];
    cholmod_triplet *T = cholmod_allocate_triplet(dr->nU, dr->nU, nz + 1, 1, CHOLMOD_REAL, cm);
    if (!T) return NOMEM(e);
    int32_t *Ti = T->i, *Tj = T->j;
    double *Tx = T->x;
    size_t q = 0;
    for (int di = 0; di < s->nd; di++) {
        aug_mdomain *d = &s->d[di];
        if (d->mode != AUG_MD_FE || !d->A) continue;
        const int32_t *Ap = d->A->p, *Ai = d->A->i, *mp = dr->dmap[di];
        const double *Ax = d->A->x;
        for (int64_t j = 0; j < d->nf; j++)
            for (int32_t p = Ap[j]; p < Ap[j + 1]; p++) {
                int32_t a = mp[Ai[p]], b = mp[j];
                Ti[q] = a < b ? a : b, Tj[q] = a < b ? b : a, Tx[q++] = Ax[p];
            }
    }
    T->nnz = q;
    dr->AU = cholmod_triplet_to_sparse(T, q, cm);
    cholmod_free_triplet(&T, cm);
    if (!dr->AU) return NOMEM(e);
    int32_t *keep = malloc((size_t)(dr->nU + 1) * sizeof *keep);
    if (!keep) return NOMEM(e);
    for (int64_t i = 0; i < dr->nU; i++) keep[i] = i < dr->nI ? (int32_t)i : -1;
    dr->AII = aug_sym_restrict(dr->AU, keep, dr->nI, cm);
    free(keep);
    if (!dr->AII) return NOMEM(e);
    if (dr->nI == 0) return 0;
    dr->L = aug_analyze(dr->AII, cm, e);
    if (!dr->L) return e->code;
    return aug_factorize(dr->AII, dr->L, NULL, NULL, cm, e);
}

/* T (slave rows through the masters' bases), P = AU [0; T], Z = AII^-1 P_I */
static int slaves(aug_direct *dr, aug_msim *s, const int32_t *gl, aug_err *e)
{
    cholmod_common *cm = s->cm;
    int R = dr->R;
    int64_t nG = dr->nG, nU = dr->nU, nI = dr->nI;
    dr->gsrc = malloc((size_t)(nG + 1) * sizeof *dr->gsrc);
    dr->T = calloc((size_t)(nG * R + 1), sizeof *dr->T);
    if (!dr->gsrc || !dr->T) return NOMEM(e);
    for (int64_t k = 0; k < nG; k++) dr->gsrc[k] = -1;
    for (int64_t k = 0; k < s->m; k++) {
        if (s->d[s->ca[k]].mode != AUG_MD_FE || s->d[s->cb[k]].mode != AUG_MD_RED) continue;
        int64_t gi = gl[s->cdof[k]] - nI;
        if (dr->gsrc[gi] >= 0) continue; /* another FE copy of the same node */
        dr->gsrc[gi] = (int32_t)k;
        const aug_mdomain *b = &s->d[s->cb[k]];
        for (int j = 0; j < b->r; j++) dr->T[gi + (size_t)(dr->roff[s->cb[k]] + j) * nG] = b->W[s->cib[k] + (size_t)j * b->nf];
    }
    if (R == 0 || nU == 0) return 0;
    cholmod_dense *X = cholmod_zeros(nU, R, CHOLMOD_REAL, cm), *Y = cholmod_allocate_dense(nU, R, nU, CHOLMOD_REAL, cm);
    if (!X || !Y) {
        cholmod_free_dense(&X, cm), cholmod_free_dense(&Y, cm);
        return NOMEM(e);
    }
    for (int j = 0; j < R; j++)
        memcpy((double *)X->x + (size_t)j * nU + nI, dr->T + (size_t)j * nG, (size_t)nG * sizeof(double));
    double one[2] = {1, 0}, zero[2] = {0, 0};
    int ok = cholmod_sdmult(dr->AU, 0, one, zero, X, Y, cm);
    cholmod_free_dense(&X, cm);
    dr->P = malloc((size_t)nU * R * sizeof *dr->P);
    dr->Z = malloc((size_t)(nI * R + 1) * sizeof *dr->Z);
    if (!ok || !dr->P || !dr->Z) {
        cholmod_free_dense(&Y, cm);
        return NOMEM(e);
    }
    memcpy(dr->P, Y->x, (size_t)nU * R * sizeof *dr->P);
    cholmod_free_dense(&Y, cm);
    if (nI == 0) return 0;
    cholmod_dense *B = cholmod_allocate_dense(nI, R, nI, CHOLMOD_REAL, cm);
    if (!B) return NOMEM(e);
    for (int j = 0; j < R; j++) memcpy((double *)B->x + (size_t)j * nI, dr->P + (size_t)j * nU, (size_t)nI * sizeof(double));
    cholmod_dense *Zd = cholmod_solve(CHOLMOD_A, dr->L, B, cm);
    cholmod_free_dense(&B, cm);
    if (!Zd) return NOMEM(e);
    memcpy(dr->Z, Zd->x, (size_t)nI * R * sizeof *dr->Z);
    cholmod_free_dense(&Zd, cm);
    return 0;
}

/* the reduced-reduced rows D (mrr x R) = U S V' (LAPACK dgesvd), kept
   rank k (AUG_SADDLE_RTOL, as the saddle solvers): the constraints V_k' dz = S_k^-1 U_k' g (their least-squares
   solution set); KKT = [S_R V_k; V_k' 0] factored by dsytrf */
static int schur(aug_direct *dr, aug_msim *s, aug_err *e)
{
    int R = dr->R;
    int64_t nG = dr->nG, nU = dr->nU, nI = dr->nI;
    dr->mrr = 0;
    for (int64_t k = 0; k < s->m; k++) dr->mrr += s->d[s->ca[k]].mode == AUG_MD_RED;
    int64_t mrr = dr->mrr;
    dr->rr = malloc((size_t)(mrr + 1) * sizeof *dr->rr);
    double *D = calloc((size_t)(mrr * R + 1), sizeof *D);
    if (!dr->rr || !D) return free(D), NOMEM(e);
    mrr = 0;
    for (int64_t k = 0; k < s->m; k++) {
        if (s->d[s->ca[k]].mode != AUG_MD_RED) continue;
        const aug_mdomain *a = &s->d[s->ca[k]], *b = &s->d[s->cb[k]];
        for (int j = 0; j < a->r; j++) D[mrr + (size_t)(dr->roff[a->id] + j) * dr->mrr] += a->W[s->cia[k] + (size_t)j * a->nf];
        for (int j = 0; j < b->r; j++) D[mrr + (size_t)(dr->roff[b->id] + j) * dr->mrr] -= b->W[s->cib[k] + (size_t)j * b->nf];
        dr->rr[mrr++] = (int32_t)k;
    }
    int mn = (int)(mrr < R ? mrr : R);
    dr->k = 0;
    dr->sig = malloc((size_t)(mn + 1) * sizeof *dr->sig);
    dr->Ug = malloc((size_t)(mrr * mn + 1) * sizeof *dr->Ug);
    double *Vt = malloc((size_t)(mn * R + 1) * sizeof *Vt), *sb = malloc((size_t)(mn + 1) * sizeof *sb);
    if (!dr->sig || !dr->Ug || !Vt || !sb) return free(D), free(Vt), free(sb), NOMEM(e);
    if (mrr > 0 && R > 0) {
        int info = LAPACKE_dgesvd(LAPACK_COL_MAJOR, 'S', 'S', (int)mrr, R, D, (int)mrr, dr->sig, dr->Ug,
                                  (int)mrr, Vt, mn, sb);
        if (info != 0) {
            free(D), free(Vt), free(sb);
            return aug_err_set(e, AUG_ENOCONV, -1, "MODE", "dgesvd of the %lld reduced interface rows failed (%d)",
                               (long long)mrr, info);
        }
        while (dr->k < mn && dr->sig[dr->k] > AUG_SADDLE_RTOL * dr->sig[0]) dr->k++;
    }
    free(D), free(sb);
    int k = dr->k, nk = R + k;
    dr->KKT = calloc((size_t)nk * nk + 1, sizeof *dr->KKT);
    dr->ipiv = malloc((size_t)(nk + 1) * sizeof *dr->ipiv);
    if (!dr->KKT || !dr->ipiv) return free(Vt), NOMEM(e);
    /* S_R = blockdiag(A_r) + T' P_G - P_I' Z */
    for (int di = 0; di < s->nd; di++) {
        const aug_mdomain *d = &s->d[di];
        if (d->mode != AUG_MD_RED) continue;
        int o = dr->roff[di];
        for (int j = 0; j < d->r; j++)
            for (int i = 0; i < d->r; i++) dr->KKT[(o + i) + (size_t)(o + j) * nk] = d->Ar[i + (size_t)j * d->r];
    }
    if (nG > 0 && R > 0)
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, R, R, (int)nG, 1.0, dr->T, (int)nG, dr->P + nI, (int)nU,
                    1.0, dr->KKT, nk);
    if (nI > 0 && R > 0)
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, R, R, (int)nI, -1.0, dr->P, (int)nU, dr->Z, (int)nI,
                    1.0, dr->KKT, nk);
    for (int j = 0; j < k; j++)
        for (int i = 0; i < R; i++) {
            double v = Vt[j + (size_t)i * mn];
            dr->KKT[i + (size_t)(R + j) * nk] = v, dr->KKT[(R + j) + (size_t)i * nk] = v;
        }
    free(Vt);
    if (nk == 0) return 0;
    int info = LAPACKE_dsytrf(LAPACK_COL_MAJOR, 'U', nk, dr->KKT, nk, dr->ipiv);
    if (info != 0)
        return aug_err_set(e, AUG_ESINGULAR, -1, "MODE", "the reduced coupled system is singular (dsytrf %d)", info);
    return 0;
}

/* FE copies of a node take the value of the lowest FE copy (they are one
   unknown from now on) */
static void sync_copies(aug_msim *s)
{
    for (int64_t k = 0; k < s->m; k++) {
        aug_mdomain *a = &s->d[s->ca[k]], *b = &s->d[s->cb[k]];
        if (a->mode != AUG_MD_FE || b->mode != AUG_MD_FE) continue;
        int32_t la = a->free_dof[s->cia[k]], lb = b->free_dof[s->cib[k]];
        a->u[la] = b->u[lb], a->v[la] = b->v[lb];
    }
}

/* every domain FE and an external solver: the union is the whole mesh's
   free DOFs, mapped to the solver's unknowns */
static int external(aug_direct *dr, aug_msim *s, aug_err *e)
{
    const aug_mext *x = s->ext;
    int dim = s->dim;
    dr->ext = 1;
    dr->xn = x->n(x->ctx);
    dr->xmap = malloc((size_t)(dr->nU + 1) * sizeof *dr->xmap);
    dr->xb = malloc((size_t)(dr->xn + 1) * sizeof *dr->xb);
    dr->xx = malloc((size_t)(dr->xn + 1) * sizeof *dr->xx);
    dr->bU = malloc((size_t)(dr->nU + 1) * sizeof *dr->bU);
    dr->y = malloc((size_t)(dr->nU + 1) * sizeof *dr->y);
    if (!dr->xmap || !dr->xb || !dr->xx || !dr->bU || !dr->y) return NOMEM(e);
    for (int di = 0; di < s->nd; di++) {
        const aug_mdomain *d = &s->d[di];
        for (int64_t i = 0; i < d->nf; i++) {
            int32_t l = d->free_dof[i];
            int64_t u = dr->dmap[di][i], k = x->index(x->ctx, d->nodes[l / dim], l % dim);
            if (k < 0 || k >= dr->xn)
                return aug_err_set(e, AUG_EDATA, -1, "UPDT", "node %d component %d: no unknown of the stream's "
                                   "matrix (%lld)", (int)d->nodes[l / dim], l % dim, (long long)k);
            dr->xmap[u] = k;
        }
    }
    return 0;
}

int aug_direct_build(aug_direct *dr, aug_msim *s, aug_err *e)
{
    aug_err_clear(e);
    clear(dr, s->cm);
    sync_copies(s);
    int32_t *gl = malloc((size_t)(s->nn * s->dim + 1) * sizeof *gl);
    dr->roff = calloc((size_t)s->nd + 1, sizeof *dr->roff);
    if (!gl || !dr->roff) return free(gl), NOMEM(e);
    for (int di = 0; di < s->nd; di++) {
        dr->roff[di] = dr->R;
        if (s->d[di].mode == AUG_MD_RED) dr->R += s->d[di].r;
    }
    int rc = number(dr, s, gl, e), allfe = s->nd > 0;
    for (int di = 0; di < s->nd; di++) allfe &= s->d[di].mode == AUG_MD_FE;
    if (!rc && allfe && s->ext) {
        free(gl);
        return external(dr, s, e);
    }
    if (!rc) rc = union_matrix(dr, s, e);
    if (!rc) rc = slaves(dr, s, gl, e);
    free(gl);
    if (!rc) rc = schur(dr, s, e);
    if (rc) return rc;
    int64_t nw = dr->nU + dr->R + dr->k + 1;
    dr->bU = malloc((size_t)nw * sizeof *dr->bU);
    dr->gG = malloc((size_t)(dr->nU + 1) * sizeof *dr->gG);
    dr->t = malloc((size_t)nw * sizeof *dr->t);
    dr->y = malloc((size_t)nw * sizeof *dr->y);
    dr->z = malloc((size_t)nw * sizeof *dr->z);
    dr->grr = malloc((size_t)(dr->mrr + 1) * sizeof *dr->grr);
    if (!dr->bU || !dr->gG || !dr->t || !dr->y || !dr->z || !dr->grr) return NOMEM(e);
    return 0;
}

/* the solution to the domains: du of FE copies from the union, dq */
static void scatter(aug_direct *dr, aug_msim *s)
{
    for (int di = 0; di < s->nd; di++) {
        aug_mdomain *d = &s->d[di];
        if (d->mode == AUG_MD_FE)
            for (int64_t i = 0; i < d->nf; i++) d->du[i] = dr->y[dr->dmap[di][i]];
        else
            memcpy(d->dq, dr->z + dr->roff[di], (size_t)d->r * sizeof *d->dq);
    }
}

int aug_direct_solve(aug_direct *dr, aug_msim *s, aug_err *e)
{
    aug_err_clear(e);
    cholmod_common *cm = s->cm;
    int64_t nI = dr->nI, nG = dr->nG, nU = dr->nU;
    int R = dr->R, k = dr->k, nk = R + k;
    /* union right-hand side (copies summed) and the slaves' gaps */
    memset(dr->bU, 0, (size_t)nU * sizeof *dr->bU);
    for (int di = 0; di < s->nd; di++) {
        aug_mdomain *d = &s->d[di];
        if (d->mode != AUG_MD_FE) continue;
        for (int64_t i = 0; i < d->nf; i++) dr->bU[dr->dmap[di][i]] += d->b[i];
    }
    if (dr->ext) { /* every domain FE: the stream's A_t through the external solver */
        memset(dr->xb, 0, (size_t)dr->xn * sizeof *dr->xb);
        for (int64_t i = 0; i < nU; i++) dr->xb[dr->xmap[i]] = dr->bU[i];
        if (s->ext->solve(s->ext->ctx, dr->xb, dr->xx, e)) return e->code;
        for (int64_t i = 0; i < nU; i++) dr->y[i] = dr->xx[dr->xmap[i]];
        scatter(dr, s);
        return 0;
    }
    memset(dr->gG, 0, (size_t)nU * sizeof *dr->gG);
    for (int64_t q = 0; q < nG; q++) {
        int32_t r = dr->gsrc[q];
        dr->gG[nI + q] = aug_msim_row_gap(s, r);
    }
    if (nG > 0) {
        if (aug_sym_mult(dr->AU, dr->gG, dr->t, cm)) return NOMEM(e);
        for (int64_t i = 0; i < nU; i++) dr->bU[i] -= dr->t[i];
    }
    /* y = AII^-1 b'_I */
    if (nI > 0 && aug_factor_apply_inv(dr->L, dr->bU, dr->y, &dr->X, &dr->Y, &dr->E, cm)) return NOMEM(e);
    if (nk > 0) {
        /* s = b_R + T' b'_G - P_I' y ; g_k = S_k^-1 U_k' g_rr */
        for (int di = 0; di < s->nd; di++)
            if (s->d[di].mode == AUG_MD_RED)
                memcpy(dr->z + dr->roff[di], s->d[di].br, (size_t)s->d[di].r * sizeof *dr->z);
        if (nG > 0) cblas_dgemv(CblasColMajor, CblasTrans, (int)nG, R, 1.0, dr->T, (int)nG, dr->bU + nI, 1, 1.0, dr->z, 1);
        if (nI > 0) cblas_dgemv(CblasColMajor, CblasTrans, (int)nI, R, -1.0, dr->P, (int)nU, dr->y, 1, 1.0, dr->z, 1);
        for (int64_t q = 0; q < dr->mrr; q++) {
            int32_t r = dr->rr[q];
            dr->grr[q] = aug_msim_row_gap(s, r);
        }
        if (k > 0) {
            cblas_dgemv(CblasColMajor, CblasTrans, (int)dr->mrr, k, 1.0, dr->Ug, (int)dr->mrr, dr->grr, 1, 0.0, dr->z + R, 1);
            for (int j = 0; j < k; j++) dr->z[R + j] /= dr->sig[j];
        }
        int info = LAPACKE_dsytrs(LAPACK_COL_MAJOR, 'U', nk, 1, dr->KKT, nk, dr->ipiv, dr->z, nk);
        if (info != 0) return aug_err_set(e, AUG_ESINGULAR, -1, "MODE", "dsytrs failed (%d)", info);
    }
    /* du_I = y - Z dz, du_G = T dz + g_G */
    if (nI > 0 && R > 0) cblas_dgemv(CblasColMajor, CblasNoTrans, (int)nI, R, -1.0, dr->Z, (int)nI, dr->z, 1, 1.0, dr->y, 1);
    for (int64_t q = 0; q < nG; q++) dr->y[nI + q] = dr->gG[nI + q];
    if (nG > 0 && R > 0) cblas_dgemv(CblasColMajor, CblasNoTrans, (int)nG, R, 1.0, dr->T, (int)nG, dr->z, 1, 1.0, dr->y + nI, 1);
    scatter(dr, s);
    return 0;
}
