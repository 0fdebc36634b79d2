/* Real roots of a polynomial in Bernstein form on an interval: the power basis
   and gsl up to degree 3, subdivision (de Casteljau) with bisection above. */
#include <math.h>
#include <string.h>
#include <gsl/gsl_poly.h>
#include "aug_cut.h"

static double poly(const double *c, double t) { return ((c[3] * t + c[2]) * t + c[1]) * t + c[0]; }
static double dpoly(const double *c, double t) { return (3 * c[3] * t + 2 * c[2]) * t + c[1]; }

/* Roots of c3 t^3 + c2 t^2 + c1 t + c0 in [t0, t1]: the cubic by
   gsl_poly_solve_cubic (or the quadratic / linear when the leading terms
   vanish), each polished by Newton steps on the full polynomial. */
static int roots3(const double *c, double t0, double t1, double *out)
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

/* de Casteljau at u: the value, and (when l, r are given) the Bernstein
   coefficients of the pieces [0, u] and [u, 1] (thesis eq. 3.4) */
static double casteljau(const double *b, int n, double u, double *l, double *r)
{
    double q[AUG_CURVE_MAXDEG + 1];
    memcpy(q, b, (size_t)(n + 1) * sizeof *q);
    if (l) l[0] = q[0];
    if (r) r[n] = q[n];
    for (int k = 1; k <= n; k++) {
        for (int i = 0; i + k <= n; i++) q[i] = (1 - u) * q[i] + u * q[i + 1];
        if (l) l[k] = q[0];
        if (r) r[n - k] = q[n - k];
    }
    return q[0];
}

static void add_root(double *out, int *k, int n, double t, double eps)
{
    for (int j = 0; j < *k; j++)
        if (fabs(out[j] - t) <= eps) return;
    if (*k < n) out[(*k)++] = t;
}

/* Roots of b on the local [0, 1], which is [lo, hi] of the caller: no sign
   change of the coefficients, no root (the convex hull); one change, exactly
   one, found by bisection; more, split in two. Near-zero coefficients count as
   zero, a root at a vanishing end is kept; at the depth limit (a multiple
   root or a tangency) the middle is. */
static void isolate(const double *b, int n, double lo, double hi, double tiny, int depth,
                    double *out, int *k, double eps)
{
    int changes = 0, last = 0;
    for (int i = 0; i <= n; i++) {
        int s = b[i] > tiny ? 1 : (b[i] < -tiny ? -1 : 0);
        if (s && last && s != last) changes++;
        if (s) last = s;
    }
    if (fabs(b[0]) <= tiny) add_root(out, k, n, lo, eps);
    if (fabs(b[n]) <= tiny) add_root(out, k, n, hi, eps);
    if (changes == 0) return;
    if (changes == 1 && fabs(b[0]) > tiny && fabs(b[n]) > tiny) {
        double a = 0, c = 1, fa = b[0];
        for (int it = 0; it < 200 && c - a > 1e-17; it++) {
            double m = 0.5 * (a + c), fm = casteljau(b, n, m, NULL, NULL);
            if (fm == 0) a = c = m;
            else if ((fm > 0) == (fa > 0)) {
                a = m;
                fa = fm;
            } else
                c = m;
        }
        add_root(out, k, n, lo + 0.5 * (a + c) * (hi - lo), eps);
        return;
    }
    if (depth > 60 || hi - lo < 1e-13) {
        add_root(out, k, n, 0.5 * (lo + hi), eps);
        return;
    }
    double l[AUG_CURVE_MAXDEG + 1], r[AUG_CURVE_MAXDEG + 1];
    casteljau(b, n, 0.5, l, r);
    isolate(l, n, lo, 0.5 * (lo + hi), tiny, depth + 1, out, k, eps);
    isolate(r, n, 0.5 * (lo + hi), hi, tiny, depth + 1, out, k, eps);
}

/* Roots of sum b_i beta_{n,i}(t) (thesis 003 eq. 3.5) in [t0, t1], increasing:
   degree <= 3 through the power basis a_k = C(n,k) sum_i (-1)^(k-i) C(k,i) b_i
   and roots3; higher degrees by isolate on the coefficients of [t0, t1]
   (two de Casteljau splits). -1 when all b_i vanish. */
int aug_bernstein_roots(const double *b, int n, double t0, double t1, double *t)
{
    if (n <= 3) {
        double cf[4] = {b[0], 0, 0, 0};
        if (n == 1) cf[1] = b[1] - b[0];
        else if (n == 2) {
            cf[1] = 2 * (b[1] - b[0]);
            cf[2] = b[0] - 2 * b[1] + b[2];
        } else if (n == 3) {
            cf[1] = 3 * (b[1] - b[0]);
            cf[2] = 3 * (b[0] - 2 * b[1] + b[2]);
            cf[3] = -b[0] + 3 * b[1] - 3 * b[2] + b[3];
        }
        return roots3(cf, t0, t1, t);
    }
    double bm = 0;
    for (int i = 0; i <= n; i++) bm = fmax(bm, fabs(b[i]));
    if (bm == 0) return -1;
    double l[AUG_CURVE_MAXDEG + 1], r[AUG_CURVE_MAXDEG + 1], tmp[AUG_CURVE_MAXDEG + 1];
    int k = 0;
    double span = t1 - t0, eps = 1e-12 * (span > 0 ? span : 1);
    if (!(span > 0)) {
        if (fabs(casteljau(b, n, t0, NULL, NULL)) <= 1e-14 * bm) t[k++] = t0;
        return k;
    }
    /* the coefficients of [t0, t1]: [0, t1], then its part beyond t0 / t1 */
    casteljau(b, n, t1, l, tmp);
    if (t0 > 0) casteljau(l, n, t0 / t1, tmp, r);
    else memcpy(r, l, (size_t)(n + 1) * sizeof *r);
    isolate(r, n, t0, t1, 1e-14 * bm, 0, t, &k, eps);
    for (int i = 1; i < k; i++)
        for (int j = i; j > 0 && t[j - 1] > t[j]; j--) {
            double x = t[j];
            t[j] = t[j - 1];
            t[j - 1] = x;
        }
    return k;
}
