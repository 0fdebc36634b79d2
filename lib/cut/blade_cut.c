/* 3-D cuts along a swept or given triangle surface, step by step: snap mode
   (faces nearest the surface open by node duplication) and split mode (edges
   the surface crosses split, then the faces on it open). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

#define SPLIT_TOL_MIN 1e-6

void aug_blade_cut_free(aug_blade_cut *bc)
{
    aug_soup_free(&bc->soup);
    aug_boxgrid_free(&bc->tg);
    aug_boxgrid_free(&bc->eg);
    aug_edgemap_free(&bc->pairs);
    free(bc->on);
    free(bc->buf);
    free(bc->buf2);
    memset(bc, 0, sizeof *bc);
}

static void elem_box(const aug_edit *ed, int64_t el, double lo[3], double hi[3])
{
    const int32_t *c = aug_edit_conn(ed, el);
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int a = 0; a < ed->m->nv; a++) {
        const double *x = aug_edit_x(ed, c[a]);
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], x[k]), hi[k] = fmax(hi[k], x[k]);
    }
}

int aug_blade_cut_init(aug_blade_cut *bc, const aug_mesh *m, int mode, double tol, aug_err *e)
{
    aug_err_clear(e);
    memset(bc, 0, sizeof *bc);
    if (m->dim != 3)
        return aug_err_set(e, AUG_EUSAGE, -1, "", "a surface cut needs a 3-D mesh (tet4 or hex8)");
    if (mode == AUG_PATH_SPLIT && m->etype != AUG_TET4)
        return aug_err_set(e, AUG_EUSAGE, -1, "", "--mode split needs a tet4 mesh (this one is %s: --mode snap)",
                           aug_etype_name(m->etype));
    bc->mode = mode;
    /* a split at s within rounding of an end (s = 1 - 1e-16 with --snap-tol
       0) makes a node on top of that end: an element of no volume, and the
       new edge crosses again at the same point, so the same place splits
       without end (sphere3, a flat blade: minutes, growing one node's star).
       Crossings within 1e-6 of an end snap whatever T is. */
    bc->tol = fmax(tol, SPLIT_TOL_MIN);
    for (int k = 0; k < 3; k++) bc->lo[k] = INFINITY, bc->hi[k] = -INFINITY;
    for (int64_t i = 0; i < m->nn; i++)
        for (int k = 0; k < 3; k++) {
            bc->lo[k] = fmin(bc->lo[k], m->x[3 * i + k]);
            bc->hi[k] = fmax(bc->hi[k], m->x[3 * i + k]);
        }
    double scale = 0, hsum = 0;
    for (int k = 0; k < 3; k++) scale = fmax(scale, bc->hi[k] - bc->lo[k]);
    for (int64_t el = 0; el < m->ne; el++) {
        double l = 0;
        const int32_t *c = m->conn + el * m->nv;
        for (int a = 0; a < m->nv; a++)
            for (int b = a + 1; b < m->nv; b++) {
                double d = 0;
                for (int k = 0; k < 3; k++) d += (m->x[3 * c[a] + k] - m->x[3 * c[b] + k]) * (m->x[3 * c[a] + k] - m->x[3 * c[b] + k]);
                l = fmax(l, d);
            }
        bc->h = fmax(bc->h, sqrt(l));
        hsum += sqrt(l);
    }
    double hmean = m->ne ? hsum / (double)m->ne : 1;
    bc->eps = 1e-12 * (scale > 0 ? scale : 1);
    bc->hon = 1e-9 * bc->h;
    for (int k = 0; k < 3; k++) bc->lo[k] -= bc->h, bc->hi[k] += bc->h;
    if (aug_boxgrid_init(&bc->tg, 2 * hmean, bc->lo) || aug_boxgrid_init(&bc->eg, 2 * hmean, bc->lo))
        goto nomem;
    for (int64_t el = 0; el < m->ne; el++) {
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int a = 0; a < m->nv; a++)
            for (int k = 0; k < 3; k++) {
                lo[k] = fmin(lo[k], m->x[3 * (int64_t)m->conn[el * m->nv + a] + k]);
                hi[k] = fmax(hi[k], m->x[3 * (int64_t)m->conn[el * m->nv + a] + k]);
            }
        if (aug_boxgrid_add(&bc->eg, (int32_t)el, lo, hi)) goto nomem;
    }
    return 0;
nomem:
    aug_blade_cut_free(bc);
    return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
}

/* ---- shared pieces ---- */

typedef struct segs {
    double **seg;
    int64_t *nseg, cap;
    aug_edgemap done;
} segs;

/* seg += the sides of face f (nf nodes; a triangle: its three edges), once each */
static int face_edges(segs *s, const aug_edit *ed, const int32_t *f, int nf)
{
    for (int i = 0; i < nf; i++) {
        int32_t a = f[i], b = f[(i + 1) % nf];
        if (aug_edgemap_get(&s->done, a, b)) continue;
        if (!aug_edgemap_put(&s->done, a, b)) return -1;
        if (*s->nseg == s->cap) {
            int64_t nc = s->cap ? 2 * s->cap : 64;
            double *q = aug_realloc(*s->seg, (size_t)nc * 6 * sizeof *q);
            if (!q) return -1;
            *s->seg = q;
            s->cap = nc;
        }
        memcpy(*s->seg + *s->nseg * 6, aug_edit_x(ed, a), 3 * sizeof(double));
        memcpy(*s->seg + *s->nseg * 6 + 3, aug_edit_x(ed, b), 3 * sizeof(double));
        (*s->nseg)++;
    }
    return 0;
}

/* the box lo..hi widened by w and clipped to the mesh's: 0 when empty */
static int clip_box(const aug_blade_cut *bc, const double *lo, const double *hi, double w, double *a,
                    double *b)
{
    for (int k = 0; k < 3; k++) {
        a[k] = fmax(lo[k] - w, bc->lo[k]);
        b[k] = fmin(hi[k] + w, bc->hi[k]);
        if (a[k] > b[k]) return 0;
    }
    return 1;
}

static void tri_box(const double *t, double *lo, double *hi)
{
    for (int k = 0; k < 3; k++) {
        lo[k] = fmin(t[k], fmin(t[3 + k], t[6 + k]));
        hi[k] = fmax(t[k], fmax(t[3 + k], t[6 + k]));
    }
}

/* distance of x from the surface, or a number > lim when farther than lim */
static double surf_dist(aug_blade_cut *bc, const double *x, double lim)
{
    double lo[3], hi[3], best = 2 * lim + 1;
    if (!clip_box(bc, x, x, lim, lo, hi)) return best;
    if (aug_boxgrid_query(&bc->tg, lo, hi, &bc->buf2, &bc->nbuf2, &bc->capbuf2)) return -1;
    for (int64_t i = 0; i < bc->nbuf2; i++) best = fmin(best, aug_point_tri(x, bc->soup.t + 9 * (int64_t)bc->buf2[i]));
    return best;
}

static void centroid(const aug_edit *ed, int64_t el, double c[3])
{
    const int32_t *cn = aug_edit_conn(ed, el);
    int nv = ed->m->nv;
    c[0] = c[1] = c[2] = 0;
    for (int a = 0; a < nv; a++)
        for (int k = 0; k < 3; k++) c[k] += aug_edit_x(ed, cn[a])[k] / nv;
}

/* ---- snap mode ---- */

static int snap_cut(void *ctx, const aug_edit *ed, int32_t a, int32_t b, const int32_t *f, int nf)
{
    (void)ed, (void)f, (void)nf;
    const aug_blade_cut *bc = ctx;
    return aug_edgemap_get(&bc->pairs, a, b) != NULL;
}

/* separate each distinct node of nodes[0..n) (sorted here, increasing: the
   order the plane cut uses) along the faces cut() accepts (aug_separate_node) */
static int separate_all(aug_edit *ed, int32_t *nodes, int64_t n, aug_cutface_fn cut, aug_blade_cut *bc,
                        aug_err *e)
{
    if (n > 1) qsort(nodes, (size_t)n, sizeof *nodes, aug_cmp_i32);
    for (int64_t i = 0; i < n; i++) {
        if (i && nodes[i] == nodes[i - 1]) continue;
        int nc, rc = aug_separate_node(ed, nodes[i], cut, NULL, bc, &nc, e);
        if (rc) return rc;
    }
    return 0;
}


/* Snap (AMPS sec. 4.3.2, node duplication, with the plane's side test
   generalised): the face between face neighbours A and B is cut when the
   segment between their centroids crosses a triangle of the surface
   (aug_seg_tri); its nodes' stars split along the cut faces
   (aug_separate_node). A or B meets the crossing, so only the elements whose
   box meets a new triangle's are tested against it. */
static int snap_step(aug_blade_cut *bc, aug_edit *ed, const aug_facenbr *fn, int64_t first, segs *sg,
                     aug_err *e)
{
    const aug_mesh *m = ed->m;
    int nf = fn->nf;
    int32_t *np = NULL, *nodes = NULL;
    int64_t nnp = 0, capnp = 0, nnodes = 0;
    for (int64_t t = first; t < bc->soup.n; t++) {
        const double *tri = bc->soup.t + 9 * t;
        double lo[3], hi[3], a[3], b[3];
        tri_box(tri, lo, hi);
        if (!clip_box(bc, lo, hi, bc->eps, a, b)) continue;
        if (aug_boxgrid_query(&bc->eg, a, b, &bc->buf, &bc->nbuf, &bc->capbuf)) goto nomem;
        for (int64_t i = 0; i < bc->nbuf; i++) {
            int32_t A = bc->buf[i];
            double ca[3], cb[3], s;
            centroid(ed, A, ca);
            for (int f = 0; f < nf; f++) {
                int32_t B = fn->nbr[(int64_t)A * nf + f];
                if (B < 0 || aug_edgemap_get(&bc->pairs, A, B)) continue;
                centroid(ed, B, cb);
                if (!aug_seg_tri(ca, cb, tri, bc->eps, &s)) continue;
                if (!aug_edgemap_put(&bc->pairs, A, B)) goto nomem;
                if (nnp + 2 > capnp) {
                    capnp = capnp ? 2 * capnp : 256;
                    int32_t *q = aug_realloc(np, (size_t)capnp * sizeof *q);
                    if (!q) goto nomem;
                    np = q;
                }
                np[nnp++] = A;
                np[nnp++] = B;
            }
        }
    }
    /* the nodes of the new cut faces, each once (increasing), and their edges */
    nodes = aug_malloc((size_t)(nnp / 2) * 4 * sizeof *nodes + 1);
    if (!nodes) goto nomem;
    for (int64_t i = 0; i < nnp; i += 2) {
        int32_t f[4];
        int k = aug_shared_facet(m->etype, aug_edit_conn(ed, np[i]), aug_edit_conn(ed, np[i + 1]), f);
        if (face_edges(sg, ed, f, k)) goto nomem;
        for (int q = 0; q < k; q++) nodes[nnodes++] = f[q];
        bc->nface++;
    }
    int rc = separate_all(ed, nodes, nnodes, snap_cut, bc, e);
    if (rc) {
        free(np);
        free(nodes);
        return rc;
    }
    free(np);
    free(nodes);
    return 0;
nomem:
    free(np);
    free(nodes);
    return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
}

/* ---- split mode (tet4) ---- */

static int on_grow(aug_blade_cut *bc, int64_t n)
{
    if (n <= bc->capon) return 0;
    int64_t nc = bc->capon ? bc->capon : 1024;
    while (nc < n) nc *= 2;
    unsigned char *q = aug_realloc(bc->on, (size_t)nc);
    if (!q) return -1;
    memset(q + bc->capon, 0, (size_t)(nc - bc->capon));
    bc->on = q;
    bc->capon = nc;
    return 0;
}

/* node q lies on the surface: marked, or a copy made this step of a marked node */
static int on_get(const aug_blade_cut *bc, const aug_edit *ed, int32_t q)
{
    for (;;) {
        if (q < bc->capon && bc->on[q]) return 1;
        if (q < ed->nn0) return 0;
        q = ed->parent[q - ed->nn0];
    }
}

/* The first triangle of the surface that segment p-q crosses (aug_seg_tri
   with tolerance tol, also the margin of the box clip) at a parameter t with
   t_lo < t < t_hi: 1 and *t, 0 none, -1 memory. Split's edge test and its
   face test (seg_crosses) both query the triangle grid through it. */
static int seg_first(aug_blade_cut *bc, const double *p, const double *q, double tol, double t_lo,
                     double t_hi, double *t)
{
    double lo[3], hi[3], a[3], b[3];
    for (int k = 0; k < 3; k++) lo[k] = fmin(p[k], q[k]), hi[k] = fmax(p[k], q[k]);
    if (!clip_box(bc, lo, hi, tol, a, b)) return 0;
    if (aug_boxgrid_query(&bc->tg, a, b, &bc->buf2, &bc->nbuf2, &bc->capbuf2)) return -1;
    for (int64_t i = 0; i < bc->nbuf2; i++)
        if (aug_seg_tri(p, q, bc->soup.t + 9 * (int64_t)bc->buf2[i], tol, t) && *t > t_lo && *t < t_hi)
            return 1;
    return 0;
}

/* the segment p-q crosses a triangle of the surface (aug_seg_tri, the snap
   mode's test); -1 memory */
static int seg_crosses(aug_blade_cut *bc, const double *p, const double *q)
{
    double t;
    return seg_first(bc, p, q, bc->eps, -INFINITY, INFINITY, &t);
}

/* Face f (3 nodes) between tets a and b lies on the surface: its nodes do
   (split or snapped onto it), and the segment between the centroids of a
   and b crosses the surface (the snap mode's side test). A tet whose four
   nodes are on the surface (flat on it, its nodes snapped within tol) so
   goes whole to the side of its centroid: its faces towards the other side
   open, the others stay. Refusing every face of such a tet, and a face
   whose centroid lay farther from the surface than tol times its longest
   side (a node snaps within tol times the crossing edge's length, which can
   be longer), left bridges across a surface through the whole mesh:
   sphere3 and the liver cut by a flat blade in split mode stayed one piece.
   The face's nodes stand for the surface only to within tol of their
   edges: with a large --snap-tol a whole layer of nodes snaps onto a blade
   that runs between them and the centroids next to it, and no centroid
   segment reaches the blade (the brick_n4 cut at y = 0.32 with T >= 0.28:
   the nodes at y = 0.25 snapped, the centroids above at y = 0.3125, "misses
   the mesh"; the liver at T 0.4 one piece). So the face is also cut when
   the segment between the two tets' fourth nodes crosses the surface, a
   tet flat on the surface (its fourth node on it too) represented by its
   centroid. */
static int split_cut(void *ctx, const aug_edit *ed, int32_t a, int32_t b, const int32_t *f, int nf)
{
    aug_blade_cut *bc = ctx;
    if (nf != 3) return 0;
    for (int k = 0; k < 3; k++)
        if (!on_get(bc, ed, f[k])) return 0;
    double ca[3], cb[3];
    centroid(ed, a, ca);
    centroid(ed, b, cb);
    int rc = seg_crosses(bc, ca, cb);
    if (rc == 0) {
        const double *px[2] = {ca, cb};
        int32_t el[2] = {a, b};
        int off = 0;
        for (int s = 0; s < 2; s++) {
            const int32_t *c = aug_edit_conn(ed, el[s]);
            for (int k = 0; k < 4; k++)
                if (c[k] != f[0] && c[k] != f[1] && c[k] != f[2] && !on_get(bc, ed, c[k])) {
                    px[s] = aug_edit_x(ed, c[k]);
                    off = 1;
                }
        }
        if (off) rc = seg_crosses(bc, px[0], px[1]);
    }
    if (rc < 0) bc->oom = 1; /* reported by split_step: not a face left whole */
    return rc == 1;
}

/* the tet other than el holding the three nodes f, or -1 */
static int32_t across(const aug_edit *ed, int64_t el, const int32_t *f)
{
    const aug_adj *adj = ed->adj;
    for (int32_t i = 0; i < adj->cnt[f[0]]; i++) {
        int32_t g = adj->list[f[0]][i];
        if (g == el) continue;
        const int32_t *c = aug_edit_conn(ed, g);
        int n = 0;
        for (int k = 0; k < 4; k++) n += c[k] == f[1] || c[k] == f[2];
        if (n == 2) return g;
    }
    return -1;
}

typedef struct queue {
    int32_t *q;
    int64_t n, cap;
    unsigned char *in;           /* per element: queued or done this step */
    int64_t capin;
} queue;

static int q_push(queue *w, int32_t el)
{
    if (el >= w->capin) {
        int64_t nc = w->capin ? 2 * w->capin : 1024;
        while (nc <= el) nc *= 2;
        unsigned char *p = aug_realloc(w->in, (size_t)nc);
        if (!p) return -1;
        memset(p + w->capin, 0, (size_t)(nc - w->capin));
        w->in = p;
        w->capin = nc;
    }
    if (w->in[el] & 1) return 0;
    w->in[el] |= 1;
    if (w->n == w->cap) {
        int64_t nc = w->cap ? 2 * w->cap : 256;
        int32_t *p = aug_realloc(w->q, (size_t)nc * sizeof *p);
        if (!p) return -1;
        w->q = p;
        w->cap = nc;
    }
    w->q[w->n++] = el;
    return 0;
}

/* nodes within 1e-9 h of the surface (through nodes, along faces) are on it;
   seen: nodes measured already this step */
static int mark_close(aug_blade_cut *bc, const aug_edit *ed, int64_t el, unsigned char *seen)
{
    const int32_t *c = aug_edit_conn(ed, el);
    for (int k = 0; k < 4; k++) {
        if (bc->on[c[k]] || seen[c[k]]) continue;
        seen[c[k]] = 1;
        double d = surf_dist(bc, aug_edit_x(ed, c[k]), bc->hon);
        if (d < 0) return -1;
        if (d <= bc->hon) bc->on[c[k]] = 1;
    }
    return 0;
}

/* lexicographic order of points */
static int before(const double *p, const double *q)
{
    for (int k = 0; k < 3; k++)
        if (p[k] != q[k]) return p[k] < q[k];
    return 0;
}

/* The first crossing of edge a-b with the surface that is not at an end on
   it already: 1 and *s, else 0; -1 memory. The ends are put in
   lexicographic order of their points first, so that the coincident copies
   of an edge on the two sides of an earlier cut split at the same point.
   Within a step the surface and the points are fixed and on[] only grows, so
   an edge without a crossing keeps none: it is remembered in miss (the
   several tets around an edge test it once). */
static int edge_cross(aug_blade_cut *bc, const aug_edit *ed, aug_edgemap *miss, int32_t *pa, int32_t *pb,
                      double *s)
{
    if (aug_edgemap_get(miss, *pa, *pb)) return 0;
    if (before(aug_edit_x(ed, *pb), aug_edit_x(ed, *pa))) {
        int32_t t = *pa;
        *pa = *pb;
        *pb = t;
    }
    int32_t a = *pa, b = *pb;
    /* a crossing within tol of an end already on the surface is that end */
    int rc = seg_first(bc, aug_edit_x(ed, a), aug_edit_x(ed, b), bc->hon, bc->on[a] ? bc->tol : -INFINITY,
                       bc->on[b] ? 1 - bc->tol : INFINITY, s);
    if (rc) return rc;
    return aug_edgemap_put(miss, a, b) ? 0 : -1;
}

/* the normal of triangle t (u x v of its sides from the first corner) in
   n[0..2], its length in n[3] */
static void tri_plane(const double *t, double n[4])
{
    double u[3], v[3];
    for (int k = 0; k < 3; k++) u[k] = t[3 + k] - t[k], v[k] = t[6 + k] - t[k];
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    n[3] = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* every node of el farther than 1e-9 h from the plane of triangle t (normal n,
   tri_plane), all on one side: the triangle cannot meet the element */
static int apart(const aug_blade_cut *bc, const aug_edit *ed, int32_t el, const double *t, const double *n)
{
    int plus = 0, minus = 0;
    const int32_t *c = aug_edit_conn(ed, el);
    for (int a = 0; a < ed->m->nv; a++) {
        const double *x = aug_edit_x(ed, c[a]);
        double d = (n[0] * (x[0] - t[0]) + n[1] * (x[1] - t[1]) + n[2] * (x[2] - t[2])) / n[3];
        plus += d > bc->hon;
        minus += d < -bc->hon;
    }
    return plus == ed->m->nv || minus == ed->m->nv;
}

static const int tet_edge[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

/* Split (thesis 003 sec. 3.1.2 in 3-D): every tet edge that the new surface
   crosses at parameter s with tol < s < 1 - tol is bisected there
   (aug_split_edge: each half keeps a volume fraction >= tol, no sliver); a
   crossing nearer an end snaps: that end counts as on the surface. The
   elements changed are examined again until no edge crosses (a budget of 64
   splits per element touched stops a surface folded within one element).
   Then the faces whose nodes lie on the surface (split_cut) open by node
   duplication (aug_separate_node). */
static int split_step(aug_blade_cut *bc, aug_edit *ed, int64_t first, segs *sg, aug_err *e)
{
    queue w = {0};
    aug_edgemap miss = {0};
    int32_t *nodes = NULL;
    int64_t nnodes = 0, capnodes = 0;
    if (on_grow(bc, aug_edit_nn(ed) + 1)) goto nomem;
    for (int64_t t = first; t < bc->soup.n; t++) {
        double lo[3], hi[3], a[3], b[3];
        tri_box(bc->soup.t + 9 * t, lo, hi);
        if (!clip_box(bc, lo, hi, bc->hon, a, b)) continue;
        if (aug_boxgrid_query(&bc->eg, a, b, &bc->buf, &bc->nbuf, &bc->capbuf)) goto nomem;
        double n[4];
        tri_plane(bc->soup.t + 9 * t, n);
        for (int64_t i = 0; i < bc->nbuf; i++) {
            int32_t el = bc->buf[i];
            if (el < w.capin && (w.in[el] & 1)) continue; /* queued for an earlier triangle */
            if (!apart(bc, ed, el, bc->soup.t + 9 * t, n) && q_push(&w, el)) goto nomem;
        }
    }
    unsigned char *seen = aug_calloc((size_t)aug_edit_nn(ed) + 1, 1);
    if (!seen) goto nomem;
    for (int64_t i = 0; i < w.n; i++)
        if (mark_close(bc, ed, w.q[i], seen)) {
            free(seen);
            goto nomem;
        }
    free(seen);
    if (aug_edgemap_init(&miss, (size_t)(6 * w.n + 64))) goto nomem;
    int64_t budget = 64 * w.n + 64, head = 0;
    while (head < w.n) {
        int32_t el = w.q[head++];
        w.in[el] &= (unsigned char)~1u;
        w.in[el] |= 2;
        const int32_t *c = aug_edit_conn(ed, el);
        for (int k = 0; k < 6 && budget > 0; k++) {
            int32_t a = c[tet_edge[k][0]], b = c[tet_edge[k][1]];
            if (bc->on[a] && bc->on[b]) continue;
            double s;
            int rc = edge_cross(bc, ed, &miss, &a, &b, &s);
            if (rc < 0) goto nomem;
            if (!rc) continue;
            if (s <= bc->tol) {
                bc->on[a] = 1;
                continue;
            }
            if (s >= 1 - bc->tol) {
                bc->on[b] = 1;
                continue;
            }
            int64_t ne = aug_edit_ne(ed);
            int32_t r = aug_split_edge(ed, NULL, a, b, s, e);
            if (r < 0) {
                aug_edgemap_free(&miss);
                free(w.q);
                free(w.in);
                return e->code;
            }
            budget--;
            bc->nsplit++;
            if (on_grow(bc, (int64_t)r + 1)) goto nomem;
            bc->on[r] = 1;
            /* the halves: the re-wired tets (now at r) and the added ones */
            for (int32_t j = 0; j < ed->adj->cnt[r]; j++)
                if (q_push(&w, ed->adj->list[r][j])) goto nomem;
            for (int64_t g = ne; g < aug_edit_ne(ed); g++) {
                double lo[3], hi[3];
                elem_box(ed, g, lo, hi);
                if (aug_boxgrid_add(&bc->eg, (int32_t)g, lo, hi)) goto nomem;
            }
            break; /* el changed: it is queued again at r */
        }
    }
    aug_edgemap_free(&miss);
    /* the faces on the surface among the elements examined */
    for (int64_t i = 0; i < w.n; i++) {
        int32_t el = w.q[i];
        if (w.in[el] & 4) continue; /* queued twice */
        w.in[el] |= 4;
        const int32_t *c = aug_edit_conn(ed, el);
        for (int f = 0; f < 4; f++) {
            int32_t fv[3];
            const int *l = aug_etype_facet(AUG_TET4, f);
            for (int k = 0; k < 3; k++) fv[k] = c[l[k]];
            int32_t g = across(ed, el, fv);
            if (g < 0 || (g < w.capin && (w.in[g] & 2) && g < el)) continue; /* that side counted it */
            if (!split_cut(bc, ed, el, g, fv, 3)) continue;
            if (face_edges(sg, ed, fv, 3)) goto nomem;
            if (nnodes + 3 > capnodes) {
                capnodes = capnodes ? 2 * capnodes : 256;
                int32_t *q = aug_realloc(nodes, (size_t)capnodes * sizeof *q);
                if (!q) goto nomem;
                nodes = q;
            }
            for (int k = 0; k < 3; k++) nodes[nnodes++] = fv[k];
            bc->nface++;
        }
    }
    bc->oom = 0;
    int rc = separate_all(ed, nodes, nnodes, split_cut, bc, e);
    if (!rc && bc->oom) rc = aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
    if (rc) {
        free(w.q);
        free(w.in);
        free(nodes);
        return rc;
    }
    /* the copies of nodes on the surface are on it */
    if (on_grow(bc, aug_edit_nn(ed) + 1)) goto nomem;
    for (int64_t q = ed->nn0; q < aug_edit_nn(ed); q++) bc->on[q] = (unsigned char)on_get(bc, ed, (int32_t)q);
    free(w.q);
    free(w.in);
    free(nodes);
    return 0;
nomem:
    aug_edgemap_free(&miss);
    free(w.q);
    free(w.in);
    free(nodes);
    return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
}

int aug_blade_cut_step(aug_blade_cut *bc, aug_edit *ed, const aug_facenbr *fn, const double *add,
                       int64_t nadd, double **seg, int64_t *nseg, aug_err *e)
{
    aug_err_clear(e);
    int64_t first = bc->soup.n;
    for (int64_t i = 0; i < nadd; i++) {
        const double *t = add + 9 * i;
        int rc = aug_soup_add(&bc->soup, t, t + 3, t + 6);
        if (rc < 0) return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
        if (!rc) continue;
        double lo[3], hi[3], a[3], b[3];
        tri_box(t, lo, hi);
        if (clip_box(bc, lo, hi, 0, a, b) && aug_boxgrid_add(&bc->tg, (int32_t)(bc->soup.n - 1), a, b))
            return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
    }
    segs sg = {seg, nseg, *nseg, {0}};
    int rc = bc->mode == AUG_PATH_SPLIT ? split_step(bc, ed, first, &sg, e) : snap_step(bc, ed, fn, first, &sg, e);
    aug_edgemap_free(&sg.done);
    return rc;
}
