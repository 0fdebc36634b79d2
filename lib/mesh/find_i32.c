/* Sorted int32 arrays: the qsort/bsearch order and binary search. */
#include "aug_mesh.h"

/* qsort/bsearch comparison of two int32: sign of *a - *b */
int aug_cmp_i32(const void *a, const void *b)
{
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
}

/* position of v in a[0..n) (strictly increasing), -1 if absent */
int64_t aug_find_i32(const int32_t *a, int64_t n, int32_t v)
{
    int64_t lo = 0, hi = n - 1;
    while (lo <= hi) {
        int64_t mid = lo + (hi - lo) / 2;
        if (a[mid] == v) return mid;
        if (a[mid] < v) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}
