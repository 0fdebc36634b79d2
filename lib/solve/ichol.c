/* Incomplete Cholesky IC(0) of a sparse SPD matrix with a diagonal shift on
   breakdown ([Saad] sec. 10.3.4; [Manteuffel 1980]): the pcg preconditioner. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

void aug_ichol_free(aug_ichol *R)
{
    free(R->p), free(R->i), free(R->x), free(R->perm), free(R->w);
    memset(R, 0, sizeof *R);
}

/* R'R = K + a diag(K) on the pattern of the upper triangle of K (R upper,
   by columns, rows ascending, the diagonal last): column j of R from
   R(i,j) = (K(i,j) - sum_{k<i} R(k,i) R(k,j)) / R(i,i), i < j in the pattern,
   R(j,j) = sqrt(K(j,j) (1 + a) - sum_{i<j} R(i,j)^2), fill dropped. Returns 0,
   1 at a pivot <= 0 or not finite (breakdown). w: n doubles, zero on entry
   and on return. */
static int ic0(aug_ichol *R, double a, double *w)
{
    const int *Rp = R->p, *Ri = R->i;
    double *Rx = R->x;
    for (int j = 0; j < R->n; j++) {
        int last = Rp[j + 1] - 1;
        if (last < Rp[j] || Ri[last] != j) return 1; /* no diagonal */
        for (int q = Rp[j]; q <= last; q++) w[Ri[q]] = R->k[q];
        w[j] *= 1 + a;
        double s2 = 0;
        for (int q = Rp[j]; q < last; q++) {
            int i = Ri[q];
            double s = w[i];
            for (int t = Rp[i]; t < Rp[i + 1] - 1; t++) s -= Rx[t] * w[Ri[t]];
            w[i] = s / Rx[Rp[i + 1] - 1];
            s2 += w[i] * w[i];
        }
        double d = w[j] - s2;
        int bad = !(d > 0) || !isfinite(d);
        for (int q = Rp[j]; q < last; q++) Rx[q] = w[Ri[q]], w[Ri[q]] = 0;
        w[j] = 0;
        if (bad) return 1;
        Rx[last] = sqrt(d);
    }
    return 0;
}

/* IC(0) of K (upper-stored): the pattern copied with rows sorted, then
   R'R = K + a diag(K) for a = 0, 1e-3, 2e-3, 4e-3, ... until no pivot breaks
   down (at most 40 tries); R->shift = the a used. 0, -1 out of memory, 1 no
   shift worked. */
int aug_ichol_factor(const cholmod_sparse *K, aug_ichol *R)
{
    memset(R, 0, sizeof *R);
    int n = (int)K->ncol;
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    int nz = 0;
    for (int j = 0; j < n; j++)
        for (int q = Kp[j]; q < Kp[j + 1]; q++) nz += Ki[q] <= j;
    R->n = n;
    R->p = aug_malloc((size_t)(n + 1) * sizeof *R->p);
    R->i = aug_malloc((size_t)(nz + 1) * sizeof *R->i);
    R->x = aug_malloc((size_t)(nz + 1) * sizeof *R->x);
    R->k = aug_malloc((size_t)(nz + 1) * sizeof *R->k);
    double *w = aug_calloc((size_t)n + 1, sizeof *w);
    if (!R->p || !R->i || !R->x || !R->k || !w) {
        free(w), free(R->k);
        aug_ichol_free(R);
        return -1;
    }
    R->p[0] = 0;
    for (int j = 0, c = 0; j < n; j++) {
        for (int q = Kp[j]; q < Kp[j + 1]; q++) {
            if (Ki[q] > j) continue;
            int t = c++; /* insertion by row */
            while (t > R->p[j] && R->i[t - 1] > Ki[q]) R->i[t] = R->i[t - 1], R->k[t] = R->k[t - 1], t--;
            R->i[t] = Ki[q], R->k[t] = Kx[q];
        }
        R->p[j + 1] = c;
    }
    int rc = 1;
    for (int tr = 0; tr < 40 && rc == 1; tr++) {
        R->shift = tr == 0 ? 0 : 1e-3 * ldexp(1, tr - 1);
        rc = ic0(R, R->shift, w);
    }
    free(w);
    free(R->k), R->k = NULL;
    return rc;
}

/* v := (R'R)^-1 v: R'y = v forward by columns of R, then R v = y backward */
static void solve_inplace(const aug_ichol *R, double *v)
{
    const int *Rp = R->p, *Ri = R->i;
    const double *Rx = R->x;
    for (int j = 0; j < R->n; j++) {
        double s = v[j];
        for (int q = Rp[j]; q < Rp[j + 1] - 1; q++) s -= Rx[q] * v[Ri[q]];
        v[j] = s / Rx[Rp[j + 1] - 1];
    }
    for (int j = R->n - 1; j >= 0; j--) {
        v[j] /= Rx[Rp[j + 1] - 1];
        double vj = v[j];
        for (int q = Rp[j]; q < Rp[j + 1] - 1; q++) v[Ri[q]] -= Rx[q] * vj;
    }
}

/* z = (R'R)^-1 r, or z = P (R'R)^-1 P' r with P = R->perm (ichol_amd.c) */
void aug_ichol_apply(const aug_ichol *R, const double *r, double *z)
{
    if (!R->perm) {
        if (z != r) memcpy(z, r, (size_t)R->n * sizeof *z);
        solve_inplace(R, z);
        return;
    }
    for (int k = 0; k < R->n; k++) R->w[k] = r[R->perm[k]];
    solve_inplace(R, R->w);
    for (int k = 0; k < R->n; k++) z[R->perm[k]] = R->w[k];
}
