/* Blade and surface cuts (cut --blade, --surface): the crossing and distance
   tests against brute force, the blade's motion against the Bernstein
   formula, the swept area, blade files and STL, and whole-plane blade cuts of
   the brick against the planar cut (the same cut nodes, each duplicated
   once), with K_t from scratch == K_0 padded minus the accumulated updates
   (AMPS eq. 3.1) and the volume kept at every step. */
#include <string.h>
#include "t.h"
#include "cut_check.h"

static cholmod_common cm;

/* aug_point_tri against the least distance to 200 x 200 points of the
   triangle (barycentric grid), for points around it */
static void point_tri(void)
{
    double t[9] = {0, 0, 0, 1, 0.2, 0, 0.3, 0.9, 0.4};
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 7);
    for (int q = 0; q < 40 && !t_cur_failed; q++) {
        double p[3], best = INFINITY;
        for (int k = 0; k < 3; k++) p[k] = 3 * gsl_rng_uniform(r) - 1;
        for (int i = 0; i <= 200; i++)
            for (int j = 0; i + j <= 200; j++) {
                double a = i / 200.0, b = j / 200.0, d = 0;
                for (int k = 0; k < 3; k++) {
                    double x = t[k] + a * (t[3 + k] - t[k]) + b * (t[6 + k] - t[k]);
                    d += (x - p[k]) * (x - p[k]);
                }
                best = fmin(best, sqrt(d));
            }
        double d = aug_point_tri(p, t);
        T_CHECK(d <= best + 1e-12 && d >= best - 0.01, "point %d: %g, sampled %g", q, d, best);
    }
    gsl_rng_free(r);
}

/* crossings: through the inside, beside it, an end on the plane (the - side),
   both ends on one side */
static void seg_tri(void)
{
    double t[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, s;
    double a[3] = {0.2, 0.2, -1}, b[3] = {0.2, 0.2, 3}, c[3] = {0.8, 0.8, -1}, d[3] = {0.8, 0.8, 1};
    T_CHECK(aug_seg_tri(a, b, t, 1e-12, &s) == 1 && fabs(s - 0.25) < 1e-15, "inside: s = %g", s);
    T_CHECK(aug_seg_tri(c, d, t, 1e-12, &s) == 0, "beside it accepted");
    double on[3] = {0.2, 0.2, 0}, up[3] = {0.2, 0.2, 1}, down[3] = {0.2, 0.2, -1}, up2[3] = {0.3, 0.2, 2};
    T_CHECK(aug_seg_tri(on, up, t, 1e-12, &s) == 1, "on the plane to the + side: no crossing");
    T_CHECK(aug_seg_tri(on, down, t, 1e-12, &s) == 0, "on the plane to the - side: a crossing");
    T_CHECK(aug_seg_tri(up, up2, t, 1e-12, &s) == 0, "one side crosses");
    double edge[3] = {0.5, 0.5, -1}, edge2[3] = {0.5, 0.5, 1};
    T_CHECK(aug_seg_tri(edge, edge2, t, 1e-12, &s) == 1, "through the hypotenuse: missed");
}

/* the blade's ends: straight keys interpolate; one curve line is the
   quadratic Bezier (1-u)^2 P0 + 2u(1-u) P1 + u^2 P2; the area swept by a
   blade of length 2 translating by 3 is 6 */
static void blade_motion(void)
{
    const char *txt = "# test\nblade 0 0 0  2 0 0\ncurve 0 2 1  2 2 1\nblade 0 0 2  2 0 2\nblade 0 3 2  2 3 2\n";
    FILE *f = fmemopen((void *)txt, strlen(txt), "r");
    aug_blade b;
    aug_err e;
    T_CHECK(aug_blade_parse(f, "mem", &b, &e) == 0, "%s", e.msg);
    fclose(f);
    if (t_cur_failed) return;
    T_CHECK(b.nkey == 3 && b.nctrl[0] == 1 && b.nctrl[1] == 0, "keys %d", b.nkey);
    double p[6];
    aug_blade_at(&b, 0.25, p); /* u = 0.5 of the curved interval */
    T_CHECK(fabs(p[1] - 1.0) < 1e-15 && fabs(p[2] - 1.0) < 1e-15 && fabs(p[3] - 2) < 1e-15,
            "quadratic at 1/2: (%g %g %g)", p[0], p[1], p[2]);
    aug_blade_at(&b, 0.875, p); /* u = 0.75 of the straight interval */
    T_CHECK(fabs(p[1] - 2.25) < 1e-15 && fabs(p[2] - 2) < 1e-15, "straight at 3/4: y %g", p[1]);
    aug_soup s = {0};
    T_CHECK(aug_blade_sweep(&b, 0.5, 1, &s) == 0 && s.n == 2, "%lld triangles, want 2", (long long)s.n);
    double area = 0;
    for (int64_t i = 0; i < s.n; i++) {
        const double *t = s.t + 9 * i;
        double u[3], v[3];
        for (int k = 0; k < 3; k++) u[k] = t[3 + k] - t[k], v[k] = t[6 + k] - t[k];
        area += 0.5 * sqrt(pow(u[1] * v[2] - u[2] * v[1], 2) + pow(u[2] * v[0] - u[0] * v[2], 2) +
                           pow(u[0] * v[1] - u[1] * v[0], 2));
    }
    T_CHECK(fabs(area - 6) < 1e-12, "swept area %g, want 6", area);
    s.n = 0;
    T_CHECK(aug_blade_sweep(&b, 0, 0.5, &s) == 0 && s.n == 2 * AUG_BLADE_SUB, "curved: %lld triangles",
            (long long)s.n);
    aug_soup_free(&s);
    aug_blade_free(&b);
    const char *bad[] = {"blade 0 0 0 1 1 1\n", "curve 0 0 0 1 1 1\nblade 0 0 0 1 1 1\nblade 1 1 1 2 2 2\n",
                         "blade 0 0 0 1 1 1\nblade 0 0 0 1 1\n", "blade 0 0 0 1 1 1\nblade 0 0 0 1 1 1\ncurve 0 0 0 1 1 1\n"};
    for (int i = 0; i < 4; i++) {
        f = fmemopen((void *)bad[i], strlen(bad[i]), "r");
        T_CHECK(aug_blade_parse(f, "bad", &b, &e) == AUG_EUSAGE && strstr(e.msg, "bad"), "bad file %d accepted", i);
        fclose(f);
    }
}

/* a binary STL of two triangles read back */
static void stl(void)
{
    char path[] = "/tmp/cut_blade_XXXXXX";
    int fd = mkstemp(path);
    T_CHECK(fd >= 0, "mkstemp");
    if (fd < 0) return;
    FILE *f = fdopen(fd, "wb");
    unsigned char head[84] = {0};
    head[80] = 2;
    fwrite(head, 1, 84, f);
    float v[2][12] = {{0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 0}};
    for (int i = 0; i < 2; i++) {
        fwrite(v[i], 4, 12, f);
        fwrite(head, 1, 2, f);
    }
    fclose(f);
    aug_soup s = {0};
    aug_err e;
    T_CHECK(aug_stl_read(path, &s, &e) == 0 && s.n == 2 && s.t[9 + 3] == 1 && s.t[9 + 4] == 1, "%s", e.msg);
    remove(path);
    aug_soup_free(&s);
}

/* the plane x = x0 as one blade stroke across the whole brick, in `steps`
   steps: every step checked; returns the nodes added */
static int64_t plane_blade(int mode, double x0, int steps, int64_t *nadd, double *vmin_ratio)
{
    aug_mesh m;
    aug_err e;
    cc_brick(&m, 4, 4, 8, 1, 1, 2, NULL, 0);
    cc_track T;
    if (cc_init(&T, &m, &cm)) {
        T_CHECK(0, "%s", T.why);
        return -1;
    }
    double v0min;
    double v0 = cc_total_measure(&m, &v0min);
    aug_cutter C;
    aug_cutter_init(&C, &m, T.nn0, T.map0, T.nfree0, &e);
    aug_blade_cut bc;
    T_CHECK(aug_blade_cut_init(&bc, &m, mode, 0.2, &e) == 0, "%s", e.msg);
    aug_blade b = {0};
    double key[12] = {x0, -1, 2.5, x0, 2, 2.5, x0, -1, -0.5, x0, 2, -0.5};
    int nctrl[1] = {0};
    double ctrl[AUG_BLADE_MAXCTRL * 6];
    b.nkey = 2, b.key = key, b.nctrl = nctrl, b.ctrl = ctrl;
    aug_soup s = {0};
    int64_t nn0 = m.nn, ne0 = m.ne;
    for (int step = 1; step <= steps && !t_cur_failed; step++) {
        aug_cut_step S;
        aug_cut_step_init(&S, step);
        s.n = 0;
        aug_blade_sweep(&b, (step - 1.0) / steps, (double)step / steps, &s);
        if (aug_blade_cut_step(&bc, &C.ed, &C.fn, s.t, s.n, &S.seg, &S.nseg, &e) || aug_cutter_apply(&C, &S, &e) ||
            aug_cutter_update(&C, &S, &e)) {
            T_CHECK(0, "step %d: %s", step, e.msg);
            aug_cut_step_free(&S);
            break;
        }
        if (cc_apply(&T, &S.u) || cc_check(&T, &m, &cm, step)) T_CHECK(0, "%s", T.why);
        double vmin;
        T_CHECK(fabs(cc_total_measure(&m, &vmin) - v0) < 1e-12 * v0 && vmin > 0, "step %d: volume", step);
        *vmin_ratio = vmin / v0min;
        aug_cut_step_free(&S);
    }
    *nadd = m.ne - ne0;
    int64_t nnew = m.nn - nn0;
    aug_soup_free(&s);
    aug_blade_cut_free(&bc);
    aug_cutter_free(&C);
    cc_free(&T);
    aug_mesh_free(&m);
    return nnew;
}

/* the number of cut nodes of the planar cut x = x0 of the same brick */
static int64_t plane_nodes(double x0)
{
    aug_mesh m;
    aug_err e;
    cc_brick(&m, 4, 4, 8, 1, 1, 2, NULL, 0);
    aug_adj adj;
    aug_adj_build(&adj, &m);
    aug_plane_cut pc;
    double n[3] = {1, 0, 0};
    T_CHECK(aug_plane_plan(&pc, &m, &adj, n, x0, NULL, &e) == 0, "%s", e.msg);
    int64_t k = pc.ncut;
    aug_plane_free(&pc);
    aug_adj_free(&adj);
    aug_mesh_free(&m);
    return k;
}

/* snap: a blade sweeping x = 0.6 opens the faces the plane x = 0.6 would,
   each cut node once (both halves keep their support); split through the
   grid nodes (x = 0.5, degenerate: through nodes, along faces) adds no
   element and duplicates the plane's nodes; split at x = 0.6 inserts nodes
   and no sliver (a volume fraction >= 0.2^2 of the least) */
static void plane_blades(void)
{
    int64_t nadd;
    double ratio;
    int64_t want = plane_nodes(0.6), got = plane_blade(AUG_PATH_SNAP, 0.6, 4, &nadd, &ratio);
    T_CHECK(got == want && nadd == 0, "snap: %lld new nodes, the plane cuts %lld; %lld elements added",
            (long long)got, (long long)want, (long long)nadd);
    want = plane_nodes(0.5);
    got = plane_blade(AUG_PATH_SPLIT, 0.5, 3, &nadd, &ratio);
    T_CHECK(got == want && nadd == 0, "split through nodes: %lld new nodes (want %lld), %lld elements added",
            (long long)got, (long long)want, (long long)nadd);
    got = plane_blade(AUG_PATH_SPLIT, 0.6, 5, &nadd, &ratio);
    T_CHECK(got > 0 && nadd > 0 && ratio >= 0.04 - 1e-12, "split at 0.6: %lld nodes, %lld elements, least volume %g",
            (long long)got, (long long)nadd, ratio);
}

int main(void)
{
    cholmod_start(&cm);
    cm.print = 0;
    cm.error_handler = NULL;
    T_RUN(point_tri);
    T_RUN(seg_tri);
    T_RUN(blade_motion);
    T_RUN(stl);
    T_RUN(plane_blades);
    cholmod_finish(&cm);
    T_EXIT();
}
