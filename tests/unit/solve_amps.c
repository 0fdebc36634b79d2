/* AMPS against fresh CHOLMOD solves over random cut / constraint / load
   sequences; V columns by the own path solve and by cholmod_solve2 agree; the
   output-set closure solve equals the full solve on those DOFs; the cut
   matrix of the composed sparse update equals K_t assembled densely; the
   growing work arrays keep their contents. */
#include <stdint.h>
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

/* a generated mesh, its base factor and the composed update of its steps */
typedef struct fixture {
    gsl_rng *r;
    gen g;
    cholmod_sparse *K0;
    aug_base *b;
    aug_cum c;
    aug_err e;
} fixture;

static void fix_open(fixture *f, int nx, int ny, int nz, double stiff_jump, unsigned long seed)
{
    f->r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(f->r, seed);
    gen_init(&f->g, nx, ny, nz, stiff_jump, f->r);
    f->K0 = gen_sparse(&f->g, &cm);
    cholmod_factor *L0 = cholmod_analyze(f->K0, &cm);
    cholmod_factorize(f->K0, L0, &cm);
    f->b = aug_base_new(L0, f->K0, f->g.f, -1, &cm, &f->e);
    T_CHECK(f->b != NULL, "base: %s", f->e.msg);
    aug_cum_init(&f->c, f->g.n, &f->e);
}

/* compose what the generator changed since snapshot s as step t */
static int fix_commit(fixture *f, gen_snap *s, int t)
{
    gen_assemble(&f->g);
    aug_update u;
    gen_diff(&f->g, s->K, s->ld, s->f, s->n, t, &u);
    gen_snap_free(s);
    int rc = aug_cum_apply(&f->c, &u, &f->e);
    aug_update_free(&u);
    return rc;
}

/* one random_step on the plane x = xc, composed as step t */
static int fix_random_step(fixture *f, double xc, int t)
{
    gen_snap s;
    gen_snapshot(&f->g, &s);
    random_step(&f->g, f->r, xc, 1);
    return fix_commit(f, &s, t);
}

static void fix_close(fixture *f)
{
    aug_cum_free(&f->c);
    aug_base_release(f->b, &cm);
    cholmod_free_sparse(&f->K0, &cm);
    gen_free(&f->g);
    gsl_rng_free(f->r);
}

/* run nsteps random steps, checking AMPS every step */
static void run_sequence(int nx, int ny, int nz, int nsteps, unsigned long seed, int use_cholmod,
                         double stiff_jump, double tol, int check_every, double unref, double *worst)
{
    fixture f;
    fix_open(&f, nx, ny, nz, stiff_jump, seed);
    base_had_ls = f.b && f.b->Ls;
    aug_amps a;
    aug_amps_init(&a);
    a.memo.use_cholmod = use_cholmod;
    double xc = nx / 2;
    *worst = 0;
    for (int t = 1; t <= nsteps && f.b; t++) {
        T_CHECK(fix_random_step(&f, xc, t) == 0, "apply: %s", f.e.msg);
        double *x = calloc((size_t)f.g.n, sizeof *x), tm[4];
        int rc = aug_amps_step(&a, f.b, &f.c, NULL, 0, 1e-14, x, tm, &cm, &f.e);
        T_CHECK(rc == 0, "step %d: %s", t, f.e.msg);
        T_CHECK(!a.schur.singular, "step %d: S2 reported singular (rcond %g)", t, a.schur.rcond);
        if (t % check_every == 0 || t == nsteps) {
            double *ref = gen_direct(&f.g, &cm);
            T_CHECK(ref != NULL, "reference solve failed at step %d", t);
            if (ref) {
                double d = reldiff(x, ref, f.g.n);
                if (d > *worst) *worst = d;
                T_CHECK(d <= tol, "step %d: rel diff %g > %g (n %lld, na %lld)", t, d, tol,
                        (long long)f.g.n, (long long)a.schur.na);
                /* relative residual with the generator's dense K_t */
                double *res = malloc((size_t)f.g.n * sizeof *res), *dx = malloc((size_t)f.g.n * sizeof *dx);
                double rr = 0, ff = 0, r2 = 0;
                gen_residual(&f.g, ref, res);
                for (int64_t i = 0; i < f.g.n; i++) r2 += res[i] * res[i], ff += f.g.f[i] * f.g.f[i];
                gen_residual(&f.g, x, res);
                for (int64_t i = 0; i < f.g.n; i++) rr += res[i] * res[i];
                /* AMPS is not backward stable in K_t (G = H'K^-1H carries forward
                   errors): 1e-12 (the bound on bricks) or within unref times
                   the direct solve, and after one step of iterative refinement within
                   10x of it */
                double lim = fmax(1e-12, unref * sqrt(r2 / ff));
                T_CHECK(sqrt(rr / ff) <= lim, "step %d: relres %g (direct %g)", t, sqrt(rr / ff), sqrt(r2 / ff));
                T_CHECK(aug_amps_solve_general(&a, f.b, &f.c, res, dx, &cm, &f.e) == 0, "%s", f.e.msg);
                for (int64_t i = 0; i < f.g.n; i++) x[i] += dx[i];
                gen_residual(&f.g, x, res);
                rr = 0;
                for (int64_t i = 0; i < f.g.n; i++) rr += res[i] * res[i];
                lim = fmax(1e-12, 10 * sqrt(r2 / ff));
                T_CHECK(sqrt(rr / ff) <= lim, "step %d: refined relres %g (direct %g)", t, sqrt(rr / ff), sqrt(r2 / ff));
                free(res), free(dx);
            }
            free(ref);
        }
        free(x);
    }
    aug_amps_free(&a);
    fix_close(&f);
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
    fixture f;
    fix_open(&f, 4, 4, 6, 1.0, 21);
    aug_amps a;
    aug_amps_init(&a);
    for (int t = 1; t <= 12; t++) {
        T_CHECK(fix_random_step(&f, 2, t) == 0, "apply: %s", f.e.msg);
        double *full = calloc((size_t)f.g.n, sizeof *full), *part = calloc((size_t)f.g.n, sizeof *part), tm[4];
        aug_amps_step(&a, f.b, &f.c, NULL, 0, 1e-14, full, tm, &cm, &f.e);
        int32_t out[5];
        for (int i = 0; i < 5; i++) out[i] = (int32_t)((i * 37 + t * 11) % f.g.n);
        for (int i = 1; i < 5; i++)
            for (int j = i; j > 0 && out[j] < out[j - 1]; j--) { int32_t tt = out[j]; out[j] = out[j - 1]; out[j - 1] = tt; }
        aug_amps_step(&a, f.b, &f.c, out, 5, 1e-14, part, tm, &cm, &f.e);
        T_CHECK(a.nq < f.b->n, "closure %lld not smaller than n %lld", (long long)a.nq, (long long)f.b->n);
        for (int i = 0; i < 5; i++)
            T_CHECK(t_reldiff(part[out[i]], full[out[i]]) < 1e-12 || fabs(part[out[i]] - full[out[i]]) < 1e-15,
                    "step %d dof %d: %g vs %g", t, out[i], part[out[i]], full[out[i]]);
        free(full), free(part);
    }
    aug_amps_free(&a);
    fix_close(&f);
}

/* S2's factorization carried across steps (kept leading columns, new rows
   against U11, trailing block re-eliminated) gives the field of a fresh LU of
   S2 at every step, and the carried path is actually taken */
static void amps_s2_update_matches_fresh(void)
{
    fixture f;
    fix_open(&f, 4, 4, 6, 1.0, 41);
    aug_amps a, fr; /* fr: a fresh LU of the whole S2 every step */
    aug_amps_init(&a);
    aug_amps_init(&fr);
    int partial = 0, kept = 0, carried = 0;
    double worst = 0;
    for (int t = 1; t <= 40; t++) {
        T_CHECK(fix_random_step(&f, 2, t) == 0, "apply: %s", f.e.msg);
        double *x = calloc((size_t)f.g.n, sizeof *x), *y = calloc((size_t)f.g.n, sizeof *y), tm[4];
        int64_t before = a.schur.nlu;
        T_CHECK(aug_amps_step(&a, f.b, &f.c, NULL, 0, 0, x, tm, &cm, &f.e) == 0, "%s", f.e.msg);
        if (a.schur.k0 > 0 && before > 0) partial++, kept += (int)a.schur.k0;
        if (a.schur.k0 > 0 && before > 0 && a.schur.nkept > 0) carried++;
        aug_schur_free(&fr.schur);
        T_CHECK(aug_amps_step(&fr, f.b, &f.c, NULL, 0, 0, y, tm, &cm, &f.e) == 0, "%s", f.e.msg);
        T_CHECK(fr.schur.k0 == 0 && fr.schur.na == a.schur.na, "step %d: fresh LU not full", t);
        T_CHECK(a.schur.singular == fr.schur.singular && a.schur.detsign == fr.schur.detsign,
                "step %d: singular %d/%d, det sign %d/%d", t, a.schur.singular, fr.schur.singular,
                a.schur.detsign, fr.schur.detsign);
        double d = reldiff(x, y, f.g.n);
        if (d > worst) worst = d;
        T_CHECK(d <= 1e-12, "step %d: carried vs fresh LU differ by %g", t, d);
        free(x), free(y);
    }
    T_CHECK(partial >= 10, "the carried factorization was used on %d steps only", partial);
    T_CHECK(carried >= 5, "trailing columns carried by the old L22 U22 on %d steps only", carried);
    fprintf(stderr,
            "# carried S2 factorization on %d of 40 steps (%d with trailing columns carried), %d "
            "columns kept, worst diff %.2g\n",
            partial, carried, kept, worst);
    aug_amps_free(&a);
    aug_amps_free(&fr);
    fix_close(&f);
}

/* a node left without elements makes K_t singular: S2 says so */
static void amps_singular_step(void)
{
    fixture f;
    fix_open(&f, 3, 3, 4, 1.0, 31);
    aug_amps a;
    aug_amps_init(&a);
    gen_snap s;
    gen_snapshot(&f.g, &s);
    int64_t p = (int64_t)(3 * 4 * 4 + 4 + 1); /* an interior node at z = 3 */
    gen_cut_node(&f.g, p, 1.5, 1);
    /* the copy takes every element: the copy is fine, p itself has none */
    T_CHECK(fix_commit(&f, &s, 1) == 0, "apply: %s", f.e.msg);
    double *x = calloc((size_t)f.g.n, sizeof *x), tm[4];
    int rc = aug_amps_step(&a, f.b, &f.c, NULL, 0, 1e-14, x, tm, &cm, &f.e);
    T_CHECK(rc == 0, "%s", f.e.msg);
    T_CHECK(a.schur.singular, "singular step not detected (rcond %g, det sign %d)", a.schur.rcond,
            a.schur.detsign);
    double *ref = gen_direct(&f.g, &cm);
    T_CHECK(ref == NULL, "reference factorization unexpectedly succeeded");
    free(ref);
    free(x);
    aug_amps_free(&a);
    fix_close(&f);
}

/* a non-finite entry of H'K^-1H reaches S2: the step is singular, not a
   NaN field (the solves read S2 without LAPACKE's NaN scan) */
static void amps_nonfinite_s2(void)
{
    fixture f;
    fix_open(&f, 3, 3, 5, 1.0, 47);
    aug_amps a;
    aug_amps_init(&a);
    double tm[4], *x = calloc((size_t)f.g.n * 4, sizeof *x);
    for (int t = 1; t <= 3; t++) {
        T_CHECK(fix_random_step(&f, 1.5, t) == 0, "apply: %s", f.e.msg);
        T_CHECK(aug_amps_step(&a, f.b, &f.c, NULL, 0, 0, x, tm, &cm, &f.e) == 0, "%s", f.e.msg);
    }
    aug_memo *M = &a.memo;
    T_CHECK(a.schur.na > 0 && M->m > 0 && !a.schur.singular, "no S2 to poison (na %lld)",
            (long long)a.schur.na);
    /* control: a fresh factor of the same S2 is regular */
    aug_schur_free(&a.schur);
    T_CHECK(aug_schur_factor(&a.schur, M, &f.c, 0, &f.e) == 0 && !a.schur.singular,
            "fresh S2 singular: %s", f.e.msg);
    int64_t p = -1;
    for (int64_t q = 0; q < a.schur.na && p < 0; q++)
        if (M->cpos[a.schur.A[q]] >= 0) p = a.schur.A[q];
    T_CHECK(p >= 0, "no base position in A");
    if (p >= 0) {
        double *Gp = M->G + (int64_t)M->cpos[p] * M->mcap, keep = Gp[0];
        Gp[0] = NAN;
        aug_schur_free(&a.schur);
        int rc = aug_schur_factor(&a.schur, M, &f.c, 0, &f.e);
        T_CHECK(rc == 0 && a.schur.singular, "NaN in S2: rc %d, singular %d", rc, a.schur.singular);
        Gp[0] = keep;
    }
    free(x);
    aug_amps_free(&a);
    fix_close(&f);
}

/* the cut matrix from K_0 and the composed sparse Ebar equals K_t assembled
   from scratch: every column (rows increasing, nothing but round-off
   between them), K_t x, and the relres on the changed rows */
static void cutmat_matches_dense(void)
{
    fixture f;
    fix_open(&f, 4, 3, 5, 1.0, 61);
    aug_cutmat m;
    T_CHECK(aug_cutmat_init(&m, f.K0, f.g.f, &cm, &f.e) == 0, "%s", f.e.msg);
    for (int t = 1; t <= 40; t++) {
        gen_snap sn;
        gen_snapshot(&f.g, &sn);
        random_step(&f.g, f.r, 2, 1);
        gen_assemble(&f.g);
        aug_update u;
        gen_diff(&f.g, sn.K, sn.ld, sn.f, sn.n, t, &u);
        gen_snap_free(&sn);
        T_CHECK(aug_cutmat_apply(&m, &u, &f.e) == 0, "step %d: %s", t, f.e.msg);
        aug_update_free(&u);
        int64_t n = f.g.n, ld = f.g.ncap, cmax = aug_cutmat_colmax(&m);
        T_CHECK(aug_cutmat_n(&m) == n, "order %lld vs %lld", (long long)aug_cutmat_n(&m), (long long)n);
        int32_t *idx = malloc((size_t)cmax * sizeof *idx);
        double *val = malloc((size_t)cmax * sizeof *val), *scr = calloc((size_t)n, sizeof *scr);
        double *col = calloc((size_t)n, sizeof *col), kmax = 0, worst = 0;
        for (int64_t i = 0; i < n * ld; i++) kmax = fmax(kmax, fabs(f.g.K[i]));
        for (int64_t j = 0; j < n; j++) {
            int64_t nz = aug_cutmat_column(&m, j, idx, val, scr);
            T_CHECK(nz <= cmax, "column %lld: %lld entries above colmax %lld", (long long)j, (long long)nz,
                    (long long)cmax);
            for (int64_t k = 0; k < nz; k++) {
                T_CHECK(k == 0 || idx[k] > idx[k - 1], "column %lld: rows not increasing", (long long)j);
                col[idx[k]] = val[k];
            }
            for (int64_t i = 0; i < n; i++) worst = fmax(worst, fabs(col[i] - f.g.K[i + j * ld]));
            for (int64_t k = 0; k < nz; k++) col[idx[k]] = 0;
            for (int64_t i = 0; i < n; i++) T_CHECK(scr[i] == 0, "scratch not zero on exit");
        }
        T_CHECK(worst <= 1e-12 * kmax, "step %d: column differs by %g (|K| %g)", t, worst, kmax);
        double *x = malloc((size_t)n * sizeof *x), *y = malloc((size_t)n * sizeof *y), rs = 0, fs = 0;
        for (int64_t i = 0; i < n; i++) x[i] = gsl_rng_uniform(f.r) - 0.5;
        aug_cutmat_mult(&m, x, y);
        double dy = 0;
        for (int64_t i = 0; i < n; i++) {
            double ki = 0;
            for (int64_t j = 0; j < n; j++) ki += f.g.K[i + j * ld] * x[j];
            dy = fmax(dy, fabs(y[i] - ki));
            double ri = f.g.f[i] - ki;
            fs += f.g.f[i] * f.g.f[i];
            if (i < m.cum.pcap && m.cum.pos[i] >= 0) rs += ri * ri;
        }
        T_CHECK(dy <= 1e-11 * kmax, "step %d: K_t x differs by %g", t, dy);
        double rc = aug_cutmat_relres_changed(&m, x), rd = sqrt(rs / fs);
        T_CHECK(fabs(rc - rd) <= 1e-10 * rd, "step %d: relres on S %g vs %g", t, rc, rd);
        free(idx), free(val), free(scr), free(col), free(x), free(y);
    }
    aug_cutmat_free(&m, &cm);
    fix_close(&f);
}

/* the growing work arrays keep their contents: a square one its leading
   block through several growths, a flat one its prefix */
static void mapped_arrays_grow(void)
{
    int64_t cap = 0, keep = 0;
    double *a = NULL;
    for (int64_t need = 300; need <= 3000; need = need * 3 / 2) {
        int64_t nc = aug_sq_cap(cap, need);
        T_CHECK(need <= cap ? nc == cap : nc >= need && nc % 256 == 0 && nc >= cap + cap / 4,
                "capacity %lld for %lld from %lld", (long long)nc, (long long)need, (long long)cap);
        if (nc > cap) a = aug_sq_grow(a, cap, nc, keep);
        T_CHECK(a != NULL, "grow to %lld", (long long)nc);
        if (!a) return;
        for (int64_t j = 0; j < keep; j++)
            for (int64_t i = 0; i < keep; i++)
                if (a[i + j * nc] != (double)(i + 10000 * j)) {
                    T_CHECK(0, "(%lld, %lld) lost growing %lld -> %lld", (long long)i, (long long)j,
                            (long long)cap, (long long)nc);
                    j = keep;
                    break;
                }
        cap = nc, keep = need;
        for (int64_t j = 0; j < keep; j++)
            for (int64_t i = 0; i < keep; i++) a[i + j * cap] = (double)(i + 10000 * j);
    }
    aug_map_free(a, (size_t)cap * (size_t)cap * sizeof *a);
    size_t n0 = 1000, n1 = (size_t)9 << 20;
    unsigned char *v = aug_map_grow(NULL, 0, n0);
    T_CHECK(v && (uintptr_t)v % 4096 == 0, "flat array");
    if (!v) return;
    for (size_t i = 0; i < n0; i++) v[i] = (unsigned char)(i * 7);
    v = aug_map_grow(v, n0, n1);
    T_CHECK(v != NULL, "flat growth");
    if (!v) return;
    for (size_t i = 0; i < n0; i++) T_CHECK(v[i] == (unsigned char)(i * 7), "byte %zu lost", i);
    v[n1 - 1] = 1;
    aug_map_free(v, n1);
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
    T_RUN(amps_nonfinite_s2);
    T_RUN(amps_s2_update_matches_fresh);
    T_RUN(amps_material_jump);
    T_RUN(amps_supernodal_backsolve);
    T_RUN(amps_hundreds_of_steps);
    T_RUN(cutmat_matches_dense);
    T_RUN(mapped_arrays_grow);
    cholmod_finish(&cm);
    T_EXIT();
}
