/* Path cuts on tri3 meshes (thesis ch. 3.1, 3.6): random polylines, cubic and
   rational Bezier paths in split and snap mode, and the degenerate cases (through
   nodes, along edges, tangent, partial, cross, overlapping, cut-out), with the
   invariants of every step: K_t and f_t from scratch == the accumulated updates,
   area, no sliver, conformity (angle sums), realised segments are mesh edges;
   Bezier and rational Bezier curves of any degree against the Bernstein sum,
   degree 1 and 2 against the line and the arc, a degree-5 cut. */
#include "t.h"
#include "cut_check.h"

static cholmod_common cm;

static int parse_text(const char *text, aug_path *p, aug_err *e)
{
    FILE *f = fmemopen((void *)text, strlen(text), "r");
    int rc = aug_path_parse(f, "path", p, e);
    fclose(f);
    return rc;
}

typedef struct res2 {
    int steps, error_step, flags;
    double seglen, min_eig;
    int64_t nseg;
} res2;

static int cmp_edge4(const void *a, const void *b)
{
    const double *x = a, *y = b;
    for (int k = 0; k < 4; k++)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

static void canon(double *q)
{
    if (q[0] > q[2] || (q[0] == q[2] && q[1] > q[3])) {
        double t0 = q[0], t1 = q[1];
        q[0] = q[2];
        q[1] = q[3];
        q[2] = t0;
        q[3] = t1;
    }
}

/* every realised segment is an edge of the mesh (same end coordinates) */
static int segs_are_edges(const aug_mesh *m, const double *seg, int64_t nseg)
{
    int64_t ne = m->ne * 3;
    double *E = malloc((size_t)(ne * 4) * sizeof *E);
    for (int64_t e = 0; e < m->ne; e++)
        for (int k = 0; k < 3; k++) {
            double *q = E + (e * 3 + k) * 4;
            memcpy(q, m->x + m->conn[e * 3 + k] * 2, 2 * sizeof *q);
            memcpy(q + 2, m->x + m->conn[e * 3 + (k + 1) % 3] * 2, 2 * sizeof *q);
            canon(q);
        }
    qsort(E, (size_t)ne, 4 * sizeof *E, cmp_edge4);
    int ok = 1;
    for (int64_t i = 0; i < nseg && ok; i++) {
        double q[4];
        memcpy(q, seg + i * 4, sizeof q);
        canon(q);
        ok = bsearch(q, E, (size_t)ne, 4 * sizeof *E, cmp_edge4) != NULL;
    }
    free(E);
    return ok;
}

static int chords; /* run_path: 1 = no kappa vertices (cut --chords) */

static int run_path(aug_mesh *m, const char *text, int mode, int steps, int policy, double pull,
                    res2 *res)
{
    aug_err e;
    aug_path path;
    cc_track T;
    aug_cutter C;
    aug_path_cut pc;
    memset(res, 0, sizeof *res);
    if (parse_text(text, &path, &e)) {
        T_CHECK(0, "parse: %s", e.msg);
        return -1;
    }
    if (cc_init(&T, m, &cm)) {
        T_CHECK(0, "%s", T.why);
        aug_path_free(&path);
        return -1;
    }
    aug_cutter_init(&C, m, T.nn0, T.map0, T.nfree0, &e);
    C.policy = policy;
    C.pull = pull;
    aug_path_cut_init(&pc, &path, mode, 0.05);
    pc.kappa = !chords;
    for (int step = 1; step <= steps && !t_cur_failed; step++) {
        aug_cut_step S;
        aug_cut_step_init(&S, step);
        aug_mesh before;
        cc_mesh_copy(&before, m);
        double s_to = path.total * step / steps;
        if (aug_path_step(&pc, &C.ed, s_to, &S.seg, &S.nseg, &e) || aug_cutter_apply(&C, &S, &e)) {
            T_CHECK(0, "step %d: %s", step, e.msg);
            aug_cut_step_free(&S);
            aug_mesh_free(&before);
            break;
        }
        int urc = aug_cutter_update(&C, &S, &e);
        if (urc == AUG_ESINGULAR) {
            /* only --detached error reports a piece; pin and drop must support it */
            T_CHECK(policy == AUG_DETACH_ERROR, "step %d: a piece left without support under pin/drop: %s",
                    step, e.msg);
            cc_track U;
            memset(&U, 0, sizeof U);
            U.n = U.cap = aug_cut_order(m, T.nn0, T.nfree0);
            U.K = calloc((size_t)(U.n * U.n), sizeof *U.K);
            cholmod_sparse *A = aug_assemble_cut(m, T.nn0, T.map0, T.nfree0, &cm, &e);
            cc_dense(A, U.K, U.n);
            cholmod_free_sparse(&A, &cm);
            res->min_eig = cc_min_eig_ratio(&U);
            free(U.K);
            res->error_step = step;
            aug_cut_step_free(&S);
            aug_mesh_free(&before);
            break;
        }
        if (urc) {
            T_CHECK(0, "step %d: %s", step, e.msg);
            aug_cut_step_free(&S);
            aug_mesh_free(&before);
            break;
        }
        res->flags |= S.d.flags;
        /* the library entry aug_update_build_bc on the mesh before gives the same bytes */
        aug_update u2;
        T_CHECK(aug_update_build_bc(&before, &S.d, &S.bc, T.nn0, T.map0, T.nfree0, NULL, &u2, &e) == 0, "%s", e.msg);
        int s2 = u2.m + u2.k;
        T_CHECK(u2.m == S.u.m && u2.k == S.u.k && !memcmp(u2.H, S.u.H, (size_t)u2.m * 4) &&
                    !memcmp(u2.E, S.u.E, (size_t)s2 * s2 * 8) && !memcmp(u2.df, S.u.df, (size_t)s2 * 8),
                "step %d: aug_update_build_bc differs", step);
        aug_update_free(&u2);
        T_CHECK(S.u.k == 2 * S.d.nnew, "step %d: k = %d for %lld new nodes", step, S.u.k,
                (long long)S.d.nnew);
        aug_mesh_free(&before);
        if (cc_apply(&T, &S.u) || cc_check(&T, m, &cm, step) || cc_check_angles(&T, m, step)) {
            T_CHECK(0, "%s", T.why);
            aug_cut_step_free(&S);
            break;
        }
        cc_faces ft = cc_count_faces(m);
        T_CHECK(ft.more == 0, "step %d: an edge in 3 or more triangles", step);
        T_CHECK(segs_are_edges(m, S.seg, S.nseg), "step %d: a realised segment is no mesh edge", step);
        for (int64_t i = 0; i < S.nseg; i++)
            res->seglen += hypot(S.seg[i * 4 + 2] - S.seg[i * 4], S.seg[i * 4 + 3] - S.seg[i * 4 + 1]);
        res->nseg += S.nseg;
        res->steps = step;
        aug_cut_step_free(&S);
    }
    aug_path_cut_free(&pc);
    aug_cutter_free(&C);
    cc_free(&T);
    aug_path_free(&path);
    return t_cur_failed ? -1 : 0;
}

/* nodes of m at exactly (x, y) */
static int nodes_at(const aug_mesh *m, double x, double y, double tol)
{
    int n = 0;
    for (int64_t i = 0; i < m->nn; i++) n += hypot(m->x[i * 2] - x, m->x[i * 2 + 1] - y) <= tol;
    return n;
}

static void parse_errors(void)
{
    static const char *bad[] = {"line 0 0 1\n", "bezier 0 0 1 1 2 2 3\n", "arc 0 0 1 0 1 1 0\n",
                                "circle 0 0 -1\n", "spline 0 0 1 1\n", "line 0 0 1 x\n",
                                "# nothing\n", "line 0 0 0 0\n", "polyline 0 0 1 1 2\n",
                                "line 0 0 1 nan\n", "bezier 0 0\n", "rbezier 0 0 1 1 1 0\n",
                                "rbezier 0 0 1 1 1\n", "bezier 1 1 1 1 1 1 1 1 1 1\n",
                                "line 0 0 1 1\nrbezier 0 0 1 1 1 -2\n"};
    static const int badline[] = {1, 1, 1, 1, 1, 1, 0, 1, 1, 1, 1, 1, 1, 1, 2};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        aug_path p;
        aug_err e;
        int rc = parse_text(bad[i], &p, &e);
        char want[32];
        snprintf(want, sizeof want, "path:%d:", badline[i]);
        T_CHECK(rc == AUG_EDATA && strncmp(e.msg, want, strlen(want)) == 0,
                "'%s' gave %d '%s'", bad[i], rc, e.msg);
    }
    aug_path p;
    aug_err e;
    T_CHECK(parse_text("# a comment\n\nline 0 0 1 0\nbezier 1 0 2 0 2 1 3 1 # tail\n"
                       "polyline 5 5 6 6 7 5\ncircle 0 0 1\narc 1 0 1 1 0 1 0.7071067811865476\n",
                       &p, &e) == 0, "%s", e.msg);
    T_CHECK(p.n == 2 + 2 + 4 + 1, "%d curves", p.n);
    int strokes = 0;
    for (int i = 0; i < p.n; i++) strokes += p.c[i].newstroke;
    T_CHECK(strokes == 3, "%d strokes", strokes); /* line+bezier, polyline, circle+arc */
    /* lengths: line 1; quarter arcs of the unit circle pi/2 */
    T_CHECK(fabs(p.s0[1] - 1) < 1e-12, "line length %g", p.s0[1]);
    T_CHECK(fabs(p.s0[8] - p.s0[4] - 2 * M_PI) < 1e-4, "circle length %g", p.s0[8] - p.s0[4]);
    aug_path_free(&p);
}

/* roots of curve/line meetings: on the line, and as many as sign changes */
static void curve_roots(void)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 17);
    int checked = 0;
    for (int it = 0; it < 3000 && !t_cur_failed; it++) {
        aug_curve c;
        memset(&c, 0, sizeof c);
        c.kind = 1 + it % 3;
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 2; k++) c.p[i][k] = gsl_rng_uniform(r);
        c.w = 0.2 + 2 * gsl_rng_uniform(r);
        double a[2] = {gsl_rng_uniform(r), gsl_rng_uniform(r)}, b[2] = {gsl_rng_uniform(r), gsl_rng_uniform(r)};
        double t[3];
        int n = aug_curve_line_roots(&c, a, b, 0, 1, t);
        double nx = -(b[1] - a[1]), ny = b[0] - a[0];
        for (int i = 0; i < n; i++) {
            double q[2];
            aug_curve_eval(&c, t[i], q);
            double g = nx * (q[0] - a[0]) + ny * (q[1] - a[1]);
            T_CHECK(fabs(g) < 1e-10, "kind %d: root %g off the line by %g", c.kind, t[i], g);
        }
        int changes = 0;
        double prev = 0;
        for (int k = 0; k <= 4000; k++) {
            double q[2];
            aug_curve_eval(&c, k / 4000.0, q);
            double g = nx * (q[0] - a[0]) + ny * (q[1] - a[1]);
            if (k > 0 && (g > 0) != (prev > 0)) changes++;
            prev = g;
        }
        /* tangencies aside, each sign change is a root and each root a change */
        if (n >= 0 && n == changes) checked++;
        else T_CHECK(n >= changes, "kind %d: %d roots, %d sign changes", c.kind, n, changes);
    }
    T_CHECK(checked > 2900, "only %d of 3000 root counts matched", checked);
    /* the quarter arc with w = cos 45 deg is on the circle */
    aug_curve q = {AUG_CURVE_RQUAD, {{2, 1}, {2, 2}, {1, 2}}, sqrt(0.5), 1, 0, 0, NULL};
    for (int k = 0; k <= 16; k++) {
        double p[2];
        aug_curve_eval(&q, k / 16.0, p);
        T_CHECK(fabs(hypot(p[0] - 1, p[1] - 1) - 1) < 1e-14, "arc point off the circle");
    }
    gsl_rng_free(r);
}

/* sum w_i P_i beta_{n,i}(t) / sum w_i beta_{n,i}(t) (thesis eqs. 3.5, 3.6), computed
   here from the binomials, independently of de Casteljau */
static void bernstein(const double (*P)[2], const double *W, int n, double t, double *xy)
{
    double num[2] = {0, 0}, den = 0, binom = 1;
    for (int i = 0; i <= n; i++) {
        double b = binom * pow(t, i) * pow(1 - t, n - i) * W[i];
        num[0] += b * P[i][0];
        num[1] += b * P[i][1];
        den += b;
        binom = binom * (n - i) / (i + 1);
    }
    xy[0] = num[0] / den;
    xy[1] = num[1] / den;
}

static int parse_one(const char *text, aug_path *p)
{
    aug_err e;
    int rc = parse_text(text, p, &e);
    T_CHECK(rc == 0 && p->n == 1, "'%.40s...': %s", text, e.msg);
    return rc == 0 && p->n == 1 ? 0 : -1;
}

/* bezier with 2(n+1) numbers, rbezier with n+1 (x y w): B(t) equals the Bernstein
   sum to 1e-13, B' and B'' equal central differences, the line roots lie on the
   line and are as many as the sign changes */
static void any_degree(void)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 5);
    int matched = 0, tried = 0;
    for (int it = 0; it < 400 && !t_cur_failed; it++) {
        int n = 1 + it % 9, rat = it % 2;
        if (it % 40 == 39) n = 20;
        double P[32][2], W[32];
        char text[4096];
        size_t off = (size_t)snprintf(text, sizeof text, rat ? "rbezier" : "bezier");
        for (int i = 0; i <= n; i++) {
            P[i][0] = gsl_rng_uniform(r);
            P[i][1] = gsl_rng_uniform(r);
            W[i] = rat ? 0.2 + 2 * gsl_rng_uniform(r) : 1;
            off += (size_t)snprintf(text + off, sizeof text - off, rat ? " %.17g %.17g %.17g" : " %.17g %.17g",
                                    P[i][0], P[i][1], W[i]);
        }
        snprintf(text + off, sizeof text - off, "\n");
        aug_path p;
        if (parse_one(text, &p)) break;
        const aug_curve *c = &p.c[0];
        T_CHECK((n == 3 && !rat) ? c->kind == AUG_CURVE_CUBIC : (c->kind == AUG_CURVE_BEZIER && c->deg == n),
                "degree %d: kind %d deg %d", n, c->kind, c->deg);
        for (int k = 0; k <= 20; k++) {
            double t = k / 20.0, a[2], b[2], d1[2], d2[2];
            bernstein((const double(*)[2])P, W, n, t, a);
            aug_curve_jet(c, t, b, d1, d2, NULL);
            T_CHECK(hypot(a[0] - b[0], a[1] - b[1]) < 1e-13, "degree %d rat %d: B(%g) off by %g", n, rat, t,
                    hypot(a[0] - b[0], a[1] - b[1]));
            double h = 1e-4, p1[2], m1[2], p0[2];
            if (t < h || t > 1 - h) continue;
            bernstein((const double(*)[2])P, W, n, t + h, p1);
            bernstein((const double(*)[2])P, W, n, t - h, m1);
            bernstein((const double(*)[2])P, W, n, t, p0);
            for (int j = 0; j < 2; j++) {
                double fd1 = (p1[j] - m1[j]) / (2 * h), fd2 = (p1[j] - 2 * p0[j] + m1[j]) / (h * h);
                double sc = 1 + fabs(d1[j]) + fabs(d2[j]);
                T_CHECK(fabs(fd1 - d1[j]) < 1e-5 * sc * n * n, "degree %d: B' %g vs %g", n, d1[j], fd1);
                T_CHECK(fabs(fd2 - d2[j]) < 1e-3 * sc * n * n, "degree %d: B'' %g vs %g", n, d2[j], fd2);
            }
        }
        double a[2] = {gsl_rng_uniform(r), gsl_rng_uniform(r)}, b[2] = {gsl_rng_uniform(r), gsl_rng_uniform(r)};
        double t[AUG_CURVE_MAXDEG];
        int nr = aug_curve_line_roots(c, a, b, 0, 1, t);
        double nx = -(b[1] - a[1]), ny = b[0] - a[0], prev = 0;
        for (int i = 0; i < nr; i++) {
            double q[2];
            bernstein((const double(*)[2])P, W, n, t[i], q);
            T_CHECK(fabs(nx * (q[0] - a[0]) + ny * (q[1] - a[1])) < 1e-10, "degree %d: root %g off the line", n, t[i]);
            T_CHECK(i == 0 || t[i] > t[i - 1], "degree %d: roots not increasing", n);
        }
        int changes = 0;
        for (int k = 0; k <= 4000; k++) {
            double q[2];
            bernstein((const double(*)[2])P, W, n, k / 4000.0, q);
            double g = nx * (q[0] - a[0]) + ny * (q[1] - a[1]);
            if (k > 0 && (g > 0) != (prev > 0)) changes++;
            prev = g;
        }
        tried++;
        if (nr == changes) matched++;
        else T_CHECK(nr >= changes, "degree %d: %d roots, %d sign changes", n, nr, changes);
        /* roots of a part [t0, t1] are those of [0, 1] inside it */
        double u[AUG_CURVE_MAXDEG];
        int nu = aug_curve_line_roots(c, a, b, 0.3, 0.7, u), want = 0;
        for (int i = 0; i < nr; i++) want += t[i] >= 0.3 && t[i] <= 0.7;
        T_CHECK(nu == want || nr != changes, "degree %d: %d roots in [0.3, 0.7], want %d", n, nu, want);
        aug_path_free(&p);
    }
    T_CHECK(matched >= tried - 4, "only %d of %d root counts matched", matched, tried);
    gsl_rng_free(r);
}

/* the final mesh of a one-step split cut */
static int cut_mesh(const char *text, aug_mesh *m)
{
    cc_square(m, 8, 8, 1, 1, NULL, 0);
    res2 res;
    return run_path(m, text, AUG_PATH_SPLIT, 3, AUG_DETACH_PIN, 0.0, &res);
}

static void same_mesh(const char *a, const char *b)
{
    aug_mesh ma, mb;
    cut_mesh(a, &ma);
    cut_mesh(b, &mb);
    T_CHECK(ma.nn == mb.nn && ma.ne == mb.ne, "'%s' vs '%s': %lld/%lld nodes, %lld/%lld elements", a, b,
            (long long)ma.nn, (long long)mb.nn, (long long)ma.ne, (long long)mb.ne);
    double d = 0;
    for (int64_t i = 0; i < ma.nn * 2 && ma.nn == mb.nn; i++) d = fmax(d, fabs(ma.x[i] - mb.x[i]));
    T_CHECK(d < 1e-12, "'%s' vs '%s': nodes differ by %g", a, b, d);
    T_CHECK(ma.ne != mb.ne || !memcmp(ma.conn, mb.conn, (size_t)ma.ne * 3 * sizeof *ma.conn),
            "'%s' vs '%s': connectivity differs", a, b);
    aug_mesh_free(&ma);
    aug_mesh_free(&mb);
}

/* degree 1 is the line, degree 2 the arc with w = 1, rbezier with equal weights
   the bezier, rbezier 1 w 1 the arc; a degree-5 curve (crossing itself) cuts
   with every step's invariants (run_path) in both modes */
static void low_degree(void)
{
    same_mesh("bezier 0.05 0.13 0.93 0.71\n", "line 0.05 0.13 0.93 0.71\n");
    same_mesh("bezier 0.1 0.2 0.5 1.1 0.9 0.3\n", "arc 0.1 0.2 0.5 1.1 0.9 0.3 1\n");
    same_mesh("rbezier 0.1 0.2 1 0.5 1.1 0.6 0.9 0.3 1\n", "arc 0.1 0.2 0.5 1.1 0.9 0.3 0.6\n");
    same_mesh("rbezier 0.1 0.2 2 0.4 0.9 2 0.6 -0.1 2 0.9 0.6 2\n", "bezier 0.1 0.2 0.4 0.9 0.6 -0.1 0.9 0.6\n");
    for (int mode = 0; mode < 2 && !t_cur_failed; mode++)
        for (int steps = 1; steps <= 7 && !t_cur_failed; steps += 3) {
            aug_mesh m;
            cc_square(&m, 8, 8, 1, 1, NULL, 0);
            res2 res;
            run_path(&m, "bezier 0.05 0.1 0.9 0.2 0.1 1.3 0.4 -0.5 1.1 0.8 0.95 0.9\n", mode, steps,
                     AUG_DETACH_PIN, 0.0, &res);
            T_CHECK(res.steps == steps && res.nseg > 10, "degree 5, mode %d: %d steps, %lld segments", mode,
                    res.steps, (long long)res.nseg);
            run_path(&m, "rbezier 0.9 0.05 1 0.1 0.3 3 0.9 0.6 0.5 0.2 0.95 2 0.6 0.5 1\n", mode, steps,
                     AUG_DETACH_PIN, 0.0, &res);
            T_CHECK(res.steps == steps, "rational degree 4 after degree 5, mode %d: %d steps", mode, res.steps);
            aug_mesh_free(&m);
        }
}

/* kappa of the cubic with control points P (thesis eq. 3.8 with the cube),
   from the power-basis derivatives, independently of the library */
static double cubic_kappa(const double (*P)[2], double t)
{
    double d1[2], d2[2];
    for (int k = 0; k < 2; k++) {
        double a1 = 3 * (P[1][k] - P[0][k]), a2 = 3 * (P[0][k] - 2 * P[1][k] + P[2][k]);
        double a3 = -P[0][k] + 3 * P[1][k] - 3 * P[2][k] + P[3][k];
        d1[k] = a1 + 2 * a2 * t + 3 * a3 * t * t;
        d2[k] = 2 * a2 + 6 * a3 * t;
    }
    return fabs(d1[0] * d2[1] - d1[1] * d2[0]) / pow(hypot(d1[0], d1[1]), 3);
}

/* the argmax of cubic_kappa on [t0, t1]: 100000 samples, then ternary search
   around the best to 1e-13 (the test's own search) */
static double dense_argmax(const double (*P)[2], double t0, double t1)
{
    int N = 100000, ib = 0;
    double kb = -1;
    for (int i = 0; i <= N; i++) {
        double k = cubic_kappa(P, t0 + (t1 - t0) * i / N);
        if (k > kb) {
            kb = k;
            ib = i;
        }
    }
    double a = t0 + (t1 - t0) * (ib > 0 ? ib - 1 : 0) / N, b = t0 + (t1 - t0) * (ib < N ? ib + 1 : N) / N;
    for (int it = 0; it < 200 && b - a > 1e-13; it++) {
        double m1 = a + (b - a) / 3, m2 = b - (b - a) / 3;
        if (cubic_kappa(P, m1) < cubic_kappa(P, m2)) a = m1;
        else b = m2;
    }
    return 0.5 * (a + b);
}

/* the maximum curvature point (thesis eq. 3.8): the symmetric arch has it at
   t = 1/2 with kappa = 6h / (1.5 (1 + a))^2 (closed form); random cubics
   agree with the dense search to 1e-10 in kappa (relative) and 1e-7 in t;
   kappa' = 0 there (central difference of cubic_kappa); circles and lines
   have none; the max at an end of [t0, t1] is not interior */
static void kappa_max(void)
{
    double a = 0.3, h = 0.6;
    aug_curve c = {AUG_CURVE_CUBIC, {{-1, 0}, {-a, h}, {a, h}, {1, 0}}, 0, 1, 0, 0, NULL};
    double tk, ex = 6 * h / pow(1.5 * (1 + a), 2);
    T_CHECK(aug_curve_kappa_max(&c, 0, 1, &tk) && fabs(tk - 0.5) < 1e-10, "arch: t %.17g", tk);
    T_CHECK(fabs(aug_curve_kappa(&c, tk) - ex) < 1e-12 * ex, "arch: kappa %.17g, closed form %.17g",
            aug_curve_kappa(&c, tk), ex);
    T_CHECK(fabs(dense_argmax((const double(*)[2])c.p, 0, 1) - 0.5) < 1e-7, "arch: the dense search disagrees");
    T_CHECK(aug_curve_kappa_max(&c, 0, 0.4, &tk) == 0, "arch: the max of [0, 0.4] is at its end");
    T_CHECK(aug_curve_kappa_max(&c, 0.3, 0.8, &tk) && fabs(tk - 0.5) < 1e-10, "arch on [0.3, 0.8]: %g", tk);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 9);
    int interior = 0;
    for (int it = 0; it < 60 && !t_cur_failed; it++) {
        aug_curve q;
        memset(&q, 0, sizeof q);
        q.kind = AUG_CURVE_CUBIC;
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 2; k++) q.p[i][k] = gsl_rng_uniform(r);
        double t0 = 0.5 * gsl_rng_uniform(r), t1 = t0 + 0.1 + 0.4 * gsl_rng_uniform(r);
        double td = dense_argmax((const double(*)[2])q.p, t0, t1);
        double kd = cubic_kappa((const double(*)[2])q.p, td);
        int in = aug_curve_kappa_max(&q, t0, t1, &tk);
        int din = td > t0 + 1e-6 && td < t1 - 1e-6;
        if (!in) {
            T_CHECK(!din || kd <= fmax(cubic_kappa((const double(*)[2])q.p, t0), cubic_kappa((const double(*)[2])q.p, t1)) * (1 + 1e-6),
                    "cubic %d: interior max at %g missed", it, td);
            continue;
        }
        interior++;
        double kt = cubic_kappa((const double(*)[2])q.p, tk), e = 1e-6 * (t1 - t0);
        T_CHECK(kt >= kd * (1 - 1e-10), "cubic %d: kappa %.17g at %g, dense %.17g at %g", it, kt, tk, kd, td);
        T_CHECK(fabs(tk - td) < 1e-7, "cubic %d: t %.17g, dense %.17g", it, tk, td);
        double dk = (cubic_kappa((const double(*)[2])q.p, tk + e) - cubic_kappa((const double(*)[2])q.p, tk - e)) / (2 * e);
        T_CHECK(fabs(dk) < 1e-4 * kt / (t1 - t0), "cubic %d: kappa' = %g at the max", it, dk);
    }
    T_CHECK(interior >= 10, "only %d interior maxima", interior);
    aug_curve arc = {AUG_CURVE_RQUAD, {{2, 1}, {2, 2}, {1, 2}}, sqrt(0.5), 1, 0, 0, NULL};
    aug_curve line = {AUG_CURVE_LINE, {{0, 0}, {1, 2}}, 0, 1, 0, 0, NULL};
    T_CHECK(!aug_curve_kappa_max(&arc, 0, 1, &tk) && !aug_curve_kappa_max(&line, 0, 1, &tk), "circle or line: a max");
    gsl_rng_free(r);
}

/* the cut gets a node at the curve's curvature maximum (inside one element
   piece, away from the edges), on the curve, and none under chords */
static void kappa_cut(void)
{
    static const char *text = "bezier 0.16 0.32 0.76 0.92 0.36 0.92 0.96 0.37\n";
    double P[4][2] = {{0.16, 0.32}, {0.76, 0.92}, {0.36, 0.92}, {0.96, 0.37}}, B[2];
    double td = dense_argmax((const double(*)[2])P, 0, 1);
    aug_curve c = {AUG_CURVE_CUBIC, {{0.16, 0.32}, {0.76, 0.92}, {0.36, 0.92}, {0.96, 0.37}}, 0, 1, 0, 0, NULL};
    aug_curve_eval(&c, td, B);
    for (int ch = 0; ch < 2 && !t_cur_failed; ch++) {
        aug_mesh m;
        cc_square(&m, 8, 8, 1, 1, NULL, 0);
        res2 res;
        chords = ch;
        run_path(&m, text, AUG_PATH_SPLIT, 1, AUG_DETACH_PIN, 0.0, &res);
        chords = 0;
        int at = nodes_at(&m, B[0], B[1], 1e-9);
        T_CHECK(ch ? at == 0 : at == 2, "chords %d: %d nodes at the curvature maximum (%.6f, %.6f), t %.6f", ch, at,
                B[0], B[1], td);
        aug_mesh_free(&m);
    }
}

static void random_text(gsl_rng *r, char *buf, size_t n)
{
    int nc = 1 + (int)gsl_rng_uniform_int(r, 3);
    size_t off = 0;
    double x0 = -0.2 + 1.4 * gsl_rng_uniform(r), y0 = -0.2 + 1.4 * gsl_rng_uniform(r);
    for (int i = 0; i < nc; i++) {
        double P[4][2];
        P[0][0] = x0;
        P[0][1] = y0;
        for (int k = 1; k < 4; k++) {
            P[k][0] = -0.2 + 1.4 * gsl_rng_uniform(r);
            P[k][1] = -0.2 + 1.4 * gsl_rng_uniform(r);
        }
        int kind = (int)gsl_rng_uniform_int(r, 3);
        if (kind == 0)
            off += snprintf(buf + off, n - off, "line %.6f %.6f %.6f %.6f\n", P[0][0], P[0][1], P[1][0], P[1][1]);
        else if (kind == 1)
            off += snprintf(buf + off, n - off, "bezier %.6f %.6f %.6f %.6f %.6f %.6f %.6f %.6f\n", P[0][0],
                            P[0][1], P[1][0], P[1][1], P[2][0], P[2][1], P[3][0], P[3][1]);
        else
            off += snprintf(buf + off, n - off, "arc %.6f %.6f %.6f %.6f %.6f %.6f %.3f\n", P[0][0], P[0][1],
                            P[1][0], P[1][1], P[2][0], P[2][1], 0.3 + gsl_rng_uniform(r));
        /* continue the stroke or start a new one */
        int last = kind == 0 ? 1 : (kind == 1 ? 3 : 2);
        if (gsl_rng_uniform(r) < 0.6) {
            x0 = P[last][0];
            y0 = P[last][1];
        } else {
            x0 = -0.2 + 1.4 * gsl_rng_uniform(r);
            y0 = -0.2 + 1.4 * gsl_rng_uniform(r);
        }
    }
}

static void random_paths(int mode)
{
    for (unsigned long seed = 1; seed <= 40 && !t_cur_failed; seed++) {
        gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
        gsl_rng_set(r, seed + 100 * mode);
        aug_mesh m;
        cc_square(&m, 8, 8, 1, 1, r, seed % 3 == 0 ? 0.01 : 0.0);
        char text[1024];
        random_text(r, text, sizeof text);
        res2 res;
        int steps = 3 + (int)gsl_rng_uniform_int(r, 8);
        run_path(&m, text, mode, steps, seed % 2 ? AUG_DETACH_PIN : AUG_DETACH_DROP,
                 seed % 4 == 1 ? 0.05 : 0.0, &res);
        if (t_cur_failed) fprintf(stderr, "seed %lu mode %d path:\n%s", seed, mode, text);
        aug_mesh_free(&m);
        gsl_rng_free(r);
    }
}

static void split_random(void) { random_paths(AUG_PATH_SPLIT); }
static void snap_random(void) { random_paths(AUG_PATH_SNAP); }

typedef struct dcase {
    const char *name, *text;
    double len;              /* length of the path inside the square (split mode), 0: skip */
} dcase;

static void degenerate(void)
{
    static const dcase cs[] = {
        {"along a grid line", "line 0 0.5 1 0.5\n", 1.0},
        {"along diagonal edges", "line -0.1 -0.1 1.1 1.1\n", M_SQRT2},
        {"through nodes across edges", "line 0 0.25 1 0.75\n", 0},
        {"partial inside", "line 0.3 0.3 0.6 0.45\n", 0.33541019662496846},
        {"ends on a node", "line 0.05 0.3 0.5 0.5\n", 0},
        {"ends mid-edge", "line 0.05 0.3 0.5625 0.5\n", 0},
        {"starts on a boundary node", "line 0 0.375 0.5 0.45\n", 0},
        {"cross", "line 0.1 0.55 0.9 0.55\nline 0.55 0.1 0.55 0.9\n", 1.6},
        {"overlap and re-cut",
         "line 0.05 0.4 0.7 0.4\nline 0.3 0.4 0.95 0.4\nline 0.2 0.1 0.2 0.9\n", 0},
        {"tangent bezier", "bezier 0.1 0.3 0.3 0.5666666666666667 0.5 0.5666666666666667 0.8 0.3\n", 0},
        {"tangent circle", "circle 0.5 0.5 0.3125\n", 0},
        {"zigzag polyline", "polyline 0.02 0.02 0.98 0.1 0.02 0.2 0.98 0.33 0.5 0.5\n", 0},
    };
    for (size_t i = 0; i < sizeof cs / sizeof cs[0] && !t_cur_failed; i++)
        for (int mode = 0; mode < 2 && !t_cur_failed; mode++)
            for (int steps = 1; steps <= 5 && !t_cur_failed; steps += 4) {
                aug_mesh m;
                cc_square(&m, 8, 8, 1, 1, NULL, 0);
                res2 res;
                run_path(&m, cs[i].text, mode, steps, AUG_DETACH_PIN, 0.0, &res);
                if (t_cur_failed) {
                    fprintf(stderr, "case '%s' mode %d steps %d\n", cs[i].name, mode, steps);
                    aug_mesh_free(&m);
                    break;
                }
                if (mode == AUG_PATH_SPLIT && cs[i].len > 0 && steps == 1)
                    T_CHECK(fabs(res.seglen - cs[i].len) < 1e-9, "'%s' steps %d: segments %.15g long, want %.15g",
                            cs[i].name, steps, res.seglen, cs[i].len);
                else if (mode == AUG_PATH_SPLIT && cs[i].len > 0) /* snapped step ends */
                    T_CHECK(fabs(res.seglen - cs[i].len) < 0.01 * cs[i].len, "'%s' steps %d: segments %.15g long, want %.15g",
                            cs[i].name, steps, res.seglen, cs[i].len);
                if (mode == AUG_PATH_SPLIT && i == 3) {
                    /* a partial cut: both tips stay single nodes, the opening between has two */
                    T_CHECK(nodes_at(&m, 0.3, 0.3, 1e-12) == 1 && nodes_at(&m, 0.6, 0.45, 1e-12) == 1,
                            "partial cut: tips duplicated");
                }
                if (mode == AUG_PATH_SPLIT && i == 7)
                    T_CHECK(nodes_at(&m, 0.55, 0.55, 1e-12) == 4, "cross: %d nodes at the crossing",
                            nodes_at(&m, 0.55, 0.55, 1e-12));
                if (i == 10) T_CHECK(res.flags & AUG_STEP_PINNED, "circle: disc not pinned");
                aug_mesh_free(&m);
            }
}

/* a circle punched out: under --detached error the closing step is reported,
   and K_t of that mesh is singular (smallest eigenvalue ~ 0) */
static void cut_out(void)
{
    for (int mode = 0; mode < 2 && !t_cur_failed; mode++) {
        aug_mesh m;
        cc_square(&m, 8, 8, 1, 1, NULL, 0);
        res2 res;
        run_path(&m, "circle 0.55 0.5 0.3\n", mode, 5, AUG_DETACH_ERROR, 0.0, &res);
        T_CHECK(res.error_step == 5, "mode %d: error at step %d", mode, res.error_step);
        T_CHECK(res.min_eig < 1e-13, "mode %d: reported, but K_t is regular (%g)", mode, res.min_eig);
        aug_mesh_free(&m);
    }
    for (int policy = 1; policy < 3 && !t_cur_failed; policy++) {
        aug_mesh m;
        cc_square(&m, 8, 8, 1, 1, NULL, 0);
        res2 res;
        run_path(&m, "circle 0.55 0.5 0.3\nline 0.3 0.5 0.8 0.5\n", AUG_PATH_SPLIT, 6, policy, 0.1, &res);
        T_CHECK(res.flags & AUG_STEP_DETACHED, "policy %d: flags %d", policy, res.flags);
        aug_mesh_free(&m);
    }
}

/* the planar cut on the 2-D square (a line n.x = d): invariants at every step,
   random nodes per step, the left part stays fixed, the right part's corner is
   pinned when the line cuts it off */
static void plane_2d(void)
{
    for (unsigned long seed = 1; seed <= 6 && !t_cur_failed; seed++) {
        gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
        gsl_rng_set(r, seed);
        aug_mesh m;
        aug_err e;
        cc_square(&m, 8, 8, 1, 1, r, 0.01);
        cc_track T;
        aug_cutter C;
        if (cc_init(&T, &m, &cm)) T_CHECK(0, "%s", T.why);
        aug_cutter_init(&C, &m, T.nn0, T.map0, T.nfree0, &e);
        C.policy = AUG_DETACH_PIN;
        C.pull = 0.02;
        double a = M_PI * gsl_rng_uniform(r), n[3] = {cos(a), sin(a), 0};
        double d = n[0] * (0.3 + 0.4 * gsl_rng_uniform(r)) + n[1] * (0.3 + 0.4 * gsl_rng_uniform(r));
        aug_plane_cut pc;
        T_CHECK(aug_plane_plan(&pc, &m, &C.adj, n, d, NULL, &e) == 0, "%s", e.msg);
        for (int step = 1; pc.next < pc.ncut && !t_cur_failed; step++) {
            aug_cut_step S;
            aug_cut_step_init(&S, step);
            T_CHECK(aug_plane_step(&pc, &C.ed, 1 + (int64_t)gsl_rng_uniform_int(r, 3), &S.seg, &S.nseg, &e) == 0 &&
                        aug_cutter_apply(&C, &S, &e) == 0 && aug_cutter_update(&C, &S, &e) == 0,
                    "step %d: %s", step, e.msg);
            if (!t_cur_failed && (cc_apply(&T, &S.u) || cc_check(&T, &m, &cm, step) || cc_check_angles(&T, &m, step)))
                T_CHECK(0, "seed %lu: %s", seed, T.why);
            T_CHECK(segs_are_edges(&m, S.seg, S.nseg), "step %d: a segment is no mesh edge", step);
            aug_cut_step_free(&S);
        }
        aug_plane_free(&pc);
        aug_cutter_free(&C);
        cc_free(&T);
        aug_mesh_free(&m);
        gsl_rng_free(r);
    }
}

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(parse_errors);
    T_RUN(curve_roots);
    T_RUN(any_degree);
    T_RUN(low_degree);
    T_RUN(kappa_max);
    T_RUN(kappa_cut);
    T_RUN(degenerate);
    T_RUN(split_random);
    T_RUN(snap_random);
    T_RUN(cut_out);
    T_RUN(plane_2d);
    cholmod_finish(&cm);
    T_EXIT();
}
