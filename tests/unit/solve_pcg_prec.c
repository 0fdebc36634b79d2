/* pcg's preconditioners (none, Jacobi, IC(0) with a shift on breakdown, IC(0)
   on the AMD ordering): IC(0) exact where it has no fill, its shift on
   Kershaw's matrix, the AMD ordering a permutation that removes the fill of a
   tree, every preconditioner's solution against a dense LAPACK solve of a
   square; unit rows masked out of the tolerance and relres. */
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
    int it = aug_pcg_prec(K, f, NULL, 0, x, AUG_PCG_IC, 1e-12, 100, &conv, &brk, &rr, &sh, NULL, &cm);
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
    aug_pcg_prec(K, f, NULL, 0, x, AUG_PCG_IC, 1e-12, 100, &conv, &brk, &rr, &sh, NULL, &cm);
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
    aug_ichol R;
    T_CHECK(aug_ichol_factor_amd(K, &R, &cm) == 0 && R.perm, "IC(0) on the AMD ordering of the square");
    int *seen = calloc(n, sizeof *seen), perm_ok = 1, moved = 0;
    for (int64_t k = 0; k < n; k++) {
        int v = R.perm[k];
        if (v < 0 || v >= n || seen[v]++) perm_ok = 0;
        else moved += v != k;
    }
    T_CHECK(perm_ok && moved > 0, "AMD ordering: a permutation %d, %d of %d rows moved", perm_ok, moved, (int)n);
    free(seen);
    aug_ichol_free(&R);
    int its[4];
    for (int p = 0; p < 4; p++) {
        int conv, brk;
        double rr, sh;
        memset(x, 0, n * sizeof *x);
        its[p] = aug_pcg_prec(K, f, NULL, 0, x, p, 1e-12, 10000, &conv, &brk, &rr, &sh, NULL, &cm);
        double d = 0, un = 0;
        for (int64_t i = 0; i < n; i++) d += (x[i] - u[i]) * (x[i] - u[i]), un += u[i] * u[i];
        T_CHECK(conv && rr <= 1e-12 && sqrt(d / un) <= 1e-8, "prec %d: converged %d, relres %g, error %g", p, conv,
                rr, sqrt(d / un));
    }
    T_CHECK(its[AUG_PCG_IC] < its[AUG_PCG_JACOBI] && its[AUG_PCG_IC_AMD] < its[AUG_PCG_JACOBI],
            "IC(0) %d, on AMD %d iterations, Jacobi %d", its[AUG_PCG_IC], its[AUG_PCG_IC_AMD], its[AUG_PCG_JACOBI]);
    free(A), free(f), free(u), free(x), free(map);
    cholmod_free_sparse(&K, &cm);
    aug_mesh_free(&m);
}

/* a tree (parent of i below i, node 0 a hub): on the natural ordering the
   Cholesky factor fills (children of an eliminated parent couple), so IC(0)
   differs from it; on AMD's ordering P (leaves first) chol(P'KP) has no fill
   (checked against the dense LAPACK factor) and IC(0) equals it */
static void t_amd_tree(void)
{
    int n = 40, par[40];
    double *A = calloc((size_t)n * n, sizeof *A), *B = calloc((size_t)n * n, sizeof *B);
    par[0] = -1;
    for (int i = 1; i < n; i++) par[i] = i < 8 ? 0 : (int)((7 * i + 3) % (i < 16 ? 8 : i / 2));
    for (int i = 0; i < n; i++) A[(size_t)i * n + i] = 1 + 0.1 * i;
    for (int i = 1; i < n; i++) {
        int j = par[i];
        A[(size_t)i * n + j] = A[(size_t)j * n + i] = -1;
        A[(size_t)i * n + i] += 1.5, A[(size_t)j * n + j] += 1.5;
    }
    cholmod_sparse *K = sparse_upper(A, n);
    aug_ichol R0, R;
    T_CHECK(aug_ichol_factor(K, &R0) == 0 && aug_ichol_factor_amd(K, &R, &cm) == 0 && R0.shift == 0 && R.shift == 0,
            "IC(0) of the tree, natural and AMD, without shift");
    /* B = P'AP, U'U = B by LAPACK */
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++) B[(size_t)b * n + a] = A[(size_t)R.perm[b] * n + R.perm[a]];
    double *U = malloc((size_t)n * n * sizeof *U), *U0 = malloc((size_t)n * n * sizeof *U0);
    memcpy(U, B, (size_t)n * n * sizeof *U), memcpy(U0, A, (size_t)n * n * sizeof *U0);
    T_CHECK(LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'U', n, U, n) == 0 && LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'U', n, U0, n) == 0,
            "dense Cholesky");
    double fill = 0, fill0 = 0, d = 0, d0 = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < j; i++) {
            if (B[(size_t)j * n + i] == 0) fill = fmax(fill, fabs(U[(size_t)j * n + i]));
            if (A[(size_t)j * n + i] == 0) fill0 = fmax(fill0, fabs(U0[(size_t)j * n + i]));
        }
    for (int j = 0; j < n; j++)
        for (int q = R.p[j]; q < R.p[j + 1]; q++) d = fmax(d, fabs(R.x[q] - U[(size_t)j * n + R.i[q]]));
    for (int j = 0; j < n; j++)
        for (int q = R0.p[j]; q < R0.p[j + 1]; q++) d0 = fmax(d0, fabs(R0.x[q] - U0[(size_t)j * n + R0.i[q]]));
    T_CHECK(fill <= 1e-14 && d <= 1e-12, "AMD: fill %g, |IC(0) - chol| %g", fill, d);
    T_CHECK(fill0 > 1e-3 && d0 > 1e-6, "natural ordering: fill %g and IC(0) off chol by %g", fill0, d0);
    /* the preconditioner P (R'R)^-1 P' is K^-1 exactly: one PCG step */
    double f[40], x[40] = {0};
    for (int i = 0; i < n; i++) f[i] = cos(i);
    int conv, brk;
    double rr, sh;
    int it = aug_pcg_prec(K, f, NULL, 0, x, AUG_PCG_IC_AMD, 1e-12, 100, &conv, &brk, &rr, &sh, NULL, &cm);
    T_CHECK(it == 1 && conv, "IC(0) on AMD: %d iterations, converged %d", it, conv);
    aug_ichol_free(&R0), aug_ichol_free(&R);
    cholmod_free_sparse(&K, &cm);
    free(A), free(B), free(U), free(U0);
}

/* unit rows (a constrained DOF kept in the matrix, K's row and column e_i)
   whose right-hand side dwarfs the rest, as a dropped piece's jump in a
   dynamic frame: with the mask x_i = f_i exactly, the other rows meet the
   tolerance against their own ||f||, and the relres returned is theirs
   (tests/dyn_frames.test has the frame where, unmasked, they stopped at
   3.8e-6 of it) */
static void t_unit(void)
{
    int n = 300; /* two 1-D Laplacians of 149 (CG converges over ~100 steps) */
    double *A = calloc((size_t)n * n, sizeof *A), *f = malloc(n * sizeof *f), *x = calloc(n, sizeof *x);
    double *ref = malloc(n * sizeof *ref);
    unsigned char unit[300] = {0};
    for (int i = 0; i < n; i++) {
        A[(size_t)i * n + i] = 2, f[i] = 1e-6 * (1 + i % 5);
        if (i) A[(size_t)i * n + i - 1] = A[(size_t)(i - 1) * n + i] = -1;
    }
    for (int i = 0; i < n; i += 150) { /* rows 0 and 150: unit, f = 3e-3 */
        for (int j = 0; j < n; j++) A[(size_t)i * n + j] = A[(size_t)j * n + i] = 0;
        A[(size_t)i * n + i] = 1, f[i] = 3e-3, unit[i] = 1;
    }
    memcpy(ref, f, n * sizeof *ref);
    double *Ad = malloc((size_t)n * n * sizeof *Ad);
    memcpy(Ad, A, (size_t)n * n * sizeof *Ad);
    LAPACKE_dposv(LAPACK_COL_MAJOR, 'U', n, 1, Ad, n, ref, n);
    cholmod_sparse *K = sparse_upper(A, n);
    int conv, brk;
    double rr, sh, tol = 1e-8;
    aug_pcg_prec(K, f, unit, n, x, AUG_PCG_JACOBI, tol, 1000, &conv, &brk, &rr, &sh, NULL, &cm);
    double ex = 0, fn = 0, jump = 0;
    for (int i = 0; i < n; i++) {
        if (unit[i]) {
            jump = fmax(jump, fabs(x[i] - f[i]));
            continue;
        }
        double rx = f[i];
        for (int j = 0; j < n; j++) rx -= A[(size_t)j * n + i] * x[j];
        ex += rx * rx, fn += f[i] * f[i];
    }
    ex = sqrt(ex / fn);
    double d = 0, un = 0;
    for (int i = 0; i < n; i++) d += (x[i] - ref[i]) * (x[i] - ref[i]), un += ref[i] * ref[i];
    T_CHECK(conv && jump == 0 && ex <= tol && fabs(rr - ex) <= 0.1 * ex, /* (rounding apart; over all rows it is 200x less) */
            "converged %d, unit rows off by %g, free rows' relres %g (returned %g)", conv, jump, ex, rr);
    T_CHECK(sqrt(d / un) <= 1e-6, "error against LAPACK %g", sqrt(d / un));
    cholmod_free_sparse(&K, &cm);
    free(A), free(Ad), free(f), free(x), free(ref);
}

int main(void)
{
    cholmod_start(&cm);
    T_RUN(t_unit);
    T_RUN(t_exact);
    T_RUN(t_kershaw);
    T_RUN(t_square);
    T_RUN(t_amd_tree);
    cholmod_finish(&cm);
    T_EXIT();
}
