/* A membrane (mem3) cut step through triangles refine changed at an earlier
   step: per original triangle, the region the step changed re-triangulated
   conditional Delaunay in that triangle's own plane (thesis 003 secs. 3.1.2,
   3.3.1: the 2-D machinery of refine_region2d.c on local coordinates; every
   refined triangle descended from an original one is coplanar with it), new
   cut nodes near an earlier refinement node realised at that node, and fine
   nodes left pinched between two triangles' planes given a copy. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_refine.h"

/* a new cut node within SNAP_TOL of the longest edge of the refined triangle
   holding it from an earlier refinement (Steiner) node is realised at that node */
#define SNAP_TOL 0.05
/* a cut edge passes through an inner earlier refinement node within ROUTE_TOL
   of its length (refine_region2d.c, recover_routed) */
#define ROUTE_TOL 0.01

/* the plane of an original triangle (a, b, c): origin a, e1 along ab, e2 = n x e1,
   so the triangle is counter-clockwise in (e1, e2) */
typedef struct frame {
    double o[3], e1[3], e2[3], n[3];
    double h;              /* its longest edge */
} frame;

static void frame_of(const double *a, const double *b, const double *c, frame *f)
{
    double u[3], v[3];
    aug_sub3(b, a, u), aug_sub3(c, a, v);
    aug_cross3(u, v, f->n);
    double ln = sqrt(aug_dot3(f->n, f->n)), lu = sqrt(aug_dot3(u, u));
    for (int k = 0; k < 3; k++) f->o[k] = a[k], f->n[k] /= ln, f->e1[k] = u[k] / lu;
    aug_cross3(f->n, f->e1, f->e2);
    double w[3];
    aug_sub3(c, b, w);
    f->h = fmax(lu, fmax(sqrt(aug_dot3(v, v)), sqrt(aug_dot3(w, w))));
}

static void local(const frame *f, const double *p, double *l)
{
    double d[3];
    aug_sub3(p, f->o, d);
    l[0] = aug_dot3(d, f->e1), l[1] = aug_dot3(d, f->e2);
}

static double off_plane(const frame *f, const double *p)
{
    double d[3];
    aug_sub3(p, f->o, d);
    return fabs(aug_dot3(d, f->n));
}

/* barycentric coordinates of local point p in local triangle (a, b, c) */
static void bary3(const double *a, const double *b, const double *c, const double *p, double *l)
{
    double A = aug_orient2d(a, b, c);
    l[0] = aug_orient2d(b, c, p) / A, l[1] = aug_orient2d(c, a, p) / A, l[2] = aug_orient2d(a, b, p) / A;
}

typedef struct mstep {
    aug_refiner *r;
    aug_edit *ed;
    const aug_mdelta *d;
    const int32_t *oldc;
    int64_t nnc, nec, nbase;   /* cut counts before the step; base elements before it */
    const double *seg;
    int64_t nseg;
    aug_err *e;
    aug_edgemap cadj;          /* the cut view after the step: edge -> its triangles */
    int32_t *orig;             /* affected original triangles, increasing */
    int64_t norig;
    int32_t *oslot;            /* original -> index in orig, -1 */
    int64_t *bptr;             /* base elements of orig[k]: bind[bptr[k] .. bptr[k+1]) */
    int32_t *bind;
    int64_t *pptr;             /* the step's pieces in orig[k]: pind (changed < nmod, else added) */
    int32_t *pind;
    unsigned char *img;        /* base node: the image of a cut node */
    int32_t *b2l;              /* base node -> local work node (scratch, -1) */
    int64_t nimg;
} mstep;

#define NOMEM(s) aug_err_set((s)->e, AUG_ENOMEM, -1, "MDLT", "out of memory")

/* the cut element of piece k of the step (changed ones first, then added) */
static int32_t piece_elem(const mstep *s, int64_t k)
{
    return k < s->d->nmod ? s->d->elem[k] : (int32_t)(s->nec + k - s->d->nmod);
}

static int grow_base(mstep *s, int64_t nn)
{
    if (nn <= s->nimg) return 0;
    int64_t c = s->nimg ? s->nimg : 1024;
    while (c < nn) c *= 2;
    unsigned char *m = aug_realloc(s->img, (size_t)c);
    int32_t *l = m ? aug_realloc(s->b2l, (size_t)c * sizeof *l) : NULL;
    if (m) s->img = m;
    if (!m || !l) return -1;
    s->b2l = l;
    for (int64_t i = s->nimg; i < c; i++) s->img[i] = 0, s->b2l[i] = -1;
    s->nimg = c;
    return 0;
}

/* a new node at node v's place, v its parent; made: refine's copy of v
   (its creator v, refine(1): it takes v's later constraints), else the
   cut's own node (the cut's BDLT names it) */
static int32_t copy_node(mstep *s, int32_t v, int made)
{
    double x[3];
    memcpy(x, aug_edit_x(s->ed, v), sizeof x);
    int32_t c = aug_edit_node(s->ed, x, v);
    if (c >= 0 && made && aug_refine_mem3_creators(s->r, c, &v, 1)) return -1;
    return c;
}

static void frame_orig(const mstep *s, int32_t o, frame *f)
{
    const int32_t *c = s->r->conn0 + 3 * (int64_t)o;
    frame_of(aug_edit_x(s->ed, c[0]), aug_edit_x(s->ed, c[1]), aug_edit_x(s->ed, c[2]), f);
}

/* the originals the step's pieces lie in, their base elements and pieces (CSR) */
static int collect(mstep *s)
{
    const aug_mdelta *d = s->d;
    aug_refiner *r = s->r;
    int64_t np = d->nmod + d->nadd;
    s->oslot = aug_malloc((size_t)(r->ne0 + 1) * sizeof *s->oslot);
    s->orig = aug_malloc((size_t)(np + 1) * sizeof *s->orig);
    if (!s->oslot || !s->orig) return NOMEM(s);
    for (int64_t o = 0; o < r->ne0; o++) s->oslot[o] = -1;
    for (int64_t k = 0; k < np; k++) {
        int32_t o = r->corig[piece_elem(s, k)];
        if (s->oslot[o] < 0) s->oslot[o] = 0, s->orig[s->norig++] = o;
    }
    qsort(s->orig, (size_t)s->norig, sizeof *s->orig, aug_cmp_i32);
    for (int64_t k = 0; k < s->norig; k++) s->oslot[s->orig[k]] = (int32_t)k;
    s->bptr = aug_calloc((size_t)s->norig + 2, sizeof *s->bptr);
    s->pptr = aug_calloc((size_t)s->norig + 2, sizeof *s->pptr);
    s->pind = aug_malloc((size_t)(np + 1) * sizeof *s->pind);
    if (!s->bptr || !s->pptr || !s->pind) return NOMEM(s);
    for (int64_t k = 0; k < np; k++) s->pptr[s->oslot[r->corig[piece_elem(s, k)]] + 1]++;
    for (int64_t k = 0; k < s->norig; k++) s->pptr[k + 1] += s->pptr[k];
    for (int64_t k = 0; k < np; k++) s->pind[s->pptr[s->oslot[r->corig[piece_elem(s, k)]]]++] = (int32_t)k;
    for (int64_t k = s->norig; k > 0; k--) s->pptr[k] = s->pptr[k - 1];
    s->pptr[0] = 0;
    for (int64_t b = 0; b < s->nbase; b++)
        if (s->oslot[r->borig[b]] >= 0) s->bptr[s->oslot[r->borig[b]] + 1]++;
    for (int64_t k = 0; k < s->norig; k++) s->bptr[k + 1] += s->bptr[k];
    s->bind = aug_malloc((size_t)(s->bptr[s->norig] + 1) * sizeof *s->bind);
    if (!s->bind) return NOMEM(s);
    for (int64_t b = 0; b < s->nbase; b++)
        if (s->oslot[r->borig[b]] >= 0) s->bind[s->bptr[s->oslot[r->borig[b]]]++] = (int32_t)b;
    for (int64_t k = s->norig; k > 0; k--) s->bptr[k] = s->bptr[k - 1];
    s->bptr[0] = 0;
    return 0;
}

/* is base node v on the boundary (an edge of one triangle: a lip, the sheet's edge)? */
static int on_boundary(const aug_edit *ed, int32_t v)
{
    const aug_adj *adj = ed->adj;
    for (int32_t i = 0; i < adj->cnt[v]; i++) {
        const int32_t *c = aug_edit_conn(ed, adj->list[v][i]);
        for (int k = 0; k < 3; k++) {
            int32_t y = c[k];
            if (y == v) continue;
            int n = 0;
            for (int32_t j = 0; j < adj->cnt[v]; j++) {
                const int32_t *u = aug_edit_conn(ed, adj->list[v][j]);
                n += u[0] == y || u[1] == y || u[2] == y;
            }
            if (n == 1) return 1;
        }
    }
    return 0;
}

/* Near-node handling: a new point c of the cut (not a copy) in original triangle
   o whose nearest earlier refinement node s (a base node no cut node maps to) of
   o's refined triangles is within SNAP_TOL times the longest edge of the refined
   triangle holding c is realised at s: a new node that close would leave an
   edge of SNAP_TOL h or a sliver, which bisection grades down to in many levels
   (or does not fix at all), and which spoils K_t's condition. s must be where c
   is: on the same original edge when c is on one, else inside o and off the
   boundary (never an original corner: those are cut nodes). -1: no such node. */
static int32_t snap_target(const mstep *s, int32_t c, int32_t o, const unsigned char *taken)
{
    const aug_edit *ed = s->ed;
    frame f;
    frame_orig(s, o, &f);
    const int32_t *oc = s->r->conn0 + 3 * (int64_t)o;
    double L[3][2], pc[2], lc[3];
    for (int k = 0; k < 3; k++) local(&f, aug_edit_x(ed, oc[k]), L[k]);
    local(&f, s->r->cut.x + 3 * (int64_t)c, pc);
    bary3(L[0], L[1], L[2], pc, lc);
    const double eb = 1e-9;
    int edge = -1;
    for (int k = 0; k < 3; k++)
        if (fabs(lc[k]) <= eb) edge = k;
    int64_t k = s->oslot[o];
    double h = 0, best = -INFINITY;
    for (int64_t i = s->bptr[k]; i < s->bptr[k + 1]; i++) { /* the refined triangle holding c */
        const int32_t *v = aug_edit_conn(ed, s->bind[i]);
        double P[3][2], l[3];
        for (int j = 0; j < 3; j++) local(&f, aug_edit_x(ed, v[j]), P[j]);
        bary3(P[0], P[1], P[2], pc, l);
        double m = fmin(l[0], fmin(l[1], l[2]));
        if (m > best) {
            best = m, h = 0;
            for (int j = 0; j < 3; j++) h = fmax(h, hypot(P[(j + 1) % 3][0] - P[j][0], P[(j + 1) % 3][1] - P[j][1]));
        }
    }
    int32_t t = -1;
    double dt = SNAP_TOL * h;
    for (int64_t i = s->bptr[k]; i < s->bptr[k + 1]; i++) {
        const int32_t *v = aug_edit_conn(ed, s->bind[i]);
        for (int j = 0; j < 3; j++) {
            int32_t y = v[j];
            if (s->img[y] || taken[y]) continue;
            double py[2], ly[3];
            local(&f, aug_edit_x(ed, y), py);
            double dd = hypot(py[0] - pc[0], py[1] - pc[1]);
            if (!(dd < dt || (dd == dt && y < t))) continue;
            bary3(L[0], L[1], L[2], py, ly);
            int ok = edge >= 0 ? fabs(ly[edge]) <= eb
                               : fmin(ly[0], fmin(ly[1], ly[2])) > eb && !on_boundary(ed, y);
            if (ok) dt = dd, t = y;
        }
    }
    return t;
}

/* would the step's pieces keep their orientation (and a quarter of their area)
   with every cut node at its base node's place? the first piece that would not */
static int64_t bad_piece(const mstep *s, const int32_t *cn)
{
    const aug_mesh *C = &s->r->cut;
    for (int64_t k = 0; k < s->d->nmod + s->d->nadd; k++) {
        const int32_t *v = C->conn + 3 * (int64_t)piece_elem(s, k);
        double u[3], w[3], n0[3], n1[3];
        aug_sub3(C->x + 3 * (int64_t)v[1], C->x + 3 * (int64_t)v[0], u);
        aug_sub3(C->x + 3 * (int64_t)v[2], C->x + 3 * (int64_t)v[0], w);
        aug_cross3(u, w, n0);
        const double *X[3];
        for (int j = 0; j < 3; j++) X[j] = cn[v[j]] >= 0 ? aug_edit_x(s->ed, cn[v[j]]) : C->x + 3 * (int64_t)v[j];
        aug_sub3(X[1], X[0], u), aug_sub3(X[2], X[0], w);
        aug_cross3(u, w, n1);
        if (!(aug_dot3(n0, n1) > 0.25 * aug_dot3(n0, n0))) return k;
    }
    return -1;
}

/* the base nodes of the step's new cut nodes, in the cut's order: a copy at its
   parent's base node, a point snapped (snap_target) or new; a snap that would
   fold a piece is undone */
static int new_cut_nodes(mstep *s)
{
    aug_refiner *r = s->r;
    const aug_mdelta *d = s->d;
    const aug_mesh *C = &r->cut;
    int64_t np = d->nmod + d->nadd;
    int32_t *first = aug_malloc((size_t)(d->nnew + 1) * sizeof *first);
    int32_t *snap = aug_malloc((size_t)(d->nnew + 1) * sizeof *snap);
    int32_t *cn = aug_malloc((size_t)(C->nn + 1) * sizeof *cn);
    unsigned char *taken = aug_calloc((size_t)aug_edit_nn(s->ed) + 1, 1);
    if (!first || !snap || !cn || !taken) goto nomem;
    for (int64_t i = 0; i < d->nnew; i++) first[i] = -1, snap[i] = -1;
    for (int64_t k = 0; k < np; k++) {
        const int32_t *v = C->conn + 3 * (int64_t)piece_elem(s, k);
        for (int j = 0; j < 3; j++)
            if (v[j] >= s->nnc && first[v[j] - s->nnc] < 0) first[v[j] - s->nnc] = r->corig[piece_elem(s, k)];
    }
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t c = (int32_t)(s->nnc + i), par = d->parent[i];
        if (!memcmp(C->x + 3 * (int64_t)c, C->x + 3 * (int64_t)par, 3 * sizeof(double)) || first[i] < 0) continue;
        snap[i] = snap_target(s, c, first[i], taken);
        if (snap[i] >= 0) taken[snap[i]] = 1;
    }
    for (int round = 0; round < 64; round++) { /* undo snaps that fold a piece */
        for (int64_t i = 0; i < C->nn; i++) cn[i] = i < s->nnc ? r->cnode[i] : -1;
        for (int64_t i = 0; i < d->nnew; i++) {
            int32_t c = (int32_t)(s->nnc + i), par = d->parent[i];
            if (snap[i] >= 0) cn[c] = snap[i];
            else if (!memcmp(C->x + 3 * (int64_t)c, C->x + 3 * (int64_t)par, 3 * sizeof(double))) cn[c] = cn[par];
        }
        int64_t k = bad_piece(s, cn);
        if (k < 0) break;
        const int32_t *v = C->conn + 3 * (int64_t)piece_elem(s, k);
        int undone = 0;
        for (int j = 0; j < 3; j++)
            for (int32_t c = v[j]; c >= s->nnc; c = d->parent[c - s->nnc]) {
                if (snap[c - s->nnc] >= 0) snap[c - s->nnc] = -1, undone = 1;
                if (memcmp(C->x + 3 * (int64_t)c, C->x + 3 * (int64_t)d->parent[c - s->nnc], 3 * sizeof(double))) break;
            }
        if (!undone) break; /* the cut's own piece: region2d decides */
    }
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t c = (int32_t)(s->nnc + i), par = d->parent[i], b;
        if (snap[i] >= 0) b = snap[i];
        else if (!memcmp(C->x + 3 * (int64_t)c, C->x + 3 * (int64_t)par, 3 * sizeof(double))) b = copy_node(s, r->cnode[par], 0);
        else b = aug_edit_node(s->ed, C->x + 3 * (int64_t)c, r->cnode[par]);
        if (b < 0) goto nomem;
        r->cnode[c] = b;
    }
    free(first), free(snap), free(cn), free(taken);
    return 0;
nomem:
    free(first), free(snap), free(cn), free(taken);
    return NOMEM(s);
}

/* original triangle orig[k]: its refined triangles and the step's pieces in it as
   a 2-D problem in its plane (a local refiner: work = its refined triangles,
   cut = its pieces, cnode = cut node -> local work node), re-triangulated by
   aug_refine_region2d, and the result written back to the base */
static int plane(mstep *s, int64_t k, aug_refine_q *q)
{
    aug_refiner *r = s->r, lr;
    aug_edit *ed = s->ed;
    const aug_mdelta *d = s->d;
    const aug_mesh *C = &r->cut;
    int32_t o = s->orig[k];
    frame f;
    frame_orig(s, o, &f);
    memset(&lr, 0, sizeof lr);
    aug_mesh wm, cm;
    aug_mesh_init(&wm), aug_mesh_init(&cm);
    int64_t nb = s->bptr[k + 1] - s->bptr[k], npc = s->pptr[k + 1] - s->pptr[k], nm = 0;
    int32_t *l2b = aug_malloc((size_t)(3 * nb + 1) * sizeof *l2b), *lparent = NULL, *lmap = NULL;
    int32_t *oldl = aug_malloc((size_t)(3 * npc + 1) * sizeof *oldl), *iota = aug_malloc((size_t)(npc + 1) * sizeof *iota);
    double *segl = aug_malloc((size_t)(4 * s->nseg + 1) * sizeof *segl);
    wm.x = aug_malloc((size_t)(6 * nb + 1) * sizeof *wm.x);
    wm.conn = aug_malloc((size_t)(3 * nb + 1) * sizeof *wm.conn);
    wm.mat = aug_malloc((size_t)(nb + 1) * sizeof *wm.mat);
    cm.x = aug_calloc((size_t)(2 * C->nn + 1), sizeof *cm.x);
    cm.conn = aug_malloc((size_t)(3 * npc + 1) * sizeof *cm.conn);
    cm.mat = aug_malloc((size_t)(npc + 1) * sizeof *cm.mat);
    lparent = aug_malloc((size_t)(d->nnew + 1) * sizeof *lparent);
    int rc = 0;
    if (!l2b || !oldl || !iota || !segl || !wm.x || !wm.conn || !wm.mat || !cm.x || !cm.conn || !cm.mat ||
        !lparent || aug_refine_grow_i32(&lr.cnode, &lr.capc, C->nn + 1))
        goto nomem;
    /* the local work mesh: o's refined triangles, increasing */
    wm.dim = 2, wm.nv = 3, wm.etype = AUG_TRI3;
    for (int64_t i = 0; i < nb; i++) {
        int32_t b = s->bind[s->bptr[k] + i];
        const int32_t *v = aug_edit_conn(ed, b);
        for (int j = 0; j < 3; j++) {
            if (s->b2l[v[j]] < 0) {
                s->b2l[v[j]] = (int32_t)wm.nn;
                l2b[wm.nn] = v[j];
                local(&f, aug_edit_x(ed, v[j]), wm.x + 2 * wm.nn);
                wm.nn++;
            }
            wm.conn[3 * i + j] = s->b2l[v[j]];
        }
        wm.mat[i] = aug_edit_mat(ed, b);
    }
    wm.ne = nb;
    /* the local cut mesh: o's changed pieces, then its added ones; every cut node
       at its base node's place (a snapped node where it is realised) */
    cm.dim = 2, cm.nv = 3, cm.etype = AUG_TRI3, cm.nn = C->nn;
    for (int pass = 0; pass < 2; pass++)
        for (int64_t i = s->pptr[k]; i < s->pptr[k + 1]; i++) {
            int64_t p = s->pind[i];
            if ((p < d->nmod) != (pass == 0)) continue;
            if (pass == 0) memcpy(oldl + 3 * nm, s->oldc + 3 * p, 3 * sizeof *oldl), iota[nm] = (int32_t)nm;
            int32_t el = piece_elem(s, p);
            memcpy(cm.conn + 3 * cm.ne, C->conn + 3 * (int64_t)el, 3 * sizeof *cm.conn);
            cm.mat[cm.ne++] = C->mat[el];
            if (pass == 0) nm++;
        }
    if (!nm) {
        rc = aug_err_set(s->e, AUG_EDATA, -1, "MDLT", "step %d: a piece added to original triangle %d, none of "
                         "whose triangles the step changed", (int)d->step, (int)o);
        goto out;
    }
    for (int64_t i = 0; i < 3 * cm.ne + 3 * nm; i++) {
        int32_t c = i < 3 * cm.ne ? cm.conn[i] : oldl[i - 3 * cm.ne];
        local(&f, aug_edit_x(ed, r->cnode[c]), cm.x + 2 * (int64_t)c);
    }
    for (int64_t i = 0; i < d->nnew; i++) { /* new nodes and their parents */
        int32_t c = (int32_t)(s->nnc + i), par = d->parent[i];
        local(&f, aug_edit_x(ed, r->cnode[c]), cm.x + 2 * (int64_t)c);
        local(&f, aug_edit_x(ed, r->cnode[par]), cm.x + 2 * (int64_t)par);
    }
    for (int64_t i = 0; i < C->nn; i++) lr.cnode[i] = i < s->nnc && s->b2l[r->cnode[i]] >= 0 ? s->b2l[r->cnode[i]] : -1;
    /* parents: a new node whose parent has no place in o is a point of o with an
       old corner of o's changed pieces (at another place) as parent */
    unsigned char *placed = aug_calloc((size_t)d->nnew + 1, 1);
    if (!placed) goto nomem;
    for (int64_t i = 0; i < cm.ne; i++)
        for (int j = 0; j < 3; j++)
            if (cm.conn[3 * i + j] >= s->nnc) placed[cm.conn[3 * i + j] - s->nnc] = 1;
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t c = (int32_t)(s->nnc + i), par = d->parent[i];
        int pp = par < s->nnc ? lr.cnode[par] >= 0 : placed[par - s->nnc];
        int same = !memcmp(cm.x + 2 * (int64_t)c, cm.x + 2 * (int64_t)par, 2 * sizeof(double));
        lparent[i] = par;
        if (same && pp) placed[i] = 1;
        if (pp || !placed[i]) continue;
        for (int64_t j = 0; j < 3 * nm; j++)
            if (lr.cnode[oldl[j]] >= 0 && memcmp(cm.x + 2 * (int64_t)oldl[j], cm.x + 2 * (int64_t)c, 2 * sizeof(double))) {
                lparent[i] = oldl[j];
                break;
            }
    }
    free(placed);
    int64_t nsl = 0; /* the step's path segments in o's plane */
    for (int64_t i = 0; i < s->nseg; i++) {
        const double *a = s->seg + 6 * i, *b = a + 3;
        if (off_plane(&f, a) > 1e-9 * f.h || off_plane(&f, b) > 1e-9 * f.h) continue;
        local(&f, a, segl + 4 * nsl), local(&f, b, segl + 4 * nsl + 2);
        nsl++;
    }
    lr.cut = cm;
    lr.cadj = s->cadj;
    lr.route_tol = ROUTE_TOL;
    if ((rc = aug_work_init(&lr.work, &wm))) {
        aug_err_set(s->e, rc, -1, "MDLT", "step %d: the refined triangles of original triangle %d are not manifold",
                    (int)d->step, (int)o);
        goto out;
    }
    aug_work_begin(&lr.work, d->step);
    aug_mdelta dl = *d;
    dl.nmod = nm, dl.elem = iota, dl.parent = lparent;
    aug_refine_q ql;
    memset(&ql, 0, sizeof ql);
    if ((rc = aug_refine_region2d(&lr, &dl, oldl, s->nnc, nm, segl, nsl, &ql, s->e))) goto out;
    q->region += ql.region, q->intersected += ql.intersected;
    /* back to the base: local nodes -> base nodes, triangles into their slots */
    aug_work *W = &lr.work;
    lmap = aug_malloc((size_t)(W->m.nn + 1) * sizeof *lmap);
    if (!lmap) goto nomem;
    for (int64_t i = 0; i < W->m.nn; i++) lmap[i] = i < W->nn_begin ? l2b[i] : -1;
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t c = (int32_t)(s->nnc + i), lv = lr.cnode[c];
        if (lv < 0) continue;
        if (lmap[lv] >= 0 && lmap[lv] != r->cnode[c]) {
            rc = aug_err_set(s->e, AUG_EDATA, -1, "MDLT", "step %d: new node %lld falls on node %d of the "
                             "refined mesh in original triangle %d", (int)d->step, (long long)i, (int)lmap[lv], (int)o);
            goto out;
        }
        lmap[lv] = r->cnode[c];
    }
    for (int64_t i = W->nn_begin; i < W->m.nn; i++) { /* copies of fine nodes on a separated cut edge */
        if (lmap[i] >= 0) continue;
        int32_t par = W->parent[i - W->nn_begin];
        if (par < 0 || par >= W->nn_begin) {
            rc = aug_err_set(s->e, AUG_EDATA, -1, "MDLT", "step %d: a node of original triangle %d without origin",
                             (int)d->step, (int)o);
            goto out;
        }
        if ((lmap[i] = copy_node(s, l2b[par], 1)) < 0 || grow_base(s, lmap[i] + 1))
            goto nomem;
    }
    for (int64_t t = 0; t < W->m.ne; t++) {
        if (W->stamp[t] != W->step) continue;
        int32_t cc[3];
        for (int j = 0; j < 3; j++) cc[j] = lmap[W->m.conn[3 * t + j]];
        if (t < W->ne_begin) {
            int32_t b = s->bind[s->bptr[k] + t];
            if (aug_edit_set(ed, b, cc)) goto nomem;
            r->own[b] = -1;
        } else {
            int64_t b = aug_edit_elem(ed, cc, W->m.mat[t]);
            if (b < 0 || aug_refine_grow_i32(&r->own, &r->capown, b + 1) ||
                aug_refine_grow_i32(&r->borig, &r->capborig, b + 1))
                goto nomem;
            r->own[b] = -1, r->borig[b] = o;
        }
    }
    goto out;
nomem:
    rc = NOMEM(s);
out:
    for (int64_t i = 0; i < wm.nn; i++) s->b2l[l2b[i]] = -1;
    aug_work_free(&lr.work);
    free(lr.cnode);
    free(l2b), free(oldl), free(iota), free(segl), free(lparent), free(lmap);
    aug_mesh_free(&wm);
    free(cm.x), free(cm.conn), free(cm.mat);
    return rc;
}

/* a fine node (no cut node maps to it) on a cut edge along an edge between two
   original triangles is still shared by the lips: its star, in components
   connected through its edges, keeps the component of its least triangle and
   gives each other one a copy */
static int unpinch(mstep *s)
{
    aug_edit *ed = s->ed;
    int64_t nw = ed->nmod + ed->nadd;
    int32_t *nodes = aug_malloc((size_t)(3 * nw + 1) * sizeof *nodes);
    if (!nodes) return NOMEM(s);
    int64_t nn = 0;
    for (int64_t i = 0; i < nw; i++) {
        const int32_t *c = aug_edit_conn(ed, i < ed->nmod ? ed->mod_elem[i] : ed->ne0 + (i - ed->nmod));
        for (int j = 0; j < 3; j++) nodes[nn++] = c[j];
    }
    qsort(nodes, (size_t)nn, sizeof *nodes, aug_cmp_i32);
    int rc = 0;
    for (int64_t i = 0; i < nn && !rc; i++) {
        int32_t v = nodes[i];
        if ((i && nodes[i - 1] == v) || s->img[v]) continue;
        int32_t n = ed->adj->cnt[v], star[256], comp[256];
        if (n > 256) continue;
        memcpy(star, ed->adj->list[v], (size_t)n * sizeof *star);
        qsort(star, (size_t)n, sizeof *star, aug_cmp_i32);
        for (int32_t a = 0; a < n; a++) comp[a] = a;
        for (int changed = 1; changed;) { /* components: least index over shared edges */
            changed = 0;
            for (int32_t a = 0; a < n; a++)
                for (int32_t b = 0; b < n; b++) {
                    if (comp[b] <= comp[a]) continue;
                    const int32_t *ca = aug_edit_conn(ed, star[a]), *cb = aug_edit_conn(ed, star[b]);
                    int share = 0;
                    for (int x = 0; x < 3; x++)
                        for (int y = 0; y < 3; y++) share += ca[x] != v && ca[x] == cb[y];
                    if (share) comp[b] = comp[a], changed = 1;
                }
        }
        for (int32_t a = 0; a < n && !rc; a++) {
            if (comp[a] != a || a == 0) continue;
            int32_t cp = copy_node(s, v, 1);
            if (cp < 0 || grow_base(s, cp + 1)) {
                rc = NOMEM(s);
                break;
            }
            for (int32_t b = 0; b < n; b++) {
                if (comp[b] != a) continue;
                int32_t cc[3];
                memcpy(cc, aug_edit_conn(ed, star[b]), sizeof cc);
                for (int j = 0; j < 3; j++) cc[j] = cc[j] == v ? cp : cc[j];
                if (aug_edit_set(ed, star[b], cc)) {
                    rc = NOMEM(s);
                    break;
                }
                s->r->own[star[b]] = -1;
            }
        }
    }
    free(nodes);
    return rc;
}

int aug_refine_mem3_region(aug_refiner *r, aug_edit *ed, const aug_mdelta *d, const int32_t *oldc, int64_t nnc,
                           int64_t nec, const double *seg, int64_t nseg, aug_refine_q *q, aug_err *e)
{
    mstep s;
    memset(&s, 0, sizeof s);
    s.r = r, s.ed = ed, s.d = d, s.oldc = oldc, s.nnc = nnc, s.nec = nec, s.seg = seg, s.nseg = nseg, s.e = e;
    s.nbase = aug_edit_ne(ed);
    const aug_mesh *C = &r->cut;
    int rc = 0;
    if (aug_edgemap_init(&s.cadj, (size_t)(2 * C->ne)) || grow_base(&s, aug_edit_nn(ed) + d->nnew + 1)) {
        rc = NOMEM(&s);
        goto out;
    }
    for (int64_t t = 0; t < C->ne; t++)
        for (int i = 0; i < 3; i++)
            if (aug_edgemap_link(&s.cadj, C->conn[3 * t + i], C->conn[3 * t + (i + 1) % 3], (int32_t)t) == -1) {
                rc = NOMEM(&s);
                goto out;
            }
    for (int64_t i = 0; i < nnc; i++) s.img[r->cnode[i]] = 1;
    if ((rc = collect(&s)) || (rc = new_cut_nodes(&s))) goto out;
    for (int64_t i = nnc; i < C->nn; i++) s.img[r->cnode[i]] = 1;
    q->region = q->intersected = 0;
    for (int64_t k = 0; k < s.norig; k++)
        if ((rc = plane(&s, k, q))) goto out;
    rc = unpinch(&s);
out:
    aug_edgemap_free(&s.cadj);
    free(s.orig), free(s.oslot), free(s.bptr), free(s.bind), free(s.pptr), free(s.pind), free(s.img), free(s.b2l);
    return rc;
}
