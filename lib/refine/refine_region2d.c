/* The region a 2-D cut step changed, re-triangulated conditional Delaunay in the
   refined mesh: the step's new nodes inserted by Bowyer-Watson, its cut edges
   fixed, node copies carried over side by side (thesis 003, 3.1.2 and 3.3.1). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_refine.h"

#define CX(r, i) ((r)->cut.x + 2 * (size_t)(i))
#define WX(w, i) ((w)->m.x + 2 * (size_t)(i))

/* uniform grid of the work triangles' bounding boxes (CSR) */
typedef struct grid {
    double lo[2], h[2];
    int g;
    int64_t *ptr;
    int32_t *ind;
} grid;

static void cell_range(const grid *G, const double *bl, const double *bh, int *i0, int *i1, int *j0,
                       int *j1)
{
    *i0 = (int)floor((bl[0] - G->lo[0]) / G->h[0]), *i1 = (int)floor((bh[0] - G->lo[0]) / G->h[0]);
    *j0 = (int)floor((bl[1] - G->lo[1]) / G->h[1]), *j1 = (int)floor((bh[1] - G->lo[1]) / G->h[1]);
    *i0 = *i0 < 0 ? 0 : *i0 >= G->g ? G->g - 1 : *i0;
    *i1 = *i1 < 0 ? 0 : *i1 >= G->g ? G->g - 1 : *i1;
    *j0 = *j0 < 0 ? 0 : *j0 >= G->g ? G->g - 1 : *j0;
    *j1 = *j1 < 0 ? 0 : *j1 >= G->g ? G->g - 1 : *j1;
}

static void tri_box(const double *x, const int32_t *v, double *bl, double *bh)
{
    for (int c = 0; c < 2; c++) {
        bl[c] = fmin(x[2 * v[0] + c], fmin(x[2 * v[1] + c], x[2 * v[2] + c]));
        bh[c] = fmax(x[2 * v[0] + c], fmax(x[2 * v[1] + c], x[2 * v[2] + c]));
    }
}

static int grid_build(grid *G, const aug_work *w)
{
    memset(G, 0, sizeof *G);
    double hi[2] = {-INFINITY, -INFINITY};
    G->lo[0] = G->lo[1] = INFINITY;
    for (int64_t i = 0; i < w->m.nn; i++)
        for (int c = 0; c < 2; c++)
            G->lo[c] = fmin(G->lo[c], WX(w, i)[c]), hi[c] = fmax(hi[c], WX(w, i)[c]);
    G->g = (int)fmax(1, fmin(2048, sqrt((double)w->m.ne / 2)));
    for (int c = 0; c < 2; c++) G->h[c] = fmax(hi[c] - G->lo[c], 1e-300) / G->g * (1 + 1e-12);
    int64_t nc = (int64_t)G->g * G->g;
    G->ptr = aug_calloc((size_t)nc + 1, sizeof *G->ptr);
    if (!G->ptr) return -1;
    for (int pass = 0; pass < 2; pass++) {
        for (int64_t t = 0; t < w->m.ne; t++) {
            double bl[2], bh[2];
            int i0, i1, j0, j1;
            tri_box(w->m.x, w->m.conn + 3 * t, bl, bh);
            cell_range(G, bl, bh, &i0, &i1, &j0, &j1);
            for (int i = i0; i <= i1; i++)
                for (int j = j0; j <= j1; j++) {
                    int64_t c = (int64_t)i * G->g + j;
                    if (pass == 0) G->ptr[c + 1]++;
                    else G->ind[G->ptr[c]++] = (int32_t)t;
                }
        }
        if (pass == 0) {
            for (int64_t c = 0; c < nc; c++) G->ptr[c + 1] += G->ptr[c];
            G->ind = aug_malloc((size_t)(G->ptr[nc] + 1) * sizeof *G->ind);
            if (!G->ind) return -1;
        } else {
            for (int64_t c = nc; c > 0; c--) G->ptr[c] = G->ptr[c - 1];
            G->ptr[0] = 0;
        }
    }
    return 0;
}

static void grid_free(grid *G)
{
    free(G->ptr);
    free(G->ind);
}

/* do the triangles a and b (vertex coordinate triples) overlap with positive area?
   separating axes: the six edge normals, with a tolerance relative to size */
static int overlap(const double a[3][2], const double b[3][2])
{
    const double(*t[2])[2] = {a, b};
    for (int s = 0; s < 2; s++)
        for (int i = 0; i < 3; i++) {
            const double *p = t[s][i], *q = t[s][(i + 1) % 3];
            double nx = q[1] - p[1], ny = p[0] - q[0], len = hypot(nx, ny);
            if (!(len > 0)) continue;
            nx /= len, ny /= len;
            double amin = INFINITY, amax = -INFINITY, bmin = INFINITY, bmax = -INFINITY;
            for (int k = 0; k < 3; k++) {
                double pa = a[k][0] * nx + a[k][1] * ny, pb = b[k][0] * nx + b[k][1] * ny;
                amin = fmin(amin, pa), amax = fmax(amax, pa);
                bmin = fmin(bmin, pb), bmax = fmax(bmax, pb);
            }
            double tol = 1e-9 * len;
            if (amax <= bmin + tol || bmax <= amin + tol) return 0;
        }
    return 1;
}

/* smallest barycentric coordinate of p in triangle (a, b, c) */
static double bary(const double *a, const double *b, const double *c, const double *p)
{
    double A = aug_orient2d(a, b, c);
    if (!(A > 0)) return -INFINITY;
    return fmin(aug_orient2d(b, c, p), fmin(aug_orient2d(c, a, p), aug_orient2d(a, b, p))) / A;
}

/* is the segment p-q (both ends) on one of the path segments? */
static int on_path(const double *p, const double *q, const double *seg, int64_t nseg)
{
    for (int64_t s = 0; s < nseg; s++) {
        const double *a = seg + 4 * s, *b = a + 2;
        double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
        if (!(l2 > 0)) continue;
        double tol = 1e-9 * sqrt(l2);
        const double *e[2] = {p, q};
        int ok = 1;
        for (int k = 0; k < 2 && ok; k++) {
            double d = fabs(aug_orient2d(a, b, e[k])) / sqrt(l2);
            double u = ((e[k][0] - a[0]) * dx + (e[k][1] - a[1]) * dy) / l2;
            ok = d <= tol && u >= -1e-9 && u <= 1 + 1e-9;
        }
        if (ok) return 1;
    }
    return 0;
}

/* does the open segment p-q cross the interior of triangle t (positive length)? */
static int seg_crosses(const double *a, const double *b, const double *c, const double *p,
                       const double *q)
{
    const double *v[3] = {a, b, c};
    double t0 = 0, t1 = 1;
    double A = aug_orient2d(a, b, c);
    if (!(A > 0)) return 0;
    for (int i = 0; i < 3; i++) { /* Cyrus-Beck: inside edge i when orient >= 0 */
        const double *e0 = v[i], *e1 = v[(i + 1) % 3];
        double f0 = aug_orient2d(e0, e1, p), df = aug_orient2d(e0, e1, q) - f0;
        double tol = 1e-9 * A;
        if (fabs(df) < 1e-300) {
            if (f0 <= tol) return 0;
            continue;
        }
        double th = (tol - f0) / df;
        if (df > 0) t0 = fmax(t0, th);
        else t1 = fmin(t1, th);
    }
    return t1 - t0 > 1e-9;
}

typedef struct side_key {
    int present;
    int32_t a, b;
} side_key;

/* the state of one step's re-triangulation */
typedef struct reg {
    aug_refiner *r;
    aug_work *W;
    const aug_mesh *C;          /* the cut's mesh after the step */
    const aug_mdelta *d;
    const int32_t *oldc;        /* old connectivity of d->elem */
    int64_t nnc, nec;           /* the cut's counts before the step */
    const double *seg;
    int64_t nseg;
    aug_err *e;
    grid G;
    aug_cdt cdt;                /* the local triangulation */
    aug_edgemap done;           /* constraints recovered (local pairs) */
    int64_t np, nF;
    int32_t *piece;             /* np cut elements the step wrote */
    unsigned char *mark;        /* work elements in the region */
    int32_t *F;                 /* nF region elements, increasing */
    int32_t *w2l, *l2w;         /* work node <-> local vertex */
    int32_t *loc;               /* cut node -> local vertex of its place, -1 */
    int32_t *firstp;            /* new cut node -> a piece holding it */
    unsigned char *copy;        /* new cut node: a copy of a located parent */
    int32_t *cptr, *cind;       /* local vertex -> (piece, corner) of the cut nodes there */
    int32_t nfin;
    int32_t *fin, *ftag;        /* final triangles: work nodes, material */
    double *fa0;                /* their original measures */
} reg;

#define NOMEM(g) aug_err_set((g)->e, AUG_ENOMEM, -1, "MDLT", "out of memory")

/* the region: work triangles overlapping the old geometry of the changed
   elements (F, increasing); intersected: those a pATH segment crosses */
static int find_region(reg *g, aug_refine_q *q)
{
    aug_work *W = g->W;
    for (int64_t k = 0; k < g->d->nmod; k++) {
        double A[3][2], bl[2], bh[2];
        const int32_t *v = g->oldc + 3 * k;
        for (int j = 0; j < 3; j++) A[j][0] = CX(g->r, v[j])[0], A[j][1] = CX(g->r, v[j])[1];
        tri_box(g->C->x, v, bl, bh);
        int i0, i1, j0, j1;
        cell_range(&g->G, bl, bh, &i0, &i1, &j0, &j1);
        for (int i = i0; i <= i1; i++)
            for (int j = j0; j <= j1; j++) {
                int64_t c = (int64_t)i * g->G.g + j;
                for (int64_t s = g->G.ptr[c]; s < g->G.ptr[c + 1]; s++) {
                    int32_t t = g->G.ind[s];
                    if (g->mark[t]) continue;
                    double B[3][2];
                    for (int m = 0; m < 3; m++) {
                        const double *x = WX(W, W->m.conn[3 * t + m]);
                        B[m][0] = x[0], B[m][1] = x[1];
                    }
                    if (overlap(A, B)) g->mark[t] = 1;
                }
            }
    }
    g->nF = 0;
    for (int64_t t = 0; t < W->m.ne; t++)
        if (g->mark[t]) g->F[g->nF++] = (int32_t)t;
    q->region = g->nF;
    q->intersected = 0;
    for (int64_t k = 0; k < g->nF; k++) {
        const int32_t *v = W->m.conn + 3 * (int64_t)g->F[k];
        for (int64_t s = 0; s < g->nseg; s++)
            if (seg_crosses(WX(W, v[0]), WX(W, v[1]), WX(W, v[2]), g->seg + 4 * s, g->seg + 4 * s + 2)) {
                q->intersected++;
                break;
            }
    }
    if (!g->nseg) q->intersected = g->d->nmod;
    return 0;
}

/* the local triangulation of F (tags: materials); fixed: the work mesh's fixed
   edges and material interfaces */
static int build_local(reg *g)
{
    aug_work *W = g->W;
    for (int64_t k = 0; k < g->nF; k++) {
        const int32_t *v = W->m.conn + 3 * (int64_t)g->F[k];
        int32_t lv[3];
        for (int j = 0; j < 3; j++) {
            if (g->w2l[v[j]] < 0) {
                g->w2l[v[j]] = aug_cdt_vertex(&g->cdt, WX(W, v[j])[0], WX(W, v[j])[1]);
                if (g->w2l[v[j]] < 0) return NOMEM(g);
            }
            lv[j] = g->w2l[v[j]];
        }
        if (aug_cdt_tri(&g->cdt, lv[0], lv[1], lv[2], W->m.mat[g->F[k]]) < 0) return NOMEM(g);
    }
    g->l2w = aug_malloc((size_t)(g->cdt.nv + g->d->nnew + 1) * sizeof *g->l2w);
    if (!g->l2w) return NOMEM(g);
    for (int64_t i = 0; i < W->m.nn; i++)
        if (g->w2l[i] >= 0) g->l2w[g->w2l[i]] = (int32_t)i;
    for (int64_t k = 0; k < g->nF; k++) {
        const int32_t *v = W->m.conn + 3 * (int64_t)g->F[k];
        for (int j = 0; j < 3; j++) {
            int32_t a = v[j], b = v[(j + 1) % 3];
            int64_t n = aug_work_across(W, g->F[k], a, b);
            int fix = aug_work_edge_fixed(W, a, b) || (n >= 0 && W->m.mat[n] != W->m.mat[g->F[k]]);
            if (fix && aug_cdt_fix(&g->cdt, g->w2l[a], g->w2l[b])) return NOMEM(g);
        }
    }
    return 0;
}

/* where the pieces' nodes are: old ones (also the old corners of the changed
   elements) at their work node, copies at their parent's place, new points
   located from a piece holding them (so a point on an old slit goes to its side)
   and inserted by Bowyer-Watson; a copy whose parent has no place in the region
   (a membrane's triangle holding the copy's side only) is inserted as a point */
static int insert_nodes(reg *g)
{
    const aug_mesh *C = g->C;
    const aug_mdelta *d = g->d;
    int step = d->step, rc;
    for (int64_t i = 0; i < d->nnew; i++) g->firstp[i] = -1;
    for (int64_t k = 0; k < g->np; k++) {
        const int32_t *v = C->conn + 3 * (int64_t)g->piece[k];
        for (int j = 0; j < 3; j++) {
            if (v[j] < g->nnc) {
                int32_t wn = g->r->cnode[v[j]];
                if (wn < 0 || g->w2l[wn] < 0)
                    return aug_err_set(g->e, AUG_EDATA, -1, "MDLT",
                                       "step %d: node %d of a changed element is not in the region",
                                       step, (int)v[j]);
                g->loc[v[j]] = g->w2l[wn];
            } else if (g->firstp[v[j] - g->nnc] < 0) {
                g->firstp[v[j] - g->nnc] = (int32_t)k;
            }
        }
    }
    for (int64_t k = 0; k < 3 * d->nmod; k++) {
        int32_t c = g->oldc[k], wn = c < g->nnc ? g->r->cnode[c] : -1;
        if (g->loc[c] < 0 && wn >= 0 && g->w2l[wn] >= 0) g->loc[c] = g->w2l[wn];
    }
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t c = (int32_t)(g->nnc + i), par = d->parent[i];
        const double *x = CX(g->r, c);
        g->copy[i] = !memcmp(x, CX(g->r, par), 2 * sizeof *x) && g->loc[par] >= 0;
        if (g->copy[i]) { /* a copy: same place as its parent */
            g->loc[c] = g->loc[par];
            continue;
        }
        if (g->firstp[i] < 0) continue; /* in no element */
        const int32_t *v = C->conn + 3 * (int64_t)g->piece[g->firstp[i]];
        double cen[2] = {(CX(g->r, v[0])[0] + CX(g->r, v[1])[0] + CX(g->r, v[2])[0]) / 3,
                         (CX(g->r, v[0])[1] + CX(g->r, v[1])[1] + CX(g->r, v[2])[1]) / 3};
        double wp[2] = {x[0] + 1e-6 * (cen[0] - x[0]), x[1] + 1e-6 * (cen[1] - x[1])};
        int32_t at, tw = aug_cdt_locate(&g->cdt, wp[0], wp[1], -1, NULL);
        int32_t t = aug_cdt_locate(&g->cdt, x[0], x[1], tw, &at);
        if (t < 0)
            return aug_err_set(g->e, AUG_EDATA, -1, "MDLT",
                               "step %d: new node %lld lies outside the elements the step changed",
                               step, (long long)i);
        if (at >= 0) {
            g->loc[c] = at; /* on an existing node of the refined mesh */
            continue;
        }
        int32_t lv = aug_cdt_vertex(&g->cdt, x[0], x[1]);
        if (lv < 0) return NOMEM(g);
        g->l2w[lv] = -1;
        if ((rc = aug_cdt_insert(&g->cdt, lv, t)))
            return rc == AUG_ENOMEM ? NOMEM(g)
                                    : aug_err_set(g->e, rc, -1, "MDLT", "step %d: cannot insert new node %lld",
                                                  step, (long long)i);
        g->loc[c] = lv;
    }
    return 0;
}

typedef struct routed {
    double u;
    int32_t v;
} routed;

static int cmp_routed(const void *x, const void *y)
{
    const routed *a = x, *b = y;
    return a->u < b->u ? -1 : a->u > b->u ? 1 : (a->v > b->v) - (a->v < b->v);
}

/* with r->route_tol > 0 (a membrane's triangle, refine_mem3_region.c): the cut
   edge la-lb recovered through the fine nodes (free[v]: no cut node there, off
   the region's boundary) within route_tol of its length, in their order along
   it: an earlier refinement node that close would leave a cap triangle (an
   angle near 180 degrees, not bad by the aspect bound) or a sliver that spoils
   K_t; the lip then passes through it and it is separated as a fine node */
static int recover_routed(reg *g, int32_t la, int32_t lb, const unsigned char *free_v)
{
    const aug_cdt *c = &g->cdt;
    const double *pa = c->xy + 2 * la, *pb = c->xy + 2 * lb;
    double dx = pb[0] - pa[0], dy = pb[1] - pa[1], l2 = dx * dx + dy * dy, len = sqrt(l2);
    routed *rt = NULL;
    int32_t n = 0, cap = 0;
    for (int32_t v = 0; v < c->nv; v++) {
        if (!free_v[v]) continue;
        const double *p = c->xy + 2 * v;
        double u = ((p[0] - pa[0]) * dx + (p[1] - pa[1]) * dy) / l2;
        if (!(u > g->r->route_tol && u < 1 - g->r->route_tol) ||
            !(fabs(aug_orient2d(pa, pb, p)) / len < g->r->route_tol * len))
            continue;
        if (n == cap) {
            cap = cap ? 2 * cap : 8;
            routed *q = aug_realloc(rt, (size_t)cap * sizeof *q);
            if (!q) {
                free(rt);
                return AUG_ENOMEM;
            }
            rt = q;
        }
        rt[n].u = u, rt[n].v = v, n++;
    }
    if (n > 1) qsort(rt, (size_t)n, sizeof *rt, cmp_routed); /* (rt NULL when none was routed) */
    int rc = 0;
    int32_t from = la;
    for (int32_t k = 0; k <= n && !rc; k++) {
        int32_t to = k < n ? rt[k].v : lb;
        rc = aug_cdt_recover(&g->cdt, from, to);
        from = to;
    }
    free(rt);
    return rc;
}

/* constraints: the pieces' cut edges (open in the cut mesh, or on the path),
   recovered and fixed (recover_routed on a membrane); then Lawson flips:
   constrained Delaunay */
static int recover_cuts(reg *g)
{
    const aug_mesh *C = g->C;
    unsigned char *free_v = NULL;
    if (g->r->route_tol > 0) { /* fine nodes off the region's boundary */
        free_v = aug_malloc((size_t)g->cdt.nv + 1);
        if (!free_v) return NOMEM(g);
        for (int32_t v = 0; v < g->cdt.nv; v++) free_v[v] = 1;
        for (int64_t k = 0; k < g->np; k++)
            for (int j = 0; j < 3; j++) {
                int32_t lv = g->loc[C->conn[3 * (int64_t)g->piece[k] + j]];
                if (lv >= 0) free_v[lv] = 0;
            }
        for (int32_t t = 0; t < g->cdt.nt; t++) {
            const int32_t *v = g->cdt.tri + 3 * t;
            if (v[0] < 0) continue;
            for (int j = 0; j < 3; j++)
                if (aug_cdt_across(&g->cdt, t, v[j], v[(j + 1) % 3]) < 0) free_v[v[j]] = free_v[v[(j + 1) % 3]] = 0;
        }
    }
    for (int64_t k = 0; k < g->np; k++) {
        const int32_t *v = C->conn + 3 * (int64_t)g->piece[k];
        for (int j = 0; j < 3; j++) {
            int32_t a = v[j], b = v[(j + 1) % 3];
            const int32_t *s = aug_edgemap_get(&g->r->cadj, a, b);
            int open = s && (s[0] < 0 || s[1] < 0);
            if (!open && !on_path(CX(g->r, a), CX(g->r, b), g->seg, g->nseg)) continue;
            int32_t la = g->loc[a], lb = g->loc[b];
            if (la < 0 || lb < 0 || la == lb || aug_edgemap_get(&g->done, la, lb)) continue;
            if (!aug_edgemap_put(&g->done, la, lb)) {
                free(free_v);
                return NOMEM(g);
            }
            int rc = free_v ? recover_routed(g, la, lb, free_v) : aug_cdt_recover(&g->cdt, la, lb);
            if (rc) {
                free(free_v);
                return rc == AUG_ENOMEM ? NOMEM(g)
                                        : aug_err_set(g->e, rc, -1, "MDLT",
                                                      "step %d: cut edge %d-%d crosses a fixed edge of the "
                                                      "refined mesh", g->d->step, (int)a, (int)b);
            }
        }
    }
    free(free_v);
    return aug_cdt_legalize(&g->cdt) ? NOMEM(g) : 0;
}

/* the work nodes of the cut's new nodes, in the cut's order: inserted points and
   copies get new nodes (parents mapped), points on an existing node take it */
static int new_nodes(reg *g)
{
    const aug_mdelta *d = g->d;
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t c = (int32_t)(g->nnc + i), par = d->parent[i], lv = g->loc[c];
        if (lv < 0) {
            g->r->cnode[c] = -1;
            continue;
        }
        int32_t wpar = g->r->cnode[par];
        if (wpar < 0)
            return aug_err_set(g->e, AUG_EDATA, -1, "MDLT", "step %d: parent of new node %lld unused",
                               d->step, (long long)i);
        int copy = g->copy[i];
        if (copy || g->l2w[lv] < 0) {
            int32_t wn = aug_work_node(g->W, CX(g->r, c), wpar);
            if (wn < 0) return NOMEM(g);
            if (!copy) g->l2w[lv] = wn;
            g->r->cnode[c] = wn;
        } else {
            g->r->cnode[c] = g->l2w[lv];
        }
    }
    return 0;
}

/* local vertex -> the pieces' corners at its place (CSR) */
static int candidates(reg *g)
{
    g->cptr = aug_calloc((size_t)g->cdt.nv + 1, sizeof *g->cptr);
    g->cind = aug_malloc((size_t)(3 * g->np + 1) * sizeof *g->cind);
    if (!g->cptr || !g->cind) return NOMEM(g);
    for (int pass = 0; pass < 2; pass++) {
        for (int64_t k = 0; k < g->np; k++) {
            const int32_t *v = g->C->conn + 3 * (int64_t)g->piece[k];
            for (int j = 0; j < 3; j++) {
                int32_t lv = g->loc[v[j]];
                if (lv < 0) continue;
                if (pass == 0) g->cptr[lv + 1]++;
                else g->cind[g->cptr[lv]++] = (int32_t)(k * 3 + j);
            }
        }
        if (pass == 0)
            for (int32_t i = 0; i < g->cdt.nv; i++) g->cptr[i + 1] += g->cptr[i];
        else {
            for (int32_t i = g->cdt.nv; i > 0; i--) g->cptr[i] = g->cptr[i - 1];
            g->cptr[0] = 0;
        }
    }
    return 0;
}

/* the node of corner j of local triangle p: the node (original or copy) of the
   piece holding a point of the triangle near that corner; outside the pieces
   (the region reaches past the changed elements) the work node stays */
static int32_t corner_node(const reg *g, const double *p[3], int j, int32_t x)
{
    int32_t id = g->l2w[x];
    if (g->cptr[x + 1] == g->cptr[x]) return id;
    double cen[2] = {(p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3};
    /* a quarter of the smallest altitude at the corner: inside the triangle and
       inside whichever piece around the corner holds that direction */
    double alt = 2 * aug_orient2d(p[0], p[1], p[2]) /
                 hypot(p[(j + 2) % 3][0] - p[(j + 1) % 3][0], p[(j + 2) % 3][1] - p[(j + 1) % 3][1]);
    for (int32_t s = g->cptr[x]; s < g->cptr[x + 1]; s++) {
        const int32_t *u = g->C->conn + 3 * (int64_t)g->piece[g->cind[s] / 3];
        int jj = g->cind[s] % 3;
        const double *a = CX(g->r, u[jj]), *b = CX(g->r, u[(jj + 1) % 3]), *c = CX(g->r, u[(jj + 2) % 3]);
        alt = fmin(alt, 2 * aug_orient2d(a, b, c) / hypot(c[0] - b[0], c[1] - b[1]));
    }
    double dx = cen[0] - p[j][0], dy = cen[1] - p[j][1], dl = hypot(dx, dy);
    double wp[2] = {p[j][0] + 0.25 * alt * dx / dl, p[j][1] + 0.25 * alt * dy / dl};
    double best = -1e-9;
    for (int32_t s = g->cptr[x]; s < g->cptr[x + 1]; s++) {
        const int32_t *u = g->C->conn + 3 * (int64_t)g->piece[g->cind[s] / 3];
        double bm = bary(CX(g->r, u[0]), CX(g->r, u[1]), CX(g->r, u[2]), wp);
        if (bm > best) best = bm, id = g->r->cnode[u[g->cind[s] % 3]];
    }
    return id;
}

/* original measure at point c: of the region triangle (before) holding it */
static double origin_measure(const reg *g, const double *c)
{
    const grid *G = &g->G;
    const aug_work *W = g->W;
    int gi = (int)floor((c[0] - G->lo[0]) / G->h[0]), gj = (int)floor((c[1] - G->lo[1]) / G->h[1]);
    gi = gi < 0 ? 0 : gi >= G->g ? G->g - 1 : gi;
    gj = gj < 0 ? 0 : gj >= G->g ? G->g - 1 : gj;
    int64_t cell = (int64_t)gi * G->g + gj;
    double a0 = W->area0[g->F[0]], bb = -INFINITY;
    for (int64_t s = G->ptr[cell]; s < G->ptr[cell + 1]; s++) {
        int32_t u = G->ind[s];
        if (!g->mark[u]) continue;
        const int32_t *uv = W->m.conn + 3 * (int64_t)u;
        double bm = bary(WX(W, uv[0]), WX(W, uv[1]), WX(W, uv[2]), c);
        if (bm > bb) bb = bm, a0 = W->area0[u];
    }
    return a0;
}

/* the final triangles: corners mapped to work nodes, material, original measure */
static int final_triangles(reg *g)
{
    g->fin = aug_malloc((size_t)(3 * g->cdt.nt + 1) * sizeof *g->fin);
    g->ftag = aug_malloc((size_t)(g->cdt.nt + 1) * sizeof *g->ftag);
    g->fa0 = aug_malloc((size_t)(g->cdt.nt + 1) * sizeof *g->fa0);
    if (!g->fin || !g->ftag || !g->fa0) return NOMEM(g);
    g->nfin = 0;
    for (int32_t t = 0; t < g->cdt.nt; t++) {
        const int32_t *v = g->cdt.tri + 3 * t;
        if (v[0] < 0) continue;
        const double *p[3] = {g->cdt.xy + 2 * v[0], g->cdt.xy + 2 * v[1], g->cdt.xy + 2 * v[2]};
        for (int j = 0; j < 3; j++) {
            int32_t id = corner_node(g, p, j, v[j]);
            if (id < 0)
                return aug_err_set(g->e, AUG_EDATA, -1, "MDLT", "step %d: corner without a node", g->d->step);
            g->fin[3 * g->nfin + j] = id;
        }
        double cen[2] = {(p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3};
        g->ftag[g->nfin] = g->cdt.tag[t];
        g->fa0[g->nfin] = origin_measure(g, cen);
        g->nfin++;
    }
    return 0;
}

/* a fine node (one the cut does not know) on a cut edge that the step separates
   gets a copy for one side: the side whose nodes at the edge's ends are the old
   ones keeps it (else the side with the smaller pair) */
static int separate_fine(reg *g)
{
    const aug_cdt *cdt = &g->cdt;
    int32_t *fcopy = aug_malloc((size_t)cdt->nv * sizeof *fcopy);
    if (!fcopy) return NOMEM(g);
    for (int32_t i = 0; i < cdt->nv; i++) fcopy[i] = -1;
    for (size_t h = 0; h < g->done.cap; h++) {
        if (g->done.key[h] == 0 || g->done.key[h] == UINT64_MAX) continue;
        int32_t la = (int32_t)((g->done.key[h] - 1) >> 32), lb = (int32_t)((g->done.key[h] - 1) & 0xffffffffu);
        if (aug_edgemap_get(&cdt->edges, la, lb)) continue; /* a single edge: no fine node on it */
        const double *pa = cdt->xy + 2 * la, *pb = cdt->xy + 2 * lb;
        double l2 = (pb[0] - pa[0]) * (pb[0] - pa[0]) + (pb[1] - pa[1]) * (pb[1] - pa[1]);
        /* each side's nodes at the ends, from the final triangles along the segment */
        side_key sk[2] = {{0, 0, 0}, {0, 0, 0}};
        int32_t k = 0;
        for (int32_t t = 0; t < cdt->nt; t++) {
            const int32_t *v = cdt->tri + 3 * t;
            if (v[0] < 0) continue;
            const int32_t *fv = g->fin + 3 * k++;
            for (int j = 0; j < 3; j++) {
                if (v[j] != la && v[j] != lb) continue;
                for (int s = 0; s < 2; s++) {
                    int32_t o = v[(j + 1 + s) % 3], other = v[(j + 2 - s) % 3];
                    const double *po = cdt->xy + 2 * o;
                    double u = ((po[0] - pa[0]) * (pb[0] - pa[0]) + (po[1] - pa[1]) * (pb[1] - pa[1])) / l2;
                    double dd = fabs(aug_orient2d(pa, pb, po)) / sqrt(l2);
                    if (!(dd <= 1e-9 * sqrt(l2) && u > 1e-12 && u < 1 - 1e-12)) continue;
                    if (!aug_cdt_is_fixed(cdt, v[j], o)) continue;
                    int sd = aug_orient2d(pa, pb, cdt->xy + 2 * other) > 0 ? 0 : 1;
                    sk[sd].present = 1;
                    if (v[j] == la) sk[sd].a = fv[j];
                    else sk[sd].b = fv[j];
                }
            }
        }
        if (!sk[0].present || !sk[1].present || (sk[0].a == sk[1].a && sk[0].b == sk[1].b)) continue;
        int keep = 0;
        if (sk[1].a == g->l2w[la] && sk[1].b == g->l2w[lb]) keep = 1;
        else if (!(sk[0].a == g->l2w[la] && sk[0].b == g->l2w[lb]))
            keep = (sk[1].a < sk[0].a || (sk[1].a == sk[0].a && sk[1].b < sk[0].b)) ? 1 : 0;
        k = 0;
        for (int32_t t = 0; t < cdt->nt; t++) {
            const int32_t *v = cdt->tri + 3 * t;
            if (v[0] < 0) continue;
            int32_t *fv = g->fin + 3 * k++;
            const double *p[3] = {cdt->xy + 2 * v[0], cdt->xy + 2 * v[1], cdt->xy + 2 * v[2]};
            double cen[2] = {(p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3};
            if ((aug_orient2d(pa, pb, cen) > 0 ? 0 : 1) == keep) continue;
            for (int j = 0; j < 3; j++) {
                int32_t x = v[j];
                if (g->cptr[x + 1] > g->cptr[x] || x == la || x == lb) continue; /* not a fine node */
                const double *px = cdt->xy + 2 * x;
                double u = ((px[0] - pa[0]) * (pb[0] - pa[0]) + (px[1] - pa[1]) * (pb[1] - pa[1])) / l2;
                double dd = fabs(aug_orient2d(pa, pb, px)) / sqrt(l2);
                if (!(dd <= 1e-9 * sqrt(l2) && u > 0 && u < 1)) continue;
                if (fcopy[x] < 0 && (fcopy[x] = aug_work_node(g->W, px, g->l2w[x])) < 0) {
                    free(fcopy);
                    return NOMEM(g);
                }
                aug_work_creators(g->W, fcopy[x], &g->l2w[x], 1);
                fv[j] = fcopy[x];
            }
        }
    }
    free(fcopy);
    return 0;
}

/* the final triangles into the region's slots (by material), the rest appended;
   constraints that stay interior are kept fixed; every element positive */
static int write_back(reg *g)
{
    aug_work *W = g->W;
    int rc;
    unsigned char *taken = aug_calloc((size_t)g->nfin + 1, 1);
    if (!taken) return NOMEM(g);
    for (int64_t k = 0; k < g->nF; k++)
        if ((rc = aug_work_unlink(W, g->F[k]))) goto fail;
    for (int64_t k = 0; k < g->nF; k++) { /* each slot: the first unused triangle of its material */
        int32_t mat = W->m.mat[g->F[k]], t = 0;
        while (t < g->nfin && (taken[t] || g->ftag[t] != mat)) t++;
        if (t == g->nfin) {
            free(taken);
            return aug_err_set(g->e, AUG_EDATA, -1, "MDLT",
                               "step %d: re-triangulation has fewer elements than it replaces", g->d->step);
        }
        taken[t] = 1;
        W->area0[g->F[k]] = g->fa0[t];
        if ((rc = aug_work_put(W, g->F[k], g->fin + 3 * t))) goto fail;
    }
    for (int32_t t = 0; t < g->nfin; t++)
        if (!taken[t] && aug_work_add(W, g->fin + 3 * t, g->ftag[t], g->fa0[t]) < 0) {
            rc = AUG_ENOMEM;
            goto fail;
        }
    free(taken);
    for (size_t h = 0; h < g->cdt.fixed.cap; h++) {
        if (g->cdt.fixed.key[h] == 0 || g->cdt.fixed.key[h] == UINT64_MAX) continue;
        int32_t la = (int32_t)((g->cdt.fixed.key[h] - 1) >> 32);
        int32_t lb = (int32_t)((g->cdt.fixed.key[h] - 1) & 0xffffffffu);
        if (g->l2w[la] < 0 || g->l2w[lb] < 0) continue;
        const int32_t *sl = aug_edgemap_get(&W->adj, g->l2w[la], g->l2w[lb]);
        if (sl && sl[0] >= 0 && sl[1] >= 0 && !aug_edgemap_put(&W->fixed, g->l2w[la], g->l2w[lb]))
            return NOMEM(g);
    }
    for (int64_t t = 0; t < W->m.ne; t++)
        if (W->stamp[t] == W->step && !(aug_elem_measure(&W->m, t) > 0))
            return aug_err_set(g->e, AUG_EDATA, -1, "MDLT",
                               "step %d: re-triangulation made element %lld inverted or degenerate",
                               g->d->step, (long long)t);
    return 0;
fail:
    free(taken);
    return rc == AUG_ENOMEM ? NOMEM(g)
                            : aug_err_set(g->e, rc, -1, "MDLT", "step %d: re-triangulation is not manifold",
                                          g->d->step);
}

/* A 2-D cut step in the refined mesh (thesis 003 secs. 3.1.2, 3.3.1, 3.6.1):
   find_region, build_local, insert_nodes (Bowyer-Watson), recover_cuts (cut edges
   fixed, Lawson flips: conditional Delaunay), new_nodes, candidates,
   final_triangles, separate_fine (node copies on both sides), write_back. */
int aug_refine_region2d(aug_refiner *r, const aug_mdelta *d, const int32_t *oldc, int64_t nnc,
                        int64_t nec, const double *seg, int64_t nseg, aug_refine_q *q, aug_err *e)
{
    reg g;
    memset(&g, 0, sizeof g);
    g.r = r, g.W = &r->work, g.C = &r->cut, g.d = d, g.oldc = oldc, g.nnc = nnc, g.nec = nec;
    g.seg = seg, g.nseg = nseg, g.e = e;
    g.np = d->nmod + (g.C->ne - nec);
    g.piece = aug_malloc((size_t)(g.np + 1) * sizeof *g.piece);
    g.w2l = aug_malloc((size_t)(g.W->m.nn + 1) * sizeof *g.w2l);
    g.mark = aug_calloc((size_t)g.W->m.ne + 1, 1);
    g.F = aug_malloc((size_t)(g.W->m.ne + 1) * sizeof *g.F);
    g.loc = aug_malloc((size_t)(g.C->nn + 1) * sizeof *g.loc);
    g.firstp = aug_malloc((size_t)(d->nnew + 1) * sizeof *g.firstp);
    g.copy = aug_malloc((size_t)(d->nnew + 1));
    int rc;
    if (!g.piece || !g.w2l || !g.mark || !g.F || !g.loc || !g.firstp || !g.copy || aug_cdt_init(&g.cdt) ||
        aug_edgemap_init(&g.done, 64) || grid_build(&g.G, g.W)) {
        rc = NOMEM(&g);
        goto out;
    }
    for (int64_t i = 0; i < d->nmod; i++) g.piece[i] = d->elem[i];
    for (int64_t i = nec; i < g.C->ne; i++) g.piece[d->nmod + i - nec] = (int32_t)i;
    for (int64_t i = 0; i < g.W->m.nn; i++) g.w2l[i] = -1;
    for (int64_t i = 0; i < g.C->nn; i++) g.loc[i] = -1;
    if ((rc = find_region(&g, q)) || (rc = build_local(&g)) || (rc = insert_nodes(&g)) ||
        (rc = recover_cuts(&g)) || (rc = new_nodes(&g)) || (rc = candidates(&g)) ||
        (rc = final_triangles(&g)) || (rc = separate_fine(&g)))
        goto out;
    rc = write_back(&g);
out:
    free(g.piece);
    free(g.w2l);
    free(g.mark);
    free(g.F);
    free(g.loc);
    free(g.firstp);
    free(g.copy);
    free(g.l2w);
    free(g.cptr);
    free(g.cind);
    free(g.fin);
    free(g.ftag);
    free(g.fa0);
    aug_edgemap_free(&g.done);
    aug_cdt_free(&g.cdt);
    grid_free(&g.G);
    return rc;
}
