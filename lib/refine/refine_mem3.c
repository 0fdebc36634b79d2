/* A cut step on a membrane (mem3) sheet refined in each triangle's own plane:
   longest-edge bisection and flips between coplanar triangles, neither of
   which changes the sheet's shape (thesis 003 secs. 3.2.2-3.3). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_refine.h"

/* triangle t of the edit in its own plane: edge lengths L[k] of (c[k], c[k+1]),
   aspect = l_max / l_min (thesis 003 eq. 3.10), the least angle (degrees),
   the unit normal; returns the local index of the longest edge */
static int tri_geom(const aug_edit *ed, int64_t t, double *aspect, double *amin, double *n)
{
    const int32_t *c = aug_edit_conn(ed, t);
    double v[3][3], L[3];
    for (int k = 0; k < 3; k++) {
        aug_sub3(aug_edit_x(ed, c[(k + 1) % 3]), aug_edit_x(ed, c[k]), v[k]);
        L[k] = sqrt(aug_dot3(v[k], v[k]));
    }
    int lo = 0, hi = 0;
    for (int k = 1; k < 3; k++) lo = L[k] < L[lo] ? k : lo, hi = L[k] > L[hi] ? k : hi;
    *aspect = L[hi] / L[lo];
    *amin = 180;
    for (int k = 0; k < 3; k++) { /* the angle at c[k] between v[k] and -v[k-1] */
        const double *p = v[k], *q = v[(k + 2) % 3];
        double cs = -aug_dot3(p, q) / (L[k] * L[(k + 2) % 3]);
        *amin = fmin(*amin, acos(fmax(-1, fmin(1, cs))) * 180 / M_PI);
    }
    aug_cross3(v[0], v[2], n);
    double l = sqrt(aug_dot3(n, n));
    for (int k = 0; k < 3; k++) n[k] = -n[k] / l;
    return hi;
}

/* bad: aspect > max_aspect or least angle < min_angle (each when > 0, the
   angle only when --min-angle was given: bisection with flips in each
   triangle's plane cannot flip across a fold of the sheet, and does not
   reach 20 degrees there) */
static int bad(const aug_edit *ed, int64_t t, const aug_refine_opt *o, int *longest)
{
    double a, m, n[3];
    *longest = tri_geom(ed, t, &a, &m, n);
    return (o->max_aspect > 0 && a > o->max_aspect) || (o->min_angle_given && o->min_angle > 0 && m < o->min_angle);
}

/* bad by the aspect bound alone */
static int aspect_bad(const aug_edit *ed, int64_t t, const aug_refine_opt *o)
{
    double a, m, n[3];
    tri_geom(ed, t, &a, &m, n);
    return o->max_aspect > 0 && a > o->max_aspect;
}

/* the other triangle on edge (p, q) than t, -1 for a boundary edge */
static int64_t across(const aug_edit *ed, int64_t t, int32_t p, int32_t q)
{
    const aug_adj *adj = ed->adj;
    for (int32_t i = 0; i < adj->cnt[p]; i++) {
        int32_t s = adj->list[p][i];
        const int32_t *c = aug_edit_conn(ed, s);
        if (s != t && (c[0] == q || c[1] == q || c[2] == q)) return s;
    }
    return -1;
}

/* Lawson's flip of edge (p, q) of triangle t = (r, p, q) (Lepp-Delaunay,
   thesis 003 sec. 3.3): with (q, p, s) across it in the same plane (normals
   within 1e-10) and the same original triangle and s inside the circle of r, p, q (the angles at r and s
   sum above 180 degrees), pq becomes rs: (r, p, s), (r, s, q), in that
   plane, so the sheet is unchanged; then the new edges opposite r. */
static int legalize(aug_edit *ed, const int32_t *orig, int64_t t, int32_t r, int depth, int64_t *flips)
{
    if (depth > 64) return 0;
    const int32_t *c = aug_edit_conn(ed, t);
    int k = c[0] == r ? 0 : c[1] == r ? 1 : 2;
    int32_t p = c[(k + 1) % 3], q = c[(k + 2) % 3];
    int64_t u = across(ed, t, p, q);
    if (u < 0 || orig[u] != orig[t]) return 0; /* each refined triangle stays in its original one */
    const int32_t *cu = aug_edit_conn(ed, u);
    int32_t s = cu[0] != p && cu[0] != q ? cu[0] : cu[1] != p && cu[1] != q ? cu[1] : cu[2];
    double a0, m0, n0[3], a1, m1, n1[3];
    tri_geom(ed, t, &a0, &m0, n0);
    tri_geom(ed, u, &a1, &m1, n1);
    if (aug_dot3(n0, n1) < 1 - 1e-10) return 0;
    const double *X[4] = {aug_edit_x(ed, r), aug_edit_x(ed, p), aug_edit_x(ed, q), aug_edit_x(ed, s)};
    double e1[3], e2[3], f1[3], f2[3];
    aug_sub3(X[1], X[0], e1), aug_sub3(X[2], X[0], e2), aug_sub3(X[1], X[3], f1), aug_sub3(X[2], X[3], f2);
    double ar = acos(fmax(-1, fmin(1, aug_dot3(e1, e2) / sqrt(aug_dot3(e1, e1) * aug_dot3(e2, e2)))));
    double as = acos(fmax(-1, fmin(1, aug_dot3(f1, f2) / sqrt(aug_dot3(f1, f1) * aug_dot3(f2, f2)))));
    if (!(ar + as > M_PI * (1 + 1e-12))) return 0;
    int32_t t0[3] = {r, p, s}, t1[3] = {r, s, q};
    if (aug_edit_set(ed, t, t0) || aug_edit_set(ed, u, t1)) return -1;
    ++*flips;
    if (legalize(ed, orig, t, r, depth + 1, flips) || legalize(ed, orig, u, r, depth + 1, flips)) return -1;
    return 0;
}

/* Rivara's longest-edge propagation path from t (thesis 003 sec. 3.2.2,
   fig. 3.12): from a triangle to the one across its longest edge until that
   edge is the longest of both or on the boundary (a cut's lip, the sheet's
   edge), the terminal edge (pa, pb) to bisect; -1 when the path runs longer
   than 64 */
static int lepp(const aug_edit *ed, int64_t t, int32_t *pa, int32_t *pb)
{
    int64_t cur = t;
    for (int step = 0; step < 64; step++) {
        double a, m, n[3];
        int k = tri_geom(ed, cur, &a, &m, n);
        const int32_t *c = aug_edit_conn(ed, cur);
        int32_t x = c[k], y = c[(k + 1) % 3];
        int64_t nb = across(ed, cur, x, y);
        if (nb < 0) { /* a terminal edge on the boundary: its midpoint is on the sheet's edge */
            *pa = x, *pb = y;
            return 0;
        }
        int kn = tri_geom(ed, nb, &a, &m, n);
        const int32_t *cn = aug_edit_conn(ed, nb);
        int32_t xn = cn[kn], yn = cn[(kn + 1) % 3];
        if ((xn == x && yn == y) || (xn == y && yn == x)) {
            *pa = x, *pb = y;
            return 0;
        }
        cur = nb;
    }
    return -1;
}

/* the triangles of node r, legalized (after r split an edge) */
static int legalize_star(aug_edit *ed, const int32_t *orig, int32_t r, int64_t *flips)
{
    int32_t star[64];
    int n = 0;
    for (int32_t i = 0; i < ed->adj->cnt[r] && n < 64; i++) star[n++] = ed->adj->list[r][i];
    for (int i = 0; i < n; i++) {
        const int32_t *c = aug_edit_conn(ed, star[i]);
        if ((c[0] == r || c[1] == r || c[2] == r) && legalize(ed, orig, star[i], r, 0, flips)) return -1;
    }
    return 0;
}

/* the maps of the intact mesh: cut-view node and element i are base i */
int aug_refine_mem3_init(aug_refiner *r)
{
    const aug_mesh *m = &r->base;
    if (aug_refine_grow_i32(&r->cnode, &r->capc, m->nn + 1) || aug_refine_grow_i32(&r->cel, &r->capce, m->ne + 1) ||
        aug_refine_grow_i32(&r->own, &r->capown, m->ne + 1))
        return -1;
    if (aug_refine_grow_i32(&r->corig, &r->capcorig, m->ne + 1) || aug_refine_grow_i32(&r->borig, &r->capborig, m->ne + 1))
        return -1;
    r->conn0 = aug_malloc((size_t)(3 * m->ne + 1) * sizeof *r->conn0);
    if (!r->conn0) return -1;
    memcpy(r->conn0, m->conn, (size_t)(3 * m->ne) * sizeof *r->conn0);
    r->ne0 = m->ne;
    for (int64_t i = 0; i < m->nn; i++) r->cnode[i] = (int32_t)i;
    for (int64_t t = 0; t < m->ne; t++) r->cel[t] = r->own[t] = r->corig[t] = r->borig[t] = (int32_t)t;
    return 0;
}

/* which of the n old triangles (connectivity oldc in the cut view m) holds
   point p: the least barycentric coordinate in its plane, less the distance
   off it relative to its size, largest */
static int64_t holder3(const aug_mesh *m, const int32_t *oldc, int64_t n, const double *p)
{
    int64_t best = -1;
    double bb = -INFINITY;
    for (int64_t k = 0; k < n; k++) {
        const double *a = m->x + 3 * (int64_t)oldc[3 * k], *b = m->x + 3 * (int64_t)oldc[3 * k + 1],
                     *c = m->x + 3 * (int64_t)oldc[3 * k + 2];
        double u[3], v[3], w[3], nn[3], t[3], l = INFINITY;
        aug_sub3(b, a, u), aug_sub3(c, a, v);
        aug_cross3(u, v, nn);
        double A = aug_dot3(nn, nn);
        const double *X[3] = {a, b, c};
        for (int j = 0; j < 3; j++) {
            aug_sub3(X[(j + 2) % 3], X[(j + 1) % 3], u), aug_sub3(p, X[(j + 1) % 3], w);
            aug_cross3(u, w, t);
            l = fmin(l, aug_dot3(t, nn) / A);
        }
        aug_sub3(p, a, w);
        double off = fabs(aug_dot3(w, nn)) / A; /* distance / sqrt(2 area) ... relative */
        if (l - off > bb) bb = l - off, best = k;
    }
    return best;
}

/* can edge (p, q) of triangle t not flip (the sheet's edge, a lip, a fold, or
   the edge of its original triangle)? */
static int stiff_edge(const aug_edit *ed, const int32_t *orig, int64_t t, int32_t p, int32_t q)
{
    int64_t u = across(ed, t, p, q);
    return u < 0 || orig[u] != orig[t];
}

/* a corner sharper than thmin between two edges that cannot flip: bisection
   keeps that angle in a child, so the triangle is left (as tri3's corners
   between two constrained edges, bisect2d.c) */
static int hopeless_mem3(const aug_edit *ed, const int32_t *orig, int64_t t, double thmin)
{
    const int32_t *c = aug_edit_conn(ed, t);
    for (int k = 0; k < 3; k++) {
        double u[3], v[3];
        aug_sub3(aug_edit_x(ed, c[(k + 1) % 3]), aug_edit_x(ed, c[k]), u);
        aug_sub3(aug_edit_x(ed, c[(k + 2) % 3]), aug_edit_x(ed, c[k]), v);
        double ang = acos(fmax(-1, fmin(1, aug_dot3(u, v) / sqrt(aug_dot3(u, u) * aug_dot3(v, v))))) * 180 / M_PI;
        if (ang < thmin && stiff_edge(ed, orig, t, c[k], c[(k + 1) % 3]) && stiff_edge(ed, orig, t, c[(k + 2) % 3], c[k])) {
            return 1;
        }
    }
    return 0;
}

int aug_refine_mem3_creators(aug_refiner *r, int32_t node, const int32_t *c, int n)
{
    if (aug_refine_grow_i32(&r->cre3, &r->capcre3, 4 * ((int64_t)node + 1))) return -1; /* (-1 filled) */
    for (int k = 0; k < 4; k++) r->cre3[4 * (int64_t)node + k] = k < n ? c[k] : -1;
    return 0;
}

/* the terminal edge (pa, pb) bisected (aug_split_edge): the new triangles lie in
   the originals of those they split (borig); the new node or -1 */
static int32_t bisect_mem3(aug_refiner *r, aug_edit *ed, int32_t pa, int32_t pb, aug_err *e)
{
    int32_t tris[64], nt = 0;
    for (int32_t i = 0; i < ed->adj->cnt[pa] && nt < 64; i++) {
        const int32_t *c = aug_edit_conn(ed, ed->adj->list[pa][i]);
        if (c[0] == pb || c[1] == pb || c[2] == pb) tris[nt++] = ed->adj->list[pa][i];
    }
    int64_t na = ed->nadd;
    int32_t nr = aug_split_edge(ed, NULL, pa, pb, 0.5, e);
    if (nr < 0) return -1;
    if (aug_refine_mem3_creators(r, nr, (int32_t[2]){pa, pb}, 2)) {
        aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
        return -1;
    }
    if (aug_refine_grow_i32(&r->borig, &r->capborig, ed->ne0 + ed->nadd + 1)) {
        aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
        return -1;
    }
    for (int64_t i = na; i < ed->nadd; i++) r->borig[ed->ne0 + i] = r->borig[tris[i - na]];
    return nr;
}

/* constrained components of node q (new nodes: their parent's), as aug_split_edge */
static int nfix_mem3(const aug_edit *ed, int32_t q)
{
    while (q >= ed->nn0) q = ed->parent[q - ed->nn0];
    int n = 0;
    for (int c = 0; c < 3; c++) n += aug_mesh_fixed(ed->m, q * 3 + c, NULL);
    return n;
}

/* orientation of p against edge a->b in the plane of normal n (> 0: left) */
static double orient_n(const double *a, const double *b, const double *p, const double *n)
{
    double u[3], v[3], w[3];
    aug_sub3(b, a, u), aug_sub3(p, a, v);
    aug_cross3(u, v, w);
    return aug_dot3(w, n);
}

/* Rivara's Lepp-Delaunay step on an interior terminal edge (a, b) whose two
   triangles lie in one original triangle (bisect2d.c's centroid, in that
   triangle's plane): the centroid of the quadrilateral splits the triangle
   holding it in three, then coplanar flips of its star; the midpoints of
   plain bisection stay collinear and keep a small angle alive. The new node,
   or -1 when the centroid is on the edge or not strictly inside (bisect
   instead), -2 out of memory. Its parent: the corner with the fewest
   constrained components, then the nearest, then the lowest index. */
static int32_t centroid_mem3(aug_refiner *r, aug_edit *ed, int32_t a, int32_t b)
{
    int32_t tt[2], nt = 0;
    for (int32_t i = 0; i < ed->adj->cnt[a] && nt < 3; i++) {
        const int32_t *c = aug_edit_conn(ed, ed->adj->list[a][i]);
        if (c[0] == b || c[1] == b || c[2] == b) {
            if (nt < 2) tt[nt] = ed->adj->list[a][i];
            nt++;
        }
    }
    if (nt != 2 || r->borig[tt[0]] != r->borig[tt[1]]) return -1;
    int32_t x[2];
    for (int k = 0; k < 2; k++) {
        const int32_t *c = aug_edit_conn(ed, tt[k]);
        x[k] = c[0] != a && c[0] != b ? c[0] : c[1] != a && c[1] != b ? c[1] : c[2];
    }
    int32_t q4[4] = {a, b, x[0], x[1]};
    double cen[3] = {0, 0, 0}, asp, am, nrm[3];
    for (int k = 0; k < 4; k++)
        for (int j = 0; j < 3; j++) cen[j] += 0.25 * aug_edit_x(ed, q4[k])[j];
    tri_geom(ed, tt[0], &asp, &am, nrm);
    double oa = orient_n(aug_edit_x(ed, a), aug_edit_x(ed, b), cen, nrm);
    double ox = orient_n(aug_edit_x(ed, a), aug_edit_x(ed, b), aug_edit_x(ed, x[0]), nrm);
    if (fabs(oa) <= 1e-9 * fabs(ox)) return -1;
    int32_t t = (oa > 0) == (ox > 0) ? tt[0] : tt[1];
    int32_t c[3];
    memcpy(c, aug_edit_conn(ed, t), sizeof c);
    for (int k = 0; k < 3; k++)
        if (!(orient_n(aug_edit_x(ed, c[k]), aug_edit_x(ed, c[(k + 1) % 3]), cen, nrm) > 0)) return -1;
    int32_t par = q4[0];
    for (int k = 1; k < 4; k++) {
        int sk = nfix_mem3(ed, q4[k]), sp = nfix_mem3(ed, par);
        double u[3], v[3];
        aug_sub3(aug_edit_x(ed, q4[k]), cen, u), aug_sub3(aug_edit_x(ed, par), cen, v);
        double dk = aug_dot3(u, u), dp = aug_dot3(v, v);
        if (sk < sp || (sk == sp && (dk < dp || (dk == dp && q4[k] < par)))) par = q4[k];
    }
    int32_t m = aug_edit_node(ed, cen, par);
    if (m < 0 || aug_refine_mem3_creators(r, m, q4, 4)) return -2;
    int32_t c1[3] = {c[0], c[1], m}, c2[3] = {c[1], c[2], m}, c3[3] = {c[2], c[0], m};
    int32_t mat = aug_edit_mat(ed, t);
    if (aug_edit_set(ed, t, c1)) return -2;
    int64_t s2 = aug_edit_elem(ed, c2, mat), s3 = aug_edit_elem(ed, c3, mat);
    if (s2 < 0 || s3 < 0 || aug_refine_grow_i32(&r->borig, &r->capborig, s3 + 1)) return -2;
    r->borig[s2] = r->borig[s3] = r->borig[t];
    return m;
}

/* bisection's floor: an edge this much shorter than the shortest edge of its
   original triangle is not bisected; refine stops with an error instead */
#define FLOOR_REL 1e-4

/* One cut step on mem3 (aug_refine_step's contract). When no triangle the cut
   changes was changed by refine before, the cut's MDLT d is replayed into an
   edit of r->base through the maps of cut-view nodes and elements to base ones
   (r->cnode, r->cel), bc's DOFs mapped the same way; else the step is
   re-triangulated in the refined mesh per original triangle, in its plane
   (aug_refine_mem3_region). Then, worst first among the triangles the step
   wrote and those refinement makes, a bad triangle (bad) has the terminal edge
   of its longest-edge propagation path (lepp) bisected at the midpoint
   (aug_split_edge: both triangles on it, the new node's parent the less
   constrained end; a lip's half keeps its side, so the cut stays open and its
   chords stay edges, in halves), until it is good, and the star of the new
   node legalized by coplanar flips within its original triangle -- thesis 003
   fig. 3.12's recursive local bisection with Lepp-Delaunay flips, measured in
   each triangle's plane. Stops at max_new new nodes (capped); an edge below
   FLOOR_REL of its original triangle's shortest edge to bisect is an error
   (bisection running away). The folded MDLT out, its UPDT (eq. 3.1, when u !=
   NULL), the quality figures q. */
int aug_refine_step_mem3(aug_refiner *r, const aug_mdelta *d, const aug_bdelta *bc, const double *seg,
                         int64_t nseg, aug_mdelta *out, aug_bdelta *outbc, aug_update *u, aug_refine_q *q,
                         aug_err *e)
{
    aug_err_clear(e);
    memset(q, 0, sizeof *q);
    aug_mdelta_init(out);
    aug_mesh *B = &r->base;
    aug_adj adj;
    aug_edit ed;
    int32_t *old = NULL, *oldc = NULL;
    int64_t *work = NULL, nw = 0, capw = 0;
    int rc = 0, recut = 0;
    if (aug_adj_build(&adj, B)) return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
    aug_edit_init(&ed, B, &adj);
    aug_mesh *C = &r->cut;
    int64_t nnc = C->nn, nec = C->ne;
    if (aug_refine_grow_i32(&r->cnode, &r->capc, nnc + d->nnew + 1) || aug_refine_grow_i32(&r->cel, &r->capce, nec + d->nadd + 1) ||
        aug_refine_grow_i32(&r->corig, &r->capcorig, nec + d->nadd + 1))
        goto nomem;
    for (int64_t i = 0; i < d->nmod; i++) {
        if (d->elem[i] < 0 || d->elem[i] >= nec) {
            rc = aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: changed element %d out of range", (int)d->step,
                             (int)d->elem[i]);
            goto done;
        }
        recut |= r->cel[d->elem[i]] < 0;
    }
    for (int64_t i = 0; i < d->nnew; i++)
        if (d->parent[i] < 0 || d->parent[i] >= nnc + i || (d->parent[i] < nnc && r->cnode[d->parent[i]] < 0)) {
            rc = aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: bad parent of new node %lld", (int)d->step,
                             (long long)i);
            goto done;
        }
    for (int64_t i = 0; i < 3 * (d->nmod + d->nadd); i++) {
        int32_t c = i < 3 * d->nmod ? d->conn[i] : d->conn_add[i - 3 * d->nmod];
        if (c < 0 || c >= nnc + d->nnew) {
            rc = aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: element node %d out of range", (int)d->step, (int)c);
            goto done;
        }
    }
    oldc = aug_malloc((size_t)(3 * d->nmod + 1) * sizeof *oldc);
    if (!oldc) goto nomem;
    for (int64_t i = 0; i < d->nmod; i++) memcpy(oldc + 3 * i, C->conn + 3 * (int64_t)d->elem[i], 3 * sizeof *oldc);
    if (!recut) {
        for (int64_t i = 0; i < d->nnew; i++) {
            int32_t b = aug_edit_node(&ed, d->x + i * 3, r->cnode[d->parent[i]]);
            if (b < 0) goto nomem;
            r->cnode[nnc + i] = b;
        }
        int32_t mc[3];
        for (int64_t i = 0; i < d->nmod + d->nadd; i++) {
            const int32_t *c = i < d->nmod ? d->conn + i * 3 : d->conn_add + (i - d->nmod) * 3;
            for (int k = 0; k < 3; k++) mc[k] = r->cnode[c[k]];
            if (i < d->nmod) {
                if (aug_edit_set(&ed, r->cel[d->elem[i]], mc)) goto nomem;
            } else {
                int64_t b = aug_edit_elem(&ed, mc, d->mat_add[i - d->nmod]);
                if (b < 0 || aug_refine_grow_i32(&r->own, &r->capown, b + 1)) goto nomem;
                r->cel[nec + i - d->nmod] = (int32_t)b;
                r->own[b] = (int32_t)(nec + i - d->nmod);
            }
        }
    }
    if ((rc = aug_mesh_apply(C, d, e))) goto done;
    for (int64_t i = 0; i < d->nadd; i++) { /* the original triangle of each added piece */
        const int32_t *v = C->conn + 3 * (nec + i);
        double cen[3];
        for (int k = 0; k < 3; k++) cen[k] = (C->x[3 * v[0] + k] + C->x[3 * v[1] + k] + C->x[3 * v[2] + k]) / 3;
        int64_t h = holder3(C, oldc, d->nmod, cen);
        r->corig[nec + i] = h >= 0 ? r->corig[d->elem[h]] : r->corig[d->elem[0]];
    }
    if (!recut) {
        if (aug_refine_grow_i32(&r->borig, &r->capborig, B->ne + d->nadd + 1)) goto nomem;
        for (int64_t i = 0; i < d->nadd; i++) r->borig[B->ne + i] = r->corig[nec + i];
        capw = d->nmod + d->nadd + 64;
        work = aug_malloc((size_t)capw * sizeof *work);
        if (!work) goto nomem;
        for (int64_t i = 0; i < d->nmod; i++) work[nw++] = r->cel[d->elem[i]];
        for (int64_t i = 0; i < d->nadd; i++) work[nw++] = B->ne + i;
        q->intersected = q->region = d->nmod;
    } else {
        if (aug_refine_grow_i32(&r->own, &r->capown, B->ne + 1) || aug_refine_grow_i32(&r->borig, &r->capborig, B->ne + 1))
            goto nomem;
        if ((rc = aug_refine_mem3_region(r, &ed, d, oldc, nnc, nec, seg, nseg, q, e))) goto done;
        for (int64_t i = 0; i < d->nmod; i++) r->cel[d->elem[i]] = -1;
        for (int64_t i = 0; i < d->nadd; i++) r->cel[nec + i] = -1;
        capw = ed.nmod + ed.nadd + 64;
        work = aug_malloc((size_t)capw * sizeof *work);
        if (!work) goto nomem;
        for (int64_t i = 0; i < ed.nmod; i++) work[nw++] = ed.mod_elem[i];
        for (int64_t i = 0; i < ed.nadd; i++) work[nw++] = ed.ne0 + i;
    }
    double a, m, n[3];
    for (int64_t i = 0; i < nw; i++) {
        tri_geom(&ed, work[i], &a, &m, n);
        q->aspect_mean0 += a / (double)nw, q->aspect_max0 = fmax(q->aspect_max0, a);
        q->min_angle0 = i ? fmin(q->min_angle0, m) : m;
    }
    q->cut_added = d->nadd, q->cut_nodes = d->nnew;
    q->written0 = nw;
    double thmin = r->opt.min_angle_given ? r->opt.min_angle : 0;
    /* a triangle with an angle th has l_max / l_min >= 1 / (2 sin(th/2)) */
    double thasp = r->opt.max_aspect > 0.5 ? 2 * asin(1 / (2 * r->opt.max_aspect)) * 180 / M_PI : 0;
    /* refine(1) --max-new: new nodes of the folded step, the cut's and the
       region's included (as 2-D and 3-D count them) */
    int64_t budget = r->opt.max_new > 0 ? r->opt.max_new : aug_refine_default_cap(d->nmod + d->nadd, 3);
    for (int64_t k = 0; k < nw; k++) {
        int lng;
        int64_t t = work[k];
        if (!bad(&ed, t, &r->opt, &lng) || hopeless_mem3(&ed, r->borig, t, aspect_bad(&ed, t, &r->opt) ? thasp / 2 : thmin)) continue;
        int32_t pa, pb;
        if (lepp(&ed, t, &pa, &pb)) continue;
        if (ed.nnew >= budget) {
            q->capped = 1;
            break;
        }
        const int32_t *oc = r->conn0 + 3 * (int64_t)r->borig[t];
        double l0 = INFINITY, dv[3];
        for (int j = 0; j < 3; j++) {
            aug_sub3(aug_edit_x(&ed, oc[(j + 1) % 3]), aug_edit_x(&ed, oc[j]), dv);
            l0 = fmin(l0, sqrt(aug_dot3(dv, dv)));
        }
        aug_sub3(aug_edit_x(&ed, pb), aug_edit_x(&ed, pa), dv);
        if (sqrt(aug_dot3(dv, dv)) < FLOOR_REL * l0) {
            if (hopeless_mem3(&ed, r->borig, t, thasp)) continue; /* left: bad_left */
            const double *xa = aug_edit_x(&ed, pa);
            rc = aug_err_set(e, AUG_EDATA, -1, "MDLT",
                             "step %d: bisection runs away at (%.6g, %.6g, %.6g): an edge of %.3g, below %g of "
                             "its original triangle's shortest edge", (int)d->step, xa[0], xa[1], xa[2],
                             sqrt(aug_dot3(dv, dv)), FLOOR_REL);
            goto done;
        }
        int32_t nr = centroid_mem3(r, &ed, pa, pb);
        if (nr == -2) goto nomem;
        if (nr < 0) nr = bisect_mem3(r, &ed, pa, pb, e);
        if (nr < 0) {
            rc = e->code;
            goto done;
        }
        q->bisections++;
        if (legalize_star(&ed, r->borig, nr, &q->flips)) goto nomem;
        /* t again, and the star of the new node */
        if (nw + 2 + ed.adj->cnt[nr] > capw) {
            capw = 2 * (nw + 2 + ed.adj->cnt[nr]);
            int64_t *wq = aug_realloc(work, (size_t)capw * sizeof *wq);
            if (!wq) goto nomem;
            work = wq;
        }
        work[nw++] = t;
        for (int32_t i = 0; i < ed.adj->cnt[nr]; i++) work[nw++] = ed.adj->list[nr][i];
    }
    /* the folded MDLT's nnew and nadd (aug_edit_end), as 2-D and 3-D count
       them: the cut's own nodes and triangles included (the bisections'
       alone were counted, and a region that re-triangulated the cut's
       pieces into fewer counted elems_added -2) */
    q->nodes = ed.nnew;
    q->added = ed.nadd;
    /* figures of the elements the folded step writes: a re-wired element
       whose connectivity is back to what it was is not written
       (aug_edit_end) and not counted */
    int64_t cnt = 0;
    for (int64_t i = 0; i < ed.nmod + ed.nadd; i++) {
        int64_t t = i < ed.nmod ? ed.mod_elem[i] : ed.ne0 + (i - ed.nmod);
        if (i < ed.nmod && !memcmp(aug_edit_conn(&ed, t), ed.mod_old + (int64_t)i * 3, 3 * sizeof(int32_t)))
            continue;
        int lng;
        tri_geom(&ed, t, &a, &m, n);
        q->aspect_mean += a, q->aspect_max = fmax(q->aspect_max, a);
        q->min_angle = cnt ? fmin(q->min_angle, m) : m;
        q->bad_left += bad(&ed, t, &r->opt, &lng);
        cnt++;
    }
    if (cnt) q->aspect_mean /= (double)cnt;
    q->written = cnt;
    /* a cut-view triangle whose base triangle refinement changed is no longer mapped */
    for (int64_t i = 0; i < ed.nmod + ed.nadd; i++) {
        int64_t b = i < ed.nmod ? ed.mod_elem[i] : ed.ne0 + (i - ed.nmod);
        if (aug_refine_grow_i32(&r->own, &r->capown, b + 1)) goto nomem;
        int32_t c = r->own[b];
        if (c < 0) continue;
        const int32_t *cb = aug_edit_conn(&ed, b), *cc = C->conn + (int64_t)c * 3;
        if (cb[0] != r->cnode[cc[0]] || cb[1] != r->cnode[cc[1]] || cb[2] != r->cnode[cc[2]]) r->cel[c] = -1, r->own[b] = -1;
    }
    q->area_ratio = q->area_ratio0 = NAN; /* no original measure is kept for mem3 */
    if ((rc = aug_edit_end(&ed, d->step, out, &old, e))) goto done;
    out->flags = d->flags;
    if (outbc && bc) {
        aug_bdelta_init(outbc);
        outbc->step = bc->step;
        for (int64_t i = 0; i < bc->nfix + bc->nload && !rc; i++) {
            int32_t dof = i < bc->nfix ? bc->fix_dof[i] : bc->load_dof[i - bc->nfix];
            if (dof < 0 || dof / 3 >= C->nn) {
                rc = aug_err_set(e, AUG_EDATA, -1, "BDLT", "step %d: DOF %d out of range", (int)bc->step, (int)dof);
                goto done;
            }
            dof = r->cnode[dof / 3] * 3 + dof % 3;
            rc = i < bc->nfix ? aug_bdelta_fix(outbc, dof, bc->fix_val[i])
                              : aug_bdelta_load(outbc, dof, bc->load_val[i - bc->nfix]);
        }
        if (rc) goto nomem;
        /* the nodes refine made take their creators' constraints (refiner.c) */
        if (bc->nfix > 0 && (rc = aug_refine_fix_made(B, B->nn + out->nnew, out->parent, B->nn, r->cre3,
                                                      r->capcre3 / 4, outbc, e)))
            goto done;
        if (aug_bdelta_finish(outbc)) goto nomem;
    }
    if (u && (rc = aug_update_build_bc(B, out, bc ? outbc : NULL, r->nn0, r->map0, r->nfree0, r->dyn, u, e)))
        goto done;
    if ((rc = aug_mesh_apply(B, out, e))) goto done;
    if (bc && outbc && ((rc = aug_mesh_apply_bc(B, outbc, e)) || (rc = aug_mesh_apply_bc(C, bc, e)))) goto done;
    goto done;
nomem:
    rc = aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
done:
    free(work);
    free(old);
    free(oldc);
    aug_edit_free(&ed);
    aug_adj_free(&adj);
    return rc;
}
