/* refine on the thesis's square (50 x 50 nodes, 4,802 triangles) for its cut
   patterns (thesis 003, fig. 5.1, 5.9): a single cubic Bezier cut, intersecting
   cuts, a flower punch of rational quadratic arcs, many cuts, and a path passing
   1e-9 from a vertex. After every pattern: conformity, the cut segments as mesh
   edges on both sides, no triangle above aspect 3 (except in corners too sharp
   for any triangle), total area, and the downstream mesh equal to the refiner's.
   Also: determinism, constraints following the parent rule at the fixed edge,
   --area-ratio, --min-angle, a cut that does not separate (its edges stay
   fixed), and a cut across a material interface. */
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

/* a cut through the fixed bottom edge: every node on y = 0 (old and refinement
   midpoints) is fixed in both components, every other node refine made is free
   (midpoints and centroids take the parent with the fewest constraints; the
   cut's own nodes keep the cut's parents and are not checked) */
static void constraints_follow_parents(void)
{
    run s;
    run_init(&s, 50);
    gen_poly g = {0};
    double P[4][2] = {{0.3, -0.05}, {0.35, 0.1}, {0.55, 0.05}, {0.62, 0.27}};
    poly_cubic(&g, P, 200);
    char why[300];
    T_CHECK(run_step(&s, &g, why, sizeof why) == 0, "%.300s", why);
    check_run(&s, "bottom");
    unsigned char *fx = calloc((size_t)s.D.nn * 2, 1), *cutn = calloc((size_t)s.D.nn, 1);
    for (int64_t i = 0; i < s.D.nfix; i++) fx[s.D.fix_dof[i]] = 1;
    for (int64_t c = 2500; c < s.C.nn; c++)
        if (s.R.cnode[c] >= 0) cutn[s.R.cnode[c]] = 1;
    int64_t wrong = 0;
    for (int64_t i = 0; i < s.D.nn; i++) {
        if (cutn[i]) continue;
        int on = s.D.x[2 * i + 1] == 0;
        if (fx[2 * i] != on || fx[2 * i + 1] != on) {
            if (wrong < 4) printf("# node %lld at (%.17g, %.17g): fixed %d %d\n", (long long)i, s.D.x[2 * i], s.D.x[2 * i + 1], fx[2 * i], fx[2 * i + 1]);
            wrong++;
        }
    }
    T_CHECK(wrong == 0, "%lld nodes with constraints that do not match y = 0", (long long)wrong);
    T_CHECK(s.added > s.cut_added, "no refinement near the boundary");
    free(fx);
    free(cutn);
    free(g.p);
    run_free(&s);
}

/* --area-ratio: refinement stops at elements smaller than R times their
   original; fewer elements, and every triangle still above the bound is small */
static void area_ratio_criterion(void)
{
    run s[2];
    int64_t added[2];
    for (int k = 0; k < 2; k++) {
        memset(&s[k], 0, sizeof s[k]);
        gen_square(&s[k].C, 50);
        gen_square(&s[k].D, 50);
        aug_refine_opt o;
        aug_refine_opt_default(&o);
        o.area_ratio = k ? 0.03 : 0;
        aug_err e;
        aug_refiner_init(&s[k].R, &s[k].C, &o, &e);
        gen_poly g = {0};
        double c[2] = {0.503, 0.497};
        poly_flower(&g, c, 0.2, 0.31, 5, 0.1);
        char why[300];
        T_CHECK(run_step(&s[k], &g, why, sizeof why) == 0, "%.300s", why);
        added[k] = s[k].added;
        free(g.p);
    }
    T_CHECK(added[1] < added[0], "area ratio 0.03 added %lld, none %lld", (long long)added[1], (long long)added[0]);
    int64_t big = 0;
    for (int64_t t = 0; t < s[1].R.work.m.ne; t++) {
        aug_quality q;
        aug_elem_quality(&s[1].R.work.m, t, &q);
        if (q.aspect > 3 * (1 + 1e-9) && q.measure > 0.03 * s[1].R.work.area0[t]) big++;
    }
    T_CHECK(big == 0, "%lld triangles above the bound and the area ratio", (long long)big);
    printf("# area ratio 0.03: %lld elements added, none: %lld\n", (long long)added[1], (long long)added[0]);
    run_free(&s[0]);
    run_free(&s[1]);
}

/* --min-angle 20: no angle below 20 degrees after refine (the cut's corners here
   are all wider) */
static void min_angle_criterion(void)
{
    run s;
    memset(&s, 0, sizeof s);
    gen_square(&s.C, 50);
    gen_square(&s.D, 50);
    aug_refine_opt o;
    aug_refine_opt_default(&o);
    o.min_angle = 20;
    aug_err e;
    aug_refiner_init(&s.R, &s.C, &o, &e);
    gen_poly g = {0};
    double P[4][2] = {{0.2, 0.31}, {0.43, 0.93}, {0.61, 0.07}, {0.83, 0.71}};
    poly_cubic(&g, P, 300);
    char why[300];
    T_CHECK(run_step(&s, &g, why, sizeof why) == 0, "%.300s", why);
    check_run(&s, "min-angle");
    double amin = 180;
    for (int64_t t = 0; t < s.D.ne; t++) {
        aug_quality q;
        aug_elem_quality(&s.D, t, &q);
        amin = fmin(amin, q.min_angle);
    }
    T_CHECK(amin >= 20 - 1e-9, "smallest angle %.3g", amin);
    T_CHECK(s.last.bad_left == 0 && s.last.capped == 0, "bad left %lld, capped %lld",
            (long long)s.last.bad_left, (long long)s.last.capped);
    printf("# min angle 20: smallest %.2f, %lld added\n", amin, (long long)s.added);
    free(g.p);
    run_free(&s);
}

/* a cut that splits without separating: its edges are interior constraints that
   bisection and flips must keep (fixed edges of the refined mesh) */
static void cut_without_separation(void)
{
    gen_separate = 0;
    run s;
    run_init(&s, 50);
    gen_poly g = {0};
    double A[4][2] = {{0.15, 0.52}, {0.4, 0.2}, {0.6, 0.85}, {0.86, 0.47}};
    double B[4][2] = {{0.48, 0.13}, {0.75, 0.42}, {0.25, 0.6}, {0.53, 0.88}};
    poly_cubic(&g, A, 300);
    char why[300];
    T_CHECK(run_step(&s, &g, why, sizeof why) == 0, "%.300s", why);
    free(g.p);
    memset(&g, 0, sizeof g);
    poly_cubic(&g, B, 300);
    T_CHECK(run_step(&s, &g, why, sizeof why) == 0, "%.300s", why);
    check_run(&s, "unseparated");
    int64_t open = 0;
    for (size_t h = 0; h < s.R.work.adj.cap; h++)
        if (s.R.work.adj.key[h] && s.R.work.adj.key[h] != UINT64_MAX &&
            (s.R.work.adj.val[2 * h] < 0 || s.R.work.adj.val[2 * h + 1] < 0))
            open++;
    T_CHECK(open == 196, "%lld open edges, the square has 196", (long long)open);
    T_CHECK(s.R.work.fixed.n > 0, "no fixed edges kept");
    free(g.p);
    run_free(&s);
    gen_separate = 1;
}

/* two materials (x < 0.5 and x > 0.5): a cut across the interface; every
   triangle keeps the material of where it lies (interfaces are fixed edges) */
static void material_interface(void)
{
    run s;
    run_init(&s, 50);
    for (int k = 0; k < 2; k++) {
        aug_mesh *m = k ? &s.D : &s.C;
        m->mats = realloc(m->mats, 2 * sizeof *m->mats);
        m->mats[1] = m->mats[0];
        m->mats[1].id = 6, m->mats[1].E = 5000;
        m->nmat = 2;
        for (int64_t t = 0; t < m->ne; t++) {
            const int32_t *v = m->conn + 3 * t;
            double cx = (m->x[2 * v[0]] + m->x[2 * v[1]] + m->x[2 * v[2]]) / 3;
            m->mat[t] = cx < 0.5;
        }
    }
    aug_refiner_free(&s.R);
    aug_err e;
    T_CHECK(aug_refiner_init(&s.R, &s.C, NULL, &e) == 0, "init %s", e.msg);
    gen_poly g = {0};
    double P[4][2] = {{0.2, 0.3}, {0.45, 0.55}, {0.55, 0.45}, {0.81, 0.7}};
    poly_cubic(&g, P, 200);
    char why[300];
    T_CHECK(run_step(&s, &g, why, sizeof why) == 0, "%.300s", why);
    check_run(&s, "materials");
    /* the material of the original triangle holding each centroid (50 x 50 grid:
       the cell, then the side of its diagonal) */
    int64_t wrong = 0;
    for (int64_t t = 0; t < s.D.ne; t++) {
        const int32_t *v = s.D.conn + 3 * t;
        double cx = (s.D.x[2 * v[0]] + s.D.x[2 * v[1]] + s.D.x[2 * v[2]]) / 3;
        double cy = (s.D.x[2 * v[0] + 1] + s.D.x[2 * v[1] + 1] + s.D.x[2 * v[2] + 1]) / 3;
        int i = (int)(cx * 49), j = (int)(cy * 49);
        double u = cx * 49 - i, w = cy * 49 - j;
        int64_t orig = 2 * ((int64_t)j * 49 + i) + (w > u); /* (a,b,c) below the diagonal, (a,c,d) above */
        wrong += s.D.mat[t] != s.C.mat[orig];
    }
    T_CHECK(wrong == 0, "%lld triangles with the other side's material", (long long)wrong);
    free(g.p);
    run_free(&s);
}

int main(void)
{
    T_RUN(single_bezier);
    T_RUN(intersecting_cuts);
    T_RUN(flower_punch);
    T_RUN(many_cuts);
    T_RUN(near_vertex);
    T_RUN(deterministic);
    T_RUN(constraints_follow_parents);
    T_RUN(area_ratio_criterion);
    T_RUN(min_angle_criterion);
    T_RUN(cut_without_separation);
    T_RUN(material_interface);
    T_EXIT();
}
