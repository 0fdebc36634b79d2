/* Comma-separated numbers in the text of a spec (scene options, constraints). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include "aug_stream.h"

/* s = "x1,x2,...,xn", 1 <= n <= max finite numbers (strtod's syntax, no
   overflow or underflow), nothing after the last: n with v[0..n) set, else -1
   (v may be partly written) */
int aug_parse_reals(const char *s, double *v, int max)
{
    int n = 0;
    for (const char *p = s;; p++) {
        char *end;
        if (n == max) return -1;
        errno = 0;
        v[n] = strtod(p, &end);
        if (end == p || errno || !isfinite(v[n])) return -1;
        n++;
        p = end;
        if (*p == 0) return n;
        if (*p != ',') return -1;
    }
}
