/* Segments and points against triangles: the crossing tests and distances of
   the 3-D surface cuts. */
#include <math.h>
#include "aug_cut.h"

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void sub3(const double *a, const double *b, double *c)
{
    for (int k = 0; k < 3; k++) c[k] = a[k] - b[k];
}

/* The plane of t (unit normal n through t0) separates p from q when exactly
   one of n.(p - t0), n.(q - t0) exceeds eps (a point within eps counts on
   the - side, as the plane cut's n.x > d); the crossing x = p + s (q - p)
   lies in t when its barycentric coordinates (b1, b2) in t's plane satisfy
   b1, b2 >= -1e-9, b1 + b2 <= 1 + 1e-9 (Moller & Trumbore 1997). */
int aug_seg_tri(const double *p, const double *q, const double *t, double eps, double *s)
{
    double u[3], v[3], n[3], w[3];
    sub3(t + 3, t, u);
    sub3(t + 6, t, v);
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double nl = sqrt(dot3(n, n));
    if (!(nl > 0)) return 0;
    sub3(p, t, w);
    double dp = dot3(n, w) / nl;
    sub3(q, t, w);
    double dq = dot3(n, w) / nl;
    if ((dp > eps) == (dq > eps)) return 0;
    double sp = dp / (dp - dq);
    if (sp < 0) sp = 0;
    if (sp > 1) sp = 1;
    double x[3];
    for (int k = 0; k < 3; k++) x[k] = p[k] + sp * (q[k] - p[k]) - t[k];
    double uu = dot3(u, u), uv = dot3(u, v), vv = dot3(v, v), xu = dot3(x, u), xv = dot3(x, v);
    double den = uu * vv - uv * uv;
    double b1 = (vv * xu - uv * xv) / den, b2 = (uu * xv - uv * xu) / den;
    if (!(b1 >= -1e-9 && b2 >= -1e-9 && b1 + b2 <= 1 + 1e-9)) return 0;
    *s = sp;
    return 1;
}

/* Ericson 2005 sec. 5.1.5 (ClosestPtPointTriangle): the closest point of t
   to p by the Voronoi region of p (a vertex, an edge, the face) */
double aug_point_tri(const double *p, const double *t)
{
    const double *a = t, *b = t + 3, *c = t + 6;
    double ab[3], ac[3], ap[3], bp[3], cp[3], x[3];
    sub3(b, a, ab);
    sub3(c, a, ac);
    sub3(p, a, ap);
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) return sqrt(dot3(ap, ap));
    sub3(p, b, bp);
    double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) return sqrt(dot3(bp, bp));
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double s = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++) x[k] = a[k] + s * ab[k] - p[k];
        return sqrt(dot3(x, x));
    }
    sub3(p, c, cp);
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) return sqrt(dot3(cp, cp));
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double s = d2 / (d2 - d6);
        for (int k = 0; k < 3; k++) x[k] = a[k] + s * ac[k] - p[k];
        return sqrt(dot3(x, x));
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        double s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++) x[k] = b[k] + s * (c[k] - b[k]) - p[k];
        return sqrt(dot3(x, x));
    }
    double den = 1 / (va + vb + vc), v = vb * den, w = vc * den;
    for (int k = 0; k < 3; k++) x[k] = a[k] + ab[k] * v + ac[k] * w - p[k];
    return sqrt(dot3(x, x));
}
