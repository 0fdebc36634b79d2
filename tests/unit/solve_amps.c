/* AMPS against fresh CHOLMOD solves over random cut / constraint / load
   sequences; V columns by the own path solve and by cholmod_solve2 agree; the
   output-set closure solve equals the full solve on those DOFs. */
#include "t.h"
#include "solve_gen.h"

static cholmod_common cm;
static int base_had_ls; /* the last base got a supernodal factor */

/* one random step on g: cut a node on the plane x = xc, constrain a DOF, or
   change loads on a few DOFs */
static void random_step(gen *g, gsl_rng *r, double xc, int allow_cons)
{
    double u = gsl_rng_uniform(r);
    if (u < 0.6 || !allow_cons) {
        for (int tries = 0; tries < 200; tries++) {
            int64_t p = (int64_t)gsl_rng_uniform_int(r, (unsigned long)g->nn0);
            if (g->x[p * 3] != xc || g->cut[p] || g->x[p * 3 + 2] == 0) continue;
            if (gen_cut_node(g, p, xc, 0)) {
                if (gsl_rng_uniform(r) < 0.5) g->loads[g->n - 3] += 0.05;
                return;
            }
        }
    }
    if (u < 0.8 && allow_cons) {
        int64_t j = (int64_t)gsl_rng_uniform_int(r, (unsigned long)g->n);
        if (!g->cons[j]) g->cons[j] = 1, g->cval[j] = 0.01 * (gsl_rng_uniform(r) - 0.5);
        return;
    }
    for (int t = 0; t < 4; t++) g->loads[gsl_rng_uniform_int(r, (unsigned long)g->n)] += 0.03;
}

static double reldiff(const double *a, const double *b, int64_t n)
{
    double d = 0, s = 0;
    for (int64_t i = 0; i < n; i++) d += (a[i] - b[i]) * (a[i] - b[i]), s += b[i] * b[i];
    return sqrt(d / (s > 0 ? s : 1));
}

/* run nsteps random steps, checking AMPS every step */
static void run_sequence(int nx, int ny, int nz, int nsteps, unsigned long seed, int use_cholmod,
                         double stiff_jump, double tol, int check_every, double unref, double *worst)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, seed);
    gen g;
    gen_init(&g, nx, ny, nz, stiff_jump, r);
    cholmod_sparse *K0 = gen_sparse(&g, &cm);
    cholmod_factor *L0 = cholmod_analyze(K0, &cm);
    cholmod_factorize(K0, L0, &cm);
    aug_err e;
    aug_base *b = aug_base_new(L0, K0, g.f, -1, &cm, &e);
    T_CHECK(b != NULL, "base: %s", e.msg);
    base_had_ls = b && b->Ls;
    aug_cum c;
    aug_cum_init(&c, g.n, &e);
    aug_amps a;
    aug_amps_init(&a);
    a.memo.use_cholmod = use_cholmod;
    double xc = nx / 2;
    *worst = 0;
    for (int t = 1; t <= nsteps && b; t++) {
        gen_snap s;
        gen_snapshot(&g, &s);
        random_step(&g, r, xc, 1);
        gen_assemble(&g);
        aug_update u;
        gen_diff(&g, s.K, s.ld, s.f, s.n, t, &u);
        gen_snap_free(&s);
        T_CHECK(aug_cum_apply(&c, &u, &e) == 0, "apply: %s", e.msg);
        aug_update_free(&u);
        double *x = calloc((size_t)g.n, sizeof *x), tm[4];
        int rc = aug_amps_step(&a, b, &c, NULL, 0, 1e-14, x, tm, &cm, &e);
        T_CHECK(rc == 0, "step %d: %s", t, e.msg);
        T_CHECK(!a.schur.singular, "step %d: S2 reported singular (rcond %g)", t, a.schur.rcond);
        if (t % check_every == 0 || t == nsteps) {
            double *ref = gen_direct(&g, &cm);
            T_CHECK(ref != NULL, "reference solve failed at step %d", t);
            if (ref) {
                double d = reldiff(x, ref, g.n);
                if (d > *worst) *worst = d;
                T_CHECK(d <= tol, "step %d: rel diff %g > %g (n %lld, na %lld)", t, d, tol,
                        (long long)g.n, (long long)a.schur.na);
                /* relative residual with the generator's dense K_t */
                double rr = 0, ff = 0;
                for (int64_t i = 0; i < g.n; i++) {
                    double s2 = -g.f[i];
                    for (int64_t j = 0; j < g.n; j++) s2 += g.K[i + j * g.ncap] * x[j];
                    rr += s2 * s2, ff += g.f[i] * g.f[i];
                }
                double r2 = 0;
                for (int64_t i = 0; i < g.n; i++) {
                    double s2 = -g.f[i];
                    for (int64_t j = 0; j < g.n; j++) s2 += g.K[i + j * g.ncap] * ref[j];
                    r2 += s2 * s2;
                }
                /* AMPS is not backward stable in K_t (G = H'K^-1H carries forward
                   errors): 1e-12 (the bound on bricks) or within unref times
                   the direct solve, and after one step of iterative refinement within
                   10x of it */
                double lim = fmax(1e-12, unref * sqrt(r2 / ff));
                T_CHECK(sqrt(rr / ff) <= lim, "step %d: relres %g (direct %g)", t, sqrt(rr / ff), sqrt(r2 / ff));
                double *res = malloc((size_t)g.n * sizeof *res), *dx = malloc((size_t)g.n * sizeof *dx);
                for (int64_t i = 0; i < g.n; i++) {
                    double s2 = g.f[i];
                    for (int64_t j = 0; j < g.n; j++) s2 -= g.K[i + j * g.ncap] * x[j];
                    res[i] = s2;
                }
                T_CHECK(aug_amps_solve_general(&a, b, &c, res, dx, &cm, &e) == 0, "%s", e.msg);
                rr = 0;
                for (int64_t i = 0; i < g.n; i++) x[i] += dx[i];
                for (int64_t i = 0; i < g.n; i++) {
                    double s2 = -g.f[i];
                    for (int64_t j = 0; j < g.n; j++) s2 += g.K[i + j * g.ncap] * x[j];
                    rr += s2 * s2;
                }
                lim = fmax(1e-12, 10 * sqrt(r2 / ff));
                T_CHECK(sqrt(rr / ff) <= lim, "step %d: refined relres %g (direct %g)", t, sqrt(rr / ff), sqrt(r2 / ff));
                free(res), free(dx);
            }
            free(ref);
        }
        free(x);
    }
    aug_amps_free(&a);
    aug_cum_free(&c);
    aug_base_release(b, &cm);
    cholmod_free_sparse(&K0, &cm);
    gen_free(&g);
    gsl_rng_free(r);
}

static void amps_matches_direct(void)
{
    double w;
    run_sequence(4, 4, 6, 30, 11, 0, 1.0, 1e-10, 1, 1e3, &w);
}

static void amps_cholmod_reach_matches(void)
{
    double w;
    run_sequence(3, 3, 5, 15, 12, 1, 1.0, 1e-10, 1, 1e3, &w);
}

static void amps_hundreds_of_steps(void)
{
    double w;
    run_sequence(4, 3, 6, 200, 13, 0, 1.0, 1e-10, 40, 1e3, &w);
}

/* a base above AUG_SUPERNODAL_MIN back-substitutes through the supernodal
   factor Ls = L D^1/2: same accuracy */
static void amps_supernodal_backsolve(void)
{
    double w;
    run_sequence(8, 8, 12, 16, 15, 0, 1.0, 1e-10, 4, 1e3, &w);
    T_CHECK(base_had_ls, "no supernodal factor on a base of order >= %d", AUG_SUPERNODAL_MIN);
}

static void amps_material_jump(void)
{
    double w;
    /* cond(K) ~ 1e6 here: forward error bound cond * 1e-15 */
    run_sequence(3, 3, 6, 24, 14, 0, 1e3, 1e-8, 3, 1e5, &w);
}

/* the closure solve on a few DOFs equals the full solve there */
static void amps_output_closure(void)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 21);
    gen g;
    gen_init(&g, 4, 4, 6, 1.0, r);
    cholmod_sparse *K0 = gen_sparse(&g, &cm);
    cholmod_factor *L0 = cholmod_analyze(K0, &cm);
    cholmod_factorize(K0, L0, &cm);
    aug_err e;
    aug_base *b = aug_base_new(L0, K0, g.f, -1, &cm, &e);
    aug_cum c;
    aug_cum_init(&c, g.n, &e);
    aug_amps a;
    aug_amps_init(&a);
    for (int t = 1; t <= 12; t++) {
        gen_snap s;
        gen_snapshot(&g, &s);
        random_step(&g, r, 2, 1);
        gen_assemble(&g);
        aug_update u;
        gen_diff(&g, s.K, s.ld, s.f, s.n, t, &u);
        gen_snap_free(&s);
        aug_cum_apply(&c, &u, &e);
        aug_update_free(&u);
        double *full = calloc((size_t)g.n, sizeof *full), *part = calloc((size_t)g.n, sizeof *part), tm[4];
        aug_amps_step(&a, b, &c, NULL, 0, 1e-14, full, tm, &cm, &e);
        int32_t out[5];
        for (int i = 0; i < 5; i++) out[i] = (int32_t)((i * 37 + t * 11) % g.n);
        for (int i = 1; i < 5; i++)
            for (int j = i; j > 0 && out[j] < out[j - 1]; j--) { int32_t tt = out[j]; out[j] = out[j - 1]; out[j - 1] = tt; }
        aug_amps_step(&a, b, &c, out, 5, 1e-14, part, tm, &cm, &e);
        T_CHECK(a.nq < b->n, "closure %lld not smaller than n %lld", (long long)a.nq, (long long)b->n);
        for (int i = 0; i < 5; i++)
            T_CHECK(t_reldiff(part[out[i]], full[out[i]]) < 1e-12 || fabs(part[out[i]] - full[out[i]]) < 1e-15,
                    "step %d dof %d: %g vs %g", t, out[i], part[out[i]], full[out[i]]);
        free(full), free(part);
    }
    aug_amps_free(&a);
    aug_cum_free(&c);
    aug_base_release(b, &cm);
    cholmod_free_sparse(&K0, &cm);
    gen_free(&g);
    gsl_rng_free(r);
}

/* S2's factorization carried across steps (kept leading columns, new rows
   against U11, trailing block re-eliminated) gives the field of a fresh LU of
   S2 at every step, and the carried path is actually taken */
static void amps_s2_update_matches_fresh(void)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 41);
    gen g;
    gen_init(&g, 4, 4, 6, 1.0, r);
    cholmod_sparse *K0 = gen_sparse(&g, &cm);
    cholmod_factor *L0 = cholmod_analyze(K0, &cm);
    cholmod_factorize(K0, L0, &cm);
    aug_err e;
    aug_base *b = aug_base_new(L0, K0, g.f, -1, &cm, &e);
    aug_cum c;
    aug_cum_init(&c, g.n, &e);
    aug_amps a, f;
    aug_amps_init(&a);
    aug_amps_init(&f);
    int partial = 0, kept = 0;
    double worst = 0;
    for (int t = 1; t <= 40; t++) {
        gen_snap s;
        gen_snapshot(&g, &s);
        random_step(&g, r, 2, 1);
        gen_assemble(&g);
        aug_update u;
        gen_diff(&g, s.K, s.ld, s.f, s.n, t, &u);
        gen_snap_free(&s);
        aug_cum_apply(&c, &u, &e);
        aug_update_free(&u);
        double *x = calloc((size_t)g.n, sizeof *x), *y = calloc((size_t)g.n, sizeof *y), tm[4];
        int64_t before = a.schur.nlu;
        T_CHECK(aug_amps_step(&a, b, &c, NULL, 0, 0, x, tm, &cm, &e) == 0, "%s", e.msg);
        if (a.schur.k0 > 0 && before > 0) partial++, kept += (int)a.schur.k0;
        aug_schur_free(&f.schur); /* a fresh LU of the whole S2 */
        T_CHECK(aug_amps_step(&f, b, &c, NULL, 0, 0, y, tm, &cm, &e) == 0, "%s", e.msg);
        T_CHECK(f.schur.k0 == 0 && f.schur.na == a.schur.na, "step %d: fresh LU not full", t);
        T_CHECK(a.schur.singular == f.schur.singular && a.schur.detsign == f.schur.detsign,
                "step %d: singular %d/%d, det sign %d/%d", t, a.schur.singular, f.schur.singular,
                a.schur.detsign, f.schur.detsign);
        double d = reldiff(x, y, g.n);
        if (d > worst) worst = d;
        T_CHECK(d <= 1e-12, "step %d: carried vs fresh LU differ by %g", t, d);
        free(x), free(y);
    }
    T_CHECK(partial >= 10, "the carried factorization was used on %d steps only", partial);
    fprintf(stderr, "# carried S2 factorization on %d of 40 steps, %d columns kept, worst diff %.2g\n",
            partial, kept, worst);
    aug_amps_free(&a);
    aug_amps_free(&f);
    aug_cum_free(&c);
    aug_base_release(b, &cm);
    cholmod_free_sparse(&K0, &cm);
    gen_free(&g);
    gsl_rng_free(r);
}

/* a node left without elements makes K_t singular: S2 says so */
static void amps_singular_step(void)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 31);
    gen g;
    gen_init(&g, 3, 3, 4, 1.0, r);
    cholmod_sparse *K0 = gen_sparse(&g, &cm);
    cholmod_factor *L0 = cholmod_analyze(K0, &cm);
    cholmod_factorize(K0, L0, &cm);
    aug_err e;
    aug_base *b = aug_base_new(L0, K0, g.f, -1, &cm, &e);
    aug_cum c;
    aug_cum_init(&c, g.n, &e);
    aug_amps a;
    aug_amps_init(&a);
    gen_snap s;
    gen_snapshot(&g, &s);
    int64_t p = (int64_t)(3 * 4 * 4 + 4 + 1); /* an interior node at z = 3 */
    gen_cut_node(&g, p, 1.5, 1);
    /* the copy takes every element: the copy is fine, p itself has none */
    gen_assemble(&g);
    aug_update u;
    gen_diff(&g, s.K, s.ld, s.f, s.n, 1, &u);
    gen_snap_free(&s);
    aug_cum_apply(&c, &u, &e);
    aug_update_free(&u);
    double *x = calloc((size_t)g.n, sizeof *x), tm[4];
    int rc = aug_amps_step(&a, b, &c, NULL, 0, 1e-14, x, tm, &cm, &e);
    T_CHECK(rc == 0, "%s", e.msg);
    T_CHECK(a.schur.singular, "singular step not detected (rcond %g, det sign %d)", a.schur.rcond,
            a.schur.detsign);
    double *ref = gen_direct(&g, &cm);
    T_CHECK(ref == NULL, "reference factorization unexpectedly succeeded");
    free(ref);
    free(x);
    aug_amps_free(&a);
    aug_cum_free(&c);
    aug_base_release(b, &cm);
    cholmod_free_sparse(&K0, &cm);
    gen_free(&g);
    gsl_rng_free(r);
}

int main(void)
{
    cholmod_start(&cm);
    cm.print = 0;
    cm.error_handler = NULL;
    T_RUN(amps_matches_direct);
    T_RUN(amps_cholmod_reach_matches);
    T_RUN(amps_output_closure);
    T_RUN(amps_singular_step);
    T_RUN(amps_s2_update_matches_fresh);
    T_RUN(amps_material_jump);
    T_RUN(amps_supernodal_backsolve);
    T_RUN(amps_hundreds_of_steps);
    cholmod_finish(&cm);
    T_EXIT();
}
