/* Test generator for refine, independent of bin/cut: the thesis's square (n x n
   nodes, each cell split in 2: 50 -> 2,500 vertices, 4,802 triangles), the cut
   curves (cubic Bezier, rational quadratic arcs) as polylines, and a small
   split-mode cutter that writes one step as MDLT + pATH (formats/stream.md 7.1,
   7.6): a node at every path/edge crossing, crossed triangles split, crossing
   nodes duplicated on the path's right. Plus checks of the result. */
#ifndef REFINE_GEN_H
#define REFINE_GEN_H

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_refine.h"

static inline void gen_square(aug_mesh *m, int n)
{
    aug_mesh_init(m);
    m->dim = 2, m->nv = 3, m->etype = AUG_TRI3;
    m->nn = (int64_t)n * n;
    m->x = malloc((size_t)m->nn * 2 * sizeof *m->x);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            m->x[2 * (j * n + i)] = (double)i / (n - 1);
            m->x[2 * (j * n + i) + 1] = (double)j / (n - 1);
        }
    m->ne = 2 * (int64_t)(n - 1) * (n - 1);
    m->conn = malloc((size_t)m->ne * 3 * sizeof *m->conn);
    m->mat = calloc((size_t)m->ne, sizeof *m->mat);
    int64_t k = 0;
    for (int j = 0; j < n - 1; j++)
        for (int i = 0; i < n - 1; i++) {
            int32_t a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
            int32_t t1[3] = {a, b, c}, t2[3] = {a, c, d};
            memcpy(m->conn + 3 * k++, t1, sizeof t1);
            memcpy(m->conn + 3 * k++, t2, sizeof t2);
        }
    m->nmat = 1;
    m->mats = calloc(1, sizeof *m->mats);
    m->mats[0].id = 5;
    strcpy(m->mats[0].name, "square");
    m->mats[0].E = 1000, m->mats[0].nu = 0.3, m->mats[0].rho = 1, m->mats[0].t = 1;
    m->nfix = 2 * n;
    m->fix_dof = malloc((size_t)m->nfix * sizeof *m->fix_dof);
    m->fix_val = calloc((size_t)m->nfix, sizeof *m->fix_val);
    for (int i = 0; i < n; i++) m->fix_dof[2 * i] = 2 * i, m->fix_dof[2 * i + 1] = 2 * i + 1;
    m->nload = n;
    m->load_dof = malloc((size_t)n * sizeof *m->load_dof);
    m->load_val = malloc((size_t)n * sizeof *m->load_val);
    for (int i = 0; i < n; i++) m->load_dof[i] = 2 * ((n - 1) * n + i) + 1, m->load_val[i] = 1;
    m->have = AUG_HAVE_NODE | AUG_HAVE_ELEM | AUG_HAVE_MATL | AUG_HAVE_FIXD | AUG_HAVE_LOAD;
}

/* ---- curves as polylines ---- */
typedef struct gen_poly {
    int n, cap, closed;
    double *p; /* 2 per point */
} gen_poly;

static inline void poly_add(gen_poly *g, double x, double y)
{
    if (g->n && fabs(g->p[2 * g->n - 2] - x) < 1e-15 && fabs(g->p[2 * g->n - 1] - y) < 1e-15) return;
    if (g->n == g->cap) {
        g->cap = g->cap ? 2 * g->cap : 64;
        g->p = realloc(g->p, (size_t)g->cap * 2 * sizeof *g->p);
    }
    g->p[2 * g->n] = x, g->p[2 * g->n + 1] = y;
    g->n++;
}

/* cubic Bezier (thesis eq. 3.1) sampled at k+1 parameters */
static inline void poly_cubic(gen_poly *g, const double P[4][2], int k)
{
    for (int i = 0; i <= k; i++) {
        double t = (double)i / k, s = 1 - t;
        double b0 = s * s * s, b1 = 3 * t * s * s, b2 = 3 * t * t * s, b3 = t * t * t;
        poly_add(g, b0 * P[0][0] + b1 * P[1][0] + b2 * P[2][0] + b3 * P[3][0],
                 b0 * P[0][1] + b1 * P[1][1] + b2 * P[2][1] + b3 * P[3][1]);
    }
}

/* rational quadratic Bezier (thesis eq. 3.7), end weights 1, middle weight w */
static inline void poly_rquad(gen_poly *g, const double P[3][2], double w, int k)
{
    for (int i = 0; i <= k; i++) {
        double t = (double)i / k, s = 1 - t;
        double b0 = s * s, b1 = 2 * w * t * s, b2 = t * t, den = b0 + b1 + b2;
        poly_add(g, (b0 * P[0][0] + b1 * P[1][0] + b2 * P[2][0]) / den,
                 (b0 * P[0][1] + b1 * P[1][1] + b2 * P[2][1]) / den);
    }
}

/* flower punch: k petals, each a rational quadratic arc between consecutive
   points on a circle (centre c, radius r0) bulging out to radius r1 */
static inline void poly_flower(gen_poly *g, const double c[2], double r0, double r1, int k, double phase)
{
    g->closed = 1;
    for (int i = 0; i < k; i++) {
        double a0 = phase + 2 * M_PI * i / k, a1 = phase + 2 * M_PI * (i + 1) / k, am = 0.5 * (a0 + a1);
        double P[3][2] = {{c[0] + r0 * cos(a0), c[1] + r0 * sin(a0)},
                          {c[0] + r1 * cos(am), c[1] + r1 * sin(am)},
                          {c[0] + r0 * cos(a1), c[1] + r0 * sin(a1)}};
        poly_rquad(g, P, cos(M_PI / k), 24);
    }
    if (g->n > 1 && hypot(g->p[0] - g->p[2 * g->n - 2], g->p[1] - g->p[2 * g->n - 1]) < 1e-12) g->n--;
}

/* ---- the split-mode cutter ---- */
static int gen_separate = 1; /* 0: split only, the cut edges stay shared (no copies) */
typedef struct gen_cross {
    int32_t a, b;   /* edge (a < b) */
    double u;       /* position on a->b */
    double s;       /* path parameter */
    double x[2];
    int32_t node;   /* new node */
} gen_cross;

static int cmp_cross(const void *x, const void *y)
{
    double a = ((const gen_cross *)x)->s, b = ((const gen_cross *)y)->s;
    return (a > b) - (a < b);
}

static double gen_cross2(const double *a, const double *b) { return a[0] * b[1] - a[1] * b[0]; }

/* One split-mode cut step of polyline g on mesh m: fills d (MDLT, relative to m)
   and seg (pATH, 4 doubles per segment). 0, or < 0 when the path hits a vertex
   (-2), crosses an edge twice (-3), has a tip outside or on an edge (-4), or
   crosses a triangle in a way this cutter does not split (-5). */
static inline int gen_cut(const aug_mesh *m, const gen_poly *g, int32_t step, aug_mdelta *d, double **seg,
                   int64_t *nseg)
{
    aug_mdelta_init(d);
    d->step = step;
    *seg = NULL;
    *nseg = 0;
    aug_edgemap em;
    aug_edgemap_init(&em, (size_t)(2 * m->ne));
    for (int64_t t = 0; t < m->ne; t++)
        for (int i = 0; i < 3; i++) aug_edgemap_link(&em, m->conn[3 * t + i], m->conn[3 * t + (i + 1) % 3], (int32_t)t);
    int ns = g->closed ? g->n : g->n - 1;
    gen_cross *X = NULL;
    int nx = 0, capx = 0, rc = 0;
    /* crossings of every path segment with every edge (brute force, bounding boxes) */
    for (int k = 0; k < ns && !rc; k++) {
        const double *p = g->p + 2 * k, *q = g->p + 2 * ((k + 1) % g->n);
        double r[2] = {q[0] - p[0], q[1] - p[1]};
        double lo[2] = {fmin(p[0], q[0]), fmin(p[1], q[1])}, hi[2] = {fmax(p[0], q[0]), fmax(p[1], q[1])};
        for (size_t h = 0; h < em.cap && !rc; h++) {
            if (em.key[h] == 0 || em.key[h] == UINT64_MAX) continue;
            int32_t a = (int32_t)((em.key[h] - 1) >> 32), b = (int32_t)((em.key[h] - 1) & 0xffffffffu);
            const double *pa = m->x + 2 * a, *pb = m->x + 2 * b;
            if (fmax(pa[0], pb[0]) < lo[0] || fmin(pa[0], pb[0]) > hi[0] || fmax(pa[1], pb[1]) < lo[1] ||
                fmin(pa[1], pb[1]) > hi[1])
                continue;
            double sv[2] = {pb[0] - pa[0], pb[1] - pa[1]}, w[2] = {pa[0] - p[0], pa[1] - p[1]};
            double den = gen_cross2(r, sv);
            if (fabs(den) < 1e-300) continue;
            double t = gen_cross2(w, sv) / den, u = gen_cross2(w, r) / den;
            if (t < 0 || t >= 1 || u < -1e-12 || u > 1 + 1e-12) continue;
            if (u < 1e-13 || u > 1 - 1e-13) {
                rc = -2;
                break;
            }
            if (nx == capx) capx = capx ? 2 * capx : 64, X = realloc(X, (size_t)capx * sizeof *X);
            gen_cross *c = &X[nx++];
            c->a = a, c->b = b, c->u = u, c->s = k + t;
            c->x[0] = pa[0] + u * sv[0], c->x[1] = pa[1] + u * sv[1];
        }
    }
    qsort(X, (size_t)nx, sizeof *X, cmp_cross);
    /* per triangle: its crossings (at most one per edge) and tips */
    int32_t *tc = calloc((size_t)m->ne * 3, sizeof *tc); /* crossing index + 1 per edge slot */
    int32_t tip_t[2] = {-1, -1};
    double tip_x[2][2];
    aug_edgemap seen;
    aug_edgemap_init(&seen, 64);
    { /* a crossing found by two path segments (at their common point) counts once */
        int k = 0;
        for (int i = 0; i < nx; i++) {
            int dupl = 0;
            for (int j = k - 1; j >= 0 && X[i].s - X[j].s < 1e-9 && !dupl; j--)
                dupl = X[j].a == X[i].a && X[j].b == X[i].b;
            if (!dupl) X[k++] = X[i];
        }
        nx = k;
    }
    for (int i = 0; i < nx && !rc; i++) {
        int32_t *sl = aug_edgemap_put(&seen, X[i].a, X[i].b);
        if (sl[0] >= 0) {
#ifdef GEN_DEBUG
            fprintf(stderr, "edge %d-%d crossed at s=%.9f and s=%.9f\n", X[i].a, X[i].b, X[sl[0]].s, X[i].s);
#endif
            rc = -3;
        }
        sl[0] = i;
        const int32_t *tt = aug_edgemap_get(&em, X[i].a, X[i].b);
        for (int s = 0; s < 2; s++) {
            if (tt[s] < 0) continue;
            const int32_t *v = m->conn + 3 * (int64_t)tt[s];
            for (int j = 0; j < 3; j++) {
                int32_t p = v[j], q = v[(j + 1) % 3];
                if ((p == X[i].a && q == X[i].b) || (p == X[i].b && q == X[i].a)) tc[3 * tt[s] + j] = i + 1;
            }
        }
    }
    if (!g->closed)
        for (int e = 0; e < 2 && !rc; e++) {
            const double *p = g->p + 2 * (e ? g->n - 1 : 0);
            for (int64_t t = 0; t < m->ne; t++) {
                const int32_t *v = m->conn + 3 * t;
                const double *a = m->x + 2 * v[0], *b = m->x + 2 * v[1], *c = m->x + 2 * v[2];
                double A = aug_orient2d(a, b, c);
                double l0 = aug_orient2d(b, c, p) / A, l1 = aug_orient2d(c, a, p) / A, l2 = aug_orient2d(a, b, p) / A;
                if (fmin(l0, fmin(l1, l2)) < -1e-12) continue;
                if (fmin(l0, fmin(l1, l2)) < 1e-9) rc = -4;
                tip_t[e] = (int32_t)t;
                tip_x[e][0] = p[0], tip_x[e][1] = p[1];
                break;
            }
        }
    /* new nodes: crossings in path order, tips, then copies */
    int64_t nn = m->nn;
    int32_t nnew = 0;
    int32_t *par = malloc((size_t)(2 * nx + 3) * sizeof *par);
    double *xn = malloc((size_t)(2 * nx + 3) * 2 * sizeof *xn);
    for (int i = 0; i < nx; i++) {
        X[i].node = (int32_t)(nn + nnew);
        par[nnew] = X[i].u < 0.5 ? X[i].a : X[i].b;
        xn[2 * nnew] = X[i].x[0], xn[2 * nnew + 1] = X[i].x[1];
        nnew++;
    }
    int32_t tip_node[2] = {-1, -1};
    for (int e = 0; e < 2; e++) {
        if (tip_t[e] < 0) continue;
        const int32_t *v = m->conn + 3 * (int64_t)tip_t[e];
        int32_t best = v[0];
        for (int j = 1; j < 3; j++)
            if (hypot(m->x[2 * v[j]] - tip_x[e][0], m->x[2 * v[j] + 1] - tip_x[e][1]) <
                hypot(m->x[2 * best] - tip_x[e][0], m->x[2 * best + 1] - tip_x[e][1]))
                best = v[j];
        tip_node[e] = (int32_t)(nn + nnew);
        par[nnew] = best;
        xn[2 * nnew] = tip_x[e][0], xn[2 * nnew + 1] = tip_x[e][1];
        nnew++;
    }
    int32_t copy0 = (int32_t)(nn + nnew);
    for (int i = 0; i < nx && gen_separate; i++) {
        par[nnew] = X[i].node;
        xn[2 * nnew] = X[i].x[0], xn[2 * nnew + 1] = X[i].x[1];
        nnew++;
    }
    /* split the crossed triangles */
    int32_t *mod = NULL, *modc = NULL, *addc = NULL, *addm = NULL;
    int64_t nmod = 0, nadd = 0;
    mod = malloc((size_t)(m->ne + 1) * sizeof *mod);
    modc = malloc((size_t)(m->ne + 1) * 3 * sizeof *modc);
    addc = malloc((size_t)(3 * m->ne + 1) * 3 * sizeof *addc);
    addm = malloc((size_t)(3 * m->ne + 1) * sizeof *addm);
    *seg = malloc((size_t)(nx + 2) * 4 * sizeof **seg);
    for (int64_t t = 0; t < m->ne && !rc; t++) {
        const int32_t *v = m->conn + 3 * t;
        int ncr = (tc[3 * t] > 0) + (tc[3 * t + 1] > 0) + (tc[3 * t + 2] > 0);
        int tipe = tip_t[0] == t ? 0 : tip_t[1] == t ? 1 : -1;
        if (tip_t[0] == t && tip_t[1] == t) rc = -5;
        if (ncr == 0 && tipe < 0) continue;
        int32_t pc[4][3];
        int npc = 0;
        int32_t cs = -1, ce = -1; /* chord start/end nodes (original numbering) */
        double csx[2], cex[2];
        if (ncr == 2 && tipe < 0) {
            int j = 0; /* rotate: crossings on edges (A,B) and (C,A) */
            while (!(tc[3 * t + j] && tc[3 * t + (j + 2) % 3])) j++;
            int32_t A = v[j], B = v[(j + 1) % 3], Cc = v[(j + 2) % 3];
            gen_cross *p = &X[tc[3 * t + j] - 1], *q = &X[tc[3 * t + (j + 2) % 3] - 1];
            int32_t P = p->node, Q = q->node;
            int32_t a1[3] = {A, P, Q};
            memcpy(pc[npc++], a1, sizeof a1);
            double lpc = hypot(p->x[0] - m->x[2 * Cc], p->x[1] - m->x[2 * Cc + 1]);
            double lbq = hypot(q->x[0] - m->x[2 * B], q->x[1] - m->x[2 * B + 1]);
            if (lpc <= lbq) {
                int32_t a2[3] = {P, B, Cc}, a3[3] = {P, Cc, Q};
                memcpy(pc[npc++], a2, sizeof a2);
                memcpy(pc[npc++], a3, sizeof a3);
            } else {
                int32_t a2[3] = {P, B, Q}, a3[3] = {B, Cc, Q};
                memcpy(pc[npc++], a2, sizeof a2);
                memcpy(pc[npc++], a3, sizeof a3);
            }
            int fwd = p->s < q->s;
            if (g->closed && fabs(p->s - q->s) > 0.5 * ns) fwd = !fwd;
            gen_cross *s0 = fwd ? p : q, *s1 = fwd ? q : p;
            cs = s0->node, ce = s1->node;
            memcpy(csx, s0->x, sizeof csx);
            memcpy(cex, s1->x, sizeof cex);
        } else if (ncr == 1 && tipe >= 0) {
            int j = 0;
            while (!tc[3 * t + j]) j++;
            int32_t A = v[j], B = v[(j + 1) % 3], Cc = v[(j + 2) % 3];
            gen_cross *p = &X[tc[3 * t + j] - 1];
            int32_t P = p->node, M = tip_node[tipe];
            int32_t a1[3] = {A, P, M}, a2[3] = {P, B, M}, a3[3] = {B, Cc, M}, a4[3] = {Cc, A, M};
            memcpy(pc[npc++], a1, sizeof a1);
            memcpy(pc[npc++], a2, sizeof a2);
            memcpy(pc[npc++], a3, sizeof a3);
            memcpy(pc[npc++], a4, sizeof a4);
            if (tipe == 0) cs = M, ce = P, memcpy(csx, tip_x[0], sizeof csx), memcpy(cex, p->x, sizeof cex);
            else cs = P, ce = M, memcpy(csx, p->x, sizeof csx), memcpy(cex, tip_x[1], sizeof cex);
        } else {
            rc = -5;
            break;
        }
        double *sg = *seg + 4 * (*nseg)++;
        sg[0] = csx[0], sg[1] = csx[1], sg[2] = cex[0], sg[3] = cex[1];
        /* pieces right of the chord take the crossing nodes' copies */
        for (int k = 0; k < npc; k++) {
            double cx = 0, cy = 0;
            for (int j = 0; j < 3; j++) {
                int32_t n = pc[k][j];
                const double *x = n < nn ? m->x + 2 * n : xn + 2 * (n - nn);
                cx += x[0] / 3, cy += x[1] / 3;
            }
            double c[2] = {cx, cy};
            if (gen_separate && aug_orient2d(csx, cex, c) < 0)
                for (int j = 0; j < 3; j++) {
                    int32_t n = pc[k][j];
                    if (n >= nn && n < nn + nx) pc[k][j] = copy0 + (n - (int32_t)nn);
                }
        }
        (void)cs, (void)ce;
        mod[nmod] = (int32_t)t;
        memcpy(modc + 3 * nmod++, pc[0], sizeof pc[0]);
        for (int k = 1; k < npc; k++) {
            memcpy(addc + 3 * nadd, pc[k], sizeof pc[k]);
            addm[nadd++] = m->mat[t];
        }
    }
    if (!rc) {
        d->nnew = nnew;
        d->parent = par, par = NULL;
        d->x = xn, xn = NULL;
        d->nmod = nmod;
        d->elem = mod, mod = NULL;
        d->conn = modc, modc = NULL;
        d->nadd = nadd;
        d->conn_add = addc, addc = NULL;
        d->mat_add = addm, addm = NULL;
    } else {
        free(*seg);
        *seg = NULL;
        *nseg = 0;
    }
    free(par), free(xn), free(mod), free(modc), free(addc), free(addm);
    free(X);
    free(tc);
    aug_edgemap_free(&em);
    aug_edgemap_free(&seen);
    return rc;
}

/* ---- checks ---- */

/* each edge in at most two triangles, with opposite orientations; every edge of
   one triangle on the square's boundary or on a cut segment; all triangles
   positive; returns the number of violations */
static inline int64_t chk_conform(const aug_mesh *m, const double *seg, int64_t nseg, double *area)
{
    aug_edgemap dir;
    aug_edgemap_init(&dir, (size_t)(2 * m->ne));
    int64_t bad = 0;
    *area = 0;
    for (int64_t t = 0; t < m->ne; t++) {
        double a = aug_elem_measure(m, t);
        if (!(a > 0)) bad++;
        *area += a;
        for (int i = 0; i < 3; i++) {
            int32_t p = m->conn[3 * t + i], q = m->conn[3 * t + (i + 1) % 3];
            int32_t *s = aug_edgemap_put(&dir, p, q);
            int sl = p < q ? 0 : 1;
            if (s[sl] >= 0) bad++;
            s[sl] = (int32_t)t;
        }
    }
    for (size_t h = 0; h < dir.cap; h++) {
        if (dir.key[h] == 0 || dir.key[h] == UINT64_MAX) continue;
        if (dir.val[2 * h] >= 0 && dir.val[2 * h + 1] >= 0) continue;
        int32_t a = (int32_t)((dir.key[h] - 1) >> 32), b = (int32_t)((dir.key[h] - 1) & 0xffffffffu);
        const double *pa = m->x + 2 * a, *pb = m->x + 2 * b;
        int onb = 0;
        for (int c = 0; c < 2 && !onb; c++)
            onb = (pa[c] == 0 && pb[c] == 0) || (pa[c] == 1 && pb[c] == 1);
        for (int64_t s = 0; s < nseg && !onb; s++) {
            const double *u = seg + 4 * s, *v = u + 2;
            double l = hypot(v[0] - u[0], v[1] - u[1]);
            double da = fabs(aug_orient2d(u, v, pa)) / l, db = fabs(aug_orient2d(u, v, pb)) / l;
            double sa = ((pa[0] - u[0]) * (v[0] - u[0]) + (pa[1] - u[1]) * (v[1] - u[1])) / (l * l);
            double sb = ((pb[0] - u[0]) * (v[0] - u[0]) + (pb[1] - u[1]) * (v[1] - u[1])) / (l * l);
            onb = da < 1e-9 && db < 1e-9 && sa > -1e-9 && sa < 1 + 1e-9 && sb > -1e-9 && sb < 1 + 1e-9;
        }
        if (!onb) bad++;
    }
    aug_edgemap_free(&dir);
    return bad;
}

static int cmp_dbl(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* every cut segment is a union of mesh edges on each of its sides: the edges
   lying on it, taken with the triangle on one side, cover it; returns the number
   of segment sides not covered */
static inline int64_t chk_cut_edges(const aug_mesh *m, const double *seg, int64_t nseg)
{
    int64_t gaps = 0;
    double *iv = malloc((size_t)(6 * m->ne + 2) * 2 * sizeof *iv);
    for (int64_t s = 0; s < nseg; s++) {
        const double *u = seg + 4 * s, *v = u + 2;
        double l = hypot(v[0] - u[0], v[1] - u[1]);
        double lo[2] = {fmin(u[0], v[0]) - 1e-9, fmin(u[1], v[1]) - 1e-9};
        double hi[2] = {fmax(u[0], v[0]) + 1e-9, fmax(u[1], v[1]) + 1e-9};
        for (int side = 0; side < 2; side++) {
            int64_t k = 0;
            for (int64_t t = 0; t < m->ne; t++)
                for (int i = 0; i < 3; i++) {
                    const double *pa = m->x + 2 * m->conn[3 * t + i], *pb = m->x + 2 * m->conn[3 * t + (i + 1) % 3];
                    const double *pc = m->x + 2 * m->conn[3 * t + (i + 2) % 3];
                    if (pa[0] < lo[0] || pa[0] > hi[0] || pa[1] < lo[1] || pa[1] > hi[1]) continue;
                    if (pb[0] < lo[0] || pb[0] > hi[0] || pb[1] < lo[1] || pb[1] > hi[1]) continue;
                    if (fabs(aug_orient2d(u, v, pa)) > 1e-9 * l * l || fabs(aug_orient2d(u, v, pb)) > 1e-9 * l * l)
                        continue;
                    if ((aug_orient2d(u, v, pc) > 0) != (side == 0)) continue;
                    double sa = ((pa[0] - u[0]) * (v[0] - u[0]) + (pa[1] - u[1]) * (v[1] - u[1])) / (l * l);
                    double sb = ((pb[0] - u[0]) * (v[0] - u[0]) + (pb[1] - u[1]) * (v[1] - u[1])) / (l * l);
                    iv[2 * k] = fmin(sa, sb), iv[2 * k + 1] = fmax(sa, sb), k++;
                }
            qsort(iv, (size_t)k, 2 * sizeof *iv, cmp_dbl);
            double reach = 0;
            for (int64_t i = 0; i < k && reach < 1 - 1e-9; i++)
                if (iv[2 * i] <= reach + 1e-9) reach = fmax(reach, iv[2 * i + 1]);
            if (reach < 1 - 1e-9) gaps++;
        }
    }
    free(iv);
    return gaps;
}

/* triangles above the aspect bound that do not sit in a corner too sharp for it
   (a corner between two edges of one triangle each, sharper than 2 asin(1/2A)) */
static inline int64_t chk_aspect(const aug_mesh *m, double A, double *maxasp, int64_t *corners)
{
    aug_edgemap em;
    aug_edgemap_init(&em, (size_t)(2 * m->ne));
    for (int64_t t = 0; t < m->ne; t++)
        for (int i = 0; i < 3; i++) aug_edgemap_link(&em, m->conn[3 * t + i], m->conn[3 * t + (i + 1) % 3], (int32_t)t);
    double thmin = 2 * asin(1 / (2 * A));
    int64_t bad = 0;
    *maxasp = 0;
    *corners = 0;
    for (int64_t t = 0; t < m->ne; t++) {
        aug_quality q;
        aug_elem_quality(m, t, &q);
        if (q.aspect <= A * (1 + 1e-9)) {
            *maxasp = fmax(*maxasp, q.aspect);
            continue;
        }
        const int32_t *v = m->conn + 3 * t;
        int sharp = 0;
        for (int i = 0; i < 3 && !sharp; i++) {
            const double *p = m->x + 2 * v[i], *a = m->x + 2 * v[(i + 1) % 3], *b = m->x + 2 * v[(i + 2) % 3];
            double ang = atan2(fabs(aug_orient2d(p, a, b)), (a[0] - p[0]) * (b[0] - p[0]) + (a[1] - p[1]) * (b[1] - p[1]));
            const int32_t *s1 = aug_edgemap_get(&em, v[i], v[(i + 1) % 3]), *s2 = aug_edgemap_get(&em, v[i], v[(i + 2) % 3]);
            int c1 = s1[0] < 0 || s1[1] < 0, c2 = s2[0] < 0 || s2[1] < 0;
            sharp = ang < thmin && c1 && c2;
        }
        if (sharp) (*corners)++;
        else {
            bad++;
            *maxasp = fmax(*maxasp, q.aspect);
        }
    }
    aug_edgemap_free(&em);
    return bad;
}
#endif
