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

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(kept_up_to_date);
    printf("measured: Galerkin vs from-scratch rel %.2e\n", worst);
    cholmod_finish(&cm);
    T_EXIT();
}
