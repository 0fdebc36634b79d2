/* Galerkin projections kept along the incremental SVD (paper 004 eq. 3):
   Up' G Up after every add (growth, rotation, truncation, compaction)
   against U' K U from scratch with the explicit basis and a dense K. */
#include "t.h"
#include "modal_gen.h"
#include "aug_fem.h"

static cholmod_common cm;

/* sparse symmetric K (upper stored) and its dense copy: a 1-D Laplacian
   plus random symmetric couplings, made diagonally dominant */
static cholmod_sparse *sparse_spd(int64_t n, double *Kd)
{
    cholmod_triplet *T = cholmod_allocate_triplet(n, n, 6 * n, 1, CHOLMOD_REAL, &cm);
    memset(Kd, 0, (size_t)n * n * sizeof *Kd);
    int *Ti = T->i, *Tj = T->j;
    double *V = T->x;
    size_t k = 0;
    for (int64_t i = 0; i < n; i++) {
        int64_t js[3] = {i, i + 1, (int64_t)(g_unif() * n)};
        for (int t = 0; t < 3; t++) {
            int64_t j = js[t];
            if (j >= n || (t == 2 && j <= i + 1)) continue;
            double v = t == 0 ? 8 + g_unif() : -1 + 0.5 * g_normal();
            Ti[k] = (int)i, Tj[k] = (int)j, V[k] = v, k++;
            Kd[i + j * n] += v;
            if (j != i) Kd[j + i * n] += v;
        }
    }
    T->nnz = k;
    cholmod_sparse *K = cholmod_triplet_to_sparse(T, 0, &cm);
    cholmod_free_triplet(&T, &cm);
    return K;
}

static double worst;

/* Kr (r x r) vs U' Kd U with U explicit */
static void compare(const aug_isvd *s, const double *Kd, const double *Kr, int add)
{
    int64_t n = s->n;
    int r = s->r;
    double *U = malloc((size_t)n * r * sizeof *U), *KU = calloc((size_t)n * r, sizeof *KU);
    aug_isvd_basis(s, U);
    for (int j = 0; j < r; j++)
        for (int64_t b = 0; b < n; b++)
            for (int64_t a = 0; a < n; a++) KU[a + j * n] += Kd[a + b * n] * U[b + j * n];
    double dmax = 0, rmax = 0;
    for (int i = 0; i < r; i++)
        for (int j = 0; j < r; j++) {
            double v = 0;
            for (int64_t a = 0; a < n; a++) v += U[a + i * n] * KU[a + j * n];
            dmax = fmax(dmax, fabs(Kr[i + j * r] - v));
            rmax = fmax(rmax, fabs(v));
        }
    if (dmax / rmax > worst) worst = dmax / rmax;
    T_CHECK(dmax <= 1e-12 * rmax, "add %d: max |Kr - U'KU| %.2e of %.2e", add, dmax, rmax);
    free(U), free(KU);
}

/* n = 150; rank cap 10, qcap 12 (compactions), rtol 1e-3, low-rank + noise
   snapshots then random ones (rank capped), M = K here is enough: the
   projection is linear in the matrix */
static void kept_up_to_date(void)
{
    int64_t n = 150;
    int m = 45;
    double *Kd = malloc((size_t)n * n * sizeof *Kd);
    cholmod_sparse *K = sparse_spd(n, Kd);
    double *X = g_snapshots(n, m, 4, 1e-5);
    for (size_t i = (size_t)n * 20; i < (size_t)n * m; i++) X[i] = g_normal();
    aug_isvd s;
    aug_galerkin g;
    aug_err e;
    aug_isvd_init(&s, n, 10, 12, 1e-3, &e);
    T_CHECK(aug_galerkin_init(&g, &s, K, &cm, &e) == 0, "init: %s", e.msg);
    double *Kr = malloc(11 * 11 * sizeof *Kr);
    int ncompact = 0, ngrew = 0;
    for (int j = 0; j < m; j++) {
        T_CHECK(aug_isvd_add(&s, X + (size_t)j * n, &e) == 0, "add: %s", e.msg);
        ncompact += s.compacted, ngrew += s.grew;
        T_CHECK(aug_galerkin_sync(&g, &s, K, &cm, &e) == 0, "sync %d: %s", j, e.msg);
        aug_galerkin_reduced(&g, &s, Kr);
        compare(&s, Kd, Kr, j);
        if (j == 30) {
            aug_isvd_compact(&s, &e);
            T_CHECK(aug_galerkin_sync(&g, &s, K, &cm, &e) == 0, "sync after compact: %s", e.msg);
            aug_galerkin_reduced(&g, &s, Kr);
            compare(&s, Kd, Kr, j);
        }
    }
    T_CHECK(ncompact >= 5 && ngrew >= 20 && s.r == 10, "compactions %d, growths %d, rank %d", ncompact, ngrew, s.r);
    /* a Galerkin state built from the current basis agrees too */
    aug_galerkin g2;
    T_CHECK(aug_galerkin_init(&g2, &s, K, &cm, &e) == 0, "init 2: %s", e.msg);
    aug_galerkin_reduced(&g2, &s, Kr);
    compare(&s, Kd, Kr, -1);
    /* a skipped sync is refused, not silently wrong */
    aug_isvd_add(&s, X, &e);
    aug_isvd_add(&s, X + n, &e);
    int rc = aug_galerkin_sync(&g2, &s, K, &cm, &e);
    T_CHECK(rc == AUG_EUSAGE || (s.grew == 0 && s.compacted == 0), "skipped sync accepted");
    aug_galerkin_free(&g), aug_galerkin_free(&g2), aug_isvd_free(&s);
    cholmod_free_sparse(&K, &cm);
    free(Kd), free(X), free(Kr);
}

/* W = I set directly (aug_isvd_identity, aug_galerkin_identity: O(n^2))
   equals the route of n unit snapshots and a Galerkin state grown column by
   column: the same basis I, K_r = K; compaction changes nothing; a later
   snapshot (inside the span) keeps the rank and the projection in step */
static void identity_direct(void)
{
    int64_t n = 60;
    double *Kd = malloc((size_t)n * n * sizeof *Kd);
    cholmod_sparse *K = sparse_spd(n, Kd);
    aug_isvd s, t;
    aug_galerkin g, g2, gt;
    aug_err e;
    T_CHECK(aug_isvd_identity(&s, n, &e) == 0, "identity: %s", e.msg);
    T_CHECK(aug_galerkin_identity(&g, &s, K, &e) == 0, "galerkin identity: %s", e.msg);
    T_CHECK(aug_galerkin_init(&g2, &s, K, &cm, &e) == 0, "galerkin init: %s", e.msg);
    aug_isvd_init(&t, n, (int)n, 0, 0, &e);
    aug_galerkin_init(&gt, &t, K, &cm, &e);
    double *x = calloc((size_t)n, sizeof *x);
    for (int64_t i = 0; i < n; i++) {
        memset(x, 0, (size_t)n * sizeof *x);
        x[i] = 1;
        T_CHECK(aug_isvd_add(&t, x, &e) == 0 && aug_galerkin_sync(&gt, &t, K, &cm, &e) == 0, "unit add %lld: %s",
                (long long)i, e.msg);
    }
    T_CHECK(s.r == n && t.r == n, "ranks %d, %d of %lld", s.r, t.r, (long long)n);
    double *U = malloc((size_t)n * n * sizeof *U), *V = malloc((size_t)n * n * sizeof *V);
    double *Kr = malloc((size_t)n * n * sizeof *Kr), *Kr2 = malloc((size_t)n * n * sizeof *Kr2);
    aug_isvd_basis(&s, U);
    aug_isvd_basis(&t, V);
    /* U = I exactly; V V' = I (the unit snapshots' basis is I up to rotation) */
    double du = 0, dv = 0;
    for (int64_t i = 0; i < n; i++)
        for (int64_t j = 0; j < n; j++) {
            double vv = 0;
            for (int64_t k = 0; k < n; k++) vv += V[i + k * n] * V[j + k * n];
            du = fmax(du, fabs(U[i + j * n] - (i == j))), dv = fmax(dv, fabs(vv - (i == j)));
        }
    T_CHECK(du == 0 && dv <= 1e-13, "I: %.2e, unit snapshots V V' - I: %.2e", du, dv);
    aug_galerkin_reduced(&g, &s, Kr);
    aug_galerkin_reduced(&g2, &s, Kr2);
    double dk = 0;
    for (size_t i = 0; i < (size_t)n * n; i++) dk = fmax(dk, fabs(Kr[i] - Kd[i])), dk = fmax(dk, fabs(Kr2[i] - Kd[i]));
    T_CHECK(dk <= 1e-14 * 9, "K_r - K: %.2e", dk);
    aug_galerkin_reduced(&gt, &t, Kr);
    compare(&t, Kd, Kr, -2);
    T_CHECK(aug_isvd_compact(&s, &e) == 0 && !s.compacted && aug_galerkin_sync(&g, &s, K, &cm, &e) == 0,
            "compact of W = I: compacted %d", s.compacted);
    for (int64_t i = 0; i < n; i++) x[i] = g_normal();
    T_CHECK(aug_isvd_add(&s, x, &e) == 0 && aug_galerkin_sync(&g, &s, K, &cm, &e) == 0, "add to I: %s", e.msg);
    T_CHECK(s.r == n && !s.grew && !s.unit_up, "after an add: rank %d, grew %d, unit_up %d", s.r, s.grew, s.unit_up);
    aug_galerkin_reduced(&g, &s, Kr);
    compare(&s, Kd, Kr, -3);
    /* a Galerkin state of W = I is refused for another basis */
    aug_galerkin g3;
    T_CHECK(aug_galerkin_identity(&g3, &t, K, &e) == AUG_EUSAGE, "identity Galerkin of a rotated basis accepted");
    aug_galerkin_free(&g), aug_galerkin_free(&g2), aug_galerkin_free(&gt);
    aug_isvd_free(&s), aug_isvd_free(&t);
    cholmod_free_sparse(&K, &cm);
    free(Kd), free(x), free(U), free(V), free(Kr), free(Kr2);
}

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(kept_up_to_date);
    T_RUN(identity_direct);
    printf("measured: Galerkin vs from-scratch rel %.2e\n", worst);
    cholmod_finish(&cm);
    T_EXIT();
}
