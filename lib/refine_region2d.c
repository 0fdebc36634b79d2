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

int aug_refine_region2d(aug_refiner *r, const aug_mdelta *d, const int32_t *oldc, int64_t nnc,
                        int64_t nec, const double *seg, int64_t nseg, aug_refine_q *q, aug_err *e)
{
    aug_work *W = &r->work;
    const aug_mesh *C = &r->cut;
    int step = d->step;
    int rc = AUG_ENOMEM;
    grid G;
    aug_cdt cdt;
    memset(&cdt, 0, sizeof cdt);
    int64_t np = d->nmod + (C->ne - nec), nF = 0;
    int32_t *piece = aug_malloc((size_t)(np + 1) * sizeof *piece);
    int32_t *w2l = aug_malloc((size_t)(W->m.nn + 1) * sizeof *w2l);
    unsigned char *mark = aug_calloc((size_t)W->m.ne + 1, 1);
    int32_t *F = aug_malloc((size_t)(W->m.ne + 1) * sizeof *F);
    int32_t *loc = aug_malloc((size_t)(C->nn + 1) * sizeof *loc);
    int32_t *firstp = aug_malloc((size_t)(d->nnew + 1) * sizeof *firstp);
    int32_t *l2w = NULL, *cptr = NULL, *cind = NULL, *fin = NULL, *ftag = NULL, *fcopy = NULL;
    double *fa0 = NULL;
    aug_edgemap done;
    memset(&done, 0, sizeof done);
    memset(&G, 0, sizeof G);
    if (!piece || !w2l || !mark || !F || !loc || !firstp || aug_cdt_init(&cdt) ||
        aug_edgemap_init(&done, 64) || grid_build(&G, W))
        goto fail;
    for (int64_t i = 0; i < d->nmod; i++) piece[i] = d->elem[i];
    for (int64_t i = nec; i < C->ne; i++) piece[d->nmod + i - nec] = (int32_t)i;
    for (int64_t i = 0; i < W->m.nn; i++) w2l[i] = -1;
    for (int64_t i = 0; i < C->nn; i++) loc[i] = -1;

    /* F: work triangles overlapping the old geometry of the changed elements */
    for (int64_t k = 0; k < d->nmod; k++) {
        double A[3][2], bl[2], bh[2];
        const int32_t *v = oldc + 3 * k;
        for (int j = 0; j < 3; j++) A[j][0] = CX(r, v[j])[0], A[j][1] = CX(r, v[j])[1];
        tri_box(C->x, v, bl, bh);
        int i0, i1, j0, j1;
        cell_range(&G, bl, bh, &i0, &i1, &j0, &j1);
        for (int i = i0; i <= i1; i++)
            for (int j = j0; j <= j1; j++) {
                int64_t c = (int64_t)i * G.g + j;
                for (int64_t s = G.ptr[c]; s < G.ptr[c + 1]; s++) {
                    int32_t t = G.ind[s];
                    if (mark[t]) continue;
                    double B[3][2];
                    for (int m = 0; m < 3; m++) {
                        const double *x = WX(W, W->m.conn[3 * t + m]);
                        B[m][0] = x[0], B[m][1] = x[1];
                    }
                    if (overlap(A, B)) mark[t] = 1, F[nF++] = t;
                }
            }
    }
    {   /* F in increasing order */
        int64_t k = 0;
        for (int64_t t = 0; t < W->m.ne; t++)
            if (mark[t]) F[k++] = (int32_t)t;
    }
    q->region = nF;
    q->intersected = 0;
    for (int64_t k = 0; k < nF; k++) {
        const int32_t *v = W->m.conn + 3 * (int64_t)F[k];
        for (int64_t s = 0; s < nseg; s++)
            if (seg_crosses(WX(W, v[0]), WX(W, v[1]), WX(W, v[2]), seg + 4 * s, seg + 4 * s + 2)) {
                q->intersected++;
                break;
            }
    }
    if (!nseg) q->intersected = d->nmod;

    /* the local triangulation of F; fixed: interior constraints and material interfaces */
    for (int64_t k = 0; k < nF; k++) {
        const int32_t *v = W->m.conn + 3 * (int64_t)F[k];
        int32_t lv[3];
        for (int j = 0; j < 3; j++) {
            if (w2l[v[j]] < 0) {
                w2l[v[j]] = aug_cdt_vertex(&cdt, WX(W, v[j])[0], WX(W, v[j])[1]);
                if (w2l[v[j]] < 0) goto fail;
            }
            lv[j] = w2l[v[j]];
        }
        if (aug_cdt_tri(&cdt, lv[0], lv[1], lv[2], W->m.mat[F[k]]) < 0) goto fail;
    }
    int32_t nlv0 = cdt.nv;
    l2w = aug_malloc((size_t)(nlv0 + d->nnew + 1) * sizeof *l2w);
    if (!l2w) goto fail;
    for (int64_t i = 0; i < W->m.nn; i++)
        if (w2l[i] >= 0) l2w[w2l[i]] = (int32_t)i;
    for (int64_t k = 0; k < nF; k++) {
        const int32_t *v = W->m.conn + 3 * (int64_t)F[k];
        for (int j = 0; j < 3; j++) {
            int32_t a = v[j], b = v[(j + 1) % 3];
            int64_t n = aug_work_across(W, F[k], a, b);
            int fix = aug_work_edge_fixed(W, a, b) || (n >= 0 && W->m.mat[n] != W->m.mat[F[k]]);
            if (fix && aug_cdt_fix(&cdt, w2l[a], w2l[b])) goto fail;
        }
    }

    /* locations of the pieces' nodes: old ones where they are, new ones inserted */
    for (int64_t i = 0; i < d->nnew; i++) firstp[i] = -1;
    for (int64_t k = 0; k < np; k++) {
        const int32_t *v = C->conn + 3 * (int64_t)piece[k];
        for (int j = 0; j < 3; j++) {
            if (v[j] < nnc) {
                int32_t wn = r->cnode[v[j]];
                if (wn < 0 || w2l[wn] < 0) {
                    rc = aug_err_set(e, AUG_EDATA, -1, "MDLT",
                                     "step %d: node %d of a changed element is not in the region",
                                     step, (int)v[j]);
                    goto out;
                }
                loc[v[j]] = w2l[wn];
            } else if (firstp[v[j] - nnc] < 0) {
                firstp[v[j] - nnc] = (int32_t)k;
            }
        }
    }
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t c = (int32_t)(nnc + i), par = d->parent[i];
        const double *x = CX(r, c);
        if (!memcmp(x, CX(r, par), 2 * sizeof *x)) { /* a copy: same place as its parent */
            loc[c] = loc[par];
            continue;
        }
        if (firstp[i] < 0) continue; /* in no element */
        const int32_t *v = C->conn + 3 * (int64_t)piece[firstp[i]];
        double cen[2] = {(CX(r, v[0])[0] + CX(r, v[1])[0] + CX(r, v[2])[0]) / 3,
                         (CX(r, v[0])[1] + CX(r, v[1])[1] + CX(r, v[2])[1]) / 3};
        double wp[2] = {x[0] + 1e-6 * (cen[0] - x[0]), x[1] + 1e-6 * (cen[1] - x[1])};
        int32_t at, tw = aug_cdt_locate(&cdt, wp[0], wp[1], -1, NULL);
        int32_t t = aug_cdt_locate(&cdt, x[0], x[1], tw, &at);
        if (t < 0) {
            rc = aug_err_set(e, AUG_EDATA, -1, "MDLT",
                             "step %d: new node %lld lies outside the elements the step changed",
                             step, (long long)i);
            goto out;
        }
        if (at >= 0) {
            loc[c] = at; /* on an existing node of the refined mesh */
            continue;
        }
        int32_t lv = aug_cdt_vertex(&cdt, x[0], x[1]);
        if (lv < 0) goto fail;
        l2w[lv] = -1;
        if ((rc = aug_cdt_insert(&cdt, lv, t))) {
            if (rc == AUG_ENOMEM) goto fail;
            rc = aug_err_set(e, rc, -1, "MDLT", "step %d: cannot insert new node %lld", step,
                             (long long)i);
            goto out;
        }
        loc[c] = lv;
    }

    /* constraints: the pieces' cut edges (open in the cut mesh, or on the path) */
    for (int64_t k = 0; k < np; k++) {
        const int32_t *v = C->conn + 3 * (int64_t)piece[k];
        for (int j = 0; j < 3; j++) {
            int32_t a = v[j], b = v[(j + 1) % 3];
            const int32_t *s = aug_edgemap_get(&r->cadj, a, b);
            int open = s && (s[0] < 0 || s[1] < 0);
            if (!open && !on_path(CX(r, a), CX(r, b), seg, nseg)) continue;
            int32_t la = loc[a], lb = loc[b];
            if (la < 0 || lb < 0 || la == lb || aug_edgemap_get(&done, la, lb)) continue;
            if (!aug_edgemap_put(&done, la, lb)) goto fail;
            if ((rc = aug_cdt_recover(&cdt, la, lb))) {
                if (rc == AUG_ENOMEM) goto fail;
                rc = aug_err_set(e, rc, -1, "MDLT",
                                 "step %d: cut edge %d-%d crosses a fixed edge of the refined mesh",
                                 step, (int)a, (int)b);
                goto out;
            }
        }
    }
    if (aug_cdt_legalize(&cdt)) goto fail;

    /* new work nodes, in the cut's order: inserted points and copies */
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t c = (int32_t)(nnc + i), par = d->parent[i], lv = loc[c];
        if (lv < 0) {
            r->cnode[c] = -1;
            continue;
        }
        int32_t wpar = r->cnode[par];
        if (wpar < 0) {
            rc = aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: parent of new node %lld unused",
                             step, (long long)i);
            goto out;
        }
        int copy = !memcmp(CX(r, c), CX(r, par), 2 * sizeof(double));
        if (copy || l2w[lv] < 0) {
            int32_t wn = aug_work_node(W, CX(r, c), wpar);
            if (wn < 0) goto fail;
            if (!copy) l2w[lv] = wn;
            r->cnode[c] = wn;
        } else {
            r->cnode[c] = l2w[lv];
        }
    }

    /* candidates: local vertex -> the pieces' nodes there (CSR) */
    cptr = aug_calloc((size_t)cdt.nv + 1, sizeof *cptr);
    cind = aug_malloc((size_t)(3 * np + 1) * sizeof *cind);
    if (!cptr || !cind) goto fail;
    for (int pass = 0; pass < 2; pass++) {
        for (int64_t k = 0; k < np; k++) {
            const int32_t *v = C->conn + 3 * (int64_t)piece[k];
            for (int j = 0; j < 3; j++) {
                if (loc[v[j]] < 0) continue;
                if (pass == 0) cptr[loc[v[j]] + 1]++;
                else cind[cptr[loc[v[j]]]++] = (int32_t)(k * 3 + j);
            }
        }
        if (pass == 0)
            for (int32_t i = 0; i < cdt.nv; i++) cptr[i + 1] += cptr[i];
        else {
            for (int32_t i = cdt.nv; i > 0; i--) cptr[i] = cptr[i - 1];
            cptr[0] = 0;
        }
    }

    /* final connectivity: each corner takes the node of the piece its wedge lies in */
    fin = aug_malloc((size_t)(3 * cdt.nt + 1) * sizeof *fin);
    ftag = aug_malloc((size_t)(cdt.nt + 1) * sizeof *ftag);
    fa0 = aug_malloc((size_t)(cdt.nt + 1) * sizeof *fa0);
    if (!fin || !ftag || !fa0) goto fail;
    int32_t nfin = 0;
    for (int32_t t = 0; t < cdt.nt; t++) {
        const int32_t *v = cdt.tri + 3 * t;
        if (v[0] < 0) continue;
        const double *p[3] = {cdt.xy + 2 * v[0], cdt.xy + 2 * v[1], cdt.xy + 2 * v[2]};
        double cen[2] = {(p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3};
        for (int j = 0; j < 3; j++) {
            int32_t x = v[j], id = l2w[x];
            if (cptr[x + 1] > cptr[x]) {
                /* a point in t near corner j, within the pieces around it */
                double alt = 2 * aug_orient2d(p[0], p[1], p[2]) /
                             hypot(p[(j + 2) % 3][0] - p[(j + 1) % 3][0], p[(j + 2) % 3][1] - p[(j + 1) % 3][1]);
                for (int32_t s = cptr[x]; s < cptr[x + 1]; s++) {
                    const int32_t *u = C->conn + 3 * (int64_t)piece[cind[s] / 3];
                    int jj = cind[s] % 3;
                    const double *a = CX(r, u[jj]), *b = CX(r, u[(jj + 1) % 3]), *c = CX(r, u[(jj + 2) % 3]);
                    alt = fmin(alt, 2 * aug_orient2d(a, b, c) / hypot(c[0] - b[0], c[1] - b[1]));
                }
                double dx = cen[0] - p[j][0], dy = cen[1] - p[j][1], dl = hypot(dx, dy);
                double wp[2] = {p[j][0] + 0.25 * alt * dx / dl, p[j][1] + 0.25 * alt * dy / dl};
                double best = -1e-9;
                for (int32_t s = cptr[x]; s < cptr[x + 1]; s++) {
                    const int32_t *u = C->conn + 3 * (int64_t)piece[cind[s] / 3];
                    double bm = bary(CX(r, u[0]), CX(r, u[1]), CX(r, u[2]), wp);
                    if (bm > best) best = bm, id = r->cnode[u[cind[s] % 3]];
                }
            }
            if (id < 0) {
                rc = aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: corner without a node", step);
                goto out;
            }
            fin[3 * nfin + j] = id;
        }
        ftag[nfin] = cdt.tag[t];
        /* original measure: of the work triangle (before) holding the centroid */
        double a0 = NAN, bb = -INFINITY;
        int gi = (int)floor((cen[0] - G.lo[0]) / G.h[0]), gj = (int)floor((cen[1] - G.lo[1]) / G.h[1]);
        gi = gi < 0 ? 0 : gi >= G.g ? G.g - 1 : gi;
        gj = gj < 0 ? 0 : gj >= G.g ? G.g - 1 : gj;
        int64_t c = (int64_t)gi * G.g + gj;
        for (int64_t s = G.ptr[c]; s < G.ptr[c + 1]; s++) {
            int32_t u = G.ind[s];
            if (!mark[u]) continue;
            const int32_t *uv = W->m.conn + 3 * (int64_t)u;
            double bm = bary(WX(W, uv[0]), WX(W, uv[1]), WX(W, uv[2]), cen);
            if (bm > bb) bb = bm, a0 = W->area0[u];
        }
        fa0[nfin] = isnan(a0) ? W->area0[F[0]] : a0;
        nfin++;
    }

    /* fine nodes on a cut edge that the step separates get a copy on one side */
    fcopy = aug_malloc((size_t)cdt.nv * sizeof *fcopy);
    if (!fcopy) goto fail;
    for (int32_t i = 0; i < cdt.nv; i++) fcopy[i] = -1;
    for (size_t h = 0; h < done.cap; h++) {
        if (done.key[h] == 0 || done.key[h] == UINT64_MAX) continue;
        int32_t la = (int32_t)((done.key[h] - 1) >> 32), lb = (int32_t)((done.key[h] - 1) & 0xffffffffu);
        if (aug_edgemap_get(&cdt.edges, la, lb)) continue; /* a single edge: no fine node on it */
        const double *pa = cdt.xy + 2 * la, *pb = cdt.xy + 2 * lb;
        double l2 = (pb[0] - pa[0]) * (pb[0] - pa[0]) + (pb[1] - pa[1]) * (pb[1] - pa[1]);
        /* the two sides' nodes at the ends, from the final triangles touching the segment */
        side_key sk[2] = {{0, 0, 0}, {0, 0, 0}};
        int32_t k = 0;
        for (int32_t t = 0; t < cdt.nt; t++) {
            const int32_t *v = cdt.tri + 3 * t;
            if (v[0] < 0) continue;
            int32_t *fv = fin + 3 * k++;
            for (int j = 0; j < 3; j++) {
                if (v[j] != la && v[j] != lb) continue;
                int32_t o1 = v[(j + 1) % 3], o2 = v[(j + 2) % 3];
                /* an edge of t along the segment from this end */
                for (int s = 0; s < 2; s++) {
                    int32_t o = s ? o2 : o1, other = s ? o1 : o2;
                    const double *po = cdt.xy + 2 * o;
                    double u = ((po[0] - pa[0]) * (pb[0] - pa[0]) + (po[1] - pa[1]) * (pb[1] - pa[1])) / l2;
                    double dd = fabs(aug_orient2d(pa, pb, po)) / sqrt(l2);
                    if (!(dd <= 1e-9 * sqrt(l2) && u > 1e-12 && u < 1 - 1e-12)) continue;
                    if (!aug_cdt_is_fixed(&cdt, v[j], o)) continue;
                    int sd = aug_orient2d(pa, pb, cdt.xy + 2 * other) > 0 ? 0 : 1;
                    sk[sd].present = 1;
                    if (v[j] == la) sk[sd].a = fv[j];
                    else sk[sd].b = fv[j];
                }
            }
        }
        if (!sk[0].present || !sk[1].present || (sk[0].a == sk[1].a && sk[0].b == sk[1].b)) continue;
        int keep = 0;
        if (sk[1].a == l2w[la] && sk[1].b == l2w[lb]) keep = 1;
        else if (!(sk[0].a == l2w[la] && sk[0].b == l2w[lb]))
            keep = (sk[1].a < sk[0].a || (sk[1].a == sk[0].a && sk[1].b < sk[0].b)) ? 1 : 0;
        k = 0;
        for (int32_t t = 0; t < cdt.nt; t++) {
            const int32_t *v = cdt.tri + 3 * t;
            if (v[0] < 0) continue;
            int32_t *fv = fin + 3 * k++;
            const double *p[3] = {cdt.xy + 2 * v[0], cdt.xy + 2 * v[1], cdt.xy + 2 * v[2]};
            double cen[2] = {(p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3};
            int sd = aug_orient2d(pa, pb, cen) > 0 ? 0 : 1;
            if (sd == keep) continue;
            for (int j = 0; j < 3; j++) {
                int32_t x = v[j];
                if (cptr[x + 1] > cptr[x] || x == la || x == lb) continue; /* not a fine node */
                const double *px = cdt.xy + 2 * x;
                double u = ((px[0] - pa[0]) * (pb[0] - pa[0]) + (px[1] - pa[1]) * (pb[1] - pa[1])) / l2;
                double dd = fabs(aug_orient2d(pa, pb, px)) / sqrt(l2);
                if (!(dd <= 1e-9 * sqrt(l2) && u > 0 && u < 1)) continue;
                if (fcopy[x] < 0) {
                    fcopy[x] = aug_work_node(W, px, l2w[x]);
                    if (fcopy[x] < 0) goto fail;
                }
                fv[j] = fcopy[x];
            }
        }
    }

    /* write back: the region's slots by material, then new elements */
    for (int64_t k = 0; k < nF; k++)
        if ((rc = aug_work_unlink(W, F[k]))) goto werr;
    {
        int64_t used = 0;
        unsigned char *taken = aug_calloc((size_t)nfin + 1, 1);
        if (!taken) goto fail;
        for (int64_t k = 0; k < nF; k++) { /* each slot: the first unused triangle of its material */
            int32_t mat = W->m.mat[F[k]], t = 0;
            while (t < nfin && (taken[t] || ftag[t] != mat)) t++;
            if (t == nfin) {
                free(taken);
                rc = aug_err_set(e, AUG_EDATA, -1, "MDLT",
                                 "step %d: re-triangulation has fewer elements than it replaces",
                                 step);
                goto out;
            }
            taken[t] = 1;
            used++;
            W->area0[F[k]] = fa0[t];
            if ((rc = aug_work_put(W, F[k], fin + 3 * t))) {
                free(taken);
                goto werr;
            }
        }
        for (int32_t t = 0; t < nfin; t++) {
            if (taken[t]) continue;
            if (aug_work_add(W, fin + 3 * t, ftag[t], fa0[t]) < 0) {
                free(taken);
                goto fail;
            }
        }
        free(taken);
        (void)used;
    }
    for (int64_t t = 0; t < W->m.ne; t++) /* every new element positive */
        if (W->stamp[t] == W->step && !(aug_elem_measure(&W->m, t) > 0)) {
            rc = aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: re-triangulation made element %lld "
                             "inverted or degenerate", step, (long long)t);
            goto out;
        }
    rc = 0;
    goto out;
werr:
    if (rc != AUG_ENOMEM) {
        rc = aug_err_set(e, rc, -1, "MDLT", "step %d: re-triangulation is not manifold", step);
        goto out;
    }
fail:
    rc = aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
out:
    free(piece);
    free(w2l);
    free(mark);
    free(F);
    free(loc);
    free(firstp);
    free(l2w);
    free(cptr);
    free(cind);
    free(fin);
    free(ftag);
    free(fa0);
    free(fcopy);
    aug_edgemap_free(&done);
    aug_cdt_free(&cdt);
    grid_free(&G);
    return rc;
}
