/* The reduced implicit step (paper 004 eq. 2 with aug_dyn.h's integrators):
   W = I reproduces a dense full step, a random orthonormal W the dense
   Galerkin system, both integrators, with Rayleigh damping. */
#include "t.h"
#include "modal_gen.h"

/* x = A^-1 b for dense A (n x n) by LAPACK's LU (dgesv), A, b copied */
static void dense_solve(const double *A, const double *b, double *x, int n)
{
    double *F = malloc((size_t)n * n * sizeof *F);
    int *piv = malloc(n * sizeof *piv);
    memcpy(F, A, (size_t)n * n * sizeof *F);
    memcpy(x, b, n * sizeof *x);
    LAPACKE_dgesv(LAPACK_COL_MAJOR, n, 1, F, n, piv, x, n);
    free(F), free(piv);
}

/* random SPD n x n: B B' / n + shift I */
static void spd(double *A, int n, double shift)
{
    double *B = malloc((size_t)n * n * sizeof *B);
    for (int i = 0; i < n * n; i++) B[i] = g_normal();
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double v = i == j ? shift : 0;
            for (int t = 0; t < n; t++) v += B[i + t * n] * B[j + t * n] / n;
            A[i + j * n] = v;
        }
    free(B);
}

/* y = P' A P (P n x r) */
static void galerkin_dense(const double *A, const double *P, int n, int r, double *y)
{
    for (int i = 0; i < r; i++)
        for (int j = 0; j < r; j++) {
            double v = 0;
            for (int a = 0; a < n; a++)
                for (int b = 0; b < n; b++) v += P[a + i * n] * A[a + b * n] * P[b + j * n];
            y[i + j * r] = v;
        }
}

static double worst_id, worst_w;

/* 5 steps; reduced (W = P) vs dense full integration in the subspace:
   (P'AP) dq = P'(h M P q' + gamma h^2 (f - K P q)) with the same rules */
static void run(int integrator, int n, int r, int identity)
{
    aug_dynp p;
    aug_err e;
    T_CHECK(aug_dynp_set(&p, integrator, 1, 0.01, 0.3, 0.002) == 0, "dynp");
    double *K = malloc((size_t)n * n * sizeof *K), *M = malloc((size_t)n * n * sizeof *M);
    spd(K, n, 50), spd(M, n, 1);
    double *P = calloc((size_t)n * r, sizeof *P);
    if (identity)
        for (int i = 0; i < n; i++) P[i + i * n] = 1;
    else {
        double *X = g_snapshots(n, r, 0, 0), sv[64];
        g_svd(X, n, r, sv, P);
        free(X);
    }
    aug_basis W = {n, r, r, P, NULL, 0}; /* identity: r = n and P = I */
    double *Kr = malloc((size_t)r * r * sizeof *Kr), *Mr = malloc((size_t)r * r * sizeof *Mr);
    galerkin_dense(K, P, n, r, Kr), galerkin_dense(M, P, n, r, Mr);
    /* full (W = I) or dense-projected oracle state in full coordinates */
    double *f = malloc(n * sizeof *f), *fr = malloc(r * sizeof *fr), *q = calloc(r, sizeof *q),
           *qd = calloc(r, sizeof *qd), *uo = calloc(n, sizeof *uo), *vo = calloc(n, sizeof *vo),
           *u = malloc(n * sizeof *u), *work = malloc((n + r) * sizeof *work);
    double *A = malloc((size_t)n * n * sizeof *A), *b = malloc(n * sizeof *b), *du = malloc(n * sizeof *du);
    double h = p.h, g2 = aug_dynp_gamma(&p) * h * h;
    for (int i = 0; i < n; i++) f[i] = g_normal();
    for (int i = 0; i < n * n; i++) A[i] = p.cM * M[i] + p.cK * K[i];
    for (int step = 0; step < 5; step++) {
        aug_basis_project(&W, f, fr, work);
        T_CHECK(aug_reduced_step(&p, r, Kr, Mr, fr, q, qd, &e) == 0, "step: %s", e.msg);
        aug_basis_expand(&W, q, u, work);
        if (identity) {
            for (int i = 0; i < n; i++) {
                double v = g2 * f[i];
                for (int j = 0; j < n; j++) v += h * M[i + j * n] * vo[j] - g2 * K[i + j * n] * uo[j];
                b[i] = v;
            }
            dense_solve(A, b, du, n);
            for (int i = 0; i < n; i++) {
                uo[i] += du[i];
                vo[i] = integrator == AUG_INT_EULER ? du[i] / h : 2 * du[i] / h - vo[i];
            }
        } else {
            /* oracle in the subspace with full matrices: b = P'(h M v + g2 (f - K u)) */
            double *t = malloc(n * sizeof *t), *br = malloc(r * sizeof *br), *Ar = malloc((size_t)r * r * sizeof *Ar),
                   *dq = malloc(r * sizeof *dq);
            for (int i = 0; i < n; i++) {
                double v = g2 * f[i];
                for (int j = 0; j < n; j++) v += h * M[i + j * n] * vo[j] - g2 * K[i + j * n] * uo[j];
                t[i] = v;
            }
            for (int i = 0; i < r; i++) {
                br[i] = 0;
                for (int a = 0; a < n; a++) br[i] += P[a + i * n] * t[a];
            }
            galerkin_dense(A, P, n, r, Ar);
            dense_solve(Ar, br, dq, r);
            for (int a = 0; a < n; a++) {
                double d = 0;
                for (int i = 0; i < r; i++) d += P[a + i * n] * dq[i];
                uo[a] += d;
                vo[a] = integrator == AUG_INT_EULER ? d / h : 2 * d / h - vo[a];
            }
            free(t), free(br), free(Ar), free(dq);
        }
        double dmax = 0, umax = 0;
        for (int i = 0; i < n; i++) dmax = fmax(dmax, fabs(u[i] - uo[i])), umax = fmax(umax, fabs(uo[i]));
        double rel = dmax / umax;
        if (identity && rel > worst_id) worst_id = rel;
        if (!identity && rel > worst_w) worst_w = rel;
        T_CHECK(rel <= 1e-12, "%s n %d r %d step %d: rel %.2e", aug_integrator_name(integrator), n, r, step, rel);
    }
    free(K), free(M), free(P), free(Kr), free(Mr), free(f), free(fr), free(q), free(qd), free(uo), free(vo), free(u),
        free(work), free(A), free(b), free(du);
}

static void identity_euler(void) { run(AUG_INT_EULER, 40, 40, 1); }
static void identity_newmark(void) { run(AUG_INT_NEWMARK, 40, 40, 1); }
static void subspace_euler(void) { run(AUG_INT_EULER, 60, 7, 0); }
static void subspace_newmark(void) { run(AUG_INT_NEWMARK, 60, 7, 0); }

static void not_definite(void)
{
    aug_dynp p;
    aug_err e;
    aug_dynp_set(&p, AUG_INT_EULER, 1, 0.01, 0, 0);
    double K[4] = {1, 0, 0, -1e9}, M[4] = {1, 0, 0, 1}, f[2] = {0, 0}, q[2] = {0, 0}, qd[2] = {0, 0};
    T_CHECK(aug_reduced_step(&p, 2, K, M, f, q, qd, &e) == AUG_ESINGULAR, "indefinite A_r accepted");
    T_CHECK(aug_reduced_step(&p, 0, K, M, f, q, qd, &e) == AUG_EUSAGE, "rank 0 accepted");
}

int main(void)
{
    T_RUN(identity_euler);
    T_RUN(identity_newmark);
    T_RUN(subspace_euler);
    T_RUN(subspace_newmark);
    T_RUN(not_definite);
    printf("measured: W = I vs full dense rel %.2e, W random vs dense Galerkin rel %.2e\n", worst_id, worst_w);
    T_EXIT();
}
