/* Monotonic wall clock: the per-phase timings of tIMe records and the tools. */
#include <time.h>
#include "aug_stream.h"

/* seconds since an arbitrary origin (CLOCK_MONOTONIC) */
double aug_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
