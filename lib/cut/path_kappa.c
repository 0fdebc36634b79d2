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
    aug_curve_jet(c, t, b, d1, d2);
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

/* argmax of kappa on [t0, t1] (thesis eq. 3.8, "the maximum value of k(t)"):
   kappa sampled at 16 (n + 1) >= 64 equal steps brackets the largest value;
   golden section on the two steps around it gives t to rounding. Interior
   (1) when the bracket is not at an end and kappa there exceeds kappa at both
   ends by a relative 1e-9 (so a circle or a line, of constant kappa, has no
   such point); 0 and *tk = t0 otherwise. */
int aug_curve_kappa_max(const aug_curve *c, double t0, double t1, double *tk)
{
    *tk = t0;
    double span = t1 - t0;
    if (!(span > 1e-12)) return 0;
    int n = c->kind == AUG_CURVE_BEZIER ? c->deg : (c->kind == AUG_CURVE_CUBIC ? 3 : 2);
    if (c->kind == AUG_CURVE_LINE) return 0;
    int ns = 16 * (n + 1) < 64 ? 64 : 16 * (n + 1);
    int ib = 0;
    double kb = -1;
    for (int i = 0; i <= ns; i++) {
        double k = kap(c, t0 + span * i / ns);
        if (k > kb) {
            kb = k;
            ib = i;
        }
    }
    if (ib == 0 || ib == ns) return 0;
    const double g = 0.5 * (sqrt(5.0) - 1);
    double a = t0 + span * (ib - 1) / ns, b = t0 + span * (ib + 1) / ns;
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
    double t = f1 >= f2 ? x1 : x2, kt = fmax(f1, f2);
    double ke = fmax(kap(c, t0), kap(c, t1));
    if (!(kt > ke * (1 + 1e-9)) || t <= t0 + 1e-9 * span || t >= t1 - 1e-9 * span) return 0;
    *tk = t;
    return 1;
}
