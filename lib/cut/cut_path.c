/* Path cuts through tri3 meshes (thesis ch. 3.1, 3.6): walk the curve from node
   to node through the element stars, insert (split) or snap to the points
   where it leaves each star (and, split mode, the point of maximum curvature
   inside each element, thesis sec. 3.1.2), then separate the realised cut edges. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

#define BARY_EPS 1e-9     /* a point this far (relative) outside a triangle is on it */
#define PROBE 1e-3        /* probe distance relative to the local edge length */
#define MAX_WALK 1000000  /* safety bound on walk iterations per curve */

typedef struct walk {
    aug_path_cut *pc;
    aug_edit *ed;
    const aug_curve *c;
    int32_t *cand;        /* nodes to try to separate after the walk */
    int64_t ncand, capcand;
    int32_t *sp;          /* the step's cut edges as node pairs, in walk order */
    int64_t nsp, capsp;
    aug_err *e;
} walk;

/* the least snap tolerance of a path cut (cut(1) --snap-tol) */
#define PATH_TOL_MIN 1e-9

int aug_path_cut_init(aug_path_cut *pc, const aug_path *path, int mode, double tol)
{
    memset(pc, 0, sizeof *pc);
    pc->path = path;
    pc->mode = mode;
    /* at least PATH_TOL_MIN: a path through a node (or along a row of
       nodes) meets it at s = 0 only up to rounding, and --snap-tol 0 made
       a new node there, on top of the old one (a zero-area triangle) */
    pc->tol = tol > PATH_TOL_MIN ? tol : PATH_TOL_MIN;
    pc->kappa = 1;
    pc->node = -1;
    pc->curve = -1;
    return 0;
}

void aug_path_cut_free(aug_path_cut *pc)
{
    aug_edgemap_free(&pc->cut);
    free(pc->twin);
    memset(pc, 0, sizeof *pc);
}

static const double *X(const walk *w, int32_t n) { return aug_edit_x(w->ed, n); }

/* barycentric coordinates of q in triangle t (conn order) */
static void bary(const walk *w, int64_t t, const double *q, double *l)
{
    const int32_t *c = aug_edit_conn(w->ed, t);
    const double *a = X(w, c[0]), *b = X(w, c[1]), *d = X(w, c[2]);
    double det = (b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1]);
    l[1] = ((q[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (q[1] - a[1])) / det;
    l[2] = ((b[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (b[1] - a[1])) / det;
    l[0] = 1 - l[1] - l[2];
}

static double minb(const double *l) { return fmin(l[0], fmin(l[1], l[2])); }

/* shortest edge of the triangles around node n */
static double local_size(const walk *w, int32_t n)
{
    double h = INFINITY;
    const aug_adj *adj = w->ed->adj;
    for (int32_t i = 0; i < adj->cnt[n]; i++) {
        const int32_t *c = aug_edit_conn(w->ed, adj->list[n][i]);
        for (int k = 0; k < 3; k++) {
            const double *p = X(w, c[k]), *q = X(w, c[(k + 1) % 3]);
            h = fmin(h, hypot(q[0] - p[0], q[1] - p[1]));
        }
    }
    return isfinite(h) ? h : 1.0;
}

/* a point on the curve a little after t (at most t1) */
static void probe(const walk *w, double t, double t1, double h, double *q)
{
    double d[2];
    aug_curve_deriv(w->c, t, d);
    double sp = hypot(d[0], d[1]);
    double dt = sp > 0 ? PROBE * h / sp : 1e-6;
    if (dt > t1 - t) dt = t1 - t;
    if (dt < 1e-12) dt = fmin(1e-12, 1 - t);
    aug_curve_eval(w->c, t + dt, q);
}

/* triangle of star(n) holding q best (largest least barycentric); -1 if none within BARY_EPS */
static int64_t star_tri(const walk *w, int32_t n, const double *q, double *lout)
{
    const aug_adj *adj = w->ed->adj;
    int64_t best = -1;
    double bm = -INFINITY, l[3];
    for (int32_t i = 0; i < adj->cnt[n]; i++) {
        int64_t t = adj->list[n][i];
        bary(w, t, q, l);
        double mb = minb(l);
        if (mb > bm || (mb == bm && t < best)) {
            bm = mb;
            best = t;
            if (lout) memcpy(lout, l, sizeof l);
        }
    }
    return bm >= -BARY_EPS ? best : -1;
}

static int add_cand(walk *w, int32_t n)
{
    if (w->ncand == w->capcand) {
        int64_t nc = w->capcand ? 2 * w->capcand : 64;
        int32_t *q = aug_realloc(w->cand, (size_t)nc * sizeof *q);
        if (!q) return -1;
        w->cand = q;
        w->capcand = nc;
    }
    w->cand[w->ncand++] = n;
    return 0;
}

static int add_seg(walk *w, int32_t a, int32_t b)
{
    if (w->nsp == w->capsp) {
        int64_t nc = w->capsp ? 2 * w->capsp : 64;
        int32_t *q = aug_realloc(w->sp, (size_t)(nc * 2) * sizeof *q);
        if (!q) return -1;
        w->sp = q;
        w->capsp = nc;
    }
    w->sp[w->nsp * 2] = a;
    w->sp[w->nsp * 2 + 1] = b;
    w->nsp++;
    if (!aug_edgemap_put(&w->pc->cut, a, b) || add_cand(w, a) || add_cand(w, b)) return -1;
    return 0;
}

/* edge (a, b) was split at r: the step's segments along it follow */
static int split_seg(walk *w, int32_t a, int32_t b, int32_t r)
{
    for (int64_t i = 0; i < w->nsp; i++) {
        int32_t *q = w->sp + i * 2;
        if (!((q[0] == a && q[1] == b) || (q[0] == b && q[1] == a))) continue;
        int32_t y = q[1];
        q[1] = r;
        if (add_seg(w, r, y)) return -1;
        /* keep walk order: move the new half right after its first half */
        int32_t t0 = w->sp[(w->nsp - 1) * 2], t1 = w->sp[(w->nsp - 1) * 2 + 1];
        memmove(w->sp + (i + 2) * 2, w->sp + (i + 1) * 2, (size_t)((w->nsp - 2 - i) * 2) * sizeof *w->sp);
        w->sp[(i + 1) * 2] = t0;
        w->sp[(i + 1) * 2 + 1] = t1;
        i++;
    }
    return 0;
}

#define NOMEM() aug_err_set(w->e, AUG_ENOMEM, -1, "MDLT", "out of memory")

/* the node for a point on edge (a, b) at parameter s: an end within the snap
   tolerance (snap mode: the nearer end), else a new node splitting the edge */
static int32_t on_edge(walk *w, int32_t a, int32_t b, double s)
{
    if (s < 0) s = 0;
    if (s > 1) s = 1;
    if (w->pc->mode == AUG_PATH_SNAP) return s <= 0.5 ? a : b;
    if (s < w->pc->tol) return a;
    if (s > 1 - w->pc->tol) return b;
    int was_cut = aug_edgemap_get(&w->pc->cut, a, b) != NULL;
    int32_t r = aug_split_edge(w->ed, &w->pc->cut, a, b, s, w->e);
    if (r >= 0 && ((was_cut && add_cand(w, r)) || split_seg(w, a, b, r))) {
        NOMEM();
        return -1;
    }
    return r;
}

/* the node for a point with barycentric l in triangle t */
static int32_t in_tri(walk *w, int64_t t, const double *l)
{
    const int32_t *c = aug_edit_conn(w->ed, t);
    int32_t cc[3] = {c[0], c[1], c[2]};
    int big = 0;
    for (int k = 1; k < 3; k++)
        if (l[k] > l[big]) big = k;
    if (w->pc->mode == AUG_PATH_SNAP) return cc[big];
    double tol = w->pc->tol;
    int nsmall = 0, small = -1;
    for (int k = 0; k < 3; k++)
        if (l[k] < tol) {
            nsmall++;
            small = k;
        }
    if (nsmall >= 2 || l[big] > 1 - tol) return cc[big];
    if (nsmall == 1) {
        int j = (small + 1) % 3, k = (small + 2) % 3;
        double lj = fmax(l[j], 0), lk = fmax(l[k], 0);
        return on_edge(w, cc[j], cc[k], lk / (lj + lk));
    }
    double ll[3] = {l[0], l[1], l[2]};
    return aug_split_tri(w->ed, t, ll, w->e);
}

/* is edge (a, b) held by one triangle only? */
static int boundary_edge(const walk *w, int32_t a, int32_t b)
{
    const aug_adj *adj = w->ed->adj;
    int n = 0;
    for (int32_t i = 0; i < adj->cnt[a]; i++) {
        const int32_t *c = aug_edit_conn(w->ed, adj->list[a][i]);
        n += c[0] == b || c[1] == b || c[2] == b;
    }
    return n == 1;
}

typedef struct hit {
    double t, s;
    int32_t a, b;
} hit;

/* where the curve, after t and up to t1, first meets edge (a, b) away from
   node n (thesis 003 eq. 3.3, by aug_curve_line_roots): parameter and edge
   parameter; 0 if it does not */
static int edge_hit(const walk *w, int32_t a, int32_t b, double t, double t1, int32_t n, int strict,
                    hit *h)
{
    double r[AUG_CURVE_MAXDEG];
    const double *pa = X(w, a), *pb = X(w, b);
    int k = aug_curve_line_roots(w->c, pa, pb, t, t1, r);
    double L2 = (pb[0] - pa[0]) * (pb[0] - pa[0]) + (pb[1] - pa[1]) * (pb[1] - pa[1]);
    for (int i = 0; i < k; i++) {
        if (strict && r[i] <= t + 1e-12) continue;
        double q[2];
        aug_curve_eval(w->c, r[i], q);
        double s = ((q[0] - pa[0]) * (pb[0] - pa[0]) + (q[1] - pa[1]) * (pb[1] - pa[1])) / L2;
        if (s < -1e-9 || s > 1 + 1e-9) continue;
        if (n >= 0) {
            const double *pn = X(w, n);
            if (hypot(q[0] - pn[0], q[1] - pn[1]) <= 1e-12 * sqrt(L2)) continue;
        }
        h->t = r[i];
        h->s = s;
        h->a = a;
        h->b = b;
        return 1;
    }
    return 0;
}

static int cmp_hit(const void *x, const void *y)
{
    const hit *a = x, *b = y;
    if (a->t != b->t) return a->t < b->t ? -1 : 1;
    if (a->a != b->a) return a->a < b->a ? -1 : 1;
    return (a->b > b->b) - (a->b < b->b);
}

/* Where the curve enters the mesh at or after t: the point itself when it lies
   in a triangle (start), else the first crossing of a boundary edge (not at
   node `skip`) after which the curve runs inside. New node or -1 (stays out). */
static int32_t enter(walk *w, double *t, double t1, int32_t skip, int at_start)
{
    aug_edit *ed = w->ed;
    int64_t ne = aug_edit_ne(ed);
    double q[2], l[3];
    if (at_start) {
        aug_curve_eval(w->c, *t, q);
        int64_t best = -1;
        double bm = -INFINITY;
        for (int64_t el = 0; el < ne; el++) {
            double ll[3];
            bary(w, el, q, ll);
            if (minb(ll) > bm) {
                bm = minb(ll);
                best = el;
                memcpy(l, ll, sizeof l);
            }
        }
        if (best >= 0 && bm >= -BARY_EPS) return in_tri(w, best, l);
    }
    hit *hs = NULL;
    int64_t nh = 0, caph = 0;
    for (int64_t el = 0; el < ne; el++) {
        const int32_t *c = aug_edit_conn(ed, el);
        for (int k = 0; k < 3; k++) {
            int32_t a = c[k], b = c[(k + 1) % 3];
            if (a == skip || b == skip || !boundary_edge(w, a, b)) continue;
            double r[AUG_CURVE_MAXDEG];
            int nr = aug_curve_line_roots(w->c, X(w, a), X(w, b), *t, t1, r);
            for (int i = 0; i < nr; i++) {
                const double *pa = X(w, a), *pb = X(w, b);
                double L2 = (pb[0] - pa[0]) * (pb[0] - pa[0]) + (pb[1] - pa[1]) * (pb[1] - pa[1]);
                aug_curve_eval(w->c, r[i], q);
                double s = ((q[0] - pa[0]) * (pb[0] - pa[0]) + (q[1] - pa[1]) * (pb[1] - pa[1])) / L2;
                if (s < -1e-9 || s > 1 + 1e-9) continue;
                if (nh == caph) {
                    caph = caph ? 2 * caph : 32;
                    hit *nhs = aug_realloc(hs, (size_t)caph * sizeof *nhs);
                    if (!nhs) {
                        free(hs);
                        NOMEM();
                        return -2;
                    }
                    hs = nhs;
                }
                hs[nh++] = (hit){r[i], s, a, b};
            }
        }
    }
    if (nh > 1) qsort(hs, (size_t)nh, sizeof *hs, cmp_hit);
    int32_t got = -1;
    for (int64_t i = 0; i < nh && got < 0; i++) {
        hit *h = &hs[i];
        /* does the curve run into the triangle of this boundary edge? */
        int32_t tri = -1;
        for (int32_t j = 0; j < ed->adj->cnt[h->a]; j++) {
            const int32_t *c = aug_edit_conn(ed, ed->adj->list[h->a][j]);
            if (c[0] == h->b || c[1] == h->b || c[2] == h->b) tri = ed->adj->list[h->a][j];
        }
        double hloc = hypot(X(w, h->b)[0] - X(w, h->a)[0], X(w, h->b)[1] - X(w, h->a)[1]);
        probe(w, h->t, t1, hloc, q);
        int in;
        if (h->s < 1e-9 || h->s > 1 - 1e-9)
            in = star_tri(w, h->s < 0.5 ? h->a : h->b, q, NULL) >= 0;
        else {
            bary(w, tri, q, l);
            in = minb(l) >= -BARY_EPS;
        }
        if (!in || h->t >= t1) continue;
        *t = h->t;
        got = on_edge(w, h->a, h->b, h->s);
        if (got < 0) got = -2;
    }
    free(hs);
    return got;
}

/* The piece of the curve over [t, tn] inside a triangle of star(n): its
   point of maximum curvature (thesis 003 sec. 3.1.2, figs. 3.6, 3.20, eq. 3.8,
   aug_curve_kappa_max), when inside the piece, as a node (in_tri, the snap
   tolerance applies); n when there is none, -1 on failure. */
static int32_t kappa_node(walk *w, int32_t n, double t, double tn, double *tk)
{
    double q[2], l[3];
    if (!aug_curve_kappa_max(w->c, t, tn, tk)) return n;
    aug_curve_eval(w->c, *tk, q);
    int64_t tri = star_tri(w, n, q, l);
    return tri < 0 ? n : in_tri(w, tri, l);
}

/* Walk curve w->c over [t, t1] from the state node; see the file comment. */
static int walk_curve(walk *w, double t, double t1, int fresh)
{
    aug_path_cut *pc = w->pc;
    int32_t n = pc->node;
    double q[2], kdone = -1;      /* the end of the last piece given its kappa node */
    if (n < 0) {
        n = enter(w, &t, t1, -1, fresh);
        if (n == -2) return w->e->code;
    }
    int it;
    for (it = 0; n >= 0 && it < MAX_WALK; it++) {
        double h = local_size(w, n);
        if (t >= t1 - 1e-12) break;
        probe(w, t, t1, h, q);
        if (star_tri(w, n, q, NULL) < 0) {
            /* the curve leaves the mesh here (a boundary or an open cut) */
            int32_t m = enter(w, &t, t1, n, 0);
            if (m == -2) return w->e->code;
            n = m;
            continue;
        }
        /* first exit from the star: a link edge or a boundary edge at n */
        hit best = {INFINITY, 0, -1, -1}, hh;
        const aug_adj *adj = w->ed->adj;
        for (int32_t i = 0; i < adj->cnt[n]; i++) {
            const int32_t *c = aug_edit_conn(w->ed, adj->list[n][i]);
            int k = c[0] == n ? 0 : (c[1] == n ? 1 : 2);
            int32_t u = c[(k + 1) % 3], v = c[(k + 2) % 3];
            if (edge_hit(w, u, v, t, t1, n, 1, &hh) && hh.t < best.t) best = hh;
            if (boundary_edge(w, n, u) && edge_hit(w, n, u, t, t1, n, 1, &hh) && hh.t < best.t)
                best = hh;
            if (boundary_edge(w, v, n) && edge_hit(w, v, n, t, t1, n, 1, &hh) && hh.t < best.t)
                best = hh;
        }
        int32_t y;
        double tn = best.a >= 0 && best.t <= t1 ? best.t : t1, tk;
        if (pc->kappa && pc->mode == AUG_PATH_SPLIT && tn > kdone + 1e-9) {
            kdone = tn;
            y = kappa_node(w, n, t, tn, &tk);
            if (y < 0) return w->e->code ? w->e->code : NOMEM();
            if (y != n) {
                if (add_seg(w, n, y)) return NOMEM();
                n = y;
                t = tk;
                continue;
            }
        }
        if (best.a >= 0 && best.t <= t1) {
            tn = best.t;
            y = on_edge(w, best.a, best.b, best.s);
        } else {
            double l[3];
            tn = t1;
            aug_curve_eval(w->c, t1, q);
            int64_t tri = star_tri(w, n, q, l);
            if (tri < 0) { /* rounding: the end lies just outside; take the nearest vertex */
                y = n;
            } else {
                y = in_tri(w, tri, l);
            }
        }
        if (y < 0) return w->e->code ? w->e->code : NOMEM();
        if (y != n && add_seg(w, n, y)) return NOMEM();
        n = y;
        t = tn;
    }
    if (it == MAX_WALK)
        return aug_err_set(w->e, AUG_EDATA, -1, "pATH", "the walk along path line %d does not advance",
                           w->c->line);
    pc->node = n;
    pc->t = t;
    return 0;
}

static int cut_edge(void *ctx, const aug_edit *ed, int32_t a, int32_t b, const int32_t *f, int nf)
{
    (void)ed;
    (void)a;
    (void)b;
    const aug_path_cut *pc = ctx;
    return nf == 2 && aug_edgemap_get(&pc->cut, f[0], f[1]) != NULL;
}

/* walk every curve overlapping arc lengths (s, s_to], then separate the nodes
   of the cut edges made (thesis ch. 3.6: partial, cross and re-cuts alike) */
int aug_path_step(aug_path_cut *pc, aug_edit *ed, double s_to, double **seg, int64_t *nseg,
                  aug_err *e)
{
    aug_err_clear(e);
    if (ed->m->dim != 2 || ed->m->nv != 3)
        return aug_err_set(e, AUG_EDATA, -1, "ELEM", "path cuts need a tri3 mesh");
    const aug_path *p = pc->path;
    walk w;
    memset(&w, 0, sizeof w);
    w.pc = pc;
    w.ed = ed;
    w.e = e;
    int rc = 0;
    if (s_to > p->total) s_to = p->total;
    int first = 1;
    for (int i = 0; i < p->n && rc == 0; i++) {
        double a = p->s0[i], b = p->s0[i + 1];
        if (b <= pc->s || a >= s_to) continue;
        w.c = &p->c[i];
        double ta = aug_path_param(p, i, fmax(pc->s, a) - a);
        double tb = aug_path_param(p, i, fmin(s_to, b) - a);
        int fresh = pc->s <= a;
        if (fresh && p->c[i].newstroke) pc->node = -1;
        if (!fresh && pc->curve != i) pc->node = -1;
        pc->curve = i;
        if (first && pc->node >= 0 && pc->ntwin > 0) {
            /* which of the state node and its copies holds the continuation */
            double q[2];
            int32_t best = -1;
            for (int64_t j = -1; j < pc->ntwin && best < 0; j++) {
                int32_t n = j < 0 ? pc->node : pc->twin[j];
                probe(&w, ta, tb, local_size(&w, n), q);
                if (star_tri(&w, n, q, NULL) >= 0) best = n;
            }
            pc->node = best;
        }
        first = 0;
        pc->ntwin = 0;
        rc = walk_curve(&w, ta, tb, fresh);
    }
    pc->s = s_to;
    /* the realised segments, as they are now (later splits included) */
    if (rc == 0 && w.nsp) {
        double *q = aug_realloc(*seg, (size_t)((*nseg + w.nsp) * 4) * sizeof *q);
        if (!q) rc = aug_err_set(e, AUG_ENOMEM, -1, "pATH", "out of memory");
        else {
            *seg = q;
            for (int64_t i = 0; i < w.nsp; i++) {
                memcpy(q + (*nseg + i) * 4, aug_edit_x(ed, w.sp[i * 2]), 2 * sizeof *q);
                memcpy(q + (*nseg + i) * 4 + 2, aug_edit_x(ed, w.sp[i * 2 + 1]), 2 * sizeof *q);
            }
            *nseg += w.nsp;
        }
    }
    /* separate: every node on a cut edge of this step or on a split cut edge */
    if (rc == 0 && w.ncand) {
        qsort(w.cand, (size_t)w.ncand, sizeof *w.cand, aug_cmp_i32);
        int64_t k = 0;
        for (int64_t i = 0; i < w.ncand; i++)
            if (k == 0 || w.cand[k - 1] != w.cand[i]) w.cand[k++] = w.cand[i];
        for (int64_t i = 0; i < k && rc == 0; i++) {
            int32_t n = w.cand[i];
            int64_t before = aug_edit_nn(ed);
            int nc;
            rc = aug_separate_node(ed, n, cut_edge, NULL, pc, &nc, e);
            if (rc == 0 && n == pc->node && nc > 0) {
                int32_t *t = aug_realloc(pc->twin, (size_t)nc * sizeof *t);
                if (!t) {
                    rc = aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
                    break;
                }
                pc->twin = t;
                pc->ntwin = nc;
                for (int j = 0; j < nc; j++) t[j] = (int32_t)(before + j);
            }
        }
    }
    free(w.cand);
    free(w.sp);
    return rc;
}
