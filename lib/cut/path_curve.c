/* Cut path curves: line, cubic Bezier (thesis eq. 3.1) and rational quadratic
   Bezier (thesis eq. 3.7); their intersections with straight lines (eq. 3.3). */
#include <math.h>
#include <string.h>
#include <gsl/gsl_poly.h>
#include "aug_cut.h"

/* B(t): line (1-t) P0 + t P1; cubic Bezier (thesis 003 eq. 3.1); rational
   quadratic Bezier with weights 1, w, 1 (eq. 3.7) */
void aug_curve_eval(const aug_curve *c, double t, double xy[2])
{
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

/* B'(t) of the three kinds (the quotient rule for the rational arc) */
void aug_curve_deriv(const aug_curve *c, double t, double dxy[2])
{
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

static double poly(const double *c, double t) { return ((c[3] * t + c[2]) * t + c[1]) * t + c[0]; }
static double dpoly(const double *c, double t) { return (3 * c[3] * t + 2 * c[2]) * t + c[1]; }

/* Roots of c3 t^3 + c2 t^2 + c1 t + c0 in [t0, t1]: the cubic by
   gsl_poly_solve_cubic (or the quadratic / linear when the leading terms
   vanish), each polished by Newton steps on the full polynomial. */
static int roots(const double *c, double t0, double t1, double *out)
{
    double cm = fmax(fmax(fabs(c[0]), fabs(c[1])), fmax(fabs(c[2]), fabs(c[3])));
    double r[3];
    int n = 0;
    if (cm == 0) return -1;
    if (fabs(c[3]) > 1e-10 * cm)
        n = gsl_poly_solve_cubic(c[2] / c[3], c[1] / c[3], c[0] / c[3], &r[0], &r[1], &r[2]);
    else if (fabs(c[2]) > 1e-10 * cm)
        n = gsl_poly_solve_quadratic(c[2], c[1], c[0], &r[0], &r[1]);
    else if (fabs(c[1]) > 1e-10 * cm) {
        r[0] = -c[0] / c[1];
        n = 1;
    } else
        return -1;
    int k = 0;
    double span = t1 - t0, eps = 1e-12 * (span > 0 ? span : 1);
    for (int i = 0; i < n; i++) {
        double t = r[i];
        for (int it = 0; it < 3; it++) {
            double d = dpoly(c, t);
            if (d == 0) break;
            double nt = t - poly(c, t) / d;
            if (!isfinite(nt) || fabs(nt - t) > 0.1 * (span > 0 ? span : 1)) break;
            t = nt;
        }
        if (t < t0 - eps || t > t1 + eps) continue;
        t = t < t0 ? t0 : (t > t1 ? t1 : t);
        int dup = 0;
        for (int j = 0; j < k; j++) dup |= fabs(out[j] - t) <= eps;
        if (!dup) out[k++] = t;
    }
    for (int i = 1; i < k; i++)
        for (int j = i; j > 0 && out[j - 1] > out[j]; j--) {
            double x = out[j];
            out[j] = out[j - 1];
            out[j - 1] = x;
        }
    return k;
}

/* the t in [t0, t1] where B(t) meets the line through a and b (thesis 003 eq. 3.3):
   roots of n.(B(t) - a), n normal to ab, a polynomial of degree <= 3 from the
   Bernstein coefficients n.(P_i - a) (the rational arc's numerator, weights
   applied); ascending, at most 3; -1 when that polynomial is constant (the curve
   on the line or parallel to it) */
int aug_curve_line_roots(const aug_curve *c, const double a[2], const double b[2], double t0,
                         double t1, double t[3])
{
    /* g(x) = n . (x - a), n normal to ab; g is affine, so g(B(t)) has the
       Bernstein coefficients g(P_i) (times the weights for the rational arc) */
    double n[2] = {-(b[1] - a[1]), b[0] - a[0]}, g[4] = {0, 0, 0, 0}, cf[4] = {0, 0, 0, 0};
    int np = c->kind == AUG_CURVE_LINE ? 2 : (c->kind == AUG_CURVE_CUBIC ? 4 : 3);
    double ext = 0;
    for (int i = 0; i < np; i++) {
        g[i] = n[0] * (c->p[i][0] - a[0]) + n[1] * (c->p[i][1] - a[1]);
        ext = fmax(ext, fabs(c->p[i][0] - a[0]) + fabs(c->p[i][1] - a[1]));
    }
    double nl = fabs(n[0]) + fabs(n[1]);
    if (c->kind == AUG_CURVE_LINE) {
        cf[0] = g[0];
        cf[1] = g[1] - g[0];
    } else if (c->kind == AUG_CURVE_CUBIC) {
        cf[0] = g[0];
        cf[1] = 3 * (g[1] - g[0]);
        cf[2] = 3 * (g[0] - 2 * g[1] + g[2]);
        cf[3] = -g[0] + 3 * g[1] - 3 * g[2] + g[3];
    } else {
        double b1 = c->w * g[1];
        cf[0] = g[0];
        cf[1] = 2 * (b1 - g[0]);
        cf[2] = g[0] - 2 * b1 + g[2];
    }
    double gm = 0;
    for (int i = 0; i < np; i++) gm = fmax(gm, fabs(g[i]));
    if (gm <= 1e-12 * nl * (ext > 0 ? ext : 1)) return -1;
    return roots(cf, t0, t1, t);
}
