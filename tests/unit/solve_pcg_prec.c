/* pcg's preconditioners (none, Jacobi, IC(0) with a shift on breakdown):
   IC(0) exact where it has no fill, its shift on Kershaw's matrix, every
   preconditioner's solution against a dense LAPACK solve of a square. */
#include <lapacke.h>
#include "t.h"
#include "fem_mesh.h"
#include "aug_solve.h"

static cholmod_common cm;

/* upper-stored sparse copy of the dense symmetric n x n A */
static cholmod_sparse *sparse_upper(const double *A, int n)
{
    int nz = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i <= j; i++) nz += A[(size_t)j * n + i] != 0;
    cholmod_sparse *K = cholmod_allocate_sparse(n, n, nz, 1, 1, 1, CHOLMOD_REAL, &cm);
    int *Kp = K->p, *Ki = K->i, q = 0;
    double *Kx = K->x;
    for (int j = 0; j < n; j++) {
        Kp[j] = q;
        for (int i = 0; i <= j; i++)
            if (A[(size_t)j * n + i] != 0) Ki[q] = i, Kx[q++] = A[(size_t)j * n + i];
    }
    Kp[n] = q;
    return K;
}

/* tridiagonal: IC(0) = the Cholesky factor, PCG converges in one step */
static void t_exact(void)
{
    int n = 50;
    double *A = calloc((size_t)n * n, sizeof *A), *f = malloc(n * sizeof *f), *x = calloc(n, sizeof *x);
    for (int i = 0; i < n; i++) {
        A[(size_t)i * n + i] = 2 + 0.01 * i, f[i] = 1 + i % 3;
        if (i) A[(size_t)i * n + i - 1] = A[(size_t)(i - 1) * n + i] = -1;
    }
    cholmod_sparse *K = sparse_upper(A, n);
    int conv, brk;
    double rr, sh;
    int it = aug_pcg_prec(K, f, x, AUG_PCG_IC, 1e-12, 100, &conv, &brk, &rr, &sh, &cm);
    T_CHECK(it == 1 && conv && sh == 0, "iterations %d, converged %d, shift %g", it, conv, sh);
    cholmod_free_sparse(&K, &cm);
    free(A), free(f), free(x);
}

/* Kershaw's SPD matrix (J. Comput. Phys. 26, 1978): IC(0) breaks down at a
   zero shift; a shifted one exists and PCG solves it */
static void t_kershaw(void)
{
    double A[16] = {3, -2, 0, 2, -2, 3, -2, 0, 0, -2, 3, -2, 2, 0, -2, 3}, f[4] = {1, 2, 3, 4}, x[4] = {0};
    cholmod_sparse *K = sparse_upper(A, 4);
    aug_ichol R;
    T_CHECK(aug_ichol_factor(K, &R) == 0 && R.shift > 0, "shift %g (IC(0) of Kershaw's matrix breaks down)", R.shift);
    aug_ichol_free(&R);
    int conv, brk;
    double rr, sh;
    aug_pcg_prec(K, f, x, AUG_PCG_IC, 1e-12, 100, &conv, &brk, &rr, &sh, &cm);
    double ref[4] = {1, 2, 3, 4};
    LAPACKE_dposv(LAPACK_COL_MAJOR, 'U', 4, 1, A, 4, ref, 4);
    double d = 0;
    for (int i = 0; i < 4; i++) d = fmax(d, fabs(x[i] - ref[i]));
    T_CHECK(conv && sh > 0 && d <= 1e-10, "converged %d, shift %g, error %g", conv, sh, d);
    cholmod_free_sparse(&K, &cm);
}

/* a 12 x 12 square fixed at x = 0: none, Jacobi and IC(0) reach the dense
   solution; IC(0) in fewer iterations than Jacobi */
static void t_square(void)
{
    aug_mesh m;
    aug_err e;
    tm_rect(&m, 12, 12, 1, 1, 1000, 0.3, 1);
    tm_fix_plane(&m, 0, 0, NULL);
    int32_t *map = malloc((size_t)13 * 13 * 2 * sizeof *map);
    int64_t n = aug_dofmap(&m, map);
    cholmod_sparse *K = aug_assemble(&m, map, n, AUG_MAT_K, &cm, &e);
    double *A = tm_dense(K), *f = malloc(n * sizeof *f), *u = malloc(n * sizeof *u), *x = malloc(n * sizeof *x);
    for (int64_t i = 0; i < n; i++) f[i] = sin(1.0 + i);
    memcpy(u, f, n * sizeof *u);
    LAPACKE_dposv(LAPACK_COL_MAJOR, 'U', (int)n, 1, A, (int)n, u, (int)n);
    int its[3];
    for (int p = 0; p < 3; p++) {
        int conv, brk;
        double rr, sh;
        memset(x, 0, n * sizeof *x);
        its[p] = aug_pcg_prec(K, f, x, p, 1e-12, 10000, &conv, &brk, &rr, &sh, &cm);
        double d = 0, un = 0;
        for (int64_t i = 0; i < n; i++) d += (x[i] - u[i]) * (x[i] - u[i]), un += u[i] * u[i];
        T_CHECK(conv && rr <= 1e-12 && sqrt(d / un) <= 1e-8, "prec %d: converged %d, relres %g, error %g", p, conv,
                rr, sqrt(d / un));
    }
    T_CHECK(its[AUG_PCG_IC] < its[AUG_PCG_JACOBI], "IC(0) %d iterations, Jacobi %d", its[AUG_PCG_IC],
            its[AUG_PCG_JACOBI]);
    free(A), free(f), free(u), free(x), free(map);
    cholmod_free_sparse(&K, &cm);
    aug_mesh_free(&m);
}

int main(void)
{
    cholmod_start(&cm);
    T_RUN(t_exact);
    T_RUN(t_kershaw);
    T_RUN(t_square);
    cholmod_finish(&cm);
    T_EXIT();
}
