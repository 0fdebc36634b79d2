/* Cut path curves: line, cubic Bezier (thesis eq. 3.1), rational quadratic
   Bezier (thesis eq. 3.7), and (path_bezier.c) any degree, rational or not;
   their intersections with straight lines (eq. 3.3). */
#include <math.h>
#include <string.h>
#include "aug_cut.h"

/* B(t): line (1-t) P0 + t P1; cubic Bezier (thesis 003 eq. 3.1); rational
   quadratic Bezier with weights 1, w, 1 (eq. 3.7); any other degree by
   de Casteljau (eqs. 3.4-3.6, aug_curve_jet) */
void aug_curve_eval(const aug_curve *c, double t, double xy[2])
{
    if (c->kind == AUG_CURVE_BEZIER) {
        aug_curve_jet(c, t, xy, NULL, NULL, NULL);
        return;
    }
    double s = 1 - t;
    for (int k = 0; k < 2; k++) {
        if (c->kind == AUG_CURVE_LINE)
            xy[k] = s * c->p[0][k] + t * c->p[1][k];
        else if (c->kind == AUG_CURVE_CUBIC)
            xy[k] = s * s * s * c->p[0][k] + 3 * t * s * s * c->p[1][k] +
                    3 * t * t * s * c->p[2][k] + t * t * t * c->p[3][k];
        else {
            double d = s * s + 2 * c->w * t * s + t * t;
            xy[k] = (s * s * c->p[0][k] + 2 * c->w * t * s * c->p[1][k] + t * t * c->p[2][k]) / d;
        }
    }
}

/* B'(t) of the four kinds (the quotient rule for the rational ones) */
void aug_curve_deriv(const aug_curve *c, double t, double dxy[2])
{
    if (c->kind == AUG_CURVE_BEZIER) {
        double b[2];
        aug_curve_jet(c, t, b, dxy, NULL, NULL);
        return;
    }
    double s = 1 - t;
    for (int k = 0; k < 2; k++) {
        if (c->kind == AUG_CURVE_LINE)
            dxy[k] = c->p[1][k] - c->p[0][k];
        else if (c->kind == AUG_CURVE_CUBIC)
            dxy[k] = 3 * s * s * (c->p[1][k] - c->p[0][k]) + 6 * s * t * (c->p[2][k] - c->p[1][k]) +
                     3 * t * t * (c->p[3][k] - c->p[2][k]);
        else {
            double w = c->w;
            double N = s * s * c->p[0][k] + 2 * w * t * s * c->p[1][k] + t * t * c->p[2][k];
            double dN = -2 * s * c->p[0][k] + 2 * w * (s - t) * c->p[1][k] + 2 * t * c->p[2][k];
            double D = s * s + 2 * w * t * s + t * t, dD = -2 * s + 2 * w * (s - t) + 2 * t;
            dxy[k] = (dN * D - N * dD) / (D * D);
        }
    }
}

/* the t in [t0, t1] where B(t) meets the line through a and b (thesis 003 eq. 3.3):
   roots of n.(B(t) - a), n normal to ab; g(x) = n.(x - a) is affine, so the
   numerator of g(B(t)) has the Bernstein coefficients w_i g(P_i) (eqs. 3.5,
   3.6), solved by aug_bernstein_roots; ascending; -1 when all g(P_i) vanish
   (the curve on the line) */
int aug_curve_line_roots(const aug_curve *c, const double a[2], const double b[2], double t0,
                         double t1, double *t)
{
    double hh[4][3], g[AUG_CURVE_MAXDEG + 1];
    const double *h;
    int n = aug_curve_homog(c, hh, &h);
    double nv[2] = {-(b[1] - a[1]), b[0] - a[0]}, ext = 0, gm = 0;
    for (int i = 0; i <= n; i++) {
        const double *hi = h + 3 * i;
        double x = hi[0] / hi[2], y = hi[1] / hi[2];
        if (c->kind != AUG_CURVE_BEZIER) {
            x = c->p[i][0];
            y = c->p[i][1];
        }
        double gi = nv[0] * (x - a[0]) + nv[1] * (y - a[1]);
        ext = fmax(ext, fabs(x - a[0]) + fabs(y - a[1]));
        gm = fmax(gm, fabs(gi));
        g[i] = c->kind == AUG_CURVE_RQUAD && i == 1 ? c->w * gi : (c->kind == AUG_CURVE_BEZIER ? hi[2] * gi : gi);
    }
    double nl = fabs(nv[0]) + fabs(nv[1]);
    if (gm <= 1e-12 * nl * (ext > 0 ? ext : 1)) return -1;
    return aug_bernstein_roots(g, n, t0, t1, t);
}
