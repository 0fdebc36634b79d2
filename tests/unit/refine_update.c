/* The refined steps keep the update invariant (AMPS eq. 3.1, formats/stream.md
   7.2): after every folded step, K_t and f_t assembled from scratch on the refined
   mesh equal [K_{t-1} 0; 0 I] - Hbar (E + [0 0; 0 I]) Hbar' and [f_{t-1}; 0] +
   Hbar df, entry by entry; also with a BDLT (constraint and load) on the step and
   on a step without mesh change. */
#include <math.h>
#include <string.h>
#include "aug_cut.h"
#include "refine_gen.h"
#include "t.h"

/* dense symmetric copy of an upper-stored CHOLMOD matrix */
static double *dense(cholmod_sparse *A)
{
    int64_t n = (int64_t)A->nrow;
    double *D = calloc((size_t)(n * n + 1), sizeof *D);
    const int32_t *p = A->p, *i = A->i;
    const double *x = A->x;
    for (int64_t j = 0; j < n; j++)
        for (int32_t k = p[j]; k < p[j + 1]; k++) D[i[k] + j * n] = D[j + i[k] * n] = x[k];
    return D;
}

typedef struct sys {
    int64_t n;
    double *K, *f;
} sys;

static int assemble(const aug_mesh *m, const aug_refiner *r, sys *s, cholmod_common *cm)
{
    aug_err e;
    cholmod_sparse *A = aug_assemble_cut(m, r->nn0, r->map0, r->nfree0, cm, &e);
    if (!A) return -1;
    s->n = (int64_t)A->nrow;
    s->K = dense(A);
    cholmod_free_sparse(&A, cm);
    s->f = calloc((size_t)s->n + 1, sizeof *s->f);
    return aug_load_cut(m, r->nn0, r->map0, r->nfree0, s->f, &e);
}

/* apply eq. 3.1 to prev; max |difference| to now relative to max |K| */
static double check_update(const sys *prev, const sys *now, const aug_update *u, double *ferr)
{
    int64_t n0 = prev->n, n = n0 + u->k, s = (int64_t)u->m + u->k;
    double *K = calloc((size_t)(n * n), sizeof *K), *f = calloc((size_t)n, sizeof *f);
    for (int64_t j = 0; j < n0; j++) {
        memcpy(K + j * n, prev->K + j * n0, (size_t)n0 * sizeof *K);
        f[j] = prev->f[j];
    }
    for (int64_t j = n0; j < n; j++) K[j + j * n] = 1;
    int64_t *H = malloc((size_t)(s + 1) * sizeof *H);
    for (int64_t a = 0; a < s; a++) H[a] = a < u->m ? u->H[a] : n0 + (a - u->m);
    for (int64_t a = 0; a < s; a++) {
        for (int64_t b = 0; b < s; b++)
            K[H[a] + H[b] * n] -= u->E[a + b * s] + (a >= u->m && a == b ? 1 : 0);
        f[H[a]] += u->df[a];
    }
    double d = 0, kmax = 0, fd = 0, fmax_ = 0;
    for (int64_t i = 0; i < n * n; i++) {
        d = fmax(d, fabs(K[i] - now->K[i]));
        kmax = fmax(kmax, fabs(now->K[i]));
    }
    for (int64_t i = 0; i < n; i++) {
        fd = fmax(fd, fabs(f[i] - now->f[i]));
        fmax_ = fmax(fmax_, fabs(now->f[i]));
    }
    *ferr = fd / fmax(fmax_, 1e-300);
    free(K), free(f), free(H);
    return d / kmax;
}

static void invariant_over_steps(void)
{
    cholmod_common cm;
    cholmod_start(&cm);
    aug_mesh C, D;
    gen_square(&C, 16);
    gen_square(&D, 16);
    aug_refiner R;
    aug_err e;
    T_CHECK(aug_refiner_init(&R, &C, NULL, &e) == 0, "init: %s", e.msg);
    sys prev, now;
    T_CHECK(assemble(&D, &R, &prev, &cm) == 0, "assemble");
    double c0[2] = {0.51, 0.49};
    double A[4][2] = {{0.12, 0.33}, {0.4, 0.8}, {0.62, 0.1}, {0.88, 0.66}};
    double B[4][2] = {{0.3, 0.09}, {0.7, 0.4}, {0.3, 0.6}, {0.66, 0.93}};
    for (int step = 1; step <= 4 && !t_cur_failed; step++) {
        gen_poly g = {0};
        if (step == 1) poly_cubic(&g, A, 150);
        else if (step == 2) poly_cubic(&g, B, 150);
        else poly_flower(&g, c0, 0.12, 0.19, 4, 0.3);
        if (step == 4) { /* the punch once more, smaller: a re-cut inside refined elements */
            free(g.p);
            memset(&g, 0, sizeof g);
            poly_flower(&g, c0, 0.07, 0.1, 3, 0.9);
        }
        aug_mdelta d, out;
        double *seg;
        int64_t nseg;
        int rc = gen_cut(&C, &g, step, &d, &seg, &nseg);
        T_CHECK(rc == 0, "step %d: generator %d", step, rc);
        if (rc) break;
        aug_mesh_apply(&C, &d, &e);
        /* step 2 also carries a BDLT: a constraint and a load on new nodes */
        aug_bdelta bc, outbc;
        aug_bdelta_init(&bc);
        bc.step = step;
        if (step == 2) {
            aug_bdelta_fix(&bc, (int32_t)(2 * (C.nn - 1)), 0.001);
            aug_bdelta_load(&bc, (int32_t)(2 * (C.nn - 2) + 1), 3.5);
            aug_bdelta_finish(&bc);
        }
        aug_update u;
        aug_refine_q q;
        rc = aug_refine_step(&R, &d, step == 2 ? &bc : NULL, seg, nseg, &out, &outbc, &u, &q, &e);
        T_CHECK(rc == 0, "step %d: refine: %s", step, e.msg);
        if (rc) break;
        aug_mesh_apply(&D, &out, &e);
        if (step == 2) aug_mesh_apply_bc(&D, &outbc, &e);
        T_CHECK(assemble(&D, &R, &now, &cm) == 0, "assemble");
        T_CHECK(now.n == prev.n + u.k, "step %d: order %lld, expected %lld + %d", step,
                (long long)now.n, (long long)prev.n, u.k);
        if (now.n == prev.n + u.k) {
            double fe, ke = check_update(&prev, &now, &u, &fe);
            T_CHECK(ke < 1e-13, "step %d: K differs by %.3g (relative)", step, ke);
            T_CHECK(fe < 1e-13, "step %d: f differs by %.3g (relative)", step, fe);
            printf("# step %d: n %lld, m %d, k %d, |dK|/|K| %.2g, |df|/|f| %.2g, added %lld\n", step,
                   (long long)now.n, u.m, u.k, ke, fe, (long long)out.nadd);
        }
        free(prev.K), free(prev.f);
        prev = now;
        aug_update_free(&u);
        aug_mdelta_free(&d);
        aug_mdelta_free(&out);
        aug_bdelta_free(&bc);
        aug_bdelta_free(&outbc);
        free(seg);
        free(g.p);
    }
    /* a step with a BDLT only */
    if (!t_cur_failed) {
        aug_bdelta bc, outbc;
        aug_bdelta_init(&bc);
        bc.step = 5;
        aug_bdelta_fix(&bc, (int32_t)(2 * (C.nn - 3)), -0.002);
        aug_bdelta_fix(&bc, (int32_t)(2 * (C.nn - 3) + 1), 0);
        aug_bdelta_finish(&bc);
        aug_update u;
        T_CHECK(aug_refine_bc_only(&R, 5, &bc, &outbc, &u, &e) == 0, "bc only: %s", e.msg);
        aug_mesh_apply_bc(&D, &outbc, &e);
        T_CHECK(assemble(&D, &R, &now, &cm) == 0, "assemble");
        double fe, ke = check_update(&prev, &now, &u, &fe);
        T_CHECK(ke < 1e-13 && fe < 1e-13, "BDLT-only step: K %.3g, f %.3g", ke, fe);
        free(now.K), free(now.f);
        aug_update_free(&u);
        aug_bdelta_free(&bc);
        aug_bdelta_free(&outbc);
    }
    free(prev.K), free(prev.f);
    aug_refiner_free(&R);
    aug_mesh_free(&C);
    aug_mesh_free(&D);
    cholmod_finish(&cm);
}

int main(void)
{
    T_RUN(invariant_over_steps);
    T_EXIT();
}
