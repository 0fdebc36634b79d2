/* Thread control of a tool: OMP_THREAD_LIMIT for libgomp (read only at start-up,
   hence one re-execution) and the run-time thread counts (aug_set_threads). */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#include "aug_tool.h"
#include "../aug_fem.h"

void aug_tool_threads(aug_tool *t, int nthreads)
{
    int n = nthreads > 0 ? nthreads : 1;
    if (!getenv("OMP_THREAD_LIMIT")) {
        char s[16];
        snprintf(s, sizeof s, "%d", n);
        if (setenv("OMP_THREAD_LIMIT", s, 1) == 0) {
            fflush(NULL);
            execv("/proc/self/exe", t->argv); /* returns only on failure: go on */
        }
    }
    aug_set_threads(n);
}
