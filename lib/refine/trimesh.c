/* The editable copy of the refined mesh: in-place edits with edge adjacency (2-D) or
   node incidence (3-D), the step's changes kept so they can be written as an MDLT. */
#include <stdlib.h>
#include <string.h>
#include "aug_refine.h"

static int grow_nodes(aug_work *w, int64_t need)
{
    if (need <= w->capn) return 0;
    int64_t cap = w->capn ? w->capn : 1024;
    while (cap < need) cap *= 2;
    double *x = aug_realloc(w->m.x, (size_t)(cap * w->m.dim) * sizeof *x);
    if (!x) return -1;
    w->m.x = x;
    int32_t *cr = aug_realloc(w->cre, (size_t)(cap * 4) * sizeof *cr);
    if (!cr) return -1;
    for (int64_t i = w->capn * 4; i < cap * 4; i++) cr[i] = -1;
    w->cre = cr;
    if (w->m.dim == 3) {
        int32_t **l = aug_realloc(w->nel, (size_t)cap * sizeof *l);
        if (!l) return -1;
        w->nel = l;
        int32_t *c = aug_realloc(w->ncnt, (size_t)cap * sizeof *c);
        if (!c) return -1;
        w->ncnt = c;
        int32_t *k = aug_realloc(w->ncap, (size_t)cap * sizeof *k);
        if (!k) return -1;
        w->ncap = k;
        for (int64_t i = w->capn; i < cap; i++) l[i] = NULL, c[i] = k[i] = 0;
    }
    w->capn = cap;
    return 0;
}

static int grow_elems(aug_work *w, int64_t need)
{
    if (need <= w->cape) return 0;
    int64_t cap = w->cape ? w->cape : 1024;
    while (cap < need) cap *= 2;
    int32_t *c = aug_realloc(w->m.conn, (size_t)(cap * w->m.nv) * sizeof *c);
    if (!c) return -1;
    w->m.conn = c;
    int32_t *mt = aug_realloc(w->m.mat, (size_t)cap * sizeof *mt);
    if (!mt) return -1;
    w->m.mat = mt;
    double *a = aug_realloc(w->area0, (size_t)cap * sizeof *a);
    if (!a) return -1;
    w->area0 = a;
    int32_t *s = aug_realloc(w->stamp, (size_t)cap * sizeof *s);
    if (!s) return -1;
    w->stamp = s;
    int32_t *v = aug_realloc(w->ver, (size_t)cap * sizeof *v);
    if (!v) return -1;
    w->ver = v;
    int32_t *o = aug_realloc(w->own, (size_t)cap * sizeof *o);
    if (!o) return -1;
    w->own = o;
    w->cape = cap;
    return 0;
}

static int inc_add(aug_work *w, int32_t node, int32_t e)
{
    if (w->ncnt[node] == w->ncap[node]) {
        int32_t cap = w->ncap[node] ? 2 * w->ncap[node] : 8;
        int32_t *l = aug_realloc(w->nel[node], (size_t)cap * sizeof *l);
        if (!l) return -1;
        w->nel[node] = l;
        w->ncap[node] = cap;
    }
    w->nel[node][w->ncnt[node]++] = e;
    return 0;
}

static void inc_del(aug_work *w, int32_t node, int32_t e)
{
    for (int32_t i = 0; i < w->ncnt[node]; i++)
        if (w->nel[node][i] == e) {
            w->nel[node][i] = w->nel[node][--w->ncnt[node]];
            return;
        }
}

/* register element e's edges (2-D) or nodes (3-D); AUG_EDATA: edge of a third triangle */
static int link_elem(aug_work *w, int64_t e)
{
    const int32_t *v = w->m.conn + e * w->m.nv;
    if (w->m.dim == 3) {
        for (int i = 0; i < 4; i++)
            if (inc_add(w, v[i], (int32_t)e)) return AUG_ENOMEM;
        return 0;
    }
    for (int i = 0; i < 3; i++) {
        int rc = aug_edgemap_link(&w->adj, v[i], v[(i + 1) % 3], (int32_t)e);
        if (rc) return rc == -1 ? AUG_ENOMEM : AUG_EDATA;
    }
    return 0;
}

static void unlink_elem(aug_work *w, int64_t e)
{
    const int32_t *v = w->m.conn + e * w->m.nv;
    if (w->m.dim == 3) {
        for (int i = 0; i < 4; i++) inc_del(w, v[i], (int32_t)e);
        return;
    }
    for (int i = 0; i < 3; i++) aug_edgemap_unlink(&w->adj, v[i], v[(i + 1) % 3], (int32_t)e);
}

int aug_work_init(aug_work *w, const aug_mesh *m)
{
    memset(w, 0, sizeof *w);
    w->m.dim = m->dim;
    w->m.nv = m->nv;
    w->m.etype = m->etype;
    w->step = -1;
    if (aug_edgemap_init(&w->adj, m->dim == 2 ? (size_t)(2 * m->ne) : 0) ||
        aug_edgemap_init(&w->fixed, 16) || grow_nodes(w, m->nn + 1) || grow_elems(w, m->ne + 1))
        goto nomem;
    memcpy(w->m.x, m->x, (size_t)(m->nn * m->dim) * sizeof(double));
    memcpy(w->m.conn, m->conn, (size_t)(m->ne * m->nv) * sizeof(int32_t));
    memcpy(w->m.mat, m->mat, (size_t)m->ne * sizeof(int32_t));
    w->m.nn = m->nn;
    w->m.ne = m->ne;
    for (int64_t e = 0; e < m->ne; e++) {
        double a = aug_elem_measure(&w->m, e);
        w->area0[e] = a < 0 ? -a : a;
        w->stamp[e] = -1;
        w->ver[e] = 0;
        w->own[e] = (int32_t)e;
        int rc = link_elem(w, e);
        if (rc) return rc;
    }
    aug_work_begin(w, -1);
    return 0;
nomem:
    aug_work_free(w);
    return AUG_ENOMEM;
}

void aug_work_free(aug_work *w)
{
    free(w->m.x);
    free(w->m.conn);
    free(w->m.mat);
    free(w->area0);
    free(w->stamp);
    free(w->ver);
    free(w->own);
    free(w->mod);
    free(w->mod_old);
    free(w->parent);
    free(w->cre);
    if (w->nel)
        for (int64_t i = 0; i < w->capn; i++) free(w->nel[i]);
    free(w->nel);
    free(w->ncnt);
    free(w->ncap);
    aug_edgemap_free(&w->adj);
    aug_edgemap_free(&w->fixed);
    memset(w, 0, sizeof *w);
}

void aug_work_begin(aug_work *w, int32_t step)
{
    w->step = step;
    w->nn_begin = w->m.nn;
    w->ne_begin = w->m.ne;
    w->nmod = 0;
}

int32_t aug_work_node(aug_work *w, const double *x, int32_t parent)
{
    int64_t k = w->m.nn - w->nn_begin;
    if (grow_nodes(w, w->m.nn + 1)) return -1;
    if (k + 1 > w->capparent) {
        int64_t cap = w->capparent ? 2 * w->capparent : 256;
        int32_t *p = aug_realloc(w->parent, (size_t)cap * sizeof *p);
        if (!p) return -1;
        w->parent = p;
        w->capparent = cap;
    }
    memcpy(w->m.x + w->m.nn * w->m.dim, x, (size_t)w->m.dim * sizeof *x);
    if (w->m.dim == 3) w->ncnt[w->m.nn] = 0;
    w->parent[k] = parent;
    return (int32_t)w->m.nn++;
}

void aug_work_creators(aug_work *w, int32_t node, const int32_t *c, int n)
{
    for (int k = 0; k < 4; k++) w->cre[(int64_t)node * 4 + k] = k < n ? c[k] : -1;
}

static int record_mod(aug_work *w, int64_t e)
{
    int nv = w->m.nv;
    if (e >= w->ne_begin || w->stamp[e] == w->step) return 0;
    if (w->nmod == w->capmod) {
        int64_t cap = w->capmod ? 2 * w->capmod : 256;
        int32_t *m = aug_realloc(w->mod, (size_t)cap * sizeof *m);
        if (!m) return AUG_ENOMEM;
        w->mod = m;
        int32_t *o = aug_realloc(w->mod_old, (size_t)(cap * nv) * sizeof *o);
        if (!o) return AUG_ENOMEM;
        w->mod_old = o;
        w->capmod = cap;
    }
    w->mod[w->nmod] = (int32_t)e;
    memcpy(w->mod_old + w->nmod * nv, w->m.conn + e * nv, (size_t)nv * sizeof(int32_t));
    w->nmod++;
    w->stamp[e] = w->step;
    return 0;
}

int aug_work_unlink(aug_work *w, int64_t e)
{
    if (record_mod(w, e)) return AUG_ENOMEM;
    unlink_elem(w, e);
    w->stamp[e] = w->step;
    w->ver[e]++;
    return 0;
}

int aug_work_put(aug_work *w, int64_t e, const int32_t *conn)
{
    memcpy(w->m.conn + e * w->m.nv, conn, (size_t)w->m.nv * sizeof *conn);
    w->stamp[e] = w->step;
    w->ver[e]++;
    return link_elem(w, e);
}

int aug_work_set(aug_work *w, int64_t e, const int32_t *conn)
{
    int rc = aug_work_unlink(w, e);
    return rc ? rc : aug_work_put(w, e, conn);
}

int64_t aug_work_add(aug_work *w, const int32_t *conn, int32_t mat, double area0)
{
    int64_t e = w->m.ne;
    if (grow_elems(w, e + 1)) return -1;
    memcpy(w->m.conn + e * w->m.nv, conn, (size_t)w->m.nv * sizeof *conn);
    w->m.mat[e] = mat;
    w->area0[e] = area0;
    w->stamp[e] = w->step;
    w->ver[e] = 0;
    w->own[e] = -1;
    w->m.ne++;
    if (link_elem(w, e)) return -1;
    return e;
}

int64_t aug_work_across(const aug_work *w, int64_t t, int32_t a, int32_t b)
{
    const int32_t *s = aug_edgemap_get(&w->adj, a, b);
    if (!s) return -1;
    return s[0] == t ? s[1] : s[0];
}

int aug_work_edge_fixed(const aug_work *w, int32_t a, int32_t b)
{
    return aug_edgemap_get(&w->fixed, a, b) != NULL;
}

static int cmp_mod_i64(const void *x, const void *y)
{
    int64_t a = *(const int64_t *)x, b = *(const int64_t *)y;
    return (a > b) - (a < b);
}

int aug_work_delta(const aug_work *w, int32_t step, int32_t flags, aug_mdelta *d,
                   int32_t **oldconn, aug_err *e)
{
    int nv = w->m.nv, dim = w->m.dim;
    aug_mdelta_init(d);
    d->step = step;
    d->flags = flags;
    d->nnew = w->m.nn - w->nn_begin;
    d->nadd = w->m.ne - w->ne_begin;
    int64_t *ord = aug_malloc((size_t)(w->nmod + 1) * sizeof *ord);
    d->parent = aug_malloc((size_t)(d->nnew + 1) * sizeof *d->parent);
    d->x = aug_malloc((size_t)(d->nnew * dim + 1) * sizeof *d->x);
    d->elem = aug_malloc((size_t)(w->nmod + 1) * sizeof *d->elem);
    d->conn = aug_malloc((size_t)(w->nmod * nv + 1) * sizeof *d->conn);
    d->conn_add = aug_malloc((size_t)(d->nadd * nv + 1) * sizeof *d->conn_add);
    d->mat_add = aug_malloc((size_t)(d->nadd + 1) * sizeof *d->mat_add);
    int32_t *old = aug_malloc((size_t)(w->nmod * nv + 1) * sizeof *old);
    if (!ord || !d->parent || !d->x || !d->elem || !d->conn || !d->conn_add || !d->mat_add ||
        !old) {
        free(ord);
        free(old);
        aug_mdelta_free(d);
        return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
    }
    if (d->nnew > 0) { /* (no node added: w->parent may be NULL) */
        memcpy(d->parent, w->parent, (size_t)d->nnew * sizeof *d->parent);
        memcpy(d->x, w->m.x + w->nn_begin * dim, (size_t)(d->nnew * dim) * sizeof *d->x);
    }
    /* sort the re-wired elements, keeping their old connectivity alongside */
    for (int64_t i = 0; i < w->nmod; i++) ord[i] = (int64_t)w->mod[i] << 32 | (uint32_t)i;
    qsort(ord, (size_t)w->nmod, sizeof *ord, cmp_mod_i64);
    int64_t k = 0;
    for (int64_t i = 0; i < w->nmod; i++) {
        int32_t el = (int32_t)(ord[i] >> 32);
        int64_t j = (int64_t)(uint32_t)ord[i];
        const int32_t *now = w->m.conn + (int64_t)el * nv, *was = w->mod_old + j * nv;
        if (!memcmp(now, was, (size_t)nv * sizeof *now)) continue; /* written back unchanged */
        d->elem[k] = el;
        memcpy(d->conn + k * nv, now, (size_t)nv * sizeof *now);
        memcpy(old + k * nv, was, (size_t)nv * sizeof *was);
        k++;
    }
    d->nmod = k;
    memcpy(d->conn_add, w->m.conn + w->ne_begin * nv, (size_t)(d->nadd * nv) * sizeof *d->conn_add);
    memcpy(d->mat_add, w->m.mat + w->ne_begin, (size_t)d->nadd * sizeof *d->mat_add);
    free(ord);
    if (oldconn) *oldconn = old;
    else free(old);
    return 0;
}
