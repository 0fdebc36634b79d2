/* Thread counts of the numerical libraries (OpenMP in CHOLMOD, OpenBLAS) and
   the CHOLMOD set-up shared by every tool. */
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include "aug_fem.h"

extern void openblas_set_num_threads(int);
extern int openblas_get_num_threads(void);
extern void omp_set_num_threads(int);
extern void omp_set_dynamic(int);

/* nthreads <= 0 means 1. OpenBLAS gets n threads, OpenMP a team of 1.
   CHOLMOD's OpenMP loops (Debian's build: the assembly of a supernode, with
   a fixed team from a num_threads clause that only OMP_THREAD_LIMIT caps,
   read once at start-up: tools re-execute themselves with it set, lib/cli
   aug_tool_threads) run between the BLAS calls, whose OpenBLAS threads spin
   (sched_yield) while they wait for work: with both at 2 on this 2-core
   machine class the brain's numeric factorization took 2.7-3.4 s against
   0.72-0.80 s on one thread, with the OpenMP team at 1 and OpenBLAS at 2
   0.70-0.75 s (bin/factor --threads 2, 2026-12-07). */
void aug_set_threads(int nthreads)
{
    int n = nthreads > 0 ? nthreads : 1;
    omp_set_dynamic(0);
    omp_set_num_threads(1);
    openblas_set_num_threads(n);
}

int aug_blas_threads(int n)
{
    int prev = openblas_get_num_threads();
    if (n >= 1 && n != prev) openblas_set_num_threads(n);
    return prev;
}

/* Blocks of 2 MiB and more are 2 MiB aligned and advised as transparent huge
   pages: a factor of 10^7 entries is touched once, and with 4 KiB pages the
   page faults of that first touch cost a fifth of the factorization time on
   this machine class (THP in madvise mode). */
#define HUGE_BLOCK ((size_t)1 << 21)
static void *huge_malloc(size_t n)
{
    if (n < HUGE_BLOCK) return malloc(n);
    size_t r = (n + HUGE_BLOCK - 1) & ~(HUGE_BLOCK - 1);
    void *p = NULL;
    if (posix_memalign(&p, HUGE_BLOCK, r)) return NULL;
#ifdef MADV_HUGEPAGE
    madvise(p, r, MADV_HUGEPAGE);
#endif
    return p;
}
static void *huge_calloc(size_t n, size_t size)
{
    if (size && n > (size_t)-1 / size) return NULL;
    if (n * size < HUGE_BLOCK) return calloc(n, size);
    void *p = huge_malloc(n * size);
    if (p) memset(p, 0, n * size);
    return p;
}

void aug_cholmod_start(cholmod_common *cm)
{
    SuiteSparse_config.malloc_func = huge_malloc;
    SuiteSparse_config.calloc_func = huge_calloc;
    cholmod_start(cm);
    cm->error_handler = NULL;
    cm->print = 0;
}
