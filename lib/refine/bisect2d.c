/* Conformal longest-edge bisection of triangles above the aspect-ratio bound:
   ACDM's localised optimisation (thesis 003, sec. 3.3.2, algorithm 1) as
   Rivara's longest-edge propagation path (LEPP) bisection with Lawson flips. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_refine.h"

#define X(w, i) ((w)->m.x + 2 * (size_t)(i))
#define C(w, t) ((w)->m.conn + 3 * (size_t)(t))

static double len2(const aug_work *w, int32_t a, int32_t b)
{
    const double *p = X(w, a), *q = X(w, b);
    double dx = q[0] - p[0], dy = q[1] - p[1];
    return dx * dx + dy * dy;
}

/* total order on edges: length, then the node pair */
static int longer(const aug_work *w, int32_t a, int32_t b, int32_t c, int32_t d)
{
    double l1 = len2(w, a, b), l2 = len2(w, c, d);
    if (l1 != l2) return l1 > l2;
    int32_t lo1 = a < b ? a : b, hi1 = a < b ? b : a, lo2 = c < d ? c : d, hi2 = c < d ? d : c;
    return lo1 != lo2 ? lo1 > lo2 : hi1 > hi2;
}

/* index i of the longest edge (conn[i], conn[i+1]) of t */
static int longest(const aug_work *w, int64_t t)
{
    const int32_t *v = C(w, t);
    int k = 0;
    for (int i = 1; i < 3; i++)
        if (longer(w, v[i], v[(i + 1) % 3], v[k], v[(k + 1) % 3])) k = i;
    return k;
}

/* angle at corner i of t, degrees */
static double corner(const aug_work *w, int64_t t, int i)
{
    const int32_t *v = C(w, t);
    const double *p = X(w, v[i]), *a = X(w, v[(i + 1) % 3]), *b = X(w, v[(i + 2) % 3]);
    double ux = a[0] - p[0], uy = a[1] - p[1], vx = b[0] - p[0], vy = b[1] - p[1];
    return atan2(fabs(ux * vy - uy * vx), ux * vx + uy * vy) * 180 / M_PI;
}

/* bad: l_max / l_min > max_aspect (thesis 003 eq. 3.10; the bound d <= 3 of sec.
   3.2.2) or an angle < min_angle; with area_ratio > 0 only when also |A| >
   area_ratio A_0 (the area ratio of thesis sec. 5.2) */
int aug_bisect2d_bad(const aug_work *w, int64_t e, const aug_refine_opt *o)
{
    const int32_t *v = C(w, e);
    double lmin = INFINITY, lmax = 0;
    for (int i = 0; i < 3; i++) {
        double l = len2(w, v[i], v[(i + 1) % 3]);
        lmin = fmin(lmin, l);
        lmax = fmax(lmax, l);
    }
    int bad = o->max_aspect > 0 && lmax > o->max_aspect * o->max_aspect * lmin;
    if (!bad && o->min_angle > 0)
        for (int i = 0; i < 3 && !bad; i++) bad = corner(w, e, i) < o->min_angle;
    if (bad && o->area_ratio > 0) {
        double a = fabs(aug_elem_measure(&w->m, e));
        bad = a > o->area_ratio * w->area0[e];
    }
    return bad;
}

/* an edge bisection cannot move: boundary, fixed, or between materials */
static int constrained(const aug_work *w, int64_t t, int32_t a, int32_t b)
{
    int64_t n = aug_work_across(w, t, a, b);
    return n < 0 || aug_work_edge_fixed(w, a, b) || w->m.mat[n] != w->m.mat[t];
}

/* a corner between two constrained edges sharper than the bound allows: the
   longest/shortest ratio of a triangle with angle th is >= 1 / (2 sin(th/2)) */
static int hopeless(const aug_work *w, int64_t t, double thmin)
{
    const int32_t *v = C(w, t);
    for (int i = 0; i < 3; i++) {
        if (corner(w, t, i) >= thmin) continue;
        int32_t p = v[i], a = v[(i + 1) % 3], b = v[(i + 2) % 3];
        if (constrained(w, t, p, a) && constrained(w, t, b, p)) return 1;
    }
    return 0;
}

static int32_t score(const aug_work *w, const aug_parent_rule *pr, int32_t node)
{
    while (node >= pr->nscore && node >= w->nn_begin) node = w->parent[node - w->nn_begin];
    return node < pr->nscore ? pr->score[node] : 0;
}

typedef struct ivec {
    int64_t *p;
    int64_t n, cap, head;
} ivec;

static int ipush(ivec *v, int64_t x)
{
    if (v->n == v->cap) {
        int64_t cap = v->cap ? 2 * v->cap : 256;
        int64_t *q = aug_realloc(v->p, (size_t)cap * sizeof *q);
        if (!q) return -1;
        v->p = q;
        v->cap = cap;
    }
    v->p[v->n++] = x;
    return 0;
}

/* flip the edge {u, v} of triangle t (which holds m) when the opposite vertex of
   its neighbour lies strictly in t's circumcircle and the quadrilateral is convex
   ([Lawson 1977]); recurse on the new edges (depth <= 64); never a boundary, fixed
   or material edge */
static int legalize(aug_work *w, int64_t t, int32_t u, int32_t v, int32_t m, ivec *touched,
                    aug_bisect_stats *st, int depth)
{
    if (depth > 64) return 0;
    int64_t n = aug_work_across(w, t, u, v);
    if (n < 0 || aug_work_edge_fixed(w, u, v) || w->m.mat[n] != w->m.mat[t]) return 0;
    const int32_t *a = C(w, t);
    int i = a[0] == m ? 0 : a[1] == m ? 1 : 2;
    int32_t p = a[(i + 1) % 3], q = a[(i + 2) % 3]; /* t = (m, p, q) ccw, edge p->q */
    const int32_t *b = C(w, n);
    int32_t y = b[0] != p && b[0] != q ? b[0] : b[1] != p && b[1] != q ? b[1] : b[2];
    const double *xm = X(w, m), *xp = X(w, p), *xq = X(w, q), *xy = X(w, y);
    double ar = aug_orient2d(xp, xq, xm);
    if (aug_incircle(xp, xq, xm, xy, 1e-10) <= 0) return 0;
    if (aug_orient2d(xp, xy, xm) <= 1e-12 * ar || aug_orient2d(xy, xq, xm) <= 1e-12 * ar) return 0;
    double a0 = 0.5 * (w->area0[t] + w->area0[n]);
    int32_t c1[3] = {m, p, y}, c2[3] = {m, y, q};
    int rc = aug_work_unlink(w, t);
    if (!rc) rc = aug_work_unlink(w, n);
    if (!rc) rc = aug_work_put(w, t, c1);
    if (!rc) rc = aug_work_put(w, n, c2);
    if (rc) return rc;
    w->area0[t] = w->area0[n] = a0;
    st->flips++;
    if (ipush(touched, t) || ipush(touched, n)) return AUG_ENOMEM;
    rc = legalize(w, t, p, y, m, touched, st, depth + 1);
    if (!rc) rc = legalize(w, n, y, q, m, touched, st, depth + 1);
    return rc;
}

/* bisect edge {a, b}: both triangles on it split at the midpoint */
static int bisect(aug_work *w, int32_t a, int32_t b, const aug_parent_rule *pr, int flip,
                  ivec *touched, aug_bisect_stats *st)
{
    const int32_t *s = aug_edgemap_get(&w->adj, a, b);
    if (!s) return AUG_EDATA;
    int64_t tt[2] = {s[0], s[1]};
    int32_t sa = score(w, pr, a), sb = score(w, pr, b);
    int32_t par = sa != sb ? (sa < sb ? a : b) : (a < b ? a : b); /* equidistant: lower index */
    double mid[2] = {0.5 * (X(w, a)[0] + X(w, b)[0]), 0.5 * (X(w, a)[1] + X(w, b)[1])};
    int32_t m = aug_work_node(w, mid, par);
    if (m < 0) return AUG_ENOMEM;
    aug_work_creators(w, m, (int32_t[2]){a, b}, 2);
    if (aug_work_edge_fixed(w, a, b)) {
        aug_edgemap_del(&w->fixed, a, b);
        if (!aug_edgemap_put(&w->fixed, a, m) || !aug_edgemap_put(&w->fixed, m, b)) return AUG_ENOMEM;
    }
    int64_t kids[4];
    int nk = 0;
    for (int k = 0; k < 2; k++) {
        int64_t t = tt[k];
        if (t < 0) continue;
        const int32_t *v = C(w, t);
        int i = 0;
        while (!((v[i] == a && v[(i + 1) % 3] == b) || (v[i] == b && v[(i + 1) % 3] == a))) i++;
        int32_t p = v[i], q = v[(i + 1) % 3], x = v[(i + 2) % 3];
        int32_t c1[3] = {p, m, x}, c2[3] = {m, q, x};
        int rc = aug_work_set(w, t, c1);
        if (rc) return rc;
        int64_t t2 = aug_work_add(w, c2, w->m.mat[t], w->area0[t]);
        if (t2 < 0) return AUG_ENOMEM;
        kids[nk++] = t, kids[nk++] = t2;
    }
    st->bisections++;
    for (int k = 0; k < nk; k++)
        if (ipush(touched, kids[k])) return AUG_ENOMEM;
    if (!flip) return 0;
    for (int k = 0; k < nk; k++) {
        const int32_t *v = C(w, kids[k]);
        if (v[0] != m && v[1] != m && v[2] != m) continue; /* flipped away meanwhile */
        int i = v[0] == m ? 0 : v[1] == m ? 1 : 2;
        int rc = legalize(w, kids[k], v[(i + 1) % 3], v[(i + 2) % 3], m, touched, st, 0);
        if (rc) return rc;
    }
    return 0;
}

/* Delaunay insertion of the centroid of the terminal quadrilateral t1 + t2 (their
   common longest edge a-b is interior and free): the triangle holding it is split
   in three, then Lawson flips of the edges opposite to it (Rivara's Lepp-Delaunay,
   which avoids the collinear midpoints that keep a small angle alive) */
static int centroid(aug_work *w, int64_t t1, int64_t t2, int32_t a, int32_t b,
                    const aug_parent_rule *pr, int flip, ivec *touched, aug_bisect_stats *st)
{
    const int32_t *u1 = C(w, t1), *u2 = C(w, t2);
    int32_t x1 = u1[0] != a && u1[0] != b ? u1[0] : u1[1] != a && u1[1] != b ? u1[1] : u1[2];
    int32_t x2 = u2[0] != a && u2[0] != b ? u2[0] : u2[1] != a && u2[1] != b ? u2[1] : u2[2];
    int32_t q4[4] = {a, b, x1, x2};
    double c[2] = {0, 0};
    for (int k = 0; k < 4; k++) c[0] += 0.25 * X(w, q4[k])[0], c[1] += 0.25 * X(w, q4[k])[1];
    double oa = aug_orient2d(X(w, a), X(w, b), c), ox = aug_orient2d(X(w, a), X(w, b), X(w, x1));
    if (fabs(oa) <= 1e-9 * fabs(ox)) return 1; /* on the edge: bisect it instead */
    int64_t t = (oa > 0) == (ox > 0) ? t1 : t2;
    const int32_t *v = C(w, t);
    int32_t p = v[0], q = v[1], x = v[2];
    /* the centroid must be strictly inside t */
    if (!(aug_orient2d(X(w, p), X(w, q), c) > 0 && aug_orient2d(X(w, q), X(w, x), c) > 0 &&
          aug_orient2d(X(w, x), X(w, p), c) > 0))
        return 1;
    int32_t par = q4[0];
    for (int k = 1; k < 4; k++) { /* fewest constraints, then nearest, then lowest index */
        int32_t sk = score(w, pr, q4[k]), sp = score(w, pr, par);
        double dk = (X(w, q4[k])[0] - c[0]) * (X(w, q4[k])[0] - c[0]) + (X(w, q4[k])[1] - c[1]) * (X(w, q4[k])[1] - c[1]);
        double dp = (X(w, par)[0] - c[0]) * (X(w, par)[0] - c[0]) + (X(w, par)[1] - c[1]) * (X(w, par)[1] - c[1]);
        if (sk < sp || (sk == sp && (dk < dp || (dk == dp && q4[k] < par)))) par = q4[k];
    }
    int32_t m = aug_work_node(w, c, par);
    if (m < 0) return AUG_ENOMEM;
    aug_work_creators(w, m, q4, 4);
    int32_t c1[3] = {p, q, m}, c2[3] = {q, x, m}, c3[3] = {x, p, m};
    int rc = aug_work_set(w, t, c1);
    if (rc) return rc;
    int64_t s2 = aug_work_add(w, c2, w->m.mat[t], w->area0[t]);
    int64_t s3 = aug_work_add(w, c3, w->m.mat[t], w->area0[t]);
    if (s2 < 0 || s3 < 0) return AUG_ENOMEM;
    st->bisections++;
    int64_t kids[3] = {t, s2, s3};
    for (int k = 0; k < 3; k++)
        if (ipush(touched, kids[k])) return AUG_ENOMEM;
    if (!flip) return 0;
    for (int k = 0; k < 3; k++) {
        const int32_t *y = C(w, kids[k]);
        if (y[0] != m && y[1] != m && y[2] != m) continue;
        int i = y[0] == m ? 0 : y[1] == m ? 1 : 2;
        if ((rc = legalize(w, kids[k], y[(i + 1) % 3], y[(i + 2) % 3], m, touched, st, 0))) return rc;
    }
    return 0;
}

/* terminal edge of the longest-edge propagation path from t ([Rivara 1997]): the
   longest edge shared with the neighbour whose own longest edge it is, or a
   boundary edge */
static void lepp(const aug_work *w, int64_t t, int32_t *ea, int32_t *eb)
{
    for (int64_t steps = 0;; steps++) {
        const int32_t *v = C(w, t);
        int i = longest(w, t);
        int32_t a = v[i], b = v[(i + 1) % 3];
        int64_t n = aug_work_across(w, t, a, b);
        if (n < 0 || steps > 100000) {
            *ea = a, *eb = b;
            return;
        }
        const int32_t *u = C(w, n);
        int j = longest(w, n);
        int32_t c = u[j], d = u[(j + 1) % 3];
        if ((c == a && d == b) || (c == b && d == a)) {
            *ea = a, *eb = b;
            return;
        }
        t = n;
    }
}

/* ACDM's localised optimisation (thesis 003 sec. 3.3.2, algorithm 1) as LEPP
   bisection ([Rivara 1997]), in place of algorithm 1's bisection of a triangle and
   its neighbours: for each still-bad queued triangle t, the terminal edge of its
   LEPP is bisected (or, with o->flip, the terminal quadrilateral gets its centroid,
   Lepp-Delaunay) until t itself is split; bad triangles touched are queued. Skipped
   (counted): hopeless corners, edges below 1e-10 of the mesh extent, the node cap. */
int aug_bisect2d(aug_work *w, const int64_t *seeds, int64_t nseed, const aug_refine_opt *o,
                 const aug_parent_rule *pr, aug_bisect_stats *st, aug_err *e)
{
    memset(st, 0, sizeof *st);
    ivec q = {0}, touched = {0};
    int rc = 0;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int64_t i = 0; i < w->m.nn; i++)
        for (int c = 0; c < 2; c++) lo[c] = fmin(lo[c], X(w, i)[c]), hi[c] = fmax(hi[c], X(w, i)[c]);
    double floor2 = 1e-20 * ((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]));
    double thmin = o->max_aspect > 0.5 ? 2 * asin(1 / (2 * o->max_aspect)) * 180 / M_PI : 0;
    thmin = fmax(thmin, o->min_angle);
    int64_t cap = w->max_new > 0 ? w->max_new : o->max_new > 0 ? o->max_new : 200000;
    for (int64_t i = 0; i < nseed; i++)
        if (aug_bisect2d_bad(w, seeds[i], o) && ipush(&q, seeds[i] << 20 | (w->ver[seeds[i]] & 0xfffff)))
            goto nomem;
    while (q.head < q.n) {
        int64_t t = q.p[q.head] >> 20, ver = q.p[q.head] & 0xfffff;
        q.head++;
        if ((w->ver[t] & 0xfffff) != ver || !aug_bisect2d_bad(w, t, o)) continue;
        if (hopeless(w, t, thmin)) {
            st->skipped_corner++;
            continue;
        }
        int32_t a, b;
        const int32_t *v = C(w, t);
        int i = longest(w, t);
        if (len2(w, v[i], v[(i + 1) % 3]) < floor2) {
            st->skipped_small++;
            continue;
        }
        if (w->m.nn - w->nn_begin >= cap) {
            st->capped++;
            continue;
        }
        touched.n = 0;
        int32_t v0 = w->ver[t];
        for (int it = 0; w->ver[t] == v0 && it < 256; it++) { /* until t itself is split */
            if (w->m.nn - w->nn_begin >= cap) { /* each bisection or centroid adds one node */
                st->capped++;
                break;
            }
            lepp(w, t, &a, &b);
            const int32_t *sl = aug_edgemap_get(&w->adj, a, b);
            int64_t t1 = sl[0], t2 = sl[1];
            rc = 1;
            if (o->flip && t1 >= 0 && t2 >= 0 && !aug_work_edge_fixed(w, a, b) &&
                w->m.mat[t1] == w->m.mat[t2])
                rc = centroid(w, t1, t2, a, b, pr, o->flip, &touched, st);
            if (rc == 1) rc = bisect(w, a, b, pr, o->flip, &touched, st);
            if (rc) goto fail;
        }
        for (int64_t k = 0; k < touched.n; k++) {
            int64_t u = touched.p[k];
            if (aug_bisect2d_bad(w, u, o) && ipush(&q, u << 20 | (w->ver[u] & 0xfffff))) goto nomem;
        }
    }
    free(q.p);
    free(touched.p);
    return 0;
nomem:
    rc = AUG_ENOMEM;
fail:
    free(q.p);
    free(touched.p);
    return aug_err_set(e, rc, -1, "MDLT", "%s",
                       rc == AUG_ENOMEM ? "out of memory" : "refinement met a non-manifold edge");
}
