/* What modal writes besides the frames: a domain's basis as a MODE record,
   its linear modes (the LMA of paper 004 fig. 3) and how well its snapshot
   basis spans them, and the warped field (eqs. 16-17). */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_msim.h"

#define NOMEM(e) aug_err_set((e), AUG_ENOMEM, -1, "MODE", "out of memory")

/* columns X (nf x r, over d's free DOFs) as node-major vectors over d's nodes,
   constrained DOFs 0 */
static int fill(const aug_mdomain *d, int dim, int kind, int32_t frame, int r, const double *X,
                const double *sigma, aug_moderec *mr, aug_err *e)
{
    memset(mr, 0, sizeof *mr);
    mr->domain = d->id, mr->frame = frame, mr->dim = dim, mr->kind = kind;
    mr->count = d->nn, mr->r = r;
    int64_t nd = d->nn * dim;
    mr->nodes = malloc((size_t)(d->nn + 1) * sizeof *mr->nodes);
    mr->sigma = malloc((size_t)(r + 1) * sizeof *mr->sigma);
    mr->phi = calloc((size_t)(nd * r + 1), sizeof *mr->phi);
    if (!mr->nodes || !mr->sigma || !mr->phi) {
        aug_moderec_free(mr);
        return NOMEM(e);
    }
    memcpy(mr->nodes, d->nodes, (size_t)d->nn * sizeof *mr->nodes);
    memcpy(mr->sigma, sigma, (size_t)r * sizeof *mr->sigma);
    for (int j = 0; j < r; j++)
        for (int64_t i = 0; i < d->nf; i++) mr->phi[(size_t)j * nd + d->free_dof[i]] = X[i + (size_t)j * d->nf];
    return 0;
}

int aug_msim_mode(const aug_msim *s, int di, aug_moderec *mr, aug_err *e)
{
    aug_err_clear(e);
    const aug_mdomain *d = &s->d[di];
    if (d->mode != AUG_MD_RED || d->r < 1)
        return aug_err_set(e, AUG_EUSAGE, -1, "MODE", "domain %d has no subspace", di);
    return fill(d, s->dim, AUG_MODE_SNAPSHOT, s->frame, d->r, d->W, d->svd.S, mr, e);
}

/* paper 004 fig. 3: the K lowest modes of K x = lambda M x of the domain
   (ARPACK shift-invert on a CHOLMOD factor of K + alpha M, as factor
   --modes in a dynamic scene: aug_modes_shifted), kept for the comparison
   at its switch */
int aug_msim_lma(aug_msim *s, int di, int k, aug_moderec *mr, aug_err *e)
{
    aug_err_clear(e);
    aug_mdomain *d = &s->d[di];
    memset(mr, 0, sizeof *mr);
    free(d->lmaX);
    d->lmaX = NULL, d->nlma = 0;
    if (k > AUG_MODES_MAX) k = AUG_MODES_MAX;
    if (d->nf <= k + 1) return 0; /* too small to have k modes: none */
    d->lmaX = malloc((size_t)d->nf * k * sizeof *d->lmaX);
    if (!d->lmaX) return NOMEM(e);
    /* a domain its own constraints do not hold (a floating sub-domain,
       coupled only at its interfaces) has rigid motions with lambda = 0:
       deflated as factor --modes does (aug_free_rigid_modes), so that they
       come out exactly 0 and as rigid motions, not as Ritz values of
       rounding (-7e-12 on the free cube at --lma 3) */
    double *R = NULL;
    int64_t nr = aug_free_rigid_modes(&d->sub, d->map, d->nf, k, &R);
    if (nr < 0) return NOMEM(e);
    aug_modes md;
    int rc = aug_modes_shifted(d->K, d->M, k, 1e-10, R, (int)nr, &md, d->lmaX, s->cm, e);
    free(R);
    if (rc) return rc;
    if (!md.converged)
        return aug_err_set(e, AUG_ENOCONV, -1, "MODE", "domain %d: ARPACK did not converge on its %d lowest modes", di, k);
    d->nlma = k;
    memcpy(d->lmaL, md.lambda, (size_t)k * sizeof *d->lmaL);
    /* modes of a free piece start at lambda ~ 0 within rounding: never negative in the record */
    for (int j = 0; j < k; j++)
        if (d->lmaL[j] < 0 && d->lmaL[j] > -1e-9 * fabs(d->lmaL[k - 1])) d->lmaL[j] = 0;
    return fill(d, s->dim, AUG_MODE_LMA, s->frame, k, d->lmaX, d->lmaL, mr, e);
}

/* rel[j] = ||x_j - W W'x_j|| / ||x_j|| for the domain's LMA modes x_j against
   its current basis W (reduced) */
int aug_msim_lma_fit(const aug_msim *s, int di, double *rel)
{
    const aug_mdomain *d = &s->d[di];
    if (d->mode != AUG_MD_RED || !d->lmaX) return 0;
    int64_t n = d->nf;
    double *c = malloc((size_t)(d->r + 1) * sizeof *c), *y = malloc((size_t)(n + 1) * sizeof *y);
    if (!c || !y) return free(c), free(y), -1;
    for (int j = 0; j < d->nlma; j++) {
        const double *x = d->lmaX + (size_t)j * n;
        cblas_dgemv(CblasColMajor, CblasTrans, (int)n, d->r, 1.0, d->W, (int)n, x, 1, 0.0, c, 1);
        memcpy(y, x, (size_t)n * sizeof *y);
        cblas_dgemv(CblasColMajor, CblasNoTrans, (int)n, d->r, -1.0, d->W, (int)n, c, 1, 1.0, y, 1);
        double xn = cblas_dnrm2((int)n, x, 1);
        rel[j] = xn > 0 ? cblas_dnrm2((int)n, y, 1) / xn : 0;
    }
    free(c), free(y);
    return d->nlma;
}

/* the written field: u, or its warp R~(w) u with w = curl(u)/2 per node */
const double *aug_msim_output(aug_msim *s, const aug_mesh *m, aug_err *e)
{
    aug_err_clear(e);
    if (!s->o.warp) return s->u;
    double *w = malloc((size_t)(s->nn * 3 + 1) * sizeof *w);
    if (!w) return NOMEM(e), NULL;
    if (aug_warp_rotations(m, NULL, 0, s->u, w, e)) return free(w), NULL;
    aug_warp_apply(w, s->u, s->uw, s->nn, s->dim);
    free(w);
    return s->uw;
}
