/* Open-addressing hash map from an unordered node pair (an edge) to two int32 slots. */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

#define EMPTY 0
#define GONE UINT64_MAX

static uint64_t ekey(int32_t a, int32_t b)
{
    uint32_t lo = (uint32_t)(a < b ? a : b), hi = (uint32_t)(a < b ? b : a);
    return ((uint64_t)lo << 32 | hi) + 1;
}

/* splitmix64 finaliser */
static size_t ehash(uint64_t k, size_t mask)
{
    k ^= k >> 30;
    k *= 0xbf58476d1ce4e5b9ULL;
    k ^= k >> 27;
    k *= 0x94d049bb133111ebULL;
    k ^= k >> 31;
    return (size_t)k & mask;
}

int aug_edgemap_init(aug_edgemap *h, size_t hint)
{
    memset(h, 0, sizeof *h);
    size_t cap = 64;
    while (cap < 2 * hint) cap <<= 1;
    h->key = aug_calloc(cap, sizeof *h->key);
    h->val = aug_malloc(cap * 2 * sizeof *h->val);
    if (!h->key || !h->val) {
        aug_edgemap_free(h);
        return -1;
    }
    h->cap = cap;
    return 0;
}

void aug_edgemap_free(aug_edgemap *h)
{
    free(h->key);
    free(h->val);
    memset(h, 0, sizeof *h);
}

void aug_edgemap_clear(aug_edgemap *h)
{
    if (h->key) memset(h->key, 0, h->cap * sizeof *h->key);
    h->n = h->used = 0;
}

static size_t find(const aug_edgemap *h, uint64_t k)
{
    size_t mask = h->cap - 1, i = ehash(k, mask);
    while (h->key[i] != EMPTY) {
        if (h->key[i] == k) return i;
        i = (i + 1) & mask;
    }
    return (size_t)-1;
}

int32_t *aug_edgemap_get(const aug_edgemap *h, int32_t a, int32_t b)
{
    if (!h->cap) return NULL;
    size_t i = find(h, ekey(a, b));
    return i == (size_t)-1 ? NULL : h->val + 2 * i;
}

static int rehash(aug_edgemap *h, size_t cap)
{
    uint64_t *ok = h->key;
    int32_t *ov = h->val;
    size_t ocap = h->cap;
    uint64_t *nk = aug_calloc(cap, sizeof *nk);
    int32_t *nv = aug_malloc(cap * 2 * sizeof *nv);
    if (!nk || !nv) {
        free(nk);
        free(nv);
        return -1;
    }
    size_t mask = cap - 1;
    for (size_t i = 0; i < ocap; i++) {
        if (ok[i] == EMPTY || ok[i] == GONE) continue;
        size_t j = ehash(ok[i], mask);
        while (nk[j] != EMPTY) j = (j + 1) & mask;
        nk[j] = ok[i];
        nv[2 * j] = ov[2 * i];
        nv[2 * j + 1] = ov[2 * i + 1];
    }
    free(ok);
    free(ov);
    h->key = nk;
    h->val = nv;
    h->cap = cap;
    h->used = h->n;
    return 0;
}

int32_t *aug_edgemap_put(aug_edgemap *h, int32_t a, int32_t b)
{
    if (!h->cap && aug_edgemap_init(h, 32)) return NULL;
    uint64_t k = ekey(a, b);
    size_t i = find(h, k);
    if (i != (size_t)-1) return h->val + 2 * i;
    if (4 * (h->used + 1) > 3 * h->cap) {
        size_t cap = h->cap;
        while (2 * (h->n + 1) > cap) cap *= 2; /* live entries at most half after */
        if (rehash(h, cap)) return NULL;
    }
    size_t mask = h->cap - 1;
    i = ehash(k, mask);
    while (h->key[i] != EMPTY && h->key[i] != GONE) i = (i + 1) & mask;
    if (h->key[i] == EMPTY) h->used++;
    h->key[i] = k;
    h->val[2 * i] = h->val[2 * i + 1] = -1;
    h->n++;
    return h->val + 2 * i;
}

void aug_edgemap_del(aug_edgemap *h, int32_t a, int32_t b)
{
    if (!h->cap) return;
    size_t i = find(h, ekey(a, b));
    if (i == (size_t)-1) return;
    h->key[i] = GONE;
    h->n--;
}

int aug_edgemap_link(aug_edgemap *h, int32_t a, int32_t b, int32_t v)
{
    int32_t *s = aug_edgemap_put(h, a, b);
    if (!s) return -1;
    if (s[0] < 0) s[0] = v;
    else if (s[1] < 0) s[1] = v;
    else return -2;
    return 0;
}

void aug_edgemap_unlink(aug_edgemap *h, int32_t a, int32_t b, int32_t v)
{
    int32_t *s = aug_edgemap_get(h, a, b);
    if (!s) return;
    if (s[0] == v) s[0] = -1;
    else if (s[1] == v) s[1] = -1;
    if (s[0] < 0 && s[1] < 0) aug_edgemap_del(h, a, b);
}
