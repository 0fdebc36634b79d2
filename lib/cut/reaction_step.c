/* Reaction forces of the replayed steps (formats/stream.md 7.10): the elements
   touching a constrained DOF kept up to date from each step's mesh change, the
   matrix DOFs the reactions need from a solve restricted to an output set, and
   the rEAC of a step (or frame) from its solution. */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

void aug_react_init(aug_react *s, aug_replay *rp)
{
    memset(s, 0, sizeof *s);
    s->rp = rp;
    if (rp) rp->track = 1;
}

void aug_react_free(aug_react *s)
{
    free(s->cnode);
    free(s->in);
    free(s->elems);
    free(s->dofs);
    free(s->u);
    aug_reaction_free(&s->q);
    memset(s, 0, sizeof *s);
}

/* *p (n bytes of old contents, the rest zero) grown to n2 >= n bytes; 0 or -1 */
static int grow0(unsigned char **p, int64_t n, int64_t n2)
{
    unsigned char *q = aug_realloc(*p, (size_t)n2 + 1);
    if (!q) return -1;
    memset(q + n, 0, (size_t)(n2 - n) + 1);
    *p = q;
    return 0;
}

/* every element from scratch (the first sync, and after a BDLT constrained a
   node that was there before: its elements are not among the changed ones) */
static int rebuild(aug_react *s, const aug_mesh *m)
{
    int32_t *el;
    int64_t n = aug_react_elements(m, &el);
    if (n < 0 || grow0(&s->cnode, 0, m->nn) || grow0(&s->in, 0, m->ne)) {
        free(el);
        return -1;
    }
    free(s->elems);
    s->elems = el;
    s->nel = s->elcap = n;
    for (int64_t k = 0; k < m->nfix; k++) s->cnode[m->fix_dof[k] / m->dim] = 1;
    for (int64_t t = 0; t < n; t++) s->in[el[t]] = 1;
    return 0;
}

static int touches(const aug_react *s, const aug_mesh *m, int32_t el)
{
    const int32_t *c = m->conn + (int64_t)el * m->nv;
    for (int a = 0; a < m->nv; a++)
        if (s->cnode[c[a]]) return 1;
    return 0;
}

/* the elements each MDLT since the last sync re-wired or added (the replay's
   chg): in or out of the list by their new nodes; a new node is constrained
   when its DOFs are in the fix list (inherited or by the step's BDLT), and
   every element holding a new node was re-wired or added by the step */
static int follow(aug_react *s, const aug_mesh *m, int64_t first_new)
{
    aug_replay *rp = s->rp;
    if (grow0(&s->cnode, s->nn, m->nn) || grow0(&s->in, s->ne, m->ne)) return -1;
    for (int64_t k = first_new; k < m->nfix; k++) s->cnode[m->fix_dof[k] / m->dim] = 1;
    int changed = 0;
    for (int64_t i = 0; i < rp->nchg; i++) {
        int32_t el = rp->chg[i];
        int t = touches(s, m, el);
        if (t == s->in[el]) continue;
        changed = 1;
        s->in[el] = (unsigned char)t;
        if (!t) continue;
        if (s->nel == s->elcap) {
            int64_t cap = s->elcap ? 2 * s->elcap : 64;
            int32_t *q = aug_realloc(s->elems, (size_t)cap * sizeof *q);
            if (!q) return -1;
            s->elems = q;
            s->elcap = cap;
        }
        s->elems[s->nel++] = el;
    }
    if (!changed) return 0;
    /* drop the elements that left, sort, and keep one entry of each */
    int64_t k = 0;
    for (int64_t t = 0; t < s->nel; t++)
        if (s->in[s->elems[t]]) s->elems[k++] = s->elems[t];
    qsort(s->elems, (size_t)k, sizeof *s->elems, aug_cmp_i32);
    s->nel = 0;
    for (int64_t t = 0; t < k; t++)
        if (t == 0 || s->elems[t] != s->elems[t - 1]) s->elems[s->nel++] = s->elems[t];
    return 0;
}

/* Bring the element list up to the replayed mesh: O(changed elements + new
   constrained DOFs) per step, O(ne) when a BDLT constrained an existing node. */
int aug_react_sync(aug_react *s, aug_err *e)
{
    aug_err_clear(e);
    aug_replay *rp = s->rp;
    const aug_mesh *m = &rp->mesh;
    /* constrained DOFs of the nodes there at the last sync (the fix list is sorted) */
    int64_t lo = 0, hi = m->nfix, lim = s->nn * m->dim;
    while (lo < hi) {
        int64_t mid = lo + (hi - lo) / 2;
        if (m->fix_dof[mid] < lim) lo = mid + 1;
        else hi = mid;
    }
    int rc = !s->synced || lo != s->nfix_old ? rebuild(s, m) : follow(s, m, lo);
    if (rc) return aug_err_set(e, AUG_ENOMEM, -1, "rEAC", "out of memory");
    s->synced = 1;
    s->nn = m->nn;
    s->ne = m->ne;
    s->nfix_old = m->nfix;
    rp->nchg = 0;
    return 0;
}

int aug_react_out_dofs(aug_react *s, const int32_t **out, int64_t *nout, aug_err *e)
{
    if (aug_react_sync(s, e)) return e->code;
    if (!*out) return 0;
    const aug_mesh *m = &s->rp->mesh;
    int nv = m->nv, d = m->dim;
    int64_t need = *nout + s->nel * nv * d;
    if (need > s->dofcap) {
        int32_t *q = aug_realloc(s->dofs, (size_t)need * sizeof *q + 4);
        if (!q) return aug_err_set(e, AUG_ENOMEM, -1, "rEAC", "out of memory");
        s->dofs = q;
        s->dofcap = need;
    }
    int64_t k = *nout;
    memcpy(s->dofs, *out, (size_t)k * sizeof *s->dofs);
    for (int64_t t = 0; t < s->nel; t++)
        for (int a = 0; a < nv; a++)
            for (int c = 0; c < d; c++) {
                int64_t id = aug_replay_index(s->rp, m->conn[(int64_t)s->elems[t] * nv + a], c);
                if (id >= 0) s->dofs[k++] = (int32_t)id;
            }
    qsort(s->dofs, (size_t)k, sizeof *s->dofs, aug_cmp_i32);
    int64_t n = 0;
    for (int64_t t = 0; t < k; t++)
        if (t == 0 || s->dofs[t] != s->dofs[t - 1]) s->dofs[n++] = s->dofs[t];
    *out = s->dofs;
    *nout = n;
    return 0;
}

/* y(node, c) = x[index(node, c)] at the nodes of the elements, or def(node, c)
   outside the matrix (def NULL: 0) */
static void gather(const aug_react *s, const double *x, const aug_mesh *def, double *y)
{
    const aug_mesh *m = &s->rp->mesh;
    int nv = m->nv, d = m->dim;
    for (int64_t t = 0; t < s->nel; t++)
        for (int a = 0; a < nv; a++) {
            int32_t node = m->conn[(int64_t)s->elems[t] * nv + a];
            for (int c = 0; c < d; c++) {
                int64_t id = aug_replay_index(s->rp, node, c);
                double v = 0;
                if (id < 0 && def) aug_mesh_fixed(def, node * d + c, &v);
                y[(int64_t)node * d + c] = id >= 0 ? x[id] : v;
            }
        }
}

static int grow_f64(double **p, int64_t n)
{
    double *q = aug_realloc(*p, (size_t)n * sizeof *q + 8);
    if (!q) return -1;
    *p = q;
    return 0;
}

int aug_react_write(aug_writer *w, aug_react *s, int32_t step, const double *x,
                    const aug_react_frame *fr, aug_err *e)
{
    if (aug_react_sync(s, e)) return e->code;
    const aug_mesh *m = &s->rp->mesh;
    int64_t nd = m->nn * m->dim;
    if (nd > s->ucap && grow_f64(&s->u, nd))
        return aug_err_set(e, AUG_ENOMEM, aug_writer_count(w), "rEAC", "out of memory");
    if (nd > s->ucap) s->ucap = nd;
    aug_react_dyn dyn;
    if (fr) dyn = (aug_react_dyn){fr->v, fr->a, fr->alpha, fr->beta, fr->lumped};
    else gather(s, x, m, s->u);
    if (aug_reaction_compute(&s->q, m, s->elems, s->nel, fr ? x : s->u, fr ? &dyn : NULL, e)) {
        e->record = aug_writer_count(w);
        return e->code;
    }
    s->q.frame = fr ? fr->frame : 0;
    s->q.time = fr ? fr->time : 0.0;
    return aug_write_reaction(w, step, &s->q, e);
}
