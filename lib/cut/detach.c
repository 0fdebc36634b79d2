/* Pieces without Dirichlet support: rigid face-connected pieces, coupled through
   shared nodes and held by constraints; a non-zero rigid motion means K is singular. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_eigen.h>
#include "aug_cut.h"

#define RANK_TOL 1e-10   /* eigenvalue of the normalised Gram matrix counted as zero */
#define MAX_COUPLED 128  /* pieces analysed jointly; beyond, each unsupported piece is bad */

void aug_pieces_free(aug_pieces *p)
{
    free(p->piece);
    free(p->bad);
    free(p->first);
    free(p->size);
    free(p->queue);
    memset(p, 0, sizeof *p);
}


static int is_fixed(const aug_mesh *m, const aug_bdelta *x, int32_t dof)
{
    return aug_mesh_fixed(m, dof, NULL) || (x && aug_find_i32(x->fix_dof, x->nfix, dof) >= 0);
}

/* rigid-motion row of component c at point r (relative, scaled):
   u = a + w x r (3-D, R = 6) or u = a + w e_z x r (2-D, R = 3) */
static int rbm_row(int dim, const double *r, int c, double *row)
{
    if (dim == 2) {
        row[0] = c == 0;
        row[1] = c == 1;
        row[2] = c == 0 ? -r[1] : r[0];
        return 3;
    }
    memset(row, 0, 6 * sizeof *row);
    row[c] = 1;
    if (c == 0) { row[4] = r[2]; row[5] = -r[1]; }
    if (c == 1) { row[3] = -r[2]; row[5] = r[0]; }
    if (c == 2) { row[3] = r[1]; row[4] = -r[0]; }
    return 6;
}

typedef struct geo {
    double c[3], L;
} geo;

static void relpos(const aug_mesh *m, const geo *g, int32_t node, double *r)
{
    for (int k = 0; k < m->dim; k++) r[k] = (m->x[(int64_t)node * m->dim + k] - g->c[k]) / g->L;
}

/* G += s * a b' on an R x R block at (bi, bj) of an n x n matrix */
static void outer(double *G, int64_t n, int64_t bi, int64_t bj, const double *a, const double *b,
                  int R, double s)
{
    for (int i = 0; i < R; i++)
        for (int j = 0; j < R; j++) G[(bi + i) + (bj + j) * n] += s * a[i] * b[j];
}

/* eigenvalues (and vectors if V) of the symmetric n x n G; 0 or -1 */
static int eig(const double *G, int64_t n, double *lam, double *V)
{
    gsl_matrix *A = gsl_matrix_alloc((size_t)n, (size_t)n);
    gsl_vector *w = gsl_vector_alloc((size_t)n);
    gsl_matrix *Z = V ? gsl_matrix_alloc((size_t)n, (size_t)n) : NULL;
    int rc = -1;
    if (!A || !w || (V && !Z)) goto out;
    for (int64_t i = 0; i < n; i++)
        for (int64_t j = 0; j < n; j++) gsl_matrix_set(A, (size_t)i, (size_t)j, G[i + j * n]);
    if (V) {
        gsl_eigen_symmv_workspace *ws = gsl_eigen_symmv_alloc((size_t)n);
        if (!ws) goto out;
        gsl_eigen_symmv(A, w, Z, ws);
        gsl_eigen_symmv_free(ws);
        for (int64_t i = 0; i < n; i++)
            for (int64_t j = 0; j < n; j++) V[i + j * n] = gsl_matrix_get(Z, (size_t)i, (size_t)j);
    } else {
        gsl_eigen_symm_workspace *ws = gsl_eigen_symm_alloc((size_t)n);
        if (!ws) goto out;
        gsl_eigen_symm(A, w, ws);
        gsl_eigen_symm_free(ws);
    }
    for (int64_t i = 0; i < n; i++) lam[i] = gsl_vector_get(w, (size_t)i);
    rc = 0;
out:
    gsl_matrix_free(A);
    gsl_vector_free(w);
    if (Z) gsl_matrix_free(Z);
    return rc;
}

/* rank R: the least eigenvalue of G above RANK_TOL times the largest (> 0) */
static int full_rank(const double *G, int R)
{
    double lam[6], mx = 0, mn = INFINITY;
    if (eig(G, R, lam, NULL)) return 0;
    for (int i = 0; i < R; i++) {
        if (lam[i] > mx) mx = lam[i];
        if (lam[i] < mn) mn = lam[i];
    }
    return mx > 0 && mn > RANK_TOL * mx;
}

/* piece[] and queue[] for ne elements (with room for the elements cuts add) */
static int reserve(aug_pieces *out, int64_t ne)
{
    if (ne <= out->cap) return 0;
    int64_t nc = ne + ne / 4 + 64;
    int32_t *a = aug_realloc(out->piece, (size_t)nc * sizeof *a);
    if (!a) return -1;
    out->piece = a;
    a = aug_realloc(out->queue, (size_t)nc * sizeof *a);
    if (!a) return -1;
    out->queue = a;
    out->cap = nc;
    return 0;
}

/* the k-th of the constrained DOFs, k < ncon(m, x): the mesh's, then the
   extra ones; -1 for an extra one the mesh has already */
static int64_t ncon(const aug_mesh *m, const aug_bdelta *x) { return m->nfix + (x ? x->nfix : 0); }
static int32_t con_dof(const aug_mesh *m, const aug_bdelta *x, int64_t k)
{
    if (k < m->nfix) return m->fix_dof[k];
    int32_t dof = x->fix_dof[k - m->nfix];
    return aug_mesh_fixed(m, dof, NULL) ? -1 : dof;
}

/* one piece holding every element: do its constraints (m's and extra's) stop
   all rigid motions? 1 unsupported, 0 supported */
static int single_unsupported(const aug_mesh *m, const aug_adj *adj, const aug_bdelta *extra)
{
    int dim = m->dim, R = dim == 3 ? 6 : 3;
    /* centre and scale from the constrained nodes: the rank does not depend on
       them, the conditioning of the rows does */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t k = 0; k < ncon(m, extra); k++) {
        int32_t dof = con_dof(m, extra, k), i = dof / dim;
        if (dof < 0 || i >= m->nn || adj->cnt[i] == 0) continue;
        for (int c = 0; c < dim; c++) {
            double x = m->x[(int64_t)i * dim + c];
            if (x < lo[c]) lo[c] = x;
            if (x > hi[c]) hi[c] = x;
        }
    }
    if (!(lo[0] <= hi[0])) return 1; /* no constraint at all */
    geo g;
    double L2 = 0, G[36], r[3], row[6];
    for (int k = 0; k < dim; k++) {
        g.c[k] = 0.5 * (lo[k] + hi[k]);
        L2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    g.L = L2 > 0 ? sqrt(L2) : 1.0;
    memset(G, 0, sizeof G);
    for (int64_t k = 0; k < ncon(m, extra); k++) {
        int32_t dof = con_dof(m, extra, k), i = dof / dim;
        if (dof < 0 || i >= m->nn || adj->cnt[i] == 0) continue;
        relpos(m, &g, i, r);
        rbm_row(dim, r, dof % dim, row);
        outer(G, R, 0, 0, row, row, R, 1.0);
    }
    return !full_rank(G, R);
}

/* the whole mesh as one piece: bad when its constraints (m's and extra's) leave
   a rigid motion free (the null space of the unsupported K, [Zienkiewicz]) */
int aug_detach_find_one(const aug_mesh *m, const aug_adj *adj, const aug_bdelta *extra,
                        aug_pieces *out, aug_err *e)
{
    aug_err_clear(e);
    int64_t ne = m->ne;
    free(out->bad);
    free(out->first);
    free(out->size);
    out->np = 1;
    out->nbad = 0;
    out->bad = aug_malloc(sizeof *out->bad);
    out->first = aug_malloc(sizeof *out->first);
    out->size = aug_malloc(sizeof *out->size);
    if (!out->bad || !out->first || !out->size) goto nomem;
    out->first[0] = 0;
    out->size[0] = ne;
    if (!single_unsupported(m, adj, extra)) return 0;
    out->bad[out->nbad++] = 0;
    if (reserve(out, ne)) goto nomem;
    memset(out->piece, 0, (size_t)ne * sizeof *out->piece);
    return 0;
nomem:
    aug_pieces_free(out);
    return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory finding detached pieces");
}

static int cmp_first(const void *a, const void *b, void *ctx)
{
    const int32_t *first = ctx;
    int32_t x = first[*(const int32_t *)a], y = first[*(const int32_t *)b];
    return (x > y) - (x < y);
}

/* the state of one analysis of several pieces (aug_detach_find) */
typedef struct det {
    const aug_mesh *m;
    const aug_adj *adj;
    const aug_facenbr *fn;
    const aug_bdelta *extra;
    aug_pieces *out;
    int dim, R;                 /* R rigid motions per piece */
    int64_t np;
    geo *g;                     /* per piece: centre and scale of its rows */
    double *G;                  /* per piece: R x R Gram matrix of its own constraints */
    unsigned char *sup;         /* per piece: supported */
    int64_t *pstart;            /* node i: its pieces plist[pstart[i] .. pstart[i+1]) */
    int32_t *plist;
    int32_t *uidx;              /* piece -> index among the unsupported ones, -1 */
    int64_t nu;                 /* unsupported pieces */
} det;

/* face-connected pieces: union-find over face neighbours in one sweep
   (queue[] holds the forest), pieces numbered by their least element; per
   piece its least element and size */
static int number_pieces(det *d)
{
    aug_pieces *out = d->out;
    const aug_facenbr *fn = d->fn;
    int64_t ne = d->m->ne;
    int32_t *up = out->queue;
    for (int64_t i = 0; i < ne; i++) up[i] = (int32_t)i;
    for (int64_t el = 0; el < ne; el++) {
        const int32_t *nb = fn->nbr + el * fn->nf;
        for (int f = 0; f < fn->nf; f++) {
            int32_t o = nb[f];
            if (o <= el) continue;
            int32_t a = (int32_t)el, b = o;
            while (up[a] != a) a = up[a] = up[up[a]];
            while (up[b] != b) b = up[b] = up[up[b]];
            if (a != b) up[a < b ? b : a] = a < b ? a : b;
        }
    }
    int64_t np = 0;
    for (int64_t el = 0; el < ne; el++) {
        int32_t a = (int32_t)el;
        while (up[a] != a) a = up[a];
        out->piece[el] = a == el ? (int32_t)np++ : out->piece[a];
    }
    d->np = out->np = np;
    out->first = aug_malloc((size_t)np * sizeof *out->first + 1);
    out->size = aug_calloc((size_t)np + 1, sizeof *out->size);
    if (!out->first || !out->size) return -1;
    for (int64_t p = 0; p < np; p++) out->first[p] = -1;
    for (int64_t el = 0; el < ne; el++) {
        int32_t p = out->piece[el];
        if (out->first[p] < 0) out->first[p] = (int32_t)el;
        out->size[p]++;
    }
    return 0;
}

/* per piece: the centre and diagonal of its bounding box, to centre and
   scale its rigid-motion rows */
static int piece_geometry(det *d)
{
    const aug_mesh *m = d->m;
    int64_t np = d->np;
    int dim = m->dim, nv = m->nv;
    d->g = aug_calloc((size_t)np + 1, sizeof *d->g);
    double *lo = aug_malloc((size_t)(np * 6) * sizeof *lo + 1), *hi = lo + np * 3;
    if (!d->g || !lo) {
        free(lo);
        return -1;
    }
    for (int64_t p = 0; p < np * 3; p++) lo[p] = INFINITY, hi[p] = -INFINITY;
    for (int64_t el = 0; el < m->ne; el++) {
        int32_t p = d->out->piece[el];
        for (int a = 0; a < nv; a++)
            for (int k = 0; k < dim; k++) {
                double x = m->x[(int64_t)m->conn[el * nv + a] * dim + k];
                if (x < lo[p * 3 + k]) lo[p * 3 + k] = x;
                if (x > hi[p * 3 + k]) hi[p * 3 + k] = x;
            }
    }
    for (int64_t p = 0; p < np; p++) {
        double L2 = 0;
        for (int k = 0; k < dim; k++) {
            double a = lo[p * 3 + k], b = hi[p * 3 + k];
            d->g[p].c[k] = 0.5 * (a + b);
            L2 += (b - a) * (b - a);
        }
        d->g[p].L = L2 > 0 ? sqrt(L2) : 1.0;
    }
    free(lo);
    return 0;
}

/* the pieces of each node (unique, increasing), as lists */
static int node_pieces(det *d)
{
    const aug_adj *adj = d->adj;
    int64_t nn = d->m->nn, tot = 0;
    d->pstart = aug_malloc((size_t)(nn + 1) * sizeof *d->pstart);
    if (!d->pstart) return -1;
    for (int64_t i = 0; i < nn; i++) tot += adj->cnt[i];
    int32_t *pl = d->plist = aug_malloc((size_t)tot * sizeof *d->plist + 1);
    if (!pl) return -1;
    tot = 0;
    for (int64_t i = 0; i < nn; i++) {
        int64_t s = d->pstart[i] = tot;
        for (int32_t k = 0; k < adj->cnt[i]; k++) {
            int32_t p = d->out->piece[adj->list[i][k]], dup = 0;
            for (int64_t q = s; q < tot && !dup; q++) dup = pl[q] == p;
            if (!dup) pl[tot++] = p;
        }
        for (int64_t a = s + 1; a < tot; a++)
            for (int64_t b = a; b > s && pl[b - 1] > pl[b]; b--) {
                int32_t t = pl[b];
                pl[b] = pl[b - 1];
                pl[b - 1] = t;
            }
    }
    d->pstart[nn] = tot;
    return 0;
}

/* per piece P: G_P = sum r r' over the rigid-motion rows r of its constrained
   (node, component) pairs, the mesh's and the extra ones not already in the
   mesh; supported when G_P has full rank */
static int own_constraints(det *d)
{
    const aug_mesh *m = d->m;
    const aug_bdelta *extra = d->extra;
    int dim = d->dim, R = d->R;
    d->G = aug_calloc((size_t)(d->np * R * R) + 1, sizeof *d->G);
    d->sup = aug_calloc((size_t)d->np + 1, 1);
    if (!d->G || !d->sup) return -1;
    double r[3], row[6];
    for (int64_t k = 0; k < ncon(m, extra); k++) {
        int32_t dof = con_dof(m, extra, k), i = dof / dim;
        if (dof < 0 || i >= m->nn) continue;
        for (int64_t q = d->pstart[i]; q < d->pstart[i + 1]; q++) {
            int32_t p = d->plist[q];
            relpos(m, &d->g[p], i, r);
            rbm_row(dim, r, dof % dim, row);
            outer(d->G + (int64_t)p * R * R, R, 0, 0, row, row, R, 1.0);
        }
    }
    for (int64_t p = 0; p < d->np; p++) d->sup[p] = full_rank(d->G + p * R * R, R);
    return 0;
}

/* an unsupported piece pinned at nodes it shares with supported pieces
   (all components there) is supported, until nothing changes */
static int propagate(det *d)
{
    int dim = d->dim, R = d->R;
    double r[3], row[6];
    for (int changed = 1; changed;) {
        changed = 0;
        for (int64_t p = 0; p < d->np; p++) {
            if (d->sup[p]) continue;
            double H[36];
            memcpy(H, d->G + p * R * R, (size_t)(R * R) * sizeof *H);
            int any = 0;
            for (int64_t i = 0; i < d->m->nn; i++) {
                if (d->pstart[i + 1] - d->pstart[i] < 2) continue;
                int mine = 0, other = 0;
                for (int64_t q = d->pstart[i]; q < d->pstart[i + 1]; q++) {
                    if (d->plist[q] == p) mine = 1;
                    else if (d->sup[d->plist[q]]) other = 1;
                }
                if (!mine || !other) continue;
                any = 1;
                relpos(d->m, &d->g[p], (int32_t)i, r);
                for (int c = 0; c < dim; c++) {
                    rbm_row(dim, r, c, row);
                    outer(H, R, 0, 0, row, row, R, 1.0);
                }
            }
            if (any && full_rank(H, R)) {
                d->sup[p] = 1;
                changed = 1;
            }
        }
    }
    return 0;
}

/* the Gram matrix (n = nu R) of the unsupported pieces' motions: their own
   constraints, full pinning at nodes shared with a supported piece, and
   u_P(x_i) = u_P0(x_i) at each node i shared with P0, the first unsupported
   piece there */
static void coupled_gram(const det *d, double *big, int64_t n)
{
    const aug_mesh *m = d->m;
    int dim = d->dim, R = d->R;
    double r[3], r0[3], row[6], row2[6];
    for (int64_t p = 0; p < d->np; p++)
        if (d->uidx[p] >= 0)
            for (int i = 0; i < R; i++)
                for (int j = 0; j < R; j++)
                    big[(d->uidx[p] * R + i) + (d->uidx[p] * R + j) * n] = d->G[p * R * R + i + j * R];
    for (int64_t i = 0; i < m->nn; i++) {
        int64_t a = d->pstart[i], b = d->pstart[i + 1];
        if (b - a < 2) continue;
        int32_t p0 = -1, anysup = 0;
        for (int64_t q = a; q < b; q++) {
            if (d->sup[d->plist[q]]) anysup = 1;
            else if (p0 < 0) p0 = d->plist[q];
        }
        if (p0 < 0) continue;
        for (int64_t q = a; q < b; q++) {
            int32_t p = d->plist[q];
            if (d->sup[p]) continue;
            relpos(m, &d->g[p], (int32_t)i, r);
            if (anysup)
                for (int c = 0; c < dim; c++) {
                    rbm_row(dim, r, c, row);
                    outer(big, n, d->uidx[p] * R, d->uidx[p] * R, row, row, R, 1.0);
                }
            if (p == p0) continue;
            relpos(m, &d->g[p0], (int32_t)i, r0);
            for (int c = 0; c < dim; c++) {
                rbm_row(dim, r0, c, row);
                rbm_row(dim, r, c, row2);
                int64_t i0 = d->uidx[p0] * R, i1 = d->uidx[p] * R;
                outer(big, n, i0, i0, row, row, R, 1.0);
                outer(big, n, i1, i1, row2, row2, R, 1.0);
                outer(big, n, i0, i1, row, row2, R, -1.0);
                outer(big, n, i1, i0, row2, row, R, -1.0);
            }
        }
    }
}

/* the unsupported pieces moving in the null space of their coupled Gram
   matrix are bad (more than MAX_COUPLED: every unsupported piece is) */
static int coupled(det *d)
{
    aug_pieces *out = d->out;
    int64_t np = d->np;
    d->uidx = aug_malloc((size_t)np * sizeof *d->uidx + 1);
    out->bad = aug_malloc((size_t)np * sizeof *out->bad + 1);
    if (!d->uidx || !out->bad) return -1;
    for (int64_t p = 0; p < np; p++) d->uidx[p] = d->sup[p] ? -1 : (int32_t)d->nu++;
    if (d->nu > MAX_COUPLED) {
        for (int64_t p = 0; p < np; p++)
            if (!d->sup[p]) out->bad[out->nbad++] = (int32_t)p;
        return 0;
    }
    if (d->nu == 0) return 0;
    int R = d->R, rc = -1;
    int64_t n = d->nu * R;
    double *big = aug_calloc((size_t)(n * n), sizeof *big);
    double *lam = aug_malloc((size_t)n * sizeof *lam);
    double *V = aug_malloc((size_t)(n * n) * sizeof *V);
    unsigned char *bad = aug_calloc((size_t)np + 1, 1);
    if (!big || !lam || !V || !bad) goto out;
    coupled_gram(d, big, n);
    if (eig(big, n, lam, V)) goto out;
    double mx = 0;
    for (int64_t i = 0; i < n; i++)
        if (lam[i] > mx) mx = lam[i];
    for (int64_t j = 0; j < n; j++) {
        if (mx > 0 && lam[j] > RANK_TOL * mx) continue;
        for (int64_t p = 0; p < np; p++) {
            if (d->uidx[p] < 0) continue;
            double s2 = 0;
            for (int i = 0; i < R; i++) s2 += V[d->uidx[p] * R + i + j * n] * V[d->uidx[p] * R + i + j * n];
            if (s2 > 1e-12) bad[p] = 1;
        }
    }
    for (int64_t p = 0; p < np; p++)
        if (bad[p]) out->bad[out->nbad++] = (int32_t)p;
    rc = 0;
out:
    free(big);
    free(lam);
    free(V);
    free(bad);
    return rc;
}

/* the one piece: its own constraints decide (single_unsupported) */
static int one_piece(det *d)
{
    d->out->bad = aug_malloc(sizeof *d->out->bad);
    if (!d->out->bad) return -1;
    if (single_unsupported(d->m, d->adj, d->extra)) d->out->bad[d->out->nbad++] = 0;
    return 0;
}

/* null space of the rigid motions r_P of all pieces P subject to
   u_P(x_i)_c = 0 for constrained (i, c) and u_P(x_i) = u_Q(x_i) at shared
   nodes: pieces, their geometry, the pieces of each node, each piece's own
   support, support passed on through shared nodes, the rest coupled */
int aug_detach_find(const aug_mesh *m, const aug_adj *adj, const aug_facenbr *fn,
                    const aug_bdelta *extra, aug_pieces *out, aug_err *e)
{
    aug_err_clear(e);
    det d;
    memset(&d, 0, sizeof d);
    d.m = m, d.adj = adj, d.fn = fn, d.extra = extra, d.out = out;
    d.dim = m->dim, d.R = m->dim == 3 ? 6 : 3;
    free(out->bad);
    free(out->first);
    free(out->size);
    out->bad = out->first = NULL;
    out->size = NULL;
    out->np = out->nbad = 0;
    int rc = reserve(out, m->ne) || number_pieces(&d);
    if (!rc && d.np == 1) rc = one_piece(&d);
    else if (!rc)
        rc = piece_geometry(&d) || node_pieces(&d) || own_constraints(&d) || propagate(&d) || coupled(&d);
    if (!rc && d.np != 1) qsort_r(out->bad, (size_t)out->nbad, sizeof *out->bad, cmp_first, out->first);
    free(d.g);
    free(d.G);
    free(d.sup);
    free(d.pstart);
    free(d.plist);
    free(d.uidx);
    if (!rc) return 0;
    aug_pieces_free(out);
    return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory finding detached pieces");
}

unsigned char *aug_piece_marks(const aug_mesh *m, const aug_pieces *p, int32_t id)
{
    unsigned char *mk = aug_calloc((size_t)m->nn + 1, 1);
    if (!mk) return NULL;
    for (int64_t el = 0; el < m->ne; el++)
        if (p->piece[el] == id)
            for (int a = 0; a < m->nv; a++) mk[m->conn[el * m->nv + a]] = 1;
    for (int64_t el = 0; el < m->ne; el++)
        if (p->piece[el] != id)
            for (int a = 0; a < m->nv; a++)
                if (mk[m->conn[el * m->nv + a]]) mk[m->conn[el * m->nv + a]] = 3;
    return mk;
}

/* nodes of piece id, increasing; count in *n. Those it shares with other
   pieces (a sliver hinged on an edge or a node of the body: face-connected
   pieces meet there) are left out while at least dim others remain: fixing
   them pinned the supported body (the armadillo's one-tet slivers at step 9:
   max |u| 1.6e5 -> 1.8e4, reactions of 1.5e6 at two body nodes) */
static int32_t *piece_nodes(const aug_mesh *m, const aug_pieces *p, int32_t id, int64_t *n)
{
    unsigned char *mk = aug_piece_marks(m, p, id);
    if (!mk) return NULL;
    int64_t k = 0, own = 0;
    for (int64_t i = 0; i < m->nn; i++) k += mk[i] != 0, own += mk[i] == 1;
    unsigned char want = own >= m->dim ? 1 : 0; /* 0: every node of the piece (1 or 3) */
    int32_t *v = aug_malloc((size_t)k * sizeof *v + 1);
    if (v) {
        k = 0;
        for (int64_t i = 0; i < m->nn; i++)
            if (want ? mk[i] == want : mk[i] != 0) v[k++] = (int32_t)i;
        *n = k;
    }
    free(mk);
    return v;
}

static double dist2(const aug_mesh *m, int32_t a, int32_t b)
{
    double s = 0;
    for (int k = 0; k < m->dim; k++) {
        double d = m->x[(int64_t)a * m->dim + k] - m->x[(int64_t)b * m->dim + k];
        s += d * d;
    }
    return s;
}

static int fix0(const aug_mesh *m, const aug_bdelta *extra, aug_bdelta *b, int32_t dof)
{
    if (is_fixed(m, extra, dof)) return 0;
    return aug_bdelta_fix(b, dof, 0.0);
}

static int argmax3(const double *v, int dim, int skip)
{
    int best = -1;
    for (int k = 0; k < dim; k++)
        if (k != skip && (best < 0 || fabs(v[k]) > fabs(v[best]))) best = k;
    return best;
}

/* 3-2-1 supports: node a all components; node b (farthest from a) the
   components across ab; node c (farthest from line ab) the component along the
   normal of abc. In 2-D: a both, b the component across ab. */
int aug_detach_pin(const aug_mesh *m, const aug_pieces *p, int32_t id, const aug_bdelta *extra,
                   aug_bdelta *b, aug_err *e)
{
    aug_err_clear(e);
    int64_t n = 0;
    int dim = m->dim;
    int32_t *v = piece_nodes(m, p, id, &n);
    if (!v) return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
    int32_t a = v[0], bb = a, c = a;
    double best = -1;
    for (int64_t i = 0; i < n; i++) {
        double d = dist2(m, a, v[i]);
        if (d > best) { best = d; bb = v[i]; }
    }
    const double *xa = m->x + (int64_t)a * dim, *xb = m->x + (int64_t)bb * dim;
    double ab[3] = {0, 0, 0}, nrm[3] = {0, 0, 0};
    for (int k = 0; k < dim; k++) ab[k] = xb[k] - xa[k];
    best = -1;
    for (int64_t i = 0; dim == 3 && i < n; i++) {
        const double *xc = m->x + (int64_t)v[i] * dim;
        double ac[3] = {xc[0] - xa[0], xc[1] - xa[1], xc[2] - xa[2]};
        double q[3] = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
                       ab[0] * ac[1] - ab[1] * ac[0]};
        double s = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
        if (s > best) {
            best = s;
            c = v[i];
            memcpy(nrm, q, sizeof nrm);
        }
    }
    free(v);
    int rc = 0, along = argmax3(ab, dim, -1);
    for (int k = 0; k < dim; k++) rc |= fix0(m, extra, b, a * dim + k);
    for (int k = 0; k < dim; k++)
        if (k != along) rc |= fix0(m, extra, b, bb * dim + k);
    if (dim == 3) rc |= fix0(m, extra, b, c * dim + argmax3(nrm, 3, -1));
    if (rc) return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
    return 0;
}

/* every component of every node of the piece (piece_nodes: its own) fixed at 0 (those not yet constrained) */
int aug_detach_drop(const aug_mesh *m, const aug_pieces *p, int32_t id, const aug_bdelta *extra,
                    aug_bdelta *b, aug_err *e)
{
    aug_err_clear(e);
    int64_t n = 0;
    int32_t *v = piece_nodes(m, p, id, &n);
    if (!v) return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
    int rc = 0;
    for (int64_t i = 0; i < n; i++)
        for (int k = 0; k < m->dim; k++) rc |= fix0(m, extra, b, v[i] * m->dim + k);
    free(v);
    if (rc) return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
    return 0;
}
