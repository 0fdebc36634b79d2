/* The cut surface step by step: step k of N of a blade realises what it
   sweeps for tau in [(k-1)/N, k/N]; of a given surface the triangles whose
   progressive key (aug_soup_order) lies in ((k-1)/N, k/N] (the first step
   from 0 on). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

void aug_cutsurf_free(aug_cutsurf *s)
{
    aug_blade_free(&s->b);
    aug_soup_free(&s->all);
    aug_soup_free(&s->step);
    free(s->key);
    memset(s, 0, sizeof *s);
}

int aug_cutsurf_surface(aug_cutsurf *s, const double *dir, aug_err *e)
{
    s->blade = 0;
    s->next = 0;
    s->key = aug_malloc((size_t)s->all.n * sizeof *s->key + 1);
    if (!s->key) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    return aug_soup_order(&s->all, dir, s->key, e);
}

int aug_cutsurf_step(aug_cutsurf *s, long k, long n, aug_err *e)
{
    aug_err_clear(e);
    s->step.n = 0;
    if (s->blade) {
        if (aug_blade_sweep(&s->b, (double)(k - 1) / (double)n, (double)k / (double)n, &s->step))
            return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        return 0;
    }
    double hi = (double)k / (double)n;
    while (s->next < s->all.n && (s->key[s->next] <= hi || k == n)) {
        const double *t = s->all.t + 9 * s->next++;
        if (aug_soup_add(&s->step, t, t + 3, t + 6) < 0) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    }
    return 0;
}

int aug_cutsurf_meets(const aug_cutsurf *s, const aug_mesh *m)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < m->nn; i++)
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], m->x[3 * i + k]), hi[k] = fmax(hi[k], m->x[3 * i + k]);
    aug_soup all = {0};
    const aug_soup *a = &s->all;
    if (s->blade) {
        if (aug_blade_sweep(&s->b, 0, 1, &all)) return -1;
        a = &all;
    }
    int meets = a->n == 0 ? -2 : 0;
    for (int64_t t = 0; t < a->n && meets != 1; t++) {
        int in = 1;
        for (int k = 0; k < 3 && in; k++) {
            const double *p = a->t + 9 * t;
            in = fmin(p[k], fmin(p[3 + k], p[6 + k])) <= hi[k] && fmax(p[k], fmax(p[3 + k], p[6 + k])) >= lo[k];
        }
        meets = in;
    }
    aug_soup_free(&all);
    return meets;
}
