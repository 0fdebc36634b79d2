/* refine on the thesis's square (50 x 50 nodes, 4,802 triangles) for its cut
   patterns (thesis 003, fig. 5.1, 5.9): a single cubic Bezier cut, intersecting
   cuts, a flower punch of rational quadratic arcs, many cuts, and a path passing
   1e-9 from a vertex. After every pattern: conformity, the cut segments as mesh
   edges, no triangle above aspect 3 (except in corners too sharp for any
   triangle), total area, and the downstream mesh equal to the refiner's. */
#include <gsl/gsl_rng.h>
#include <math.h>
#include <string.h>
#include "refine_gen.h"
#include "t.h"

typedef struct run {
    aug_mesh C, D;        /* generator's cut view; downstream (original + folded steps) */
    aug_refiner R;
    double *seg;          /* every step's pATH */
    int64_t nseg;
    int step;
    aug_refine_q last;
    int64_t added, intersected, cut_added;
} run;

static void run_init(run *s, int n)
{
    memset(s, 0, sizeof *s);
    gen_square(&s->C, n);
    gen_square(&s->D, n);
    aug_refine_opt o;
    aug_refine_opt_default(&o);
    aug_err e;
    if (aug_refiner_init(&s->R, &s->C, &o, &e)) printf("# init: %s\n", e.msg);
}

static void run_free(run *s)
{
    aug_mesh_free(&s->C);
    aug_mesh_free(&s->D);
    aug_refiner_free(&s->R);
    free(s->seg);
}

/* one cut step: generate, refine, apply downstream; 0 or the failing stage */
static int run_step(run *s, const gen_poly *g, char *why, size_t nwhy)
{
    aug_mdelta d, out;
    double *seg;
    int64_t nseg;
    int rc = gen_cut(&s->C, g, s->step, &d, &seg, &nseg);
    if (rc) {
        snprintf(why, nwhy, "generator %d", rc);
        return 1;
    }
    aug_err e;
    if (aug_mesh_apply(&s->C, &d, &e)) {
        snprintf(why, nwhy, "generator's delta: %.200s", e.msg);
        return 2;
    }
    if (aug_refine_step(&s->R, &d, NULL, seg, nseg, &out, NULL, NULL, &s->last, &e)) {
        snprintf(why, nwhy, "refine: %.200s", e.msg);
        return 3;
    }
    if (aug_mesh_apply(&s->D, &out, &e)) {
        snprintf(why, nwhy, "folded delta: %.200s", e.msg);
        return 4;
    }
    s->seg = realloc(s->seg, (size_t)(s->nseg + nseg) * 4 * sizeof *s->seg);
    memcpy(s->seg + 4 * s->nseg, seg, (size_t)nseg * 4 * sizeof *seg);
    s->nseg += nseg;
    s->added += out.nadd;
    s->cut_added += d.nadd;
    s->intersected += s->last.intersected;
    s->step++;
    aug_mdelta_free(&d);
    aug_mdelta_free(&out);
    free(seg);
    return 0;
}

/* the checks every pattern must pass */
static void check_run(run *s, const char *name)
{
    double area, maxasp;
    int64_t corners;
    int64_t nc = chk_conform(&s->D, s->seg, s->nseg, &area);
    T_CHECK(nc == 0, "%s: %lld conformity violations", name, (long long)nc);
    T_CHECK(fabs(area - 1) < 1e-12, "%s: area %.17g", name, area);
    int64_t gaps = chk_cut_edges(&s->D, s->seg, s->nseg);
    T_CHECK(gaps == 0, "%s: %lld cut segments not made of edges", name, (long long)gaps);
    int64_t bad = chk_aspect(&s->D, 3, &maxasp, &corners);
    T_CHECK(bad == 0, "%s: %lld triangles above aspect 3 (max %.3g)", name, (long long)bad, maxasp);
    T_CHECK(s->D.nn == s->R.work.m.nn && s->D.ne == s->R.work.m.ne &&
                !memcmp(s->D.conn, s->R.work.m.conn, (size_t)s->D.ne * 3 * sizeof(int32_t)) &&
                !memcmp(s->D.x, s->R.work.m.x, (size_t)s->D.nn * 2 * sizeof(double)),
            "%s: downstream mesh differs from the refiner's", name);
    T_CHECK(s->D.nn == s->R.base.nn && s->D.nfix == s->R.base.nfix, "%s: base mesh differs", name);
    printf("# %s: %d steps, intersected %lld, cut added %lld, added %lld, max aspect %.3f, "
           "sharp corners %lld, nodes %lld\n",
           name, s->step, (long long)s->intersected, (long long)s->cut_added, (long long)s->added,
           maxasp, (long long)corners, (long long)s->D.nn);
}

static void single_bezier(void)
{
    run s;
    run_init(&s, 50);
    gen_poly g = {0};
    double P[4][2] = {{0.2, 0.31}, {0.43, 0.93}, {0.61, 0.07}, {0.83, 0.71}};
    poly_cubic(&g, P, 300);
    char why[300];
    T_CHECK(run_step(&s, &g, why, sizeof why) == 0, "%.300s", why);
    T_CHECK(s.last.aspect_max <= 3 + 1e-9, "step max aspect %g", s.last.aspect_max);
    T_CHECK(s.last.aspect_max0 > 3, "the unrefined split had no bad triangle (%g)", s.last.aspect_max0);
    T_CHECK(s.last.intersected > 30, "intersected %lld", (long long)s.last.intersected);
    check_run(&s, "single");
    free(g.p);
    run_free(&s);
}

static void intersecting_cuts(void)
{
    run s;
    run_init(&s, 50);
    double A[4][2] = {{0.15, 0.52}, {0.4, 0.2}, {0.6, 0.85}, {0.86, 0.47}};
    double B[4][2] = {{0.48, 0.13}, {0.75, 0.42}, {0.25, 0.6}, {0.53, 0.88}};
    double Cc[4][2] = {{0.22, 0.19}, {0.45, 0.45}, {0.55, 0.5}, {0.79, 0.83}};
    const double(*cv[3])[2] = {A, B, Cc};
    char why[300];
    for (int k = 0; k < 3; k++) {
        gen_poly g = {0};
        poly_cubic(&g, cv[k], 300);
        T_CHECK(run_step(&s, &g, why, sizeof why) == 0, "cut %d: %.300s", k, why);
        free(g.p);
    }
    check_run(&s, "intersecting");
    run_free(&s);
}

static void flower_punch(void)
{
    run s;
    run_init(&s, 50);
    gen_poly g = {0};
    double c[2] = {0.503, 0.497};
    poly_flower(&g, c, 0.2, 0.31, 5, 0.1);
    char why[300];
    T_CHECK(run_step(&s, &g, why, sizeof why) == 0, "%.300s", why);
    check_run(&s, "flower");
    free(g.p);
    run_free(&s);
}

static void many_cuts(void)
{
    run s;
    run_init(&s, 50);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 2024);
    char why[300];
    int done = 0, tries = 0;
    while (done < 8 && tries < 200) {
        tries++;
        double P[4][2];
        double cx = 0.2 + 0.6 * gsl_rng_uniform(r), cy = 0.2 + 0.6 * gsl_rng_uniform(r);
        double ang = M_PI * gsl_rng_uniform(r), L = 0.2 + 0.25 * gsl_rng_uniform(r);
        for (int i = 0; i < 4; i++) {
            double t = (i / 3.0 - 0.5) * L;
            P[i][0] = cx + t * cos(ang) + 0.08 * (gsl_rng_uniform(r) - 0.5);
            P[i][1] = cy + t * sin(ang) + 0.08 * (gsl_rng_uniform(r) - 0.5);
        }
        gen_poly g = {0};
        poly_cubic(&g, P, 200);
        aug_mdelta d;
        double *seg;
        int64_t nseg;
        int rc = gen_cut(&s.C, &g, s.step, &d, &seg, &nseg); /* dry run: can the generator cut it? */
        if (!rc) {
            aug_mdelta_free(&d);
            free(seg);
            T_CHECK(run_step(&s, &g, why, sizeof why) == 0, "cut %d: %.300s", done, why);
            done++;
        }
        free(g.p);
    }
    T_CHECK(done == 8, "only %d cuts generated", done);
    check_run(&s, "many");
    gsl_rng_free(r);
    run_free(&s);
}

/* a straight path passing 1e-9 from a vertex */
static void near_vertex(void)
{
    run s;
    run_init(&s, 50);
    double V[2] = {25.0 / 49, 24.0 / 49}, dir[2] = {cos(0.5), sin(0.5)}, nrm[2] = {-sin(0.5), cos(0.5)};
    gen_poly g = {0};
    for (int i = 0; i <= 10; i++) {
        double t = -0.17 + 0.34 * i / 10;
        poly_add(&g, V[0] + t * dir[0] + 1e-9 * nrm[0], V[1] + t * dir[1] + 1e-9 * nrm[1]);
    }
    char why[300];
    T_CHECK(run_step(&s, &g, why, sizeof why) == 0, "%.300s", why);
    check_run(&s, "near-vertex");
    free(g.p);
    run_free(&s);
}

/* the same input gives the same folded step */
static void deterministic(void)
{
    aug_mdelta out[2];
    for (int k = 0; k < 2; k++) {
        aug_mesh C;
        gen_square(&C, 30);
        aug_refiner R;
        aug_err e;
        aug_refiner_init(&R, &C, NULL, &e);
        gen_poly g = {0};
        double P[4][2] = {{0.1, 0.45}, {0.4, 0.7}, {0.6, 0.3}, {0.9, 0.55}};
        poly_cubic(&g, P, 200);
        aug_mdelta d;
        double *seg;
        int64_t nseg;
        int grc = gen_cut(&C, &g, 0, &d, &seg, &nseg);
        T_CHECK(grc == 0, "generator %d", grc);
        if (grc) return;
        aug_refine_q q;
        T_CHECK(aug_refine_step(&R, &d, NULL, seg, nseg, &out[k], NULL, NULL, &q, &e) == 0, "%.200s", e.msg);
        aug_mdelta_free(&d);
        free(seg);
        free(g.p);
        aug_refiner_free(&R);
        aug_mesh_free(&C);
    }
    T_CHECK(out[0].nnew == out[1].nnew && out[0].nmod == out[1].nmod && out[0].nadd == out[1].nadd,
            "counts differ");
    if (!t_cur_failed) {
        T_CHECK(!memcmp(out[0].x, out[1].x, (size_t)out[0].nnew * 2 * sizeof(double)) &&
                    !memcmp(out[0].parent, out[1].parent, (size_t)out[0].nnew * 4) &&
                    !memcmp(out[0].conn, out[1].conn, (size_t)out[0].nmod * 12) &&
                    !memcmp(out[0].conn_add, out[1].conn_add, (size_t)out[0].nadd * 12),
                "arrays differ");
    }
    aug_mdelta_free(&out[0]);
    aug_mdelta_free(&out[1]);
}

int main(void)
{
    T_RUN(single_bezier);
    T_RUN(intersecting_cuts);
    T_RUN(flower_punch);
    T_RUN(many_cuts);
    T_RUN(near_vertex);
    T_RUN(deterministic);
    T_EXIT();
}
