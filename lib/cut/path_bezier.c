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

/* B(t), B'(t), B''(t) by de Casteljau on the homogeneous points H_i (thesis
   eqs. 3.4-3.6): after n-2 levels three points r0, r1, r2 remain, and
   H = (1-t)^2 r0 + 2t(1-t) r1 + t^2 r2, H' = n ((1-t)(r1-r0) + t(r2-r1)),
   H'' = n(n-1)(r2 - 2 r1 + r0); B = X/W, B' = (X' - B W')/W,
   B'' = (X'' - 2 B' W' - B W'')/W (the quotient rule). */
void aug_curve_jet(const aug_curve *c, double t, double b[2], double d1[2], double d2[2])
{
    double hh[4][3], q[AUG_CURVE_MAXDEG + 1][3];
    const double *hp;
    int n = aug_curve_homog(c, hh, &hp);
    memcpy(q, hp, (size_t)(n + 1) * 3 * sizeof(double));
    double s = 1 - t, H[3], H1[3], H2[3];
    for (int k = 1; k <= n - 2; k++)
        for (int i = 0; i + k <= n; i++)
            for (int j = 0; j < 3; j++) q[i][j] = s * q[i][j] + t * q[i + 1][j];
    for (int j = 0; j < 3; j++) {
        if (n == 1) {
            H[j] = s * q[0][j] + t * q[1][j];
            H1[j] = q[1][j] - q[0][j];
            H2[j] = 0;
        } else {
            double s0 = s * q[0][j] + t * q[1][j], s1 = s * q[1][j] + t * q[2][j];
            H[j] = s * s0 + t * s1;
            H1[j] = n * (s1 - s0);
            H2[j] = n * (n - 1) * (q[2][j] - 2 * q[1][j] + q[0][j]);
        }
    }
    for (int k = 0; k < 2; k++) {
        double bk = H[k] / H[2], b1 = (H1[k] - bk * H1[2]) / H[2];
        if (b) b[k] = bk;
        if (d1) d1[k] = b1;
        if (d2) d2[k] = (H2[k] - 2 * b1 * H1[2] - bk * H2[2]) / H[2];
    }
}
