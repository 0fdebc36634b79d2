/* Modal warping (paper 004 sec. 5.1, eqs. 16-17; Mueller et al. 2002, Choi & Ko 2005): per-node
   rotation vectors from the curl of the displacement and the rotation-separation operator. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"
#include "aug_modal.h"

int aug_warp_rotations(const aug_mesh *m, const int32_t *elems, int64_t nel, const double *u,
                       double *w, aug_err *e)
{
    aug_err_clear(e);
    int d = m->dim, nv = m->nv;
    if ((d != 2 && d != 3) || aug_etype_nv(m->etype) != nv || aug_etype_dim(m->etype) != d)
        return aug_err_set(e, AUG_EUSAGE, -1, "", "warp: element type %d in %d-D", m->etype, d);
    if (!elems) nel = m->ne;
    if (nel < 0) return aug_err_set(e, AUG_EUSAGE, -1, "", "warp: %lld elements", (long long)nel);
    for (int64_t k = 0; elems && k < nel; k++)
        if (elems[k] < 0 || elems[k] >= m->ne)
            return aug_err_set(e, AUG_EUSAGE, -1, "", "warp: element %lld of %lld listed",
                               (long long)elems[k], (long long)m->ne);
    int32_t *cnt = aug_malloc((size_t)(m->nn > 0 ? m->nn : 1) * sizeof *cnt);
    if (!cnt) return aug_err_set(e, AUG_ENOMEM, -1, "", "warp: out of memory");
    memset(cnt, 0, (size_t)m->nn * sizeof *cnt);
    memset(w, 0, (size_t)m->nn * 3 * sizeof *w);
    for (int64_t k = 0; k < nel; k++) {
        int64_t el = elems ? elems[k] : k;
        const int32_t *c = m->conn + el * nv;
        double g[AUG_MAX_NV * 3], G[3][3] = {{0}}; /* G[r][s] = du_r/dx_s */
        aug_elem_grad(m, el, NULL, g);
        for (int a = 0; a < nv; a++)
            for (int r = 0; r < d; r++)
                for (int s = 0; s < d; s++) G[r][s] += u[(size_t)c[a] * d + r] * g[a * d + s];
        /* w = (1/2) curl u */
        double we[3] = {(G[2][1] - G[1][2]) / 2, (G[0][2] - G[2][0]) / 2, (G[1][0] - G[0][1]) / 2};
        for (int a = 0; a < nv; a++) {
            for (int r = 0; r < 3; r++) w[(size_t)c[a] * 3 + r] += we[r];
            cnt[c[a]]++;
        }
    }
    for (int64_t i = 0; i < m->nn; i++)
        if (cnt[i] > 1)
            for (int r = 0; r < 3; r++) w[i * 3 + r] /= cnt[i];
    free(cnt);
    return 0;
}

/* Below this angle the coefficients come from their Taylor series (11 terms:
   truncation < 1e-17 relative at t = 2); above it from the closed forms, where
   1 - cos t = 2 sin^2(t/2) has no cancellation and t - sin t loses at most a
   factor t / (t - sin t) <= 1.9 to it. Both sides are within a few ulps of
   the exact values at the switch, so R~ is continuous there to round-off. */
#define WARP_SERIES_MAX 2.0
#define WARP_TERMS 11

/* a = (1 - cos t) / t^2 = sum_k (-1)^k t^2k / (2k+2)!,
   b = (t - sin t) / t^3 = sum_k (-1)^k t^2k / (2k+3)!, of t^2 = x */
static void warp_coef(double x, double *a, double *b)
{
    double t = sqrt(x);
    if (t >= WARP_SERIES_MAX) {
        double s = sin(t / 2);
        *a = 2 * s * s / x;
        *b = (t - sin(t)) / (x * t);
        return;
    }
    double ta[WARP_TERMS], tb[WARP_TERMS];
    ta[0] = 0.5, tb[0] = 1.0 / 6;
    for (int k = 1; k < WARP_TERMS; k++) {
        ta[k] = -ta[k - 1] * x / ((2 * k + 1) * (2 * k + 2));
        tb[k] = -tb[k - 1] * x / ((2 * k + 2) * (2 * k + 3));
    }
    double sa = 0, sb = 0; /* smallest terms first */
    for (int k = WARP_TERMS - 1; k >= 0; k--) sa += ta[k], sb += tb[k];
    *a = sa, *b = sb;
}

/* eq. 17 with W = [w]x, t = |w|: W^ (1 - cos t)/t = a W, W^^2 (1 - sin t / t) = b W^2,
   W^2 = w w' - t^2 I */
void aug_warp_matrix(const double w[3], double R[9])
{
    double x = w[0] * w[0] + w[1] * w[1] + w[2] * w[2], a, b;
    warp_coef(x, &a, &b);
    double W[9] = {0, -w[2], w[1], w[2], 0, -w[0], -w[1], w[0], 0};
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            R[r * 3 + c] = (r == c) + a * W[r * 3 + c] + b * (w[r] * w[c] - (r == c) * x);
}

void aug_warp_apply(const double *w, const double *u, double *out, int64_t nn, int dim)
{
    for (int64_t i = 0; i < nn; i++) {
        double R[9], v[3] = {0, 0, 0};
        aug_warp_matrix(w + i * 3, R);
        for (int c = 0; c < dim; c++) v[c] = u[i * dim + c];
        for (int r = 0; r < dim; r++)
            out[i * dim + r] = R[r * 3] * v[0] + R[r * 3 + 1] * v[1] + R[r * 3 + 2] * v[2];
    }
}
