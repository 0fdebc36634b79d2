/* Conditional (constrained) Delaunay re-triangulation of a local planar region:
   Bowyer-Watson insertion, segment recovery ([Anglada 1997]), Lawson flips
   (thesis 003, secs. 3.2.2 and 3.3.1; [Bowyer 1981], [Watson 1981], [Lawson 1977]). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_refine.h"

#define V(c, i) ((c)->xy + 2 * (size_t)(i))
#define T(c, t) ((c)->tri + 3 * (size_t)(t))

int aug_cdt_init(aug_cdt *c)
{
    memset(c, 0, sizeof *c);
    c->eps = 1e-12;
    if (aug_edgemap_init(&c->edges, 256) || aug_edgemap_init(&c->fixed, 64)) {
        aug_cdt_free(c);
        return -1;
    }
    return 0;
}

void aug_cdt_free(aug_cdt *c)
{
    free(c->xy);
    free(c->tri);
    free(c->tag);
    free(c->freel);
    aug_edgemap_free(&c->edges);
    aug_edgemap_free(&c->fixed);
    memset(c, 0, sizeof *c);
}

void aug_cdt_reset(aug_cdt *c)
{
    c->nv = c->nt = c->nfree = 0;
    c->flips = 0;
    aug_edgemap_clear(&c->edges);
    aug_edgemap_clear(&c->fixed);
}

int32_t aug_cdt_vertex(aug_cdt *c, double x, double y)
{
    if (c->nv == c->capv) {
        int32_t cap = c->capv ? 2 * c->capv : 256;
        double *p = aug_realloc(c->xy, (size_t)cap * 2 * sizeof *p);
        if (!p) return -1;
        c->xy = p;
        c->capv = cap;
    }
    c->xy[2 * c->nv] = x;
    c->xy[2 * c->nv + 1] = y;
    return c->nv++;
}

/* (b - a) x (p - a) = twice the signed area of (a, b, p): > 0 when p is left of
   a->b (the orient2d of [Shewchuk 1997], in plain floating point) */
double aug_orient2d(const double *a, const double *b, const double *p)
{
    return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
}

static double dist2(const double *a, const double *b)
{
    double dx = b[0] - a[0], dy = b[1] - a[1];
    return dx * dx + dy * dy;
}

/* sign of orient(a, b, p): 0 when p is within eps * |ab| of the line */
static int side(const aug_cdt *c, const double *a, const double *b, const double *p)
{
    double o = aug_orient2d(a, b, p);
    double s = sqrt(dist2(a, b) * fmax(dist2(a, p), dist2(b, p)));
    if (fabs(o) <= c->eps * s) return 0;
    return o > 0 ? 1 : -1;
}

/* p on the open segment (a, b), within tolerance */
static int on_segment(const aug_cdt *c, const double *a, const double *b, const double *p)
{
    if (side(c, a, b, p)) return 0;
    double l2 = dist2(a, b);
    double s = ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / l2;
    double tol = 1e2 * c->eps;
    return s > tol && s < 1 - tol;
}

/* in-circle of (a, b, d) counter-clockwise: > 0 when p is strictly inside */
int aug_cdt_incircle(const aug_cdt *c, const double *a, const double *b, const double *d,
                     const double *p)
{
    return aug_incircle(a, b, d, p, 1e2 * c->eps);
}

/* sign of the in-circle determinant of p against (a, b, d) counter-clockwise
   (the incircle of [Shewchuk 1997] without its exact stages): > 0 strictly
   inside, 0 when |det| <= eps times its permanent (co-circular ties) */
int aug_incircle(const double *a, const double *b, const double *d, const double *p, double eps)
{
    double adx = a[0] - p[0], ady = a[1] - p[1];
    double bdx = b[0] - p[0], bdy = b[1] - p[1];
    double cdx = d[0] - p[0], cdy = d[1] - p[1];
    double al = adx * adx + ady * ady, bl = bdx * bdx + bdy * bdy, cl = cdx * cdx + cdy * cdy;
    double t1 = bdx * cdy - cdx * bdy, t2 = cdx * ady - adx * cdy, t3 = adx * bdy - bdx * ady;
    double det = al * t1 + bl * t2 + cl * t3;
    double perm = al * (fabs(bdx * cdy) + fabs(cdx * bdy)) + bl * (fabs(cdx * ady) + fabs(adx * cdy)) +
                  cl * (fabs(adx * bdy) + fabs(bdx * ady));
    double tol = eps * perm;
    return det > tol ? 1 : det < -tol ? -1 : 0;
}

static int link_tri(aug_cdt *c, int32_t t)
{
    const int32_t *v = T(c, t);
    for (int i = 0; i < 3; i++) {
        int rc = aug_edgemap_link(&c->edges, v[i], v[(i + 1) % 3], t);
        if (rc) {
            for (int j = 0; j < i; j++) aug_edgemap_unlink(&c->edges, v[j], v[(j + 1) % 3], t);
            return rc == -1 ? AUG_ENOMEM : AUG_EDATA;
        }
    }
    return 0;
}

static void kill_tri(aug_cdt *c, int32_t t)
{
    int32_t *v = T(c, t);
    for (int i = 0; i < 3; i++) aug_edgemap_unlink(&c->edges, v[i], v[(i + 1) % 3], t);
    v[0] = v[1] = v[2] = -1;
    c->freel[c->nfree++] = t;
}

static int32_t new_slot(aug_cdt *c)
{
    if (c->nfree) return c->freel[--c->nfree];
    if (c->nt == c->capt) {
        int32_t cap = c->capt ? 2 * c->capt : 256;
        int32_t *t = aug_realloc(c->tri, (size_t)cap * 3 * sizeof *t);
        if (!t) return -1;
        c->tri = t;
        int32_t *g = aug_realloc(c->tag, (size_t)cap * sizeof *g);
        if (!g) return -1;
        c->tag = g;
        int32_t *f = aug_realloc(c->freel, (size_t)cap * sizeof *f);
        if (!f) return -1;
        c->freel = f;
        c->capt = cap;
    }
    return c->nt++;
}

int32_t aug_cdt_tri(aug_cdt *c, int32_t a, int32_t b, int32_t d, int32_t tag)
{
    int32_t t = new_slot(c);
    if (t < 0) return -1;
    int32_t *v = T(c, t);
    v[0] = a, v[1] = b, v[2] = d;
    c->tag[t] = tag;
    if (link_tri(c, t)) {
        v[0] = v[1] = v[2] = -1;
        c->freel[c->nfree++] = t;
        return -1;
    }
    return t;
}

int aug_cdt_fix(aug_cdt *c, int32_t a, int32_t b)
{
    int32_t *s = aug_edgemap_put(&c->fixed, a, b);
    if (!s) return -1;
    s[0] = 1;
    return 0;
}

int aug_cdt_is_fixed(const aug_cdt *c, int32_t a, int32_t b)
{
    return aug_edgemap_get(&c->fixed, a, b) != NULL;
}

int32_t aug_cdt_across(const aug_cdt *c, int32_t t, int32_t a, int32_t b)
{
    const int32_t *s = aug_edgemap_get(&c->edges, a, b);
    if (!s) return -1;
    return s[0] == t ? s[1] : s[0];
}

/* smallest normalised barycentric coordinate of p in triangle t */
static double bary_min(const aug_cdt *c, int32_t t, const double *p)
{
    const int32_t *v = T(c, t);
    const double *a = V(c, v[0]), *b = V(c, v[1]), *d = V(c, v[2]);
    double A = aug_orient2d(a, b, d);
    if (!(A > 0)) return -INFINITY;
    double l0 = aug_orient2d(b, d, p) / A, l1 = aug_orient2d(d, a, p) / A, l2 = aug_orient2d(a, b, p) / A;
    return fmin(l0, fmin(l1, l2));
}

static int32_t at_vertex(const aug_cdt *c, int32_t t, const double *p)
{
    const int32_t *v = T(c, t);
    double h2 = 0;
    for (int i = 0; i < 3; i++) h2 = fmax(h2, dist2(V(c, v[i]), V(c, v[(i + 1) % 3])));
    for (int i = 0; i < 3; i++)
        if (dist2(V(c, v[i]), p) <= 1e4 * c->eps * c->eps * h2) return v[i]; /* 1e-10 h */
    return -1;
}

/* triangle whose closure holds p = (x, y) (least barycentric >= -1e3 eps): a
   visibility walk from hint across the edge p is farthest outside of, else the
   best triangle of a scan (-1 when none holds it); *at = a vertex at p or -1 */
int32_t aug_cdt_locate(const aug_cdt *c, double x, double y, int32_t hint, int32_t *at)
{
    double p[2] = {x, y};
    double tol = 1e3 * c->eps;
    int32_t best = -1;
    if (hint >= 0 && hint < c->nt && T(c, hint)[0] >= 0) { /* visibility walk */
        int32_t t = hint;
        for (int32_t steps = 0; steps < c->nt + 4; steps++) {
            const int32_t *v = T(c, t);
            int32_t next = -1;
            double worst = 0;
            for (int i = 0; i < 3; i++) {
                const double *a = V(c, v[i]), *b = V(c, v[(i + 1) % 3]);
                double len = sqrt(dist2(a, b));
                double d = aug_orient2d(a, b, p) / len; /* signed distance, < 0 outside */
                if (d < -tol * len && d < worst) {
                    int32_t n = aug_cdt_across(c, t, v[i], v[(i + 1) % 3]);
                    if (n >= 0) worst = d, next = n;
                }
            }
            if (next < 0) {
                if (bary_min(c, t, p) >= -tol) best = t;
                break;
            }
            t = next;
        }
    }
    if (best < 0) {
        double bm = -INFINITY;
        for (int32_t t = 0; t < c->nt; t++) {
            if (T(c, t)[0] < 0) continue;
            double m = bary_min(c, t, p);
            if (m > bm) bm = m, best = t;
        }
        if (bm < -tol) best = -1;
    }
    if (at) *at = best >= 0 ? at_vertex(c, best, p) : -1;
    return best;
}

/* ---- Bowyer-Watson insertion ---- */

typedef struct vec32 {
    int32_t *p;
    int32_t n, cap;
} vec32;

static int push(vec32 *v, int32_t x)
{
    if (v->n == v->cap) {
        int32_t cap = v->cap ? 2 * v->cap : 64;
        int32_t *q = aug_realloc(v->p, (size_t)cap * sizeof *q);
        if (!q) return -1;
        v->p = q;
        v->cap = cap;
    }
    v->p[v->n++] = x;
    return 0;
}

static int in_list(const vec32 *v, int32_t x)
{
    for (int32_t i = 0; i < v->n; i++)
        if (v->p[i] == x) return 1;
    return 0;
}

/* would adding n to the cavity remove a fixed edge that p is not on? */
static int fixed_clash(const aug_cdt *c, const vec32 *cav, int32_t n, const double *p)
{
    const int32_t *w = T(c, n);
    for (int i = 0; i < 3; i++) {
        int32_t a = w[i], b = w[(i + 1) % 3];
        if (!aug_cdt_is_fixed(c, a, b)) continue;
        int32_t m = aug_cdt_across(c, n, a, b);
        if (m >= 0 && in_list(cav, m) && !on_segment(c, V(c, a), V(c, b), p)) return 1;
    }
    return 0;
}

/* keep the cavity triangles connected to the first nforced ones */
static int reconnect(const aug_cdt *c, vec32 *cav, int nforced)
{
    vec32 keep = {0};
    for (int i = 0; i < nforced; i++)
        if (push(&keep, cav->p[i])) return -1;
    for (int32_t k = 0; k < keep.n; k++) {
        const int32_t *v = T(c, keep.p[k]);
        for (int i = 0; i < 3; i++) {
            int32_t n = aug_cdt_across(c, keep.p[k], v[i], v[(i + 1) % 3]);
            if (n >= 0 && in_list(cav, n) && !in_list(&keep, n) && push(&keep, n)) {
                free(keep.p);
                return -1;
            }
        }
    }
    free(cav->p);
    *cav = keep;
    return 0;
}

/* Bowyer-Watson insertion of vertex vi into triangle t0 holding it ([Bowyer 1981],
   [Watson 1981]; thesis 003 sec. 3.3.1): the cavity grows from t0 (and the
   triangles across an edge vi lies on) to neighbours whose circumcircle strictly
   holds vi, never across a fixed edge, is shrunk until star-shaped from vi and
   re-triangulated as vi's star; a fixed edge under vi becomes two fixed halves.
   AUG_EDATA when vi is at a vertex or t0 cannot see it. */
int aug_cdt_insert(aug_cdt *c, int32_t vi, int32_t t0)
{
    const double *p = V(c, vi);
    vec32 cav = {0}, bnd = {0}, split = {0};
    int rc = AUG_ENOMEM;
    if (at_vertex(c, t0, p) >= 0) return AUG_EDATA;
    if (push(&cav, t0)) goto out;
    int nforced = 1;
    const int32_t *v0 = T(c, t0);
    for (int i = 0; i < 3; i++) {
        if (!on_segment(c, V(c, v0[i]), V(c, v0[(i + 1) % 3]), p)) continue;
        int32_t n = aug_cdt_across(c, t0, v0[i], v0[(i + 1) % 3]);
        if (n >= 0) {
            if (push(&cav, n)) goto out;
            nforced++;
        }
    }
    for (int32_t k = 0; k < cav.n; k++) { /* grow: circumcircle holds p, no fixed edge crossed */
        int32_t t = cav.p[k];
        const int32_t *v = T(c, t);
        for (int i = 0; i < 3; i++) {
            int32_t a = v[i], b = v[(i + 1) % 3];
            int32_t n = aug_cdt_across(c, t, a, b);
            if (n < 0 || in_list(&cav, n) || aug_cdt_is_fixed(c, a, b)) continue;
            const int32_t *w = T(c, n);
            if (aug_cdt_incircle(c, V(c, w[0]), V(c, w[1]), V(c, w[2]), p) <= 0) continue;
            if (fixed_clash(c, &cav, n, p)) continue;
            if (push(&cav, n)) goto out;
        }
    }
    for (;;) { /* the cavity must be star-shaped from p: drop triangles that spoil it */
        bnd.n = split.n = 0;
        int32_t bad = -1;
        for (int32_t k = 0; k < cav.n && bad < 0; k++) {
            int32_t t = cav.p[k];
            const int32_t *v = T(c, t);
            for (int i = 0; i < 3; i++) {
                int32_t a = v[i], b = v[(i + 1) % 3];
                int32_t n = aug_cdt_across(c, t, a, b);
                if (n >= 0 && in_list(&cav, n)) continue;
                if (on_segment(c, V(c, a), V(c, b), p)) {
                    if (push(&split, a) || push(&split, b)) goto out;
                    continue;
                }
                if (side(c, V(c, a), V(c, b), p) <= 0) {
                    bad = k;
                    break;
                }
                if (push(&bnd, a) || push(&bnd, b) || push(&bnd, c->tag[t])) goto out;
            }
        }
        if (bad < 0) break;
        if (bad < nforced) {
            rc = AUG_EDATA; /* the triangle holding p cannot see its own edge */
            goto out;
        }
        cav.p[bad] = cav.p[--cav.n];
        if (reconnect(c, &cav, nforced)) goto out;
    }
    /* fixed edges inside the cavity are split by p (p on them) */
    int fixsplit[2] = {-1, -1};
    for (int32_t k = 0; k < cav.n; k++) {
        const int32_t *v = T(c, cav.p[k]);
        for (int i = 0; i < 3; i++) {
            int32_t a = v[i], b = v[(i + 1) % 3];
            if (aug_cdt_is_fixed(c, a, b) && on_segment(c, V(c, a), V(c, b), p))
                fixsplit[0] = a, fixsplit[1] = b;
        }
    }
    for (int32_t k = 0; k < split.n; k += 2)
        if (aug_cdt_is_fixed(c, split.p[k], split.p[k + 1]))
            fixsplit[0] = split.p[k], fixsplit[1] = split.p[k + 1];
    for (int32_t k = 0; k < cav.n; k++) kill_tri(c, cav.p[k]);
    for (int32_t k = 0; k < bnd.n; k += 3)
        if (aug_cdt_tri(c, bnd.p[k], bnd.p[k + 1], vi, bnd.p[k + 2]) < 0) goto out;
    if (fixsplit[0] >= 0) {
        aug_edgemap_del(&c->fixed, fixsplit[0], fixsplit[1]);
        if (aug_cdt_fix(c, fixsplit[0], vi) || aug_cdt_fix(c, vi, fixsplit[1])) goto out;
    }
    rc = 0;
out:
    free(cav.p);
    free(bnd.p);
    free(split.p);
    return rc;
}

/* ---- segment recovery ---- */

/* Delaunay triangulation of the pseudo-polygon a, chain[0..k-1], b whose chain
   lies left of a->b (Anglada 1997): the chain vertex whose circle with a, b
   holds no other splits it. */
static int pseudo(aug_cdt *c, int32_t a, int32_t b, const int32_t *ch, int32_t k, int32_t tag)
{
    if (k == 0) return 0;
    int32_t ci = 0;
    for (int32_t i = 1; i < k; i++)
        if (aug_cdt_incircle(c, V(c, a), V(c, b), V(c, ch[ci]), V(c, ch[i])) > 0) ci = i;
    if (pseudo(c, a, ch[ci], ch, ci, tag) || pseudo(c, ch[ci], b, ch + ci + 1, k - ci - 1, tag))
        return -1;
    return aug_cdt_tri(c, a, b, ch[ci], tag) < 0 ? -1 : 0;
}

/* make a-b an edge and fix it ([Anglada 1997]): the triangles a->b crosses are
   removed and the pseudo-polygons on its two sides re-triangulated Delaunay
   (pseudo); a vertex on ab splits it; AUG_EDATA when ab crosses a fixed edge or
   leaves the region */
int aug_cdt_recover(aug_cdt *c, int32_t a, int32_t b)
{
    if (a == b) return 0;
    if (aug_edgemap_get(&c->edges, a, b)) return aug_cdt_fix(c, a, b) ? AUG_ENOMEM : 0;
    const double *pa = V(c, a), *pb = V(c, b);
    int32_t t = -1, u = -1, w = -1;
    for (int32_t s = 0; s < c->nt && t < 0; s++) { /* the triangle at a that b's ray enters */
        const int32_t *v = T(c, s);
        if (v[0] < 0) continue;
        int i = v[0] == a ? 0 : v[1] == a ? 1 : v[2] == a ? 2 : -1;
        if (i < 0) continue;
        int32_t x = v[(i + 1) % 3], y = v[(i + 2) % 3];
        if (on_segment(c, pa, pb, V(c, x))) return aug_cdt_recover(c, a, x) || aug_cdt_recover(c, x, b);
        if (on_segment(c, pa, pb, V(c, y))) return aug_cdt_recover(c, a, y) || aug_cdt_recover(c, y, b);
        if (side(c, pa, V(c, x), pb) > 0 && side(c, pa, pb, V(c, y)) > 0) t = s, u = x, w = y;
    }
    if (t < 0) return AUG_EDATA;
    vec32 cross = {0}, L = {0}, R = {0};
    int rc = AUG_ENOMEM;
    int32_t tag = c->tag[t], end = b;
    if (push(&cross, t) || push(&R, u) || push(&L, w)) goto out;
    for (;;) { /* walk: u right of a->b, w left */
        if (aug_cdt_is_fixed(c, u, w)) {
            rc = AUG_EDATA;
            goto out;
        }
        int32_t n = aug_cdt_across(c, t, u, w);
        if (n < 0) {
            rc = AUG_EDATA;
            goto out;
        }
        if (push(&cross, n)) goto out;
        const int32_t *v = T(c, n);
        int32_t z = v[0] != u && v[0] != w ? v[0] : v[1] != u && v[1] != w ? v[1] : v[2];
        if (z == b) break;
        if (on_segment(c, pa, pb, V(c, z))) {
            end = z;
            break;
        }
        if (side(c, pa, pb, V(c, z)) < 0) {
            if (push(&R, z)) goto out;
            u = z;
        } else {
            if (push(&L, z)) goto out;
            w = z;
        }
        t = n;
    }
    for (int32_t k = 0; k < cross.n; k++) kill_tri(c, cross.p[k]);
    for (int32_t i = 0, j = R.n - 1; i < j; i++, j--) { /* R reversed lies left of end->a */
        int32_t x = R.p[i];
        R.p[i] = R.p[j];
        R.p[j] = x;
    }
    if (pseudo(c, a, end, L.p, L.n, tag) || pseudo(c, end, a, R.p, R.n, tag)) goto out;
    if (aug_cdt_fix(c, a, end)) goto out;
    rc = end != b ? aug_cdt_recover(c, end, b) : 0;
out:
    free(cross.p);
    free(L.p);
    free(R.p);
    return rc;
}

/* ---- Lawson flips ---- */

/* Lawson flips ([Lawson 1977]) of non-fixed interior edges between triangles of
   equal tag, while the opposite vertex lies strictly in the circumcircle and the
   quadrilateral is strictly convex: the constrained Delaunay triangulation of the
   fixed edges (thesis 003 sec. 3.2.2, "Conditional Delaunay Triangulation") */
int aug_cdt_legalize(aug_cdt *c)
{
    vec32 st = {0};
    for (int32_t t = 0; t < c->nt; t++) {
        const int32_t *v = T(c, t);
        if (v[0] < 0) continue;
        for (int i = 0; i < 3; i++)
            if (v[i] < v[(i + 1) % 3] && (push(&st, v[i]) || push(&st, v[(i + 1) % 3]))) goto nomem;
    }
    while (st.n) {
        int32_t w = st.p[--st.n], u = st.p[--st.n];
        const int32_t *s = aug_edgemap_get(&c->edges, u, w);
        if (!s || s[0] < 0 || s[1] < 0 || aug_cdt_is_fixed(c, u, w)) continue;
        int32_t t1 = s[0], t2 = s[1];
        if (c->tag[t1] != c->tag[t2]) continue;
        int32_t *a = T(c, t1), *b = T(c, t2);
        int i = a[0] == u ? 0 : a[1] == u ? 1 : 2;
        if (a[(i + 1) % 3] != w) { /* orient so that t1 holds u->w */
            int32_t x = t1;
            t1 = t2, t2 = x;
            a = T(c, t1), b = T(c, t2);
            i = a[0] == u ? 0 : a[1] == u ? 1 : 2;
        }
        int32_t x = a[(i + 2) % 3];
        int32_t y = b[0] != u && b[0] != w ? b[0] : b[1] != u && b[1] != w ? b[1] : b[2];
        if (aug_cdt_incircle(c, V(c, u), V(c, w), V(c, x), V(c, y)) <= 0) continue;
        if (side(c, V(c, u), V(c, y), V(c, x)) <= 0 || side(c, V(c, y), V(c, w), V(c, x)) <= 0)
            continue;
        int32_t tag = c->tag[t1];
        kill_tri(c, t1);
        kill_tri(c, t2);
        if (aug_cdt_tri(c, u, y, x, tag) < 0 || aug_cdt_tri(c, y, w, x, tag) < 0) goto nomem;
        c->flips++;
        if (push(&st, u) || push(&st, y) || push(&st, y) || push(&st, w) || push(&st, w) ||
            push(&st, x) || push(&st, x) || push(&st, u))
            goto nomem;
    }
    free(st.p);
    return 0;
nomem:
    free(st.p);
    return AUG_ENOMEM;
}
