/* Thread control of a tool: OMP_THREAD_LIMIT for libgomp (read only at start-up,
   hence one re-execution) and the run-time thread counts (aug_set_threads). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "aug_tool.h"
#include "../aug_fem.h"
#if defined(__has_include)
#if __has_include(<valgrind/valgrind.h>)
#include <valgrind/valgrind.h>
#define HAVE_VALGRIND_H 1
#endif
#endif

/* 1 when the tool runs under valgrind. A re-executed child would run outside
   it (valgrind follows no exec unless --trace-children=yes): valgrind would
   check only the start-up and the real run would go unchecked. The client
   request RUNNING_ON_VALGRIND answers it exactly (package valgrind, in the
   Makefile's DEPS); without the header, valgrind's preloaded vgpreload_*.so in
   LD_PRELOAD tells the same. */
static int under_valgrind(void)
{
#ifdef HAVE_VALGRIND_H
    return RUNNING_ON_VALGRIND != 0;
#else
    const char *p = getenv("LD_PRELOAD");
    return p && strstr(p, "/vgpreload_") != NULL;
#endif
}

/* Under valgrind the tool is not re-executed: OpenMP keeps its own thread
   limit (valgrind runs one thread at a time anyway) and only the run-time
   counts are set. The re-executed tool has OMP_THREAD_LIMIT=1 (CHOLMOD's
   OpenMP loops on one thread, OpenBLAS on n: lib/fem/threads.c says why)
   and, unless the user set it, OPENBLAS_NUM_THREADS=n: OpenBLAS starts its
   worker threads when it is loaded, from that or the core count, and one
   started for nothing spins for ~0.1 s before it sleeps. */
void aug_tool_threads(aug_tool *t, int nthreads)
{
    int n = nthreads > 0 ? nthreads : 1;
    if (!getenv("OMP_THREAD_LIMIT") && !under_valgrind()) {
        char s[16];
        snprintf(s, sizeof s, "%d", n);
        if ((getenv("OPENBLAS_NUM_THREADS") || setenv("OPENBLAS_NUM_THREADS", s, 1) == 0) &&
            setenv("OMP_THREAD_LIMIT", "1", 1) == 0) {
            fflush(NULL);
            execv("/proc/self/exe", t->argv); /* returns only on failure: go on */
        }
    }
    aug_set_threads(n);
}
