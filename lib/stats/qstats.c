/* Quality summary of a whole mesh: total measure, extremes, means and histograms. */
#include <math.h>
#include <string.h>
#include "aug_stats.h"

const double aug_qhist_aspect[AUG_QHIST + 1] = {1, 1.25, 1.5, 2, 3, 5, 10, 100, INFINITY};
const double aug_qhist_angle[AUG_QHIST + 1] = {0, 10, 20, 30, 40, 50, 60, 70, 180};
const double aug_qhist_sjac[AUG_QHIST + 1] = {-1, 0.2, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, INFINITY};

/* bin i with edges[i] <= v < edges[i+1]; a value within 1e-9 (relative) below
   an edge counts as on it, so 59.99999999999999 degrees falls in [60, 70) */
int aug_qhist_bin(const double *edges, double v)
{
    int b = 0;
    for (int i = 1; i < AUG_QHIST; i++)
        if (v >= edges[i] - 1e-9 * fmax(1, fabs(edges[i]))) b = i;
    return b;
}

/* sums over elements of aug_elem_quality: total signed measure; min, max, mean
   and histogram of aspect (tri3: thesis 003 eq. 3.10; tet4: R / (3 r)) and of the
   least angle; max edge ratio; hex8: min, mean and histogram of the scaled
   Jacobian; over the elements whose figures are finite (nbad counts the
   others) */
void aug_mesh_qstats(const aug_mesh *m, aug_qstats *s)
{
    memset(s, 0, sizeof *s);
    s->asp_min = s->ang_min = INFINITY;
    s->asp_max = s->ang_max = s->edge_ratio_max = -INFINITY;
    double asum = 0, gsum = 0, jsum = 0;
    s->sj_min = INFINITY;
    int64_t ngood = 0;
    for (int64_t e = 0; e < m->ne; e++) {
        aug_quality q;
        aug_elem_quality(m, e, &q);
        s->measure += q.measure;
        if (!isfinite(q.aspect) || !isfinite(q.min_angle) || !isfinite(q.edge_ratio)) {
            s->nbad++;
            continue;
        }
        ngood++;
        asum += q.aspect;
        gsum += q.min_angle;
        s->asp_min = fmin(s->asp_min, q.aspect);
        s->asp_max = fmax(s->asp_max, q.aspect);
        s->ang_min = fmin(s->ang_min, q.min_angle);
        s->ang_max = fmax(s->ang_max, q.min_angle);
        s->edge_ratio_max = fmax(s->edge_ratio_max, q.edge_ratio);
        s->asp_hist[aug_qhist_bin(aug_qhist_aspect, q.aspect)]++;
        s->ang_hist[aug_qhist_bin(aug_qhist_angle, q.min_angle)]++;
        if (m->nv == 8) {
            jsum += q.sjac;
            s->sj_min = fmin(s->sj_min, q.sjac);
            s->sj_hist[aug_qhist_bin(aug_qhist_sjac, q.sjac)]++;
        }
    }
    s->ne = m->ne;
    if (ngood) {
        s->asp_mean = asum / (double)ngood;
        s->ang_mean = gsum / (double)ngood;
        s->sj_mean = jsum / (double)ngood;
    } else {
        s->sj_min = s->sj_mean = NAN;
        s->asp_min = s->asp_max = s->asp_mean = NAN;
        s->ang_min = s->ang_max = s->ang_mean = s->edge_ratio_max = NAN;
    }
    if (m->nv != 8) s->sj_min = s->sj_mean = NAN;
}
