/* ES-CGM (thesis 003 sec. 3.5.1): the unpivoted L D L' of the covariance
   matrix (eq. 3.22) and the recomposition L F(D') L' (eqs. 3.23-3.25), dense. */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

#define NB 64

/* unblocked L D L' of the kb x kb block at M (leading dimension n), zero
   pivots (d <= tiny) give d = 0 and a zero column; returns their count */
static int ldl_block(double *M, int n, int kb, double *d, double tiny)
{
    int nz = 0;
    for (int j = 0; j < kb; j++) {
        double *cj = M + (size_t)j * n;
        double dj = cj[j];
        if (!(dj > tiny)) {
            d[j] = 0, nz++;
            for (int i = j + 1; i < kb; i++) cj[i] = 0;
            continue;
        }
        d[j] = dj;
        for (int l = j + 1; l < kb; l++) {
            double w = cj[l]; /* = L(l,j) d_j */
            double *cl = M + (size_t)l * n;
            for (int i = l; i < kb; i++) cl[i] -= cj[i] * w / dj;
        }
        for (int i = j + 1; i < kb; i++) cj[i] /= dj;
    }
    return nz;
}

/* M = L D L' (thesis 003 eq. 3.22; [Golub-Van Loan] alg. 4.1.2 blocked
   right-looking): per block of NB columns the diagonal block unblocked, the
   panel L21 D1 = A21 L11^-T (dtrsm), the trailing A22 -= S S' with
   S = L21 D1^(1/2) (dsyrk; D >= 0). */
int aug_cgm_ldl(double *M, int n, double *d)
{
    double dmax = 0;
    for (int j = 0; j < n; j++)
        if (fabs(M[(size_t)j * n + j]) > dmax) dmax = fabs(M[(size_t)j * n + j]);
    double tiny = n * 2.220446049250313e-16 * dmax;
    int nz = 0;
    for (int k = 0; k < n; k += NB) {
        int kb = n - k < NB ? n - k : NB, m = n - k - kb;
        double *A11 = M + (size_t)k * n + k, *A21 = A11 + kb, *A22 = A11 + (size_t)kb * n + kb;
        nz += ldl_block(A11, n, kb, d + k, tiny);
        if (m == 0) break;
        cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasTrans, CblasUnit, m, kb, 1.0, A11, n,
                    A21, n);
        for (int j = 0; j < kb; j++) { /* A21(:,j) = L21(:,j) d_j -> S(:,j) */
            double *c = A21 + (size_t)j * n, sj = d[k + j] > 0 ? 1 / sqrt(d[k + j]) : 0;
            for (int i = 0; i < m; i++) c[i] *= sj;
        }
        cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, m, kb, -1.0, A21, n, 1.0, A22, n);
        for (int j = 0; j < kb; j++) { /* S(:,j) -> L21(:,j) */
            double *c = A21 + (size_t)j * n, sj = d[k + j] > 0 ? 1 / sqrt(d[k + j]) : 0;
            for (int i = 0; i < m; i++) c[i] *= sj;
        }
    }
    return nz;
}

/* T = L diag(F) L' (thesis 003 eq. 3.23): W = L diag(F) with the unit
   diagonal, then W := W L' (dtrmm, L unit lower) */
void aug_cgm_recompose(const double *L, const double *F, int n, double *T)
{
    for (int j = 0; j < n; j++) {
        const double *l = L + (size_t)j * n;
        double *t = T + (size_t)j * n;
        for (int i = 0; i < j; i++) t[i] = 0;
        t[j] = F[j];
        for (int i = j + 1; i < n; i++) t[i] = l[i] * F[j];
    }
    cblas_dtrmm(CblasColMajor, CblasRight, CblasLower, CblasTrans, CblasUnit, n, n, 1.0, L, n, T, n);
}
