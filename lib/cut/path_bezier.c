/* Bezier and rational Bezier curves of any degree (thesis 003 eqs. 3.4-3.6):
   homogeneous control points and de Casteljau with two derivatives. */
#include <string.h>
#include "aug_cut.h"

/* the homogeneous control points (w_i x_i, w_i y_i, w_i) of curve c: a line
   (degree 1), the cubic (eq. 3.1), the rational quadratic with weights 1, w, 1
   (eq. 3.7) into h, a general curve its own c->h; returns the degree */
int aug_curve_homog(const aug_curve *c, double (*h)[3], const double **hp)
{
    if (c->kind == AUG_CURVE_BEZIER) {
        *hp = c->h;
        return c->deg;
    }
    int n = c->kind == AUG_CURVE_LINE ? 1 : (c->kind == AUG_CURVE_CUBIC ? 3 : 2);
    for (int i = 0; i <= n; i++) {
        double w = c->kind == AUG_CURVE_RQUAD && i == 1 ? c->w : 1;
        h[i][0] = w * c->p[i][0];
        h[i][1] = w * c->p[i][1];
        h[i][2] = w;
    }
    *hp = &h[0][0];
    return n;
}

/* B(t) and its first three derivatives by de Casteljau on the homogeneous
   points H_i (thesis eqs. 3.4-3.6): after n-k of the n levels, k+1 points r_j
   remain and H^(k) = n!/(n-k)! Delta^k r_0 (H''' = 0 below degree 3); then
   B = X/W and, from X = B W by Leibniz, B' = (X' - B W')/W,
   B'' = (X'' - 2 B' W' - B W'')/W, B''' = (X''' - 3 B'' W' - 3 B' W'' - B W''')/W.
   The curve is evaluated relative to its first control point o (B - o
   from the points w_i (x_i - o), then o added to B): the derivatives do not
   depend on where the curve lies, but the quotient rule above takes
   differences of terms of the size of B, and a circle of radius 0.2 at
   1e6 from the origin had its constant curvature read with a relative noise
   above 1e-9, so cut put curvature maxima on it (aug_curve_kappa_max).
   d1, d2, d3 may be NULL. */
void aug_curve_jet(const aug_curve *c, double t, double b[2], double d1[2], double d2[2], double d3[2])
{
    double hh[4][3], q[AUG_CURVE_MAXDEG + 1][3], H[4][3] = {{0}};
    const double *hp;
    int n = aug_curve_homog(c, hh, &hp);
    memcpy(q, hp, (size_t)(n + 1) * 3 * sizeof(double));
    double o[2] = {q[0][0] / q[0][2], q[0][1] / q[0][2]};
    for (int i = 0; i <= n; i++)
        for (int j = 0; j < 2; j++) q[i][j] -= q[i][2] * o[j];
    double s = 1 - t;
    for (int k = 0; k <= n; k++) {
        if (k > 0)
            for (int i = 0; i + k <= n; i++)
                for (int j = 0; j < 3; j++) q[i][j] = s * q[i][j] + t * q[i + 1][j];
        int left = n - k; /* q[0..left] remain: H^(left) from them */
        if (left > 3) continue;
        double f = 1;
        for (int i = 0; i < left; i++) f *= n - i;
        for (int j = 0; j < 3; j++) {
            double d = left == 0 ? q[0][j]
                     : left == 1 ? q[1][j] - q[0][j]
                     : left == 2 ? q[2][j] - 2 * q[1][j] + q[0][j]
                                 : q[3][j] - 3 * q[2][j] + 3 * q[1][j] - q[0][j];
            H[left][j] = f * d;
        }
    }
    for (int k = 0; k < 2; k++) {
        double W = H[0][2], bk = H[0][k] / W, b1 = (H[1][k] - bk * H[1][2]) / W;
        double b2 = (H[2][k] - 2 * b1 * H[1][2] - bk * H[2][2]) / W;
        if (b) b[k] = bk + o[k];
        if (d1) d1[k] = b1;
        if (d2) d2[k] = b2;
        if (d3) d3[k] = (H[3][k] - 3 * b2 * H[1][2] - 3 * b1 * H[2][2] - bk * H[3][2]) / W;
    }
}
