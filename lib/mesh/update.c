/* Per-step records MDLT (mesh delta) and UPDT (principal submatrix update, AMPS eq. 3.1). */
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
void aug_update_init(aug_update *u) { memset(u, 0, sizeof *u); }
void aug_update_free(aug_update *u)
{
    free(u->H);
    free(u->E);
    free(u->df);
    aug_update_init(u);
}

static int emit(aug_writer *w, const char *type, int32_t step, aug_buf *b, aug_err *e)
{
    int rc = b->failed ? aug_err_set(e, AUG_ENOMEM, aug_writer_count(w), type, "out of memory")
                       : aug_write(w, type, step, b->p, b->len, e);
    aug_buf_free(b);
    return rc;
}

int aug_write_mdelta(aug_writer *w, int dim, int nv, const aug_mdelta *d, aug_err *e)
{
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i64(&b, d->nnew);
    aug_buf_i32v(&b, d->parent, (size_t)d->nnew);
    aug_buf_f64v(&b, d->x, (size_t)(d->nnew * dim));
    aug_buf_i64(&b, d->nmod);
    aug_buf_i32v(&b, d->elem, (size_t)d->nmod);
    aug_buf_i32v(&b, d->conn, (size_t)(d->nmod * nv));
    aug_buf_i64(&b, d->nadd);
    aug_buf_i32v(&b, d->conn_add, (size_t)(d->nadd * nv));
    aug_buf_i32v(&b, d->mat_add, (size_t)d->nadd);
    aug_buf_i32(&b, d->flags);
    aug_buf_i32(&b, 0);
    return emit(w, "MDLT", d->step, &b, e);
}

#define BAD(...) aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type, __VA_ARGS__)

/* read a count followed by per-item arrays of `per` bytes in all */
static int count_ok(aug_cur *c, int64_t n, uint64_t per)
{
    return n >= 0 && n <= INT32_MAX && aug_cur_has(c, (uint64_t)n, per);
}

int aug_read_mdelta(const aug_rec *rec, int dim, int nv, aug_mdelta *d, aug_err *e)
{
    aug_err_clear(e);
    aug_mdelta_init(d);
    aug_cur c;
    aug_cur_init(&c, rec);
    d->step = rec->step;
    d->nnew = aug_cur_i64(&c);
    if (!count_ok(&c, d->nnew, 4 + 8 * (uint64_t)dim)) return BAD("bad new-node count");
    d->parent = aug_malloc((size_t)d->nnew * 4);
    d->x = aug_malloc((size_t)(d->nnew * dim) * 8);
    if (!d->parent || !d->x) goto nomem;
    aug_cur_i32v(&c, d->parent, (uint64_t)d->nnew);
    aug_cur_f64v(&c, d->x, (uint64_t)d->nnew * dim);
    d->nmod = aug_cur_i64(&c);
    if (!count_ok(&c, d->nmod, 4 * (uint64_t)(nv + 1))) return BAD("bad changed-element count");
    d->elem = aug_malloc((size_t)d->nmod * 4);
    d->conn = aug_malloc((size_t)(d->nmod * nv) * 4);
    if (!d->elem || !d->conn) goto nomem;
    aug_cur_i32v(&c, d->elem, (uint64_t)d->nmod);
    aug_cur_i32v(&c, d->conn, (uint64_t)d->nmod * nv);
    d->nadd = aug_cur_i64(&c);
    if (!count_ok(&c, d->nadd, 4 * (uint64_t)(nv + 1))) return BAD("bad added-element count");
    d->conn_add = aug_malloc((size_t)(d->nadd * nv) * 4);
    d->mat_add = aug_malloc((size_t)d->nadd * 4);
    if (!d->conn_add || !d->mat_add) goto nomem;
    aug_cur_i32v(&c, d->conn_add, (uint64_t)d->nadd * nv);
    aug_cur_i32v(&c, d->mat_add, (uint64_t)d->nadd);
    d->flags = aug_cur_i32(&c);
    aug_cur_i32(&c);
    if (!c.ok || c.pos != c.len) return BAD("payload size does not match its counts");
    return 0;
nomem:
    return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
}

int aug_write_update(aug_writer *w, const aug_update *u, aug_err *e)
{
    aug_buf b;
    aug_buf_init(&b);
    size_t s = (size_t)u->m + (size_t)u->k;
    aug_buf_i32(&b, u->m);
    aug_buf_i32(&b, u->k);
    aug_buf_i32v(&b, u->H, (size_t)u->m);
    aug_buf_f64v(&b, u->E, s * s);
    aug_buf_f64v(&b, u->df, s);
    return emit(w, "UPDT", u->step, &b, e);
}

int aug_read_update(const aug_rec *rec, aug_update *u, aug_err *e)
{
    aug_err_clear(e);
    aug_update_init(u);
    aug_cur c;
    aug_cur_init(&c, rec);
    u->step = rec->step;
    u->m = aug_cur_i32(&c);
    u->k = aug_cur_i32(&c);
    if (u->m < 0 || u->k < 0 || (int64_t)u->m + u->k > 1 << 20)
        return BAD("impossible sizes m = %d, k = %d", (int)u->m, (int)u->k);
    uint64_t s = (uint64_t)u->m + (uint64_t)u->k;
    if (c.len - c.pos != 4 * (uint64_t)u->m + 8 * s * s + 8 * s)
        return BAD("payload size does not match m = %d, k = %d", (int)u->m, (int)u->k);
    u->H = aug_malloc((size_t)u->m * 4);
    u->E = aug_malloc((size_t)(s * s) * 8);
    u->df = aug_malloc((size_t)s * 8);
    if (!u->H || !u->E || !u->df)
        return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    aug_cur_i32v(&c, u->H, (uint64_t)u->m);
    aug_cur_f64v(&c, u->E, s * s);
    aug_cur_f64v(&c, u->df, s);
    for (int32_t i = 0; i < u->m; i++)
        if (u->H[i] < 0 || (i > 0 && u->H[i] <= u->H[i - 1]))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "H not increasing at %d", (int)i);
    for (uint64_t i = 0; i < s; i++)
        for (uint64_t j = 0; j < i; j++)
            if (u->E[i + j * s] != u->E[j + i * s])
                return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "E is not symmetric");
    return 0;
}

/* append n ints to a sorted array */
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

static int cmp_i32(const void *a, const void *b)
{
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
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
            if (bsearch(&p, S->nodes, (size_t)S->n, sizeof p, cmp_i32) &&
                append_i32(&S->nodes, &S->n, &node, 1))
                return -1;
        }
        if (m->out_kind != AUG_OUT_ALL &&
            bsearch(&p, m->out_nodes, (size_t)m->nout, sizeof p, cmp_i32) &&
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
    return 0;
nomem:
    return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
}
