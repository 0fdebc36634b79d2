/* Advancing planar cut by node duplication (AMPS sec. 4.3.2; augmented-matrix
   paper sec. 4.3.2): the faces between elements on the two sides of n.x = d
   open node by node along the advance direction. */
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

void aug_plane_free(aug_plane_cut *pc)
{
    free(pc->side);
    free(pc->nodes);
    memset(pc, 0, sizeof *pc);
}

static double dot(const double *a, const double *b, int dim)
{
    double s = 0;
    for (int k = 0; k < dim; k++) s += a[k] * b[k];
    return s;
}

typedef struct keyed {
    int64_t key;
    int32_t node;
} keyed;

static int cmp_keyed(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return (x->node > y->node) - (x->node < y->node);
}

/* unit vector along v with the normal component removed; 0 if it vanishes */
static int in_plane(const double *n, const double *v, int dim, double *out, double scale)
{
    double vn = dot(v, n, dim), s = 0;
    for (int k = 0; k < dim; k++) {
        out[k] = v[k] - vn * n[k];
        s += out[k] * out[k];
    }
    s = sqrt(s);
    if (!(s > 1e-9 * scale)) return 0;
    for (int k = 0; k < dim; k++) out[k] /= s;
    return 1;
}

/* side(e) = [n.centroid(e) > d]; cut faces = faces shared by elements of both sides;
   cut nodes = their nodes, sorted by (x.adv, node index) */
int aug_plane_plan(aug_plane_cut *pc, const aug_mesh *m, const aug_adj *adj, const double n[3],
                   double d, const double *adv, aug_err *e)
{
    aug_err_clear(e);
    memset(pc, 0, sizeof *pc);
    int dim = m->dim, nv = m->nv, nfc = aug_etype_nfacet(m->etype), fv = aug_etype_facet_nv(m->etype);
    double len = sqrt(dot(n, n, dim));
    if (!(len > 0))
        return aug_err_set(e, AUG_EUSAGE, -1, "", dim == 2 ? "the plane normal has no x or y component "
                                                              "(a 2-D mesh: z is ignored)"
                                                            : "the plane normal is zero");
    pc->dim = dim;
    for (int k = 0; k < dim; k++) pc->n[k] = n[k] / len;
    pc->d = d / len;
    pc->ne = m->ne;
    pc->side = aug_malloc((size_t)m->ne + 1);
    unsigned char *mark = aug_calloc((size_t)m->nn + 1, 1);
    keyed *kv = NULL;
    if (!pc->side || !mark) goto nomem;
    int64_t nplus = 0;
    for (int64_t el = 0; el < m->ne; el++) {
        double c[3] = {0, 0, 0};
        for (int a = 0; a < nv; a++)
            for (int k = 0; k < dim; k++) c[k] += m->x[(int64_t)m->conn[el * nv + a] * dim + k] / nv;
        pc->side[el] = dot(c, pc->n, dim) > pc->d;
        nplus += pc->side[el];
    }
    for (int64_t el = 0; el < m->ne; el++) {
        if (!pc->side[el]) continue;
        for (int f = 0; f < nfc; f++) {
            int32_t g = aug_adj_across(m, adj, el, f);
            if (g < 0 || pc->side[g]) continue;
            pc->nface++;
            const int *l = aug_etype_facet(m->etype, f);
            for (int k = 0; k < fv; k++) mark[m->conn[el * nv + l[k]]] = 1;
        }
    }
    if (nplus == 0 || nplus == m->ne || pc->nface == 0) {
        free(mark);
        aug_plane_free(pc);
        return aug_err_set(e, AUG_EDATA, -1, "", "the plane %.17g,%.17g,%.17g,%.17g does not cut the mesh (it "
                           "parts no two neighbouring elements by their centroids)",
                           n[0], n[1], dim == 3 ? n[2] : 0.0, d);
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double cc[3] = {0, 0, 0}, cf[3] = {0, 0, 0};
    int64_t nc = 0, nf = 0;
    for (int64_t i = 0; i < m->nn; i++) {
        const double *x = m->x + i * dim;
        for (int k = 0; k < dim; k++) {
            if (x[k] < lo[k]) lo[k] = x[k];
            if (x[k] > hi[k]) hi[k] = x[k];
        }
        if (mark[i]) {
            nc++;
            for (int k = 0; k < dim; k++) cc[k] += x[k];
        }
    }
    double scale = 0;
    for (int k = 0; k < dim; k++) scale += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    scale = sqrt(scale);
    if (!(scale > 0)) scale = 1;
    for (int64_t i = 0; i < m->nfix; i++) {
        if (i > 0 && m->fix_dof[i] / dim == m->fix_dof[i - 1] / dim) continue;
        const double *x = m->x + (int64_t)(m->fix_dof[i] / dim) * dim;
        nf++;
        for (int k = 0; k < dim; k++) cf[k] += x[k];
    }
    for (int k = 0; k < dim; k++) {
        cc[k] /= nc;
        if (nf) cf[k] /= nf;
    }
    if (adv) {
        if (!in_plane(pc->n, adv, dim, pc->adv, 1.0)) {
            free(mark);
            aug_plane_free(pc);
            return aug_err_set(e, AUG_EUSAGE, -1, "", "the advance direction is normal to the plane");
        }
    } else {
        double v[3];
        for (int k = 0; k < dim; k++) v[k] = cc[k] - cf[k];
        if (!nf || !in_plane(pc->n, v, dim, pc->adv, scale)) {
            /* no fixed set to move away from: the in-plane axis of widest extent */
            double best = -1;
            for (int ax = 0; ax < dim; ax++) {
                double u[3] = {0, 0, 0}, a[3], mn = INFINITY, mx = -INFINITY;
                u[ax] = 1;
                if (!in_plane(pc->n, u, dim, a, 1.0)) continue;
                for (int64_t i = 0; i < m->nn; i++) {
                    if (!mark[i]) continue;
                    double s = dot(m->x + i * dim, a, dim);
                    if (s < mn) mn = s;
                    if (s > mx) mx = s;
                }
                if (mx - mn > best * (1 + 1e-12)) {
                    best = mx - mn;
                    memcpy(pc->adv, a, sizeof a);
                }
            }
        }
    }
    kv = aug_malloc((size_t)nc * sizeof *kv + 1);
    pc->nodes = aug_malloc((size_t)nc * sizeof *pc->nodes + 1);
    if (!kv || !pc->nodes) goto nomem;
    nc = 0;
    double q = 1e-9 * scale;
    for (int64_t i = 0; i < m->nn; i++)
        if (mark[i]) {
            kv[nc].key = (int64_t)llround(dot(m->x + i * dim, pc->adv, dim) / q);
            kv[nc++].node = (int32_t)i;
        }
    qsort(kv, (size_t)nc, sizeof *kv, cmp_keyed);
    for (int64_t i = 0; i < nc; i++) pc->nodes[i] = kv[i].node;
    pc->ncut = nc;
    pc->next = 0;
    free(kv);
    free(mark);
    return 0;
nomem:
    free(kv);
    free(mark);
    aug_plane_free(pc);
    return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory planning the cut");
}

static int cut_sides(void *ctx, const aug_edit *ed, int32_t a, int32_t b, const int32_t *f, int nf)
{
    (void)ed;
    (void)f;
    (void)nf;
    const aug_plane_cut *pc = ctx;
    if (a >= pc->ne || b >= pc->ne) return 0;
    return pc->side[a] != pc->side[b];
}

/* the - side keeps the node; ties by element index */
static int64_t rank_side(void *ctx, int32_t el)
{
    const aug_plane_cut *pc = ctx;
    int s = el < pc->ne ? pc->side[el] : 1;
    return (int64_t)s * ((int64_t)1 << 40) + el;
}

static int push_seg(double **seg, int64_t *nseg, int64_t *cap, const double *a, const double *b,
                    int dim)
{
    if (*nseg == *cap) {
        int64_t nc = *cap ? 2 * *cap : 64;
        double *q = aug_realloc(*seg, (size_t)(nc * 2 * dim) * sizeof *q);
        if (!q) return -1;
        *seg = q;
        *cap = nc;
    }
    memcpy(*seg + *nseg * 2 * dim, a, (size_t)dim * sizeof *a);
    memcpy(*seg + *nseg * 2 * dim + dim, b, (size_t)dim * sizeof *b);
    (*nseg)++;
    return 0;
}

/* the segment ab among segments lo..hi-1 of seg, either way round: by
   position, as formats 7.6 lists each edge once. Node numbers do not tell:
   after an earlier cut (cut | cut) two faces at a cut node may hold a node
   and its copy, one edge of the mesh under two numberings (the armadillo,
   a second plane: 8 segments for 7 edges) */
static int seg_seen(const double *seg, int64_t lo, int64_t hi, const double *a, const double *b, int dim)
{
    size_t sz = (size_t)dim * sizeof *a;
    for (int64_t i = lo; i < hi; i++) {
        const double *p = seg + i * 2 * dim, *q = p + dim;
        if ((!memcmp(p, a, sz) && !memcmp(q, b, sz)) || (!memcmp(p, b, sz) && !memcmp(q, a, sz))) return 1;
    }
    return 0;
}

/* duplicate cut nodes next .. next+count-1: the + side of each star gets a copy */
int aug_plane_step(aug_plane_cut *pc, aug_edit *ed, int64_t count, double **seg, int64_t *nseg,
                   aug_err *e)
{
    aug_err_clear(e);
    int dim = pc->dim;
    int64_t cap = *nseg, nseg0 = *nseg;
    aug_edgemap done = {0};
    if (pc->next >= pc->ncut)
        return aug_err_set(e, AUG_EDATA, -1, "MDLT", "all %lld cut nodes of the plane are cut",
                           (long long)pc->ncut);
    for (int64_t i = 0; i < count && pc->next < pc->ncut; i++) {
        int32_t p = pc->nodes[pc->next++];
        /* the edges of the faces this opens: p's star, + against - */
        int32_t s = ed->adj->cnt[p];
        for (int32_t a = 0; a < s; a++)
            for (int32_t b = 0; b < s; b++) {
                int32_t ea = ed->adj->list[p][a], eb = ed->adj->list[p][b];
                if (ea >= pc->ne || eb >= pc->ne || !pc->side[ea] || pc->side[eb]) continue;
                const int32_t *ca = aug_edit_conn(ed, ea), *cb = aug_edit_conn(ed, eb);
                int32_t f[4];
                int nf = aug_shared_facet(ed->m->etype, ca, cb, f);
                /* the facet's edges: every pair of a simplex facet, the sides of a quadrilateral */
                for (int x = 0; x < nf; x++)
                    for (int y = x + 1; y < nf; y++) {
                        if (nf == 4 && y != x + 1 && !(x == 0 && y == 3)) continue;
                        if (aug_edgemap_get(&done, f[x], f[y])) continue;
                        if (!aug_edgemap_put(&done, f[x], f[y])) goto nomem;
                        const double *xa = aug_edit_x(ed, f[x]), *xb = aug_edit_x(ed, f[y]);
                        if (!seg_seen(*seg, nseg0, *nseg, xa, xb, dim) && push_seg(seg, nseg, &cap, xa, xb, dim))
                            goto nomem;
                    }
            }
        int nc;
        int rc = aug_separate_node(ed, p, cut_sides, rank_side, pc, &nc, e);
        if (rc) {
            aug_edgemap_free(&done);
            return rc;
        }
    }
    aug_edgemap_free(&done);
    return 0;
nomem:
    aug_edgemap_free(&done);
    return aug_err_set(e, AUG_ENOMEM, -1, "pATH", "out of memory");
}

/* a random plane: normal uniform on the sphere (circle in 2-D), through a point
   in the middle half of the bounding box */
void aug_plane_random(const aug_mesh *m, unsigned long seed, double n[4])
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, seed);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, s = 0;
    for (int64_t i = 0; i < m->nn; i++)
        for (int k = 0; k < m->dim; k++) {
            lo[k] = fmin(lo[k], m->x[i * m->dim + k]);
            hi[k] = fmax(hi[k], m->x[i * m->dim + k]);
        }
    do {
        s = 0;
        for (int k = 0; k < 3; k++) {
            n[k] = k < m->dim ? 2 * gsl_rng_uniform(r) - 1 : 0;
            s += n[k] * n[k];
        }
    } while (s > 1 || s < 1e-4);
    n[3] = 0;
    for (int k = 0; k < m->dim; k++) {
        n[k] /= sqrt(s);
        n[3] += n[k] * (lo[k] + (0.25 + 0.5 * gsl_rng_uniform(r)) * (hi[k] - lo[k]));
    }
    gsl_rng_free(r);
}

