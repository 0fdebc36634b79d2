/* Projection error of a state onto the current subspace (paper 004 eqs.
   12-14): exact, and by Kenney-Laub small-sample statistical estimation. */
#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_modal.h"

/* ||u - U (U'u)|| / ||u|| (eq. 13) with work >= n + 2 q + r */
double aug_proj_err(const aug_isvd *s, const double *u, double *work)
{
    aug_basis W = aug_isvd_view(s);
    double un = cblas_dnrm2((int)s->n, u, 1);
    if (un == 0) return 0;
    aug_basis_residual(&W, u, work, work + s->n);
    return cblas_dnrm2((int)s->n, work, 1) / un;
}

/* W_m = Gamma(m/2) / (sqrt(pi) Gamma((m+1)/2)), which is eq. 14's product
   form: 1.3...(m-2) / 2.4...(m-1) for odd m, (2/pi) 2.4...(m-2) / 1.3...(m-1)
   for even m */
double aug_wallis(int64_t m)
{
    if (m < 1) return NAN;
    return exp(lgamma(0.5 * (double)m) - lgamma(0.5 * ((double)m + 1))) / sqrt(M_PI);
}

/* splitmix64 (Steele, Lea, Flood 2014) */
static uint64_t next64(uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* standard normal by Box-Muller */
static double gauss(uint64_t *x)
{
    double a = ((double)(next64(x) >> 11) + 0.5) * 0x1.0p-53, b = (double)(next64(x) >> 11) * 0x1.0p-53;
    return sqrt(-2 * log(a)) * cos(2 * M_PI * b);
}

/* nu = (W_k / W_n) ||Z'e||, Z = Q of the QR of an n x k Gaussian matrix
   (Haar-distributed orthonormal columns), e = u - U U'u: E nu = ||e|| since
   ||Z'e||^2 / ||e||^2 ~ Beta(k/2, (n-k)/2) and E sqrt of it = W_n / W_k. */
double aug_proj_err_estimate(const aug_isvd *s, const double *u, int k, uint64_t *seed, aug_err *e)
{
    aug_err_clear(e);
    int64_t n = s->n;
    if (k < 1 || k > n) {
        aug_err_set(e, AUG_EUSAGE, -1, "", "error estimate: %d probes for length %lld", k, (long long)n);
        return -1;
    }
    double un = cblas_dnrm2((int)n, u, 1);
    if (un == 0) return 0;
    size_t nw = (size_t)n * (k + 1) + 2 * (size_t)s->q + s->r + k + (size_t)k;
    double *Z = malloc(nw * sizeof *Z);
    if (!Z) {
        aug_err_set(e, AUG_ENOMEM, -1, "", "error estimate: out of memory (%d probes)", k);
        return -1;
    }
    double *res = Z + (size_t)n * k, *tau = res + n, *y = tau + k, *work = y + k;
    for (size_t i = 0; i < (size_t)n * k; i++) Z[i] = gauss(seed);
    if (LAPACKE_dgeqrf(LAPACK_COL_MAJOR, (int)n, k, Z, (int)n, tau) ||
        LAPACKE_dorgqr(LAPACK_COL_MAJOR, (int)n, k, k, Z, (int)n, tau)) {
        free(Z);
        aug_err_set(e, AUG_ENOCONV, -1, "", "error estimate: QR of the probes failed");
        return -1;
    }
    aug_basis W = aug_isvd_view(s);
    aug_basis_residual(&W, u, res, work);
    cblas_dgemv(CblasColMajor, CblasTrans, (int)n, k, 1.0, Z, (int)n, res, 1, 0.0, y, 1);
    double nu = aug_wallis(k) / aug_wallis(n) * cblas_dnrm2(k, y, 1);
    free(Z);
    return nu / un;
}
