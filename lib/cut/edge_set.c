/* A set of node pairs (unordered), open addressing: the pending cut edges. */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

static int64_t key(int32_t a, int32_t b)
{
    if (a > b) {
        int32_t t = a;
        a = b;
        b = t;
    }
    return ((int64_t)a << 32) | (uint32_t)b;
}

static uint64_t hash(int64_t k)
{
    uint64_t x = (uint64_t)k;
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    return x;
}

static int64_t slot(const aug_edgeset *s, int64_t k)
{
    uint64_t mask = (uint64_t)s->cap - 1;
    for (uint64_t i = hash(k) & mask;; i = (i + 1) & mask)
        if (s->key[i] == k || s->key[i] == -1) return (int64_t)i;
}

static int rehash(aug_edgeset *s, int64_t cap)
{
    int64_t *old = s->key, oc = s->cap;
    s->key = aug_malloc((size_t)cap * sizeof *s->key);
    if (!s->key) {
        s->key = old;
        return -1;
    }
    for (int64_t i = 0; i < cap; i++) s->key[i] = -1;
    s->cap = cap;
    s->n = 0;
    for (int64_t i = 0; i < oc; i++)
        if (old[i] >= 0) {
            s->key[slot(s, old[i])] = old[i];
            s->n++;
        }
    free(old);
    return 0;
}

int aug_edgeset_add(aug_edgeset *s, int32_t a, int32_t b)
{
    if ((s->n + 1) * 2 > s->cap && rehash(s, s->cap ? 2 * s->cap : 64)) return -1;
    int64_t k = key(a, b), i = slot(s, k);
    if (s->key[i] != k) {
        s->key[i] = k;
        s->n++;
    }
    return 0;
}

int aug_edgeset_has(const aug_edgeset *s, int32_t a, int32_t b)
{
    if (s->cap == 0) return 0;
    int64_t k = key(a, b);
    uint64_t mask = (uint64_t)s->cap - 1;
    for (uint64_t i = hash(k) & mask;; i = (i + 1) & mask) {
        if (s->key[i] == k) return 1;
        if (s->key[i] == -1) return 0;
    }
}

void aug_edgeset_del(aug_edgeset *s, int32_t a, int32_t b)
{
    if (s->cap == 0) return;
    int64_t k = key(a, b);
    uint64_t mask = (uint64_t)s->cap - 1;
    for (uint64_t i = hash(k) & mask;; i = (i + 1) & mask) {
        if (s->key[i] == -1) return;
        if (s->key[i] == k) {
            s->key[i] = -2;
            return;
        }
    }
}

void aug_edgeset_free(aug_edgeset *s)
{
    free(s->key);
    memset(s, 0, sizeof *s);
}
