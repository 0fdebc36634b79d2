/* A uniform hash grid of axis-aligned boxes: the triangles of a cut surface
   and the elements of a mesh, for the queries of a 3-D surface cut. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

int aug_boxgrid_init(aug_boxgrid *g, double h, const double lo[3])
{
    memset(g, 0, sizeof *g);
    g->h = h > 0 ? h : 1;
    memcpy(g->lo, lo, sizeof g->lo);
    g->cap = 1024;
    g->key = aug_calloc(g->cap, sizeof *g->key);
    g->head = aug_malloc(g->cap * sizeof *g->head);
    if (!g->key || !g->head) {
        aug_boxgrid_free(g);
        return -1;
    }
    return 0;
}

void aug_boxgrid_free(aug_boxgrid *g)
{
    free(g->key);
    free(g->head);
    free(g->item);
    free(g->next);
    free(g->mark);
    memset(g, 0, sizeof *g);
}

static void cell(const aug_boxgrid *g, const double *x, int64_t c[3])
{
    for (int k = 0; k < 3; k++) {
        double v = floor((x[k] - g->lo[k]) / g->h);
        c[k] = v < -1e6 ? -1000000 : v > 1e6 ? 1000000 : (int64_t)v;
    }
}

static uint64_t cell_id(int64_t i, int64_t j, int64_t k)
{
    return ((uint64_t)(i + 1048576) << 42) | ((uint64_t)(j + 1048576) << 21) | (uint64_t)(k + 1048576);
}

static size_t slot(const aug_boxgrid *g, uint64_t id)
{
    uint64_t h = id * 0x9E3779B97F4A7C15ull;
    size_t s = (size_t)(h >> 17) & (g->cap - 1);
    while (g->key[s] && g->key[s] != id + 1) s = (s + 1) & (g->cap - 1);
    return s;
}

static int grow(aug_boxgrid *g)
{
    aug_boxgrid o = *g;
    g->cap *= 2;
    g->key = aug_calloc(g->cap, sizeof *g->key);
    g->head = aug_malloc(g->cap * sizeof *g->head);
    if (!g->key || !g->head) {
        free(g->key);
        free(g->head);
        g->key = o.key, g->head = o.head, g->cap = o.cap;
        return -1;
    }
    for (size_t i = 0; i < o.cap; i++)
        if (o.key[i]) {
            size_t s = slot(g, o.key[i] - 1);
            g->key[s] = o.key[i];
            g->head[s] = o.head[i];
        }
    free(o.key);
    free(o.head);
    return 0;
}

int aug_boxgrid_add(aug_boxgrid *g, int32_t item, const double lo[3], const double hi[3])
{
    int64_t a[3], b[3];
    cell(g, lo, a);
    cell(g, hi, b);
    if (item >= g->capmark) {
        int64_t nc = g->capmark ? 2 * g->capmark : 1024;
        while (nc <= item) nc *= 2;
        uint32_t *m = aug_realloc(g->mark, (size_t)nc * sizeof *m);
        if (!m) return -1;
        memset(m + g->capmark, 0, (size_t)(nc - g->capmark) * sizeof *m);
        g->mark = m;
        g->capmark = nc;
    }
    for (int64_t i = a[0]; i <= b[0]; i++)
        for (int64_t j = a[1]; j <= b[1]; j++)
            for (int64_t k = a[2]; k <= b[2]; k++) {
                if (2 * (g->used + 1) > g->cap && grow(g)) return -1;
                if (g->nent == g->capent) {
                    int64_t nc = g->capent ? 2 * g->capent : 4096;
                    int32_t *it = aug_realloc(g->item, (size_t)nc * sizeof *it);
                    if (!it) return -1;
                    g->item = it;
                    int32_t *nx = aug_realloc(g->next, (size_t)nc * sizeof *nx);
                    if (!nx) return -1;
                    g->next = nx;
                    g->capent = nc;
                }
                uint64_t id = cell_id(i, j, k);
                size_t s = slot(g, id);
                if (!g->key[s]) {
                    g->key[s] = id + 1;
                    g->head[s] = -1;
                    g->used++;
                }
                g->item[g->nent] = item;
                g->next[g->nent] = g->head[s];
                g->head[s] = (int32_t)g->nent++;
            }
    return 0;
}

int aug_boxgrid_query(aug_boxgrid *g, const double lo[3], const double hi[3], int32_t **out,
                      int64_t *n, int64_t *cap)
{
    int64_t a[3], b[3];
    cell(g, lo, a);
    cell(g, hi, b);
    *n = 0;
    if (++g->gen == 0) {
        memset(g->mark, 0, (size_t)g->capmark * sizeof *g->mark);
        g->gen = 1;
    }
    for (int64_t i = a[0]; i <= b[0]; i++)
        for (int64_t j = a[1]; j <= b[1]; j++)
            for (int64_t k = a[2]; k <= b[2]; k++) {
                size_t s = slot(g, cell_id(i, j, k));
                if (!g->key[s]) continue;
                for (int32_t q = g->head[s]; q >= 0; q = g->next[q]) {
                    int32_t it = g->item[q];
                    if (g->mark[it] == g->gen) continue;
                    g->mark[it] = g->gen;
                    if (*n == *cap) {
                        int64_t nc = *cap ? 2 * *cap : 256;
                        int32_t *o = aug_realloc(*out, (size_t)nc * sizeof *o);
                        if (!o) return -1;
                        *out = o;
                        *cap = nc;
                    }
                    (*out)[(*n)++] = it;
                }
            }
    return 0;
}
