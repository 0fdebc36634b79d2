/* Monotonic wall clock for the per-phase timings of tIMe records. */
#include <time.h>
#include "aug_solve.h"

/* milliseconds since an arbitrary origin */
double aug_wall_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return 1e3 * (double)ts.tv_sec + 1e-6 * (double)ts.tv_nsec;
}
