/* Shared generators and oracles of the modal unit tests: a seeded normal
   generator, snapshot sequences, dense SVD and principal angles by LAPACK. */
#ifndef MODAL_GEN_H
#define MODAL_GEN_H
#include <lapacke.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "aug_modal.h"

static uint64_t g_seed = 12345;
static inline double g_unif(void)
{
    g_seed = g_seed * 6364136223846793005ull + 1442695040888963407ull;
    return ((double)(g_seed >> 11) + 0.5) * 0x1.0p-53;
}
static inline double g_normal(void) { return sqrt(-2 * log(g_unif())) * cos(2 * M_PI * g_unif()); }

/* X (n x m): rank-k structure B C with singular values ~ 2^-j plus noise
   (k = 0: pure Gaussian) */
static inline double *g_snapshots(int64_t n, int m, int k, double noise)
{
    double *X = malloc((size_t)n * m * sizeof *X);
    double *B = malloc((size_t)n * (k + 1) * sizeof *B), *C = malloc((size_t)(k + 1) * m * sizeof *C);
    for (size_t i = 0; i < (size_t)n * (k + 1); i++) B[i] = g_normal();
    for (size_t i = 0; i < (size_t)(k + 1) * m; i++) C[i] = g_normal();
    for (int j = 0; j < m; j++)
        for (int64_t i = 0; i < n; i++) {
            double v = k == 0 ? g_normal() : noise * g_normal();
            for (int t = 0; t < k; t++) v += B[i + t * n] * C[t + (size_t)j * (k + 1)] * ldexp(1, -t);
            X[i + (size_t)j * n] = v;
        }
    free(B);
    free(C);
    return X;
}

/* singular values (descending, min(n, m)) and left vectors (n x min) of X */
static inline void g_svd(const double *X, int64_t n, int m, double *sv, double *U)
{
    int p = n < m ? (int)n : m;
    double *A = malloc((size_t)n * m * sizeof *A), *sb = malloc((size_t)p * sizeof *sb);
    memcpy(A, X, (size_t)n * m * sizeof *A);
    LAPACKE_dgesvd(LAPACK_COL_MAJOR, 'S', 'N', (int)n, m, A, (int)n, sv, U, (int)n, NULL, 1, sb);
    free(A);
    free(sb);
}

/* smallest cosine of the principal angles between span(A) and span(B), both
   n x r with orthonormal columns: the smallest singular value of A'B */
static inline double g_min_cos(const double *A, const double *B, int64_t n, int r)
{
    double *C = calloc((size_t)r * r, sizeof *C), *sv = malloc(r * sizeof *sv);
    for (int i = 0; i < r; i++)
        for (int j = 0; j < r; j++)
            for (int64_t t = 0; t < n; t++) C[i + j * r] += A[t + i * n] * B[t + j * n];
    g_svd(C, r, r, sv, C);
    double c = sv[r - 1];
    free(C);
    free(sv);
    return c;
}
#endif
