/* The one clock of the tool chain: monotonic wall time for the tIMe records. */
#include <time.h>
#include "aug_stream.h"

/* seconds since an arbitrary origin (CLOCK_MONOTONIC) */
double aug_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
