/* Minimal unit-test harness: each T_RUN(fn) prints "PASS fn" or "FAIL fn: why". */
#ifndef T_H
#define T_H
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int t_failed_cases, t_cur_failed;
static char t_why[512];

#define T_CHECK(cond, ...)                                                   \
    do {                                                                     \
        if (!(cond) && !t_cur_failed) {                                      \
            t_cur_failed = 1;                                                \
            int t_n = snprintf(t_why, sizeof t_why, "%s:%d: ", __FILE__, __LINE__); \
            snprintf(t_why + t_n, sizeof t_why - t_n, __VA_ARGS__);          \
        }                                                                    \
    } while (0)

#define T_RUN(fn)                                                            \
    do {                                                                     \
        t_cur_failed = 0;                                                    \
        fn();                                                                \
        if (t_cur_failed) {                                                  \
            printf("FAIL %s: %s\n", #fn, t_why);                             \
            t_failed_cases++;                                                \
        } else {                                                             \
            printf("PASS %s\n", #fn);                                        \
        }                                                                    \
        fflush(stdout);                                                      \
    } while (0)

#define T_EXIT() return t_failed_cases ? 1 : 0

/* relative difference |a-b| / max(|b|, tiny) */
static inline double t_reldiff(double a, double b)
{
    double d = fabs(b) > 1e-300 ? fabs(b) : 1e-300;
    return fabs(a - b) / d;
}
#endif
