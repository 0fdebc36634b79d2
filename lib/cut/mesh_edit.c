/* The mesh edit of one cut step: new nodes, re-wired and added elements,
   turned into an MDLT record (formats/stream.md 7.1). */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

int aug_edit_init(aug_edit *ed, aug_mesh *m, aug_adj *adj)
{
    memset(ed, 0, sizeof *ed);
    ed->m = m;
    ed->adj = adj;
    aug_edit_begin(ed);
    return 0;
}

void aug_edit_free(aug_edit *ed)
{
    free(ed->xnew);
    free(ed->parent);
    free(ed->conn_add);
    free(ed->mat_add);
    free(ed->mod_elem);
    free(ed->mod_old);
    free(ed->slot);
    memset(ed, 0, sizeof *ed);
}

void aug_edit_begin(aug_edit *ed)
{
    ed->nn0 = ed->m->nn;
    ed->ne0 = ed->m->ne;
    ed->nnew = ed->nadd = ed->nmod = 0;
}

int64_t aug_edit_nn(const aug_edit *ed) { return ed->nn0 + ed->nnew; }
int64_t aug_edit_ne(const aug_edit *ed) { return ed->ne0 + ed->nadd; }

const double *aug_edit_x(const aug_edit *ed, int64_t node)
{
    int dim = ed->m->dim;
    return node < ed->nn0 ? ed->m->x + node * dim : ed->xnew + (node - ed->nn0) * dim;
}

const int32_t *aug_edit_conn(const aug_edit *ed, int64_t elem)
{
    int nv = ed->m->nv;
    return elem < ed->ne0 ? ed->m->conn + elem * nv : ed->conn_add + (elem - ed->ne0) * nv;
}

int32_t aug_edit_mat(const aug_edit *ed, int64_t elem)
{
    return elem < ed->ne0 ? ed->m->mat[elem] : ed->mat_add[elem - ed->ne0];
}

/* grow two parallel arrays (items of sza and szb bytes) to hold need items */
static int reserve2(void **pa, size_t sza, void **pb, size_t szb, int64_t *cap, int64_t need)
{
    if (need <= *cap) return 0;
    int64_t nc = *cap ? *cap : 16;
    while (nc < need) nc *= 2;
    void *q = aug_realloc(*pa, (size_t)nc * sza);
    if (!q) return -1;
    *pa = q;
    q = aug_realloc(*pb, (size_t)nc * szb);
    if (!q) return -1;
    *pb = q;
    *cap = nc;
    return 0;
}

int32_t aug_edit_node(aug_edit *ed, const double *x, int32_t parent)
{
    int dim = ed->m->dim;
    if (reserve2((void **)&ed->xnew, (size_t)dim * sizeof(double), (void **)&ed->parent,
                 sizeof(int32_t), &ed->capnew, ed->nnew + 1))
        return -1;
    int64_t node = aug_edit_nn(ed);
    if (aug_adj_grow(ed->adj, node + 1)) return -1;
    memcpy(ed->xnew + ed->nnew * dim, x, (size_t)dim * sizeof(double));
    ed->parent[ed->nnew++] = parent;
    return (int32_t)node;
}

/* remove elem from the lists of its nodes, set conn, add it back */
static int rewire(aug_edit *ed, int64_t elem, int32_t *dst, const int32_t *conn)
{
    int nv = ed->m->nv;
    for (int k = 0; k < nv; k++) aug_adj_remove(ed->adj, dst[k], (int32_t)elem);
    memmove(dst, conn, (size_t)nv * sizeof *dst);
    for (int k = 0; k < nv; k++)
        if (aug_adj_add(ed->adj, dst[k], (int32_t)elem)) return -1;
    return 0;
}

int aug_edit_set(aug_edit *ed, int64_t elem, const int32_t *conn)
{
    int nv = ed->m->nv;
    if (elem >= ed->ne0) return rewire(ed, elem, ed->conn_add + (elem - ed->ne0) * nv, conn);
    if (ed->capslot < ed->m->ne) {
        int64_t old = ed->capslot, nc = ed->m->ne + ed->m->ne / 2 + 16;
        int32_t *s = aug_realloc(ed->slot, (size_t)nc * sizeof *s);
        if (!s) return -1;
        for (int64_t i = old; i < nc; i++) s[i] = -1;
        ed->slot = s;
        ed->capslot = nc;
    }
    if (ed->slot[elem] < 0) {
        if (reserve2((void **)&ed->mod_elem, sizeof(int32_t), (void **)&ed->mod_old,
                     (size_t)nv * sizeof(int32_t), &ed->capmod, ed->nmod + 1))
            return -1;
        ed->mod_elem[ed->nmod] = (int32_t)elem;
        memcpy(ed->mod_old + ed->nmod * nv, ed->m->conn + elem * nv, (size_t)nv * sizeof(int32_t));
        ed->slot[elem] = (int32_t)ed->nmod++;
    }
    return rewire(ed, elem, ed->m->conn + elem * nv, conn);
}

int64_t aug_edit_elem(aug_edit *ed, const int32_t *conn, int32_t mat)
{
    int nv = ed->m->nv;
    if (reserve2((void **)&ed->conn_add, (size_t)nv * sizeof(int32_t), (void **)&ed->mat_add,
                 sizeof(int32_t), &ed->capadd, ed->nadd + 1))
        return -1;
    int64_t elem = aug_edit_ne(ed);
    memcpy(ed->conn_add + ed->nadd * nv, conn, (size_t)nv * sizeof(int32_t));
    ed->mat_add[ed->nadd++] = mat;
    for (int k = 0; k < nv; k++)
        if (aug_adj_add(ed->adj, conn[k], (int32_t)elem)) return -1;
    return elem;
}

int aug_edit_end(aug_edit *ed, int32_t step, aug_mdelta *d, int32_t **oldconn, aug_err *e)
{
    aug_err_clear(e);
    aug_mdelta_init(d);
    *oldconn = NULL;
    aug_mesh *m = ed->m;
    int nv = m->nv, dim = m->dim;
    d->step = step;
    /* re-wired elements whose connectivity really changed, increasing */
    int32_t *order = aug_malloc((size_t)ed->nmod * sizeof *order + 1);
    if (!order) goto nomem;
    if (ed->nmod) memcpy(order, ed->mod_elem, (size_t)ed->nmod * sizeof *order);
    qsort(order, (size_t)ed->nmod, sizeof *order, aug_cmp_i32);
    int64_t nch = 0;
    for (int64_t i = 0; i < ed->nmod; i++) {
        int32_t el = order[i];
        int32_t s = ed->slot[el];
        if (memcmp(m->conn + (int64_t)el * nv, ed->mod_old + (int64_t)s * nv, (size_t)nv * 4))
            order[nch++] = el;
    }
    d->nnew = ed->nnew;
    d->parent = aug_malloc((size_t)ed->nnew * 4 + 1);
    d->x = aug_malloc((size_t)(ed->nnew * dim) * 8 + 1);
    d->nmod = nch;
    d->elem = aug_malloc((size_t)nch * 4 + 1);
    d->conn = aug_malloc((size_t)(nch * nv) * 4 + 1);
    *oldconn = aug_malloc((size_t)(nch * nv) * 4 + 1);
    d->nadd = ed->nadd;
    d->conn_add = aug_malloc((size_t)(ed->nadd * nv) * 4 + 1);
    d->mat_add = aug_malloc((size_t)ed->nadd * 4 + 1);
    if (!d->parent || !d->x || !d->elem || !d->conn || !*oldconn || !d->conn_add || !d->mat_add)
        goto nomem;
    if (ed->nnew) {
        memcpy(d->parent, ed->parent, (size_t)ed->nnew * 4);
        memcpy(d->x, ed->xnew, (size_t)(ed->nnew * dim) * 8);
    }
    if (ed->nadd) {
        memcpy(d->conn_add, ed->conn_add, (size_t)(ed->nadd * nv) * 4);
        memcpy(d->mat_add, ed->mat_add, (size_t)ed->nadd * 4);
    }
    for (int64_t i = 0; i < nch; i++) {
        int32_t el = order[i];
        d->elem[i] = el;
        memcpy(d->conn + i * nv, m->conn + (int64_t)el * nv, (size_t)nv * 4);
        memcpy(*oldconn + i * nv, ed->mod_old + (int64_t)ed->slot[el] * nv, (size_t)nv * 4);
    }
    /* restore the mesh arrays; the adjacency already describes the mesh after d */
    for (int64_t i = 0; i < ed->nmod; i++) {
        int32_t el = ed->mod_elem[i];
        memcpy(m->conn + (int64_t)el * nv, ed->mod_old + i * nv, (size_t)nv * 4);
        ed->slot[el] = -1;
    }
    free(order);
    aug_edit_begin(ed);
    return 0;
nomem:
    free(order);
    free(*oldconn);
    *oldconn = NULL;
    aug_mdelta_free(d);
    return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
}
