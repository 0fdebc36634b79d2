/* Mesh deltas and updates in memory: init/free, and aug_mesh_apply (a step's
   mesh change applied to the current mesh, formats/stream.md 7.1). */
#include <stdlib.h>
#include <string.h>
#include "aug_update.h"

void aug_mdelta_init(aug_mdelta *d) { memset(d, 0, sizeof *d); }
void aug_mdelta_free(aug_mdelta *d)
{
    free(d->parent);
    free(d->x);
    free(d->elem);
    free(d->conn);
    free(d->conn_add);
    free(d->mat_add);
    aug_mdelta_init(d);
}
/* d := d then d2 as one step's MDLT (formats/stream.md 7.1), where d2 was
   made on the mesh after d (so its new nodes follow d's and it adds no
   elements); old: the connectivity before d of d's re-wired elements (in
   d->elem's order), extended with those d2 re-wires first; ne0: the element
   count before d. A re-wired element of d, or one d added, takes d2's
   connectivity. 0, or -1 (memory: d and *old as they were). */
int aug_mdelta_merge(aug_mdelta *d, int32_t **old, int nv, int dim, int64_t ne0, const aug_mdelta *d2,
                     const int32_t *old2)
{
    int64_t nnew = d->nnew + d2->nnew, nmod = d->nmod, extra = 0;
    for (int64_t i = 0; i < d2->nmod; i++) {
        int32_t el = d2->elem[i];
        if (el < ne0 && !bsearch(&el, d->elem, (size_t)d->nmod, sizeof el, aug_cmp_i32)) extra++;
    }
    int32_t *parent = aug_malloc((size_t)nnew * sizeof *parent + 1);
    double *x = aug_malloc((size_t)(nnew * dim) * sizeof *x + 1);
    int32_t *elem = aug_malloc((size_t)(nmod + extra) * sizeof *elem + 1);
    int32_t *conn = aug_malloc((size_t)((nmod + extra) * nv) * sizeof *conn + 1);
    int32_t *oc = aug_malloc((size_t)((nmod + extra) * nv) * sizeof *oc + 1);
    if (!parent || !x || !elem || !conn || !oc) {
        free(parent), free(x), free(elem), free(conn), free(oc);
        return -1;
    }
    if (d->nnew) memcpy(parent, d->parent, (size_t)d->nnew * sizeof *parent);
    if (d2->nnew) memcpy(parent + d->nnew, d2->parent, (size_t)d2->nnew * sizeof *parent);
    if (d->nnew) memcpy(x, d->x, (size_t)(d->nnew * dim) * sizeof *x);
    if (d2->nnew) memcpy(x + d->nnew * dim, d2->x, (size_t)(d2->nnew * dim) * sizeof *x);
    /* the two increasing lists of re-wired elements merged; d2's connectivity wins */
    int64_t a = 0, b = 0, k = 0;
    while (a < d->nmod || b < d2->nmod) {
        int32_t ea = a < d->nmod ? d->elem[a] : INT32_MAX, eb = b < d2->nmod ? d2->elem[b] : INT32_MAX;
        if (eb >= ne0 && b < d2->nmod) { /* an element d added */
            memcpy(d->conn_add + (eb - ne0) * nv, d2->conn + b * nv, (size_t)nv * sizeof *conn);
            b++;
            continue;
        }
        elem[k] = ea <= eb ? ea : eb;
        memcpy(oc + k * nv, ea <= eb ? *old + a * nv : old2 + b * nv, (size_t)nv * sizeof *oc);
        memcpy(conn + k * nv, eb <= ea ? d2->conn + b * nv : d->conn + a * nv, (size_t)nv * sizeof *conn);
        if (ea <= eb) a++;
        if (eb <= ea) b++;
        k++;
    }
    free(d->parent), free(d->x), free(d->elem), free(d->conn), free(*old);
    d->parent = parent, d->x = x, d->nnew = nnew;
    d->elem = elem, d->conn = conn, d->nmod = k, *old = oc;
    return 0;
}

void aug_update_init(aug_update *u) { memset(u, 0, sizeof *u); }
void aug_update_free(aug_update *u)
{
    free(u->H);
    free(u->E);
    free(u->df);
    free(u->EK);
    free(u->EM);
    free(u->keep);
    aug_update_init(u);
}

void aug_bdelta_init(aug_bdelta *b) { memset(b, 0, sizeof *b); }

void aug_bdelta_free(aug_bdelta *b)
{
    free(b->fix_dof);
    free(b->fix_val);
    free(b->load_dof);
    free(b->load_val);
    aug_bdelta_init(b);
}

int aug_bdelta_empty(const aug_bdelta *b) { return b->nfix == 0 && b->nload == 0; }

static int append_i32(int32_t **a, int64_t *n, const int32_t *v, int64_t k)
{
    if (k == 0) return 0;
    int32_t *q = aug_realloc(*a, (size_t)(*n + k) * sizeof **a);
    if (!q) return -1;
    memcpy(q + *n, v, (size_t)k * sizeof *v);
    *a = q;
    *n += k;
    return 0;
}

/* new node i (index nn0 + i) inherits parent's constraints, sets and output membership */
static int inherit(aug_mesh *m, int64_t nn0, const aug_mdelta *d)
{
    int dim = m->dim;
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t p = d->parent[i], node = (int32_t)(nn0 + i);
        for (int64_t f = 0; f < m->nfix; f++) {
            int32_t dof = m->fix_dof[f];
            if (dof / dim != p) continue;
            int32_t nd = node * dim + dof % dim;
            int64_t n = m->nfix;
            double v = m->fix_val[f];
            if (append_i32(&m->fix_dof, &m->nfix, &nd, 1)) return -1;
            double *q = aug_realloc(m->fix_val, (size_t)(n + 1) * sizeof(double));
            if (!q) return -1;
            q[n] = v;
            m->fix_val = q;
        }
        for (int s = 0; s < m->nset; s++) {
            aug_set *S = &m->sets[s];
            if (bsearch(&p, S->nodes, (size_t)S->n, sizeof p, aug_cmp_i32) &&
                append_i32(&S->nodes, &S->n, &node, 1))
                return -1;
        }
        if (m->out_kind != AUG_OUT_ALL &&
            bsearch(&p, m->out_nodes, (size_t)m->nout, sizeof p, aug_cmp_i32) &&
            append_i32(&m->out_nodes, &m->nout, &node, 1))
            return -1;
    }
    return 0;
}

int aug_mesh_apply(aug_mesh *m, const aug_mdelta *d, aug_err *e)
{
    aug_err_clear(e);
    int nv = m->nv, dim = m->dim;
    int64_t nn0 = m->nn;
    for (int64_t i = 0; i < d->nnew; i++)
        if (d->parent[i] < 0 || d->parent[i] >= nn0 + i)
            return aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: new node %lld has parent %d",
                               (int)d->step, (long long)i, (int)d->parent[i]);
    int64_t nn1 = nn0 + d->nnew;
    for (int64_t i = 0; i < d->nmod; i++)
        if (d->elem[i] < 0 || d->elem[i] >= m->ne)
            return aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: changed element %d out of range",
                               (int)d->step, (int)d->elem[i]);
    for (int64_t i = 0; i < (d->nmod + d->nadd) * nv; i++) {
        int32_t v = i < d->nmod * nv ? d->conn[i] : d->conn_add[i - d->nmod * nv];
        if (v < 0 || v >= nn1)
            return aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: element node %d out of range",
                               (int)d->step, (int)v);
    }
    for (int64_t i = 0; i < d->nadd; i++)
        if (d->mat_add[i] < 0 || d->mat_add[i] >= m->nmat)
            return aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: material out of range",
                               (int)d->step);
    double *x = aug_realloc(m->x, (size_t)(nn1 * dim) * sizeof(double));
    if (!x) goto nomem;
    m->x = x;
    if (d->nnew) memcpy(x + nn0 * dim, d->x, (size_t)(d->nnew * dim) * sizeof(double));
    m->nn = nn1;
    for (int64_t i = 0; i < d->nmod; i++)
        memcpy(m->conn + (size_t)d->elem[i] * nv, d->conn + i * nv, (size_t)nv * 4);
    if (d->nadd) {
        int32_t *c = aug_realloc(m->conn, (size_t)((m->ne + d->nadd) * nv) * 4);
        if (!c) goto nomem;
        m->conn = c;
        int32_t *mt = aug_realloc(m->mat, (size_t)(m->ne + d->nadd) * 4);
        if (!mt) goto nomem;
        m->mat = mt;
        memcpy(c + m->ne * nv, d->conn_add, (size_t)(d->nadd * nv) * 4);
        memcpy(mt + m->ne, d->mat_add, (size_t)d->nadd * 4);
        m->ne += d->nadd;
    }
    if (inherit(m, nn0, d)) goto nomem;
    /* a re-wired or added element must keep a positive measure, a hex8 a
       positive scaled Jacobian at every corner as in ELEM (formats/stream.md
       5.3, 7.1: two nodes of a hex exchanged make a bow-tie whose volume
       may stay positive); the mesh is not to be used after this error */
    for (int64_t i = 0; i < d->nmod + d->nadd; i++) {
        int64_t el = i < d->nmod ? d->elem[i] : m->ne - d->nadd + (i - d->nmod);
        if (m->nv == 8) {
            int corner;
            double sj = aug_hex_scaled_jacobian(m, el, &corner);
            if (!(sj > 0))
                return aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: element %lld is inverted or "
                                   "degenerate after the step (scaled Jacobian %.3g at corner %d)",
                                   (int)d->step, (long long)el, sj, corner);
            continue;
        }
        double v = aug_elem_measure(m, el);
        if (!(v > 0))
            return aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: element %lld is inverted or "
                               "degenerate after the step (%s %.3g)", (int)d->step, (long long)el,
                               dim == 3 ? "volume" : "area", v);
    }
    return 0;
nomem:
    return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
}
