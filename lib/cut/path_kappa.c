/* Curvature of a cut path curve and its maximum on a parameter interval (the
   extra path vertex of thesis 003 sec. 3.1.2, figs. 3.5, 3.6, 3.20, eq. 3.8). */
#include <float.h>
#include <math.h>
#include "aug_cut.h"

/* kappa(t) = |B'(t) x B''(t)| / |B'(t)|^3 (thesis eq. 3.8; the thesis prints
   the square, which is not invariant under scaling; the cube is the curvature);
   +inf where B' vanishes (a cusp) */
double aug_curve_kappa(const aug_curve *c, double t)
{
    double b[2], d1[2], d2[2];
    aug_curve_jet(c, t, b, d1, d2, NULL);
    double sp = hypot(d1[0], d1[1]), cr = fabs(d1[0] * d2[1] - d1[1] * d2[0]);
    if (sp == 0) return cr == 0 ? 0 : INFINITY;
    double k = cr / (sp * sp * sp);
    return isfinite(k) ? k : INFINITY;
}

static double kap(const aug_curve *c, double t)
{
    double k = aug_curve_kappa(c, t);
    return isfinite(k) ? k : DBL_MAX;
}

/* sign(C) dkappa/dt times |B'|^5, C = B' x B'': (B' x B''') |B'|^2 - 3 C (B'.B'')
   (from kappa = |C| / |B'|^3 and C' = B' x B'''); NaN where C or B' vanish */
static double slope(const aug_curve *c, double t)
{
    double b[2], d1[2], d2[2], d3[2];
    aug_curve_jet(c, t, b, d1, d2, d3);
    double C = d1[0] * d2[1] - d1[1] * d2[0], C3 = d1[0] * d3[1] - d1[1] * d3[0];
    double S2 = d1[0] * d1[0] + d1[1] * d1[1], D = d1[0] * d2[0] + d1[1] * d2[1];
    if (S2 == 0 || C == 0) return NAN;
    double F = C3 * S2 - 3 * C * D;
    return C > 0 ? F : -F;
}

/* argmax of kappa on [t0, t1] (thesis eq. 3.8, "the maximum value of k(t)"):
   kappa sampled at 16 (n + 1) >= 64 equal steps brackets the largest value
   between the two samples around it; there kappa' = 0 (slope) is solved by
   bisection to rounding (kappa itself is flat at its maximum: searching it
   would give t to the square root of rounding only), golden section on kappa
   when the slope does not change sign (a cusp). Interior (1) when that is not
   an end and kappa there exceeds kappa at both ends by a relative 1e-9 (so a
   circle or a line, of constant kappa, has no such point) and kappa times
   the extent of B on [t0, t1] exceeds 1e-9 (a straight curve of higher
   degree, collinear control points, has a kappa of rounding, 1e-16, whose
   noise made maxima: 64 extra path vertices on a cubic of the square, the
   nodes snapped to them 5.4e-4 off the line); 0 and *tk = t0 otherwise. */
int aug_curve_kappa_max(const aug_curve *c, double t0, double t1, double *tk)
{
    *tk = t0;
    double span = t1 - t0;
    if (!(span > 1e-12) || c->kind == AUG_CURVE_LINE) return 0;
    int n = c->kind == AUG_CURVE_BEZIER ? c->deg : (c->kind == AUG_CURVE_CUBIC ? 3 : 2);
    int ns = 16 * (n + 1) < 64 ? 64 : 16 * (n + 1);
    int ib = 0;
    double kb = -1, lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i <= ns; i++) {
        double k = kap(c, t0 + span * i / ns), xy[2];
        aug_curve_eval(c, t0 + span * i / ns, xy);
        for (int d = 0; d < 2; d++) lo[d] = fmin(lo[d], xy[d]), hi[d] = fmax(hi[d], xy[d]);
        if (k > kb) {
            kb = k;
            ib = i;
        }
    }
    if (ib == 0 || ib == ns || !(kb * hypot(hi[0] - lo[0], hi[1] - lo[1]) > 1e-9)) return 0;
    double a = t0 + span * (ib - 1) / ns, b = t0 + span * (ib + 1) / ns, t;
    if (slope(c, a) > 0 && slope(c, b) < 0) {
        for (int it = 0; it < 200; it++) {
            double m = 0.5 * (a + b), gm = slope(c, m);
            if (!(m > a && m < b) || isnan(gm)) break;
            if (gm > 0) a = m;
            else b = m;
        }
        t = kap(c, a) >= kap(c, b) ? a : b;
    } else {
        const double g = 0.5 * (sqrt(5.0) - 1);
        double x1 = b - g * (b - a), x2 = a + g * (b - a), f1 = kap(c, x1), f2 = kap(c, x2);
        for (int it = 0; it < 200 && b - a > 1e-15 * (1 + fabs(a)); it++) {
            if (f1 >= f2) {
                b = x2;
                x2 = x1;
                f2 = f1;
                x1 = b - g * (b - a);
                f1 = kap(c, x1);
            } else {
                a = x1;
                x1 = x2;
                f1 = f2;
                x2 = a + g * (b - a);
                f2 = kap(c, x2);
            }
        }
        t = f1 >= f2 ? x1 : x2;
    }
    double ke = fmax(kap(c, t0), kap(c, t1));
    if (!(kap(c, t) > ke * (1 + 1e-9)) || t <= t0 + 1e-9 * span || t >= t1 - 1e-9 * span) return 0;
    *tk = t;
    return 1;
}
