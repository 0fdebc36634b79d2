/* Coupled saddle-point solvers (paper 004 eq. 15/18): the dual Schur solve and
   projected PCG against an independent dense null-space solve of the same
   constraints (least squares on the dependent rows, minimum energy on the
   null space), the caches, m = 0, the shared-DOF FE solution, errors. */
#include <cblas.h>
#include "t.h"
#include "modal_gen.h"
#include "aug_fem.h"
#include "aug_saddle.h"

static cholmod_common cm;

/* sparse SPD block (upper stored) and its dense copy: a weighted 1-D
   Laplacian with random long couplings and a positive random diagonal */
static cholmod_sparse *fe_block(int n, double *Kd, double scale)
{
    cholmod_triplet *T = cholmod_allocate_triplet(n, n, 3 * n, 1, CHOLMOD_REAL, &cm);
    double *full = calloc((size_t)n * n, sizeof *full);
    for (int i = 0; i < n; i++) {
        full[i + i * n] += 0.2 + g_unif();
        int js[2] = {i + 1, (int)(g_unif() * n)};
        for (int t = 0; t < 2; t++) {
            int j = js[t];
            if (j >= n || j <= i || (t == 1 && j == i + 1)) continue;
            double w = t == 0 ? 1 + g_unif() : 0.3 * g_unif();
            full[i + i * n] += w;
            full[j + j * n] += w;
            full[i + j * n] -= w;
            full[j + i * n] -= w;
        }
    }
    int *Ti = T->i, *Tj = T->j;
    double *V = T->x;
    size_t k = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i <= j; i++)
            if (full[i + j * n] != 0) Ti[k] = i, Tj[k] = j, V[k++] = scale * full[i + j * n];
    T->nnz = k;
    for (size_t q = 0; q < (size_t)n * n; q++) Kd[q] = scale * full[q];
    free(full);
    cholmod_sparse *K = cholmod_triplet_to_sparse(T, 0, &cm);
    cholmod_free_triplet(&T, &cm);
    return K;
}

/* dense SPD n x n: B B' + n I */
static void red_block(int n, double *Ad)
{
    double *B = malloc((size_t)n * n * sizeof *B);
    for (int q = 0; q < n * n; q++) B[q] = g_normal();
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, n, n, n, 1.0, B, n, B, n, 0.0, Ad, n);
    for (int i = 0; i < n; i++) Ad[i + i * n] += n;
    free(B);
}

/* dense m x N -> cholmod_sparse (stype 0) */
static cholmod_sparse *to_sparse(const double *Cd, int m, int N)
{
    cholmod_dense D = {.nrow = m, .ncol = N, .nzmax = (size_t)m * N, .d = m, .x = (void *)Cd,
                       .xtype = CHOLMOD_REAL, .dtype = CHOLMOD_DOUBLE};
    return cholmod_dense_to_sparse(&D, 1, &cm);
}

/* Moore-Penrose data of an m x n matrix: rank (s > 1e-10 s_1), U (m x p), s, VT (n x n) */
static int svd_full(const double *M, int m, int n, double *U, double *s, double *VT)
{
    int p = m < n ? m : n;
    if (p == 0) return 0;
    double *A = malloc((size_t)m * n * sizeof *A), *sb = malloc((size_t)p * sizeof *sb);
    memcpy(A, M, (size_t)m * n * sizeof *A);
    LAPACKE_dgesvd(LAPACK_COL_MAJOR, 'S', 'A', m, n, A, m, s, U, m, VT, n, sb);
    free(A);
    free(sb);
    int r = 0;
    while (r < p && s[r] > 1e-10 * s[0]) r++;
    return r;
}

/* Reference: the dependent rows drows (nd of them) get g projected on the
   range of C(drows, :) (least squares); then x = argmin 1/2 x'Ax - r'x on
   {C x = g~} by the null space of C (full SVD), lambda = pinv(C') (r - A x).
   Returns the rank of C(drows, :). */
static int reference(const double *Cd, int m, int N, const double *Ad, const double *r,
                     const double *g, const int *drows, int nd, double *x, double *lam, double *gt)
{
    memcpy(gt, g, (size_t)m * sizeof *gt);
    int kd = 0;
    if (nd > 0) {
        double *CD = malloc((size_t)nd * N * sizeof *CD), *U = malloc((size_t)nd * nd * sizeof *U);
        double *s = malloc((size_t)nd * sizeof *s), *VT = malloc((size_t)N * N * sizeof *VT);
        for (int d = 0; d < nd; d++)
            for (int j = 0; j < N; j++) CD[d + (size_t)j * nd] = Cd[drows[d] + (size_t)j * m];
        kd = svd_full(CD, nd, N, U, s, VT);
        for (int d = 0; d < nd; d++) {
            double v = 0;
            for (int t = 0; t < kd; t++) {
                double c = 0;
                for (int q = 0; q < nd; q++) c += U[q + t * nd] * g[drows[q]];
                v += U[d + t * nd] * c;
            }
            gt[drows[d]] = v;
        }
        free(CD); free(U); free(s); free(VT);
    }
    int p = m < N ? m : N;
    double *U = malloc(((size_t)m * p + 1) * sizeof *U), *s = malloc(((size_t)p + 1) * sizeof *s);
    double *VT = malloc((size_t)N * N * sizeof *VT);
    int rho = svd_full(Cd, m, N, U, s, VT);
    if (m == 0) {
        memset(VT, 0, (size_t)N * N * sizeof *VT);
        for (int i = 0; i < N; i++) VT[i + i * N] = 1;
    }
    /* xp = V_rho S^-1 U_rho' gt */
    memset(x, 0, (size_t)N * sizeof *x);
    for (int t = 0; t < rho; t++) {
        double c = 0;
        for (int i = 0; i < m; i++) c += U[i + (size_t)t * m] * gt[i];
        c /= s[t];
        for (int j = 0; j < N; j++) x[j] += VT[t + (size_t)j * N] * c;
    }
    int nz = N - rho;
    double *Z = malloc(((size_t)N * nz + 1) * sizeof *Z), *AZ = malloc(((size_t)N * nz + 1) * sizeof *AZ);
    double *H = malloc(((size_t)nz * nz + 1) * sizeof *H), *y = malloc(((size_t)nz + 1) * sizeof *y);
    double *res = malloc((size_t)N * sizeof *res);
    for (int c = 0; c < nz; c++)
        for (int j = 0; j < N; j++) Z[j + (size_t)c * N] = VT[rho + c + (size_t)j * N];
    memcpy(res, r, (size_t)N * sizeof *res);
    cblas_dgemv(CblasColMajor, CblasNoTrans, N, N, -1.0, Ad, N, x, 1, 1.0, res, 1);
    if (nz > 0) {
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, nz, N, 1.0, Ad, N, Z, N, 0.0, AZ, N);
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, nz, nz, N, 1.0, Z, N, AZ, N, 0.0, H, nz);
        cblas_dgemv(CblasColMajor, CblasTrans, N, nz, 1.0, Z, N, res, 1, 0.0, y, 1);
        LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', nz, 1, H, nz, y, nz);
        cblas_dgemv(CblasColMajor, CblasNoTrans, N, nz, 1.0, Z, N, y, 1, 1.0, x, 1);
    }
    memcpy(res, r, (size_t)N * sizeof *res);
    cblas_dgemv(CblasColMajor, CblasNoTrans, N, N, -1.0, Ad, N, x, 1, 1.0, res, 1);
    /* lam = U_rho S^-1 V_rho' res */
    memset(lam, 0, (size_t)m * sizeof *lam);
    for (int t = 0; t < rho; t++) {
        double c = 0;
        for (int j = 0; j < N; j++) c += VT[t + (size_t)j * N] * res[j];
        c /= s[t];
        for (int i = 0; i < m; i++) lam[i] += U[i + (size_t)t * m] * c;
    }
    free(U); free(s); free(VT); free(Z); free(AZ); free(H); free(y); free(res);
    return kd;
}

static double relerr(const double *a, const double *b, int n)
{
    double d = 0, nb = 0;
    for (int i = 0; i < n; i++) d += (a[i] - b[i]) * (a[i] - b[i]), nb += b[i] * b[i];
    return nb > 0 ? sqrt(d / nb) : sqrt(d);
}

static double vnorm(const double *a, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += a[i] * a[i];
    return sqrt(s);
}

/* the mixed system: FE blocks 0 (n 40), 1 (n 30); reduced 2 (n 6), 3 (n 5)
   rows: 8 FE0-FE1 pairs, 4 FE1-reduced2 rows (+1 | -phi), 6 rows over the
   reduced columns of rank 3 (duplicate, combination, scaled copy) */
enum { NB = 4, M_PAIR = 8, M_FR = 4, M_D = 6, MM = M_PAIR + M_FR + M_D };
static const int nbs[NB] = {40, 30, 6, 5};
typedef struct sys {
    int N, m;
    cholmod_sparse *A[NB];
    double *Ab[NB];          /* dense copies */
    double *Ad;              /* N x N blockdiag */
    double *Cd;              /* m x N */
    cholmod_sparse *C;
    double *r, *g;
    int drows[M_D];
    aug_sblock blk[NB];
} sys;

static void sys_dense_A(sys *S)
{
    int N = S->N, off = 0;
    memset(S->Ad, 0, (size_t)N * N * sizeof *S->Ad);
    for (int b = 0; b < NB; b++) {
        int n = nbs[b];
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) S->Ad[off + i + (size_t)(off + j) * N] = S->Ab[b][i + j * n];
        off += n;
    }
}

static void sys_make(sys *S)
{
    memset(S, 0, sizeof *S);
    int N = 0, off[NB];
    for (int b = 0; b < NB; b++) off[b] = N, N += nbs[b];
    S->N = N;
    S->m = MM;
    for (int b = 0; b < NB; b++) {
        S->Ab[b] = malloc((size_t)nbs[b] * nbs[b] * sizeof *S->Ab[b]);
        if (b < 2) S->A[b] = fe_block(nbs[b], S->Ab[b], 1.0);
        else red_block(nbs[b], S->Ab[b]);
        S->blk[b] = (aug_sblock){.n = nbs[b], .A = S->A[b], .Ad = b < 2 ? NULL : S->Ab[b],
                                 .version = 1};
    }
    S->Ad = malloc((size_t)N * N * sizeof *S->Ad);
    sys_dense_A(S);
    int m = MM;
    S->Cd = calloc((size_t)m * N, sizeof *S->Cd);
    int row = 0;
    for (int t = 0; t < M_PAIR; t++, row++) {
        S->Cd[row + (size_t)(off[0] + 3 + 4 * t) * m] = 1;
        S->Cd[row + (size_t)(off[1] + 2 + 3 * t) * m] = -1;
    }
    for (int t = 0; t < M_FR; t++, row++) {
        S->Cd[row + (size_t)(off[1] + 1 + 3 * t) * m] = 1;
        for (int j = 0; j < nbs[2]; j++) S->Cd[row + (size_t)(off[2] + j) * m] = -g_normal();
    }
    int d0 = row;
    for (int t = 0; t < 3; t++, row++)
        for (int j = off[2]; j < N; j++) S->Cd[row + (size_t)j * m] = g_normal();
    for (int j = off[2]; j < N; j++) {
        double *c = S->Cd + (size_t)j * m;
        c[row] = c[d0 + 1];                       /* duplicate */
        c[row + 1] = 2 * c[d0] - c[d0 + 2];       /* combination */
        c[row + 2] = 0.5 * c[d0 + 1];             /* scaled copy */
    }
    row += 3;
    for (int d = 0; d < M_D; d++) S->drows[d] = d0 + d;
    S->C = to_sparse(S->Cd, m, N);
    S->r = malloc((size_t)N * sizeof *S->r);
    S->g = malloc((size_t)m * sizeof *S->g);
    for (int j = 0; j < N; j++) S->r[j] = g_normal();
    for (int i = 0; i < m; i++) S->g[i] = 0.1 * g_normal();  /* inconsistent on D */
}

static void sys_free(sys *S)
{
    for (int b = 0; b < NB; b++) {
        cholmod_free_sparse(&S->A[b], &cm);
        free(S->Ab[b]);
    }
    cholmod_free_sparse(&S->C, &cm);
    free(S->Ad); free(S->Cd); free(S->r); free(S->g);
}

/* ||C x - g|| with the test's dense C */
static double gap_of(const sys *S, const double *x, const double *g)
{
    double *t = malloc((size_t)S->m * sizeof *t);
    memcpy(t, g, (size_t)S->m * sizeof *t);
    cblas_dgemv(CblasColMajor, CblasNoTrans, S->m, S->N, 1.0, S->Cd, S->m, x, 1, -1.0, t, 1);
    double v = vnorm(t, S->m);
    free(t);
    return v;
}

static void test_mixed(void)
{
    sys S;
    sys_make(&S);
    int N = S.N, m = S.m;
    double *xr = malloc(N * sizeof *xr), *lr = malloc(m * sizeof *lr), *gt = malloc(m * sizeof *gt);
    double *x = malloc(N * sizeof *x), *l = malloc(m * sizeof *l);
    int kd = reference(S.Cd, m, N, S.Ad, S.r, S.g, S.drows, M_D, xr, lr, gt);
    T_CHECK(kd == 3, "reference rank of D %d", kd);
    aug_saddle s;
    aug_err e;
    aug_saddle_stats st;
    T_CHECK(!aug_saddle_init(&s, &cm, &e), "init");
    T_CHECK(!aug_saddle_set(&s, NB, S.blk, S.C, 1, &e), "set: %s", e.msg);
    T_CHECK(!aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e), "schur: %s", e.msg);
    T_CHECK(st.rank == 3 && st.mc == M_PAIR + M_FR + 3, "rank %d mc %d", st.rank, st.mc);
    T_CHECK(relerr(x, xr, N) < 1e-10, "schur x vs reference %g", relerr(x, xr, N));
    T_CHECK(relerr(l, lr, m) < 1e-10, "schur lambda vs reference %g", relerr(l, lr, m));
    T_CHECK(st.relres < 1e-13, "schur relres %g", st.relres);
    double gap = gap_of(&S, x, S.g);
    T_CHECK(gap > 1e-3 && t_reldiff(st.gap, gap) < 1e-10, "gap %g vs %g", st.gap, gap);
    T_CHECK(st.nfactor == NB && st.ncontrib == NB, "factorisations %lld contributions %lld",
            (long long)st.nfactor, (long long)st.ncontrib);
    /* the least-squares part: normal equations C_D'(C_D x - g_D) = 0 */
    double worst_ne = 0, cn = 0;
    for (int j = 0; j < N; j++) {
        double v = 0;
        for (int d = 0; d < M_D; d++) {
            int i = S.drows[d];
            double ri = -S.g[i];
            for (int t = 0; t < N; t++) ri += S.Cd[i + (size_t)t * m] * x[t];
            v += S.Cd[i + (size_t)j * m] * ri;
            cn = fmax(cn, fabs(S.Cd[i + (size_t)j * m]));
        }
        worst_ne = fmax(worst_ne, fabs(v));
    }
    T_CHECK(worst_ne < 1e-11 * cn * cn * (1 + vnorm(x, N)), "normal equations %g", worst_ne);
    /* ppcg */
    int rc = aug_saddle_ppcg(&s, S.r, S.g, x, l, 1e-12, 1000, 0, &st, &e);
    T_CHECK(!rc && st.converged, "ppcg: %s", e.msg);
    T_CHECK(st.relres <= 1e-12 && st.iters > 0, "ppcg relres %g iters %d", st.relres, st.iters);
    T_CHECK(relerr(x, xr, N) < 1e-8, "ppcg x vs reference %g", relerr(x, xr, N));
    T_CHECK(relerr(l, lr, m) < 1e-8, "ppcg lambda vs reference %g", relerr(l, lr, m));
    printf("  mixed: N %d m %d rank %d ppcg %d iterations, relres %.2e, |x-xref| %.2e\n", N, m,
           st.rank, st.iters, st.relres, relerr(x, xr, N));
    /* iterates are feasible for the compressed constraints (C x = g~) */
    double worst = 0;
    for (int it = 0; it <= 12; it++) {
        rc = aug_saddle_ppcg(&s, S.r, S.g, x, l, 1e-14, it, 0, &st, &e);
        T_CHECK(rc == AUG_ENOCONV && !st.converged && st.iters == it, "maxit %d: rc %d conv %d",
                it, rc, st.converged);
        worst = fmax(worst, gap_of(&S, x, gt) / (vnorm(gt, m) + vnorm(x, N)));
    }
    T_CHECK(worst < 1e-12, "iterates violate the constraints by %g", worst);
    /* warm start from the solution: at once */
    aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e);
    rc = aug_saddle_ppcg(&s, S.r, S.g, x, l, 1e-12, 1000, 1, &st, &e);
    T_CHECK(!rc && st.iters <= 1, "warm start: rc %d, %d iterations", rc, st.iters);
    aug_saddle_free(&s);
    sys_free(&S);
    free(xr); free(lr); free(gt); free(x); free(l);
}

/* init, set and one Schur solve of the mixed system into x, l */
static void first_solve(aug_saddle *s, const sys *S, double *x, double *l, aug_saddle_stats *st)
{
    aug_err e;
    aug_saddle_init(s, &cm, &e);
    aug_saddle_set(s, NB, S->blk, S->C, 1, &e);
    aug_saddle_schur(s, S->r, S->g, x, l, st, &e);
}

/* a block's new version refactors that block only; contributions of FE
   blocks off the dependent rows survive a C re-analysis */
static void test_versions(void)
{
    sys S;
    sys_make(&S);
    int N = S.N, m = S.m;
    double *xr = malloc(N * sizeof *xr), *lr = malloc(m * sizeof *lr), *gt = malloc(m * sizeof *gt);
    double *x = malloc(N * sizeof *x), *x0 = malloc(N * sizeof *x0), *l = malloc(m * sizeof *l);
    aug_saddle s;
    aug_err e;
    aug_saddle_stats st;
    first_solve(&s, &S, x0, l, &st);
    int64_t f0 = st.nfactor, c0 = st.ncontrib;
    /* nothing changed */
    T_CHECK(!aug_saddle_set(&s, NB, S.blk, S.C, 0, &e), "set: %s", e.msg);
    aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e);
    T_CHECK(st.nfactor == f0 && st.ncontrib == c0, "unchanged set redid %lld factors %lld parts",
            (long long)(st.nfactor - f0), (long long)(st.ncontrib - c0));
    T_CHECK(relerr(x, x0, N) == 0, "unchanged set changed x");
    /* C flagged changed (same values): FE parts kept, reduced ones redone */
    aug_saddle_set(&s, NB, S.blk, S.C, 1, &e);
    aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e);
    T_CHECK(st.nfactor == f0 && st.ncontrib == c0 + 2, "C re-analysis: %lld factors %lld parts",
            (long long)(st.nfactor - f0), (long long)(st.ncontrib - c0));
    T_CHECK(relerr(x, x0, N) < 1e-14, "C re-analysis changed x by %g", relerr(x, x0, N));
    /* C with a zero row on top (every row renumbered, the same entries):
       FE parts kept, the same x, lambda shifted */
    {
        cholmod_sparse *C2 = NULL;
        double *Cd2 = calloc((size_t)(m + 1) * N, sizeof *Cd2), *g2 = malloc((m + 1) * sizeof *g2);
        double *l2 = malloc((m + 1) * sizeof *l2);
        for (int j = 0; j < N; j++)
            for (int i = 0; i < m; i++) Cd2[i + 1 + (size_t)j * (m + 1)] = S.Cd[i + (size_t)j * m];
        g2[0] = 1;
        memcpy(g2 + 1, S.g, m * sizeof *g2);
        C2 = to_sparse(Cd2, m + 1, N);
        T_CHECK(!aug_saddle_set(&s, NB, S.blk, C2, 1, &e), "set: %s", e.msg);
        aug_saddle_schur(&s, S.r, g2, x, l2, &st, &e);
        T_CHECK(st.nfactor == f0 && st.ncontrib == c0 + 4, "renumbered C: %lld factors %lld parts",
                (long long)(st.nfactor - f0), (long long)(st.ncontrib - c0 - 2));
        T_CHECK(relerr(x, x0, N) < 1e-13 && relerr(l2 + 1, l, m) < 1e-12 && fabs(l2[0]) < 1e-14,
                "renumbered C: x %g lambda %g", relerr(x, x0, N), relerr(l2 + 1, l, m));
        T_CHECK(fabs(st.gap - hypot(1, gap_of(&S, x, S.g))) < 1e-12, "gap with the zero row %g",
                st.gap);
        aug_saddle_set(&s, NB, S.blk, S.C, 1, &e);
        aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e);
        T_CHECK(st.nfactor == f0 && st.ncontrib == c0 + 6 && relerr(x, x0, N) < 1e-13,
                "back to C: %lld parts, x %g", (long long)(st.ncontrib - c0), relerr(x, x0, N));
        c0 += 4;
        cholmod_free_sparse(&C2, &cm);
        free(Cd2); free(g2); free(l2);
    }
    /* block 0 gets new values and version */
    cholmod_free_sparse(&S.A[0], &cm);
    S.A[0] = fe_block(nbs[0], S.Ab[0], 3.0);
    S.blk[0].A = S.A[0];
    S.blk[0].version = 2;
    sys_dense_A(&S);
    T_CHECK(!aug_saddle_set(&s, NB, S.blk, S.C, 0, &e), "set: %s", e.msg);
    aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e);
    T_CHECK(st.nfactor == f0 + 1 && st.ncontrib == c0 + 2 + 3,
            "new version of block 0: %lld factors %lld parts", (long long)(st.nfactor - f0),
            (long long)(st.ncontrib - c0 - 2));
    reference(S.Cd, m, N, S.Ad, S.r, S.g, S.drows, M_D, xr, lr, gt);
    T_CHECK(relerr(x, xr, N) < 1e-10 && relerr(x, x0, N) > 1e-3, "after the change: %g (moved %g)",
            relerr(x, xr, N), relerr(x, x0, N));
    T_CHECK(relerr(l, lr, m) < 1e-10, "lambda after the change: %g", relerr(l, lr, m));
    aug_saddle_ppcg(&s, S.r, S.g, x, l, 1e-12, 1000, 0, &st, &e);
    T_CHECK(st.converged && relerr(x, xr, N) < 1e-8, "ppcg after the change: %g", relerr(x, xr, N));
    aug_saddle_free(&s);
    sys_free(&S);
    free(xr); free(lr); free(gt); free(x); free(x0); free(l);
}

/* no constraints: blockwise solves (C NULL and C with 0 rows) */
static void test_m0(void)
{
    sys S;
    sys_make(&S);
    int N = S.N;
    double *xr = malloc(N * sizeof *xr), *x = malloc(N * sizeof *x), *Ad = malloc((size_t)N * N * sizeof *Ad);
    memcpy(xr, S.r, N * sizeof *xr);
    memcpy(Ad, S.Ad, (size_t)N * N * sizeof *Ad);
    LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', N, 1, Ad, N, xr, N);
    cholmod_sparse *C0 = cholmod_allocate_sparse(0, N, 0, 1, 1, 0, CHOLMOD_REAL, &cm);
    aug_saddle s;
    aug_err e;
    aug_saddle_stats st;
    aug_saddle_init(&s, &cm, &e);
    for (int pass = 0; pass < 2; pass++) {
        T_CHECK(!aug_saddle_set(&s, NB, S.blk, pass ? C0 : NULL, 1, &e), "set: %s", e.msg);
        T_CHECK(!aug_saddle_schur(&s, S.r, NULL, x, NULL, &st, &e), "schur: %s", e.msg);
        T_CHECK(relerr(x, xr, N) < 1e-12 && st.mc == 0 && st.gap == 0, "m = 0 schur: %g",
                relerr(x, xr, N));
        T_CHECK(!aug_saddle_ppcg(&s, S.r, NULL, x, NULL, 1e-12, 1000, 0, &st, &e), "ppcg: %s", e.msg);
        T_CHECK(relerr(x, xr, N) < 1e-9, "m = 0 ppcg: %g", relerr(x, xr, N));
    }
    aug_saddle_free(&s);
    cholmod_free_sparse(&C0, &cm);
    sys_free(&S);
    free(xr); free(x); free(Ad);
}

/* 2-D spring network on an nx x ny grid with a positive diagonal, split at
   column p into two FE blocks sharing that column (copies coupled by rows
   x0[i] - x1[i'] = 0): the coupled solution is the shared-DOF solution */
static void shared_dof(int NX, int NY, int P)
{
    int ng = NX * NY;
    double *K = calloc((size_t)ng * ng, sizeof *K), *f = malloc(ng * sizeof *f);
    int n0 = (P + 1) * NY, n1 = (NX - P) * NY, N = n0 + n1, m = NY;
    double *K0 = calloc((size_t)n0 * n0, sizeof *K0), *K1 = calloc((size_t)n1 * n1, sizeof *K1);
    /* local numbering: block 0 node (i, j) -> i*NY + j (i <= P); block 1 -> (i-P)*NY + j */
#define ADDK(B, nb, a, b, v) ((B)[(a) + (size_t)(b) * (nb)] += (v))
    for (int i = 0; i < NX; i++)
        for (int j = 0; j < NY; j++) {
            int a = i * NY + j;
            double dg = 0.05 + 0.1 * g_unif();
            ADDK(K, ng, a, a, dg);
            if (i < P) ADDK(K0, n0, a, a, dg);
            else if (i > P) ADDK(K1, n1, a - P * NY, a - P * NY, dg);
            else {
                ADDK(K0, n0, a, a, 0.3 * dg);
                ADDK(K1, n1, a - P * NY, a - P * NY, 0.7 * dg);
            }
            int nbr[2][2] = {{i + 1, j}, {i, j + 1}};
            for (int t = 0; t < 2; t++) {
                int i2 = nbr[t][0], j2 = nbr[t][1];
                if (i2 >= NX || j2 >= NY) continue;
                int b = i2 * NY + j2;
                double w = 0.5 + g_unif();
                ADDK(K, ng, a, a, w); ADDK(K, ng, b, b, w); ADDK(K, ng, a, b, -w); ADDK(K, ng, b, a, -w);
                /* the spring belongs to block 0 when both ends are in columns <= P and
                   it is not in column P, or it is vertical in column P */
                int in0 = i2 <= P && (i < P || t == 1);
                double *B = in0 ? K0 : K1;
                int nb = in0 ? n0 : n1, sh = in0 ? 0 : P * NY;
                ADDK(B, nb, a - sh, a - sh, w); ADDK(B, nb, b - sh, b - sh, w);
                ADDK(B, nb, a - sh, b - sh, -w); ADDK(B, nb, b - sh, a - sh, -w);
            }
        }
#undef ADDK
    double *r = calloc(N, sizeof *r);
    for (int a = 0; a < ng; a++) {
        f[a] = g_normal();
        int i = a / NY;
        if (i < P) r[a] = f[a];
        else if (i > P) r[n0 + a - P * NY] = f[a];
        else {
            r[a] = 0.25 * f[a];
            r[n0 + a - P * NY] = 0.75 * f[a];
        }
    }
    LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', ng, 1, K, ng, f, ng);
    double *Cd = calloc((size_t)m * N, sizeof *Cd), *g = calloc(m, sizeof *g);
    for (int j = 0; j < NY; j++) {
        Cd[j + (size_t)(P * NY + j) * m] = 1;
        Cd[j + (size_t)(n0 + j) * m] = -1;
    }
    cholmod_sparse *C = to_sparse(Cd, m, N);
    cholmod_dense D0 = {.nrow = n0, .ncol = n0, .nzmax = (size_t)n0 * n0, .d = n0, .x = K0,
                        .xtype = CHOLMOD_REAL, .dtype = CHOLMOD_DOUBLE};
    cholmod_dense D1 = {.nrow = n1, .ncol = n1, .nzmax = (size_t)n1 * n1, .d = n1, .x = K1,
                        .xtype = CHOLMOD_REAL, .dtype = CHOLMOD_DOUBLE};
    cholmod_sparse *A0 = cholmod_dense_to_sparse(&D0, 1, &cm), *A1 = cholmod_dense_to_sparse(&D1, 1, &cm);
    cholmod_sparse *U0 = cholmod_copy(A0, 1, 1, &cm), *U1 = cholmod_copy(A1, 1, 1, &cm);
    aug_sblock blk[2] = {{.n = n0, .A = U0, .version = 1}, {.n = n1, .A = U1, .version = 1}};
    double *x = malloc(N * sizeof *x), *l = malloc(m * sizeof *l), *u = malloc(ng * sizeof *u);
    aug_saddle s;
    aug_err e;
    aug_saddle_stats st;
    aug_saddle_init(&s, &cm, &e);
    T_CHECK(!aug_saddle_set(&s, 2, blk, C, 1, &e), "set: %s", e.msg);
    for (int pass = 0; pass < 2; pass++) {
        int rc = pass ? aug_saddle_ppcg(&s, r, g, x, l, 1e-14, 1000, 0, &st, &e)
                      : aug_saddle_schur(&s, r, g, x, l, &st, &e);
        T_CHECK(!rc, "%s: %s", pass ? "ppcg" : "schur", e.msg);
        for (int a = 0; a < ng; a++) u[a] = a / NY <= P ? x[a] : x[n0 + a - P * NY];
        double d01 = 0;
        for (int j = 0; j < NY; j++) d01 = fmax(d01, fabs(x[P * NY + j] - x[n0 + j]));
        double err = relerr(u, f, ng);
        T_CHECK(err < (pass ? 1e-11 : 1e-12) && d01 < 1e-13 * vnorm(f, ng),
                "%s vs shared-DOF FE: %g (copies differ by %g)", pass ? "ppcg" : "schur", err, d01);
        T_CHECK(st.rank == 0 && st.mc == m, "rank %d mc %d", st.rank, st.mc);
    }
    aug_saddle_free(&s);
    cholmod_free_sparse(&A0, &cm); cholmod_free_sparse(&A1, &cm);
    cholmod_free_sparse(&U0, &cm); cholmod_free_sparse(&U1, &cm);
    cholmod_free_sparse(&C, &cm);
    free(K); free(f); free(K0); free(K1); free(r); free(Cd); free(g); free(x); free(l); free(u);
}

/* 6 interface rows, and 70 (more than one chunk of right-hand sides) */
static void test_shared_dof(void)
{
    shared_dof(9, 6, 4);
    shared_dof(6, 70, 2);
}

static void test_errors(void)
{
    sys S;
    sys_make(&S);
    int N = S.N, m = S.m;
    double *x = malloc(N * sizeof *x), *l = malloc(m * sizeof *l);
    aug_saddle s;
    aug_err e;
    aug_saddle_stats st;
    aug_saddle_init(&s, &cm, &e);
    /* C with the wrong column count */
    cholmod_sparse *Cbad = cholmod_allocate_sparse(m, N + 1, 0, 1, 1, 0, CHOLMOD_REAL, &cm);
    T_CHECK(aug_saddle_set(&s, NB, S.blk, Cbad, 1, &e) == AUG_EUSAGE && !strcmp(e.type, "MODE"),
            "size mismatch: %d %s", e.code, e.msg);
    aug_sblock b2[NB];
    memcpy(b2, S.blk, sizeof b2);
    b2[1].n = 29;
    T_CHECK(aug_saddle_set(&s, NB, b2, S.C, 1, &e) == AUG_EUSAGE, "block size mismatch: %d", e.code);
    memcpy(b2, S.blk, sizeof b2);
    b2[2].A = S.A[0];
    T_CHECK(aug_saddle_set(&s, NB, b2, S.C, 1, &e) == AUG_EUSAGE, "both A and Ad: %d", e.code);
    T_CHECK(aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e) == AUG_EUSAGE, "solve without a system");
    /* a reduced block with a positive diagonal that is not SPD */
    double *bad = malloc(36 * sizeof *bad);
    for (int q = 0; q < 36; q++) bad[q] = 1;
    memcpy(b2, S.blk, sizeof b2);
    b2[2].Ad = bad;
    T_CHECK(!aug_saddle_set(&s, NB, b2, S.C, 1, &e), "set: %s", e.msg);
    T_CHECK(aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e) == AUG_ESINGULAR, "indefinite reduced: %d %s",
            e.code, e.msg);
    /* an FE block with a negative diagonal: at set */
    double *Ax = S.A[1]->x;
    const int *Ap = S.A[1]->p;
    double save = Ax[Ap[1] - 1];
    Ax[Ap[1] - 1] = -1;
    S.blk[1].version = 7;
    T_CHECK(aug_saddle_set(&s, NB, S.blk, S.C, 1, &e) == AUG_ESINGULAR, "negative diagonal: %d", e.code);
    T_CHECK(aug_saddle_ppcg(&s, S.r, S.g, x, l, 1e-12, 10, 0, &st, &e) == AUG_EUSAGE,
            "solve after a failed set: %d", e.code);
    /* an FE block with a positive diagonal that is not SPD: at the factorisation */
    Ax[Ap[1] - 1] = 1e-3;
    S.blk[1].version = 8;
    T_CHECK(!aug_saddle_set(&s, NB, S.blk, S.C, 1, &e), "set: %s", e.msg);
    T_CHECK(aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e) == AUG_ESINGULAR && strstr(e.msg, "block 1"),
            "indefinite FE block: %d %s", e.code, e.msg);
    Ax[Ap[1] - 1] = save;
    S.blk[1].version = 9;
    T_CHECK(!aug_saddle_set(&s, NB, S.blk, S.C, 1, &e), "set: %s", e.msg);
    T_CHECK(!aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e), "recovered: %s", e.msg);
    T_CHECK(aug_saddle_ppcg(&s, S.r, S.g, x, l, 0, 10, 0, &st, &e) == AUG_EUSAGE, "tol 0");
    aug_saddle_free(&s);
    cholmod_free_sparse(&Cbad, &cm);
    sys_free(&S);
    free(x); free(l); free(bad);
}

/* every allocation of the library failing in turn: AUG_ENOMEM or success,
   never a crash or a leak (ASan build), and a later full run still exact */
static void test_nomem(void)
{
    sys S;
    sys_make(&S);
    int N = S.N, m = S.m;
    double *x = malloc(N * sizeof *x), *l = malloc(m * sizeof *l), *x0 = malloc(N * sizeof *x0);
    aug_saddle s;
    aug_err e;
    aug_saddle_stats st;
    first_solve(&s, &S, x0, l, &st);
    aug_saddle_free(&s);
    int ok = 0;
    for (long k = 0; k < 2000 && !ok; k++) {
        aug_saddle_init(&s, &cm, &e);
        aug_fail_after(k);
        int rc = aug_saddle_set(&s, NB, S.blk, S.C, 1, &e);
        if (!rc) rc = aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e);
        if (!rc) rc = aug_saddle_ppcg(&s, S.r, S.g, x, l, 1e-12, 1000, 0, &st, &e);
        aug_fail_after(-1);
        T_CHECK(!rc || rc == AUG_ENOMEM, "failure %ld: %d %s", k, rc, e.msg);
        ok = !rc;
        /* the same state recovers */
        rc = aug_saddle_set(&s, NB, S.blk, S.C, 1, &e);
        if (!rc) rc = aug_saddle_schur(&s, S.r, S.g, x, l, &st, &e);
        T_CHECK(!rc && relerr(x, x0, N) < 1e-12, "after failure %ld: %d %s", k, rc, e.msg);
        aug_saddle_free(&s);
    }
    T_CHECK(ok, "never succeeded");
    sys_free(&S);
    free(x); free(l); free(x0);
}

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(test_mixed);
    T_RUN(test_versions);
    T_RUN(test_m0);
    T_RUN(test_shared_dof);
    T_RUN(test_errors);
    T_RUN(test_nomem);
    cholmod_finish(&cm);
    T_EXIT();
}
