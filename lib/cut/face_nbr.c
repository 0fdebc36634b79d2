/* Element face neighbours (faces shared by two elements), kept current as a cut
   re-wires and adds elements. */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

void aug_facenbr_free(aug_facenbr *f)
{
    free(f->nbr);
    free(f->dirty);
    free(f->mark);
    free(f->queue);
    free(f->lab);
    memset(f, 0, sizeof *f);
}

static void refresh(aug_facenbr *fn, const aug_mesh *m, const aug_adj *adj, int32_t el)
{
    for (int f = 0; f < fn->nf; f++) fn->nbr[(int64_t)el * fn->nf + f] = aug_adj_across(m, adj, el, f);
}

static int reserve(aug_facenbr *fn, int64_t ne)
{
    if (ne > fn->cap) {
        int64_t nc = fn->cap ? fn->cap : 64;
        while (nc < ne) nc *= 2;
        int32_t *q = aug_realloc(fn->nbr, (size_t)(nc * fn->nf) * sizeof *q);
        if (!q) return -1;
        fn->nbr = q;
        q = aug_realloc(fn->mark, (size_t)nc * sizeof *q);
        if (!q) return -1;
        for (int64_t i = fn->cap; i < nc; i++) q[i] = 0;
        fn->mark = q;
        q = aug_realloc(fn->queue, (size_t)nc * sizeof *q);
        if (!q) return -1;
        fn->queue = q;
        q = aug_realloc(fn->lab, (size_t)nc * sizeof *q);
        if (!q) return -1;
        fn->lab = q;
        fn->cap = nc;
    }
    return 0;
}

static int32_t uf_root(int32_t *up, int32_t i)
{
    while (up[i] != i) i = up[i] = up[up[i]];
    return i;
}

/* Multi-source search: every refreshed element grows its own region through
   face neighbours; regions that meet are merged (union-find on the sources);
   done when one region remains. Regions only meet near the sources unless the
   step really separated them, so the search stays local. */
int aug_facenbr_local_connected(aug_facenbr *fn, int64_t budget)
{
    int64_t ns = fn->ndirty;
    if (ns < 2) return 1;
    if (fn->gen >= INT32_MAX - 1) {
        for (int64_t i = 0; i < fn->cap; i++) fn->mark[i] = 0;
        fn->gen = 0;
    }
    int32_t gen = ++fn->gen;
    int32_t *up = aug_malloc((size_t)ns * sizeof *up);
    if (!up) return 0;
    int64_t qh = 0, qt = 0, sets = ns;
    for (int64_t i = 0; i < ns; i++) {
        up[i] = (int32_t)i;
        int32_t el = fn->dirty[i];
        fn->mark[el] = gen;
        fn->lab[el] = (int32_t)i;
        fn->queue[qt++] = el;
    }
    while (qh < qt && sets > 1 && qt < budget) {
        int32_t el = fn->queue[qh++], a = fn->lab[el];
        for (int f = 0; f < fn->nf && sets > 1; f++) {
            int32_t o = fn->nbr[(int64_t)el * fn->nf + f];
            if (o < 0) continue;
            if (fn->mark[o] != gen) {
                fn->mark[o] = gen;
                fn->lab[o] = a;
                fn->queue[qt++] = o;
            } else {
                int32_t x = uf_root(up, a), y = uf_root(up, fn->lab[o]);
                if (x != y) {
                    up[x < y ? y : x] = x < y ? x : y;
                    sets--;
                }
            }
        }
    }
    free(up);
    return sets == 1;
}

int aug_facenbr_build(aug_facenbr *fn, const aug_mesh *m, const aug_adj *adj)
{
    memset(fn, 0, sizeof *fn);
    fn->nf = aug_etype_nfacet(m->etype);
    if (reserve(fn, m->ne)) return -1;
    fn->ne = m->ne;
    for (int64_t el = 0; el < m->ne; el++) refresh(fn, m, adj, (int32_t)el);
    fn->ndirty = 0;
    return 0;
}

int aug_facenbr_update(aug_facenbr *fn, const aug_mesh *m, const aug_adj *adj,
                       const int32_t *elems, int64_t n)
{
    int64_t ne_old = fn->ne, nf = fn->nf, nd = 0;
    if (reserve(fn, m->ne)) return -1;
    for (int64_t el = ne_old; el < m->ne; el++)
        for (int f = 0; f < nf; f++) fn->nbr[el * nf + f] = -1;
    fn->ne = m->ne;
    int32_t *dirty = aug_malloc((size_t)(n * (nf + 1) * 2 + 1) * sizeof *dirty);
    if (!dirty) return -1;
    for (int64_t i = 0; i < n; i++) {
        int32_t el = elems[i];
        dirty[nd++] = el;
        if (el < ne_old)
            for (int f = 0; f < nf; f++)
                if (fn->nbr[(int64_t)el * nf + f] >= 0) dirty[nd++] = fn->nbr[(int64_t)el * nf + f];
    }
    qsort(dirty, (size_t)nd, sizeof *dirty, aug_cmp_i32);
    int64_t w = 0;
    for (int64_t i = 0; i < nd; i++)
        if (w == 0 || dirty[w - 1] != dirty[i]) dirty[w++] = dirty[i];
    nd = w;
    for (int64_t i = 0; i < nd; i++) refresh(fn, m, adj, dirty[i]);
    /* neighbours gained by a refreshed element learn it too */
    int64_t nd2 = nd;
    for (int64_t i = 0; i < nd2; i++)
        for (int f = 0; f < nf; f++) {
            int32_t g = fn->nbr[(int64_t)dirty[i] * nf + f];
            if (g >= 0 && !bsearch(&g, dirty, (size_t)nd2, sizeof g, aug_cmp_i32)) refresh(fn, m, adj, g);
        }
    free(fn->dirty);
    fn->dirty = dirty;
    fn->ndirty = nd;
    return 0;
}
