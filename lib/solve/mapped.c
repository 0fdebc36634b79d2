/* Work arrays that grow with the steps (the memo's V and G, the LU of S2),
   mapped from the system and given back to it when grown or freed: the tools
   let malloc keep freed memory (lib/cli/tool.c), which kept every outgrown
   copy resident, and a copy on growth held the old and the new array at once.
   Up to SMALL bytes they come from the heap instead: there the factorization
   left memory already backed, while the first touch of a fresh huge page
   costs milliseconds on this kind of machine (a virtual one: 6 ms each, the
   first AMPS step's memo and S2 spent ~20 ms on theirs). */
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include "aug_solve.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define AUG_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define AUG_ASAN 1
#endif
/* under AddressSanitizer the arrays come from malloc, where it sees them */
#if defined(__linux__) && defined(MREMAP_MAYMOVE) && defined(MREMAP_FIXED) && !defined(AUG_ASAN)
#define MAPPED 1
#else
#define MAPPED 0
#endif

#define HUGE ((size_t)2 << 20)
/* the largest array taken from the heap (the tools' mmap threshold) */
#define SMALL ((size_t)64 << 20)

/* sizes in whole huge pages: the mappings start on huge-page boundaries, so
   that the kernel can back them with huge pages and move them as such */
static size_t whole(size_t n) { return (n + HUGE - 1) / HUGE * HUGE; }

/* the largest array taken from the heap: SMALL, or the heap aug_prefault
   touched; changed only while no array is mapped (aug_map_free tells a
   heap array from a mapped one by this bound) */
#if MAPPED
static size_t heap_max = SMALL;
static long nmapped;
#endif

#if MAPPED
/* a fresh mapping of n bytes (a multiple of HUGE) on a HUGE boundary */
static void *map_aligned(size_t n)
{
    char *q = mmap(NULL, n + HUGE, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (q == MAP_FAILED) return NULL;
    size_t head = (HUGE - (uintptr_t)q % HUGE) % HUGE;
    if (head) munmap(q, head);
    munmap(q + head + n, HUGE - head);
    return q + head;
}
#endif

/* p (old bytes, from the heap) as a page-aligned heap array of n bytes, its
   first old bytes kept (copied); NULL when out of memory (p unchanged) */
static void *heap_grow(void *p, size_t old, size_t n)
{
    void *q = NULL;
    if (posix_memalign(&q, 4096, n)) return NULL;
    if (old) memcpy(q, p, old);
    free(p);
    return q;
}

/* p (old bytes; NULL when old = 0) as an array of n >= old bytes, its first old
   bytes kept: up to SMALL from the heap (copied on growth), above it mapped
   on a huge-page boundary (huge pages asked for: dgetrs and the LU update
   stride through S2 a column at a time, one 4 KiB page each without them),
   grown in place or moved by the page tables (mremap), not copied.
   NULL when out of memory (p is then unchanged). */
void *aug_map_grow(void *p, size_t old, size_t n)
{
    n = whole(n ? n : 1), old = old ? whole(old) : 0;
    if (old == n) return p;
#if MAPPED
    void *q;
    if (n <= heap_max) return heap_grow(p, old, n);
    if (old && old <= heap_max) { /* from the heap to a mapping: one copy */
        if (!(q = map_aligned(n))) return NULL;
        memcpy(q, p, old);
        free(p);
        nmapped++;
    } else if (old && (q = mremap(p, old, n, 0)) != MAP_FAILED) {
        q = p; /* grown in place */
    } else {
        if (!(q = map_aligned(n))) return NULL;
        if (old && mremap(p, old, old, MREMAP_MAYMOVE | MREMAP_FIXED, q) == MAP_FAILED) {
            munmap(q, n);
            return NULL;
        }
        if (!old) nmapped++;
    }
#ifdef MADV_HUGEPAGE
    madvise(q, n, MADV_HUGEPAGE);
#endif
    return q;
#else
    return heap_grow(p, old, n);
#endif
}

/* frees an array of aug_map_grow of n bytes (NULL: nothing) */
void aug_map_free(void *p, size_t n)
{
    if (!p) return;
#if MAPPED
    if (whole(n ? n : 1) <= heap_max) {
        free(p);
    } else {
        munmap(p, whole(n ? n : 1));
        nmapped--;
    }
#else
    (void)n;
    free(p);
#endif
}

/* a (cap x cap doubles, column-major, leading dimension cap; NULL when cap =
   0) grown to ncap x ncap, leading dimension ncap, keeping its leading keep x
   keep block: the array grows in place and the columns move up, the last
   first (column j's new place starts at or after the end of column j - 1's
   old one, as keep <= cap < ncap). NULL when out of memory (a unchanged). */
double *aug_sq_grow(double *a, int64_t cap, int64_t ncap, int64_t keep)
{
    size_t old = (size_t)cap * (size_t)cap * sizeof *a;
    double *q = aug_map_grow(a, old, (size_t)ncap * (size_t)ncap * sizeof *a);
    if (!q) return NULL;
    for (int64_t j = keep - 1; j > 0; j--)
        memmove(q + j * ncap, q + j * cap, (size_t)keep * sizeof *q);
    return q;
}

/* the capacity of a square array of order need grown from cap: AUG_SCHUR_CAP0
   at first, then by a quarter at least, in multiples of 256 (huge pages are
   touched column by column up to the capacity, so it stays within 5/4 of the
   order) */
int64_t aug_sq_cap(int64_t cap, int64_t need)
{
    if (need <= cap) return cap;
    int64_t nc = cap ? cap + cap / 4 : AUG_SCHUR_CAP0;
    if (nc < need) nc = need;
    return (nc + 255) / 256 * 256;
}

/* Real-time practice (the PREEMPT_RT guides: no trimming, no mmap, the heap
   touched before the loop): bytes of heap are touched once, one write per
   page, and given back to the allocator, which keeps them (no trimming
   below them, no mmap below them); the arrays that grow with the steps
   (the memo's V and G, the LU of S2: aug_map_grow) then come from that heap
   up to its size. On a virtual machine the first touch of a page costs far
   more than the work a step does on it (this one: 32 MiB first written in
   75-110 ms, again in 1.3 ms; 11-14 us per 4 KiB page), and AMPS's arrays
   grow on every step: on the bunny of bench/organs.sh, 8-node steps, the
   page faults took ~15% of AMPS's step time. The touch itself costs that
   much once, before the first step. Returns its milliseconds, or -1 (out
   of memory: nothing kept). */
double aug_prefault(size_t bytes)
{
    if (!bytes) return 0;
    double t0 = aug_now();
#if defined(__GLIBC__)
    size_t lim = bytes + ((size_t)64 << 20), top = bytes + ((size_t)256 << 20);
    if (lim > INT_MAX) lim = INT_MAX;
    if (top > INT_MAX) top = INT_MAX;
    if (lim > ((size_t)1 << 26)) mallopt(M_MMAP_THRESHOLD, (int)lim);
    if (top > ((size_t)1 << 28)) mallopt(M_TRIM_THRESHOLD, (int)top);
#endif
    long pg = sysconf(_SC_PAGESIZE);
    size_t step = pg > 0 ? (size_t)pg : 4096;
    volatile char *p = malloc(bytes);
    if (!p) return -1;
    for (size_t o = 0; o < bytes; o += step) p[o] = 1;
    p[bytes - 1] = 1;
    free((void *)p);
#if MAPPED
    if (!nmapped && whole(bytes) > heap_max) heap_max = whole(bytes);
#endif
    return 1e3 * (aug_now() - t0);
}
