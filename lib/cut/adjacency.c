/* Node -> element adjacency of a mesh that changes: per-node element lists. */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

void aug_adj_free(aug_adj *a)
{
    for (int64_t i = 0; i < a->nn; i++) free(a->list[i]);
    free(a->list);
    free(a->cnt);
    free(a->cap);
    memset(a, 0, sizeof *a);
}

int aug_adj_grow(aug_adj *a, int64_t nn)
{
    if (nn > a->capn) {
        int64_t nc = a->capn ? a->capn : 64;
        while (nc < nn) nc *= 2;
        int32_t **l = aug_realloc(a->list, (size_t)nc * sizeof *l);
        if (!l) return -1;
        a->list = l;
        int32_t *c = aug_realloc(a->cnt, (size_t)nc * sizeof *c);
        if (!c) return -1;
        a->cnt = c;
        c = aug_realloc(a->cap, (size_t)nc * sizeof *c);
        if (!c) return -1;
        a->cap = c;
        a->capn = nc;
    }
    for (int64_t i = a->nn; i < nn; i++) {
        a->list[i] = NULL;
        a->cnt[i] = a->cap[i] = 0;
    }
    if (nn > a->nn) a->nn = nn;
    return 0;
}

int aug_adj_add(aug_adj *a, int32_t node, int32_t elem)
{
    if (a->cnt[node] == a->cap[node]) {
        int32_t nc = a->cap[node] ? 2 * a->cap[node] : 8;
        int32_t *l = aug_realloc(a->list[node], (size_t)nc * sizeof *l);
        if (!l) return -1;
        a->list[node] = l;
        a->cap[node] = nc;
    }
    a->list[node][a->cnt[node]++] = elem;
    return 0;
}

void aug_adj_remove(aug_adj *a, int32_t node, int32_t elem)
{
    int32_t *l = a->list[node];
    for (int32_t i = 0; i < a->cnt[node]; i++)
        if (l[i] == elem) {
            l[i] = l[--a->cnt[node]];
            return;
        }
}

int aug_adj_build(aug_adj *a, const aug_mesh *m)
{
    memset(a, 0, sizeof *a);
    if (aug_adj_grow(a, m->nn)) goto nomem;
    for (int64_t e = 0; e < m->ne; e++)
        for (int k = 0; k < m->nv; k++)
            if (aug_adj_add(a, m->conn[e * m->nv + k], (int32_t)e)) goto nomem;
    return 0;
nomem:
    aug_adj_free(a);
    return -1;
}

/* does element g (of m) hold node v? */
static int holds(const aug_mesh *m, int32_t g, int32_t v)
{
    for (int k = 0; k < m->nv; k++)
        if (m->conn[(int64_t)g * m->nv + k] == v) return 1;
    return 0;
}

/* the least element other than el holding every node of facet f of el: a
   search of the list of the facet's first node */
int32_t aug_adj_across(const aug_mesh *m, const aug_adj *adj, int64_t el, int f)
{
    const int *l = aug_etype_facet(m->etype, f);
    int fv = aug_etype_facet_nv(m->etype);
    const int32_t *c = m->conn + el * m->nv;
    int32_t v0 = c[l[0]], best = -1;
    for (int32_t i = 0; i < adj->cnt[v0]; i++) {
        int32_t g = adj->list[v0][i];
        if (g == el || (best >= 0 && g >= best)) continue;
        int ok = 1;
        for (int k = 1; k < fv && ok; k++) ok = holds(m, g, c[l[k]]);
        if (ok) best = g;
    }
    return best;
}
