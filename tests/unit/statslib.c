/* Unit tests of the stats layer (quality summary, step table, dump, summary,
   VTK, .pvd series, Matrix Market) on hand-made elements and streams. Also the generator of the streams
   the stats_*.test shell tests read:
     statslib gen3 FILE [deflate] [slow]   3-D stream with every record type
     statslib gen2 FILE                    2-D stream (two triangles)
   (slow: other tIMe values, the rest byte-identical). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "augcut.h"
#include "t.h"

#define DEG (180.0 / M_PI)

static int32_t *i32dup(const int32_t *v, size_t n)
{
    int32_t *p = malloc((n ? n : 1) * sizeof *p);
    memcpy(p, v, n * sizeof *p);
    return p;
}

static double *f64dup(const double *v, size_t n)
{
    double *p = malloc((n ? n : 1) * sizeof *p);
    memcpy(p, v, n * sizeof *p);
    return p;
}

static void add_set(aug_mesh *m, const char *name, const int32_t *v, int64_t n)
{
    m->sets = realloc(m->sets, (size_t)(m->nset + 1) * sizeof *m->sets);
    aug_set *s = &m->sets[m->nset++];
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "%s", name);
    s->n = n;
    s->nodes = i32dup(v, (size_t)n);
}

static void add_mat(aug_mesh *m, int id, const char *name, double E, double nu, double rho, double t)
{
    m->mats = realloc(m->mats, (size_t)(m->nmat + 1) * sizeof *m->mats);
    aug_material *a = &m->mats[m->nmat++];
    memset(a, 0, sizeof *a);
    a->id = id;
    snprintf(a->name, sizeof a->name, "%s", name);
    a->E = E, a->nu = nu, a->rho = rho, a->t = t;
}

/* regular tet (edge 2 sqrt 2, volume 8/3) and the corner tet of the unit cube
   (volume 1/6) shifted to x = 3; nelem = 1 or 2 of them (which = 0 both,
   1 only the regular one, 2 only the right one) */
static void mesh3(aug_mesh *m, int which)
{
    static const double x[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1,
                               3, 0, 0, 4, 0, 0, 3, 1, 0, 3, 0, 1};
    static const int32_t conn[] = {0, 1, 3, 2, 4, 5, 6, 7}, mat[] = {0, 1};
    aug_mesh_init(m);
    m->dim = 3, m->etype = AUG_TET4, m->nv = 4;
    m->nn = 8;
    m->x = f64dup(x, 24);
    int first = which == 2 ? 1 : 0, ne = which == 0 ? 2 : 1;
    m->ne = ne;
    m->conn = i32dup(conn + 4 * first, (size_t)ne * 4);
    m->mat = i32dup(mat + first, (size_t)ne);
    add_mat(m, 1, "steel", 2e11, 0.3, 7800, 1);
    add_mat(m, 7, "rubber", 1e6, 0.45, 1100, 1);
    m->have = AUG_HAVE_NODE | AUG_HAVE_ELEM | AUG_HAVE_MATL;
}

/* right isosceles triangle (legs 1) and an equilateral one (side 1) */
static void mesh2(aug_mesh *m)
{
    const double h = sqrt(3) / 2;
    const double x[] = {0, 0, 1, 0, 0, 1, 2, 0, 3, 0, 2.5, h};
    static const int32_t conn[] = {0, 1, 2, 3, 4, 5}, mat[] = {0, 0};
    aug_mesh_init(m);
    m->dim = 2, m->etype = AUG_TRI3, m->nv = 3;
    m->nn = 6;
    m->x = f64dup(x, 12);
    m->ne = 2;
    m->conn = i32dup(conn, 6);
    m->mat = i32dup(mat, 2);
    add_mat(m, 3, "sheet", 70e9, 0.33, 2700, 0.002);
    m->have = AUG_HAVE_NODE | AUG_HAVE_ELEM | AUG_HAVE_MATL;
}

static void put(aug_writer *w, const char *type, int32_t step, aug_buf *b)
{
    aug_err e;
    if (b->failed || aug_write(w, type, step, b->p, b->len, &e)) {
        fprintf(stderr, "statslib: write %s failed\n", type);
        exit(1);
    }
    aug_buf_free(b);
}

static void kv(aug_writer *w, const char *type, int32_t step, const char *tag, int n,
               const char **keys, const double *vals)
{
    aug_kv k;
    aug_err e;
    aug_kv_init(&k, tag);
    for (int i = 0; i < n; i++) aug_kv_set(&k, keys[i], vals[i]);
    if (aug_write_kv(w, type, step, &k, &e)) exit(1);
}

/* tridiagonal K = tridiag(-1, 4, -1) of order n: its LDL' has d_0 = 4,
   l_{j+1,j} = -1/d_j, d_{j+1} = 4 - 1/d_j */
static void matrix_records(aug_writer *w, const aug_mesh *m)
{
    aug_buf b;
    int64_t nd = m->nn * m->dim;
    int32_t *map = malloc((size_t)nd * sizeof *map);
    int64_t n = aug_dofmap(m, map);
    aug_buf_init(&b);
    aug_buf_i32(&b, m->dim), aug_buf_i32(&b, 0), aug_buf_i64(&b, nd), aug_buf_i64(&b, n);
    aug_buf_i32v(&b, map, (size_t)nd);
    put(w, "DOFM", AUG_NOSTEP, &b);
    free(map);
    aug_buf_init(&b);
    aug_buf_i32(&b, 0), aug_buf_i32(&b, 1), aug_buf_i64(&b, n), aug_buf_i64(&b, 2 * n - 1);
    for (int64_t j = 0; j <= n; j++) aug_buf_i64(&b, j == 0 ? 0 : 2 * j - 1);
    for (int64_t j = 0; j < n; j++) {
        if (j > 0) aug_buf_i32(&b, (int32_t)(j - 1));
        aug_buf_i32(&b, (int32_t)j);
    }
    for (int64_t j = 0; j < n; j++) {
        if (j > 0) aug_buf_f64(&b, -1);
        aug_buf_f64(&b, 4);
    }
    put(w, "KMAT", AUG_NOSTEP, &b);
    aug_buf_init(&b);
    aug_buf_i32(&b, 0), aug_buf_i32(&b, 0), aug_buf_i64(&b, n);
    for (int64_t i = 0; i < n; i++) aug_buf_f64(&b, (double)(i + 1));
    put(w, "FVEC", AUG_NOSTEP, &b);
    aug_buf_init(&b);
    aug_buf_i64(&b, n), aug_buf_i64(&b, 2 * n - 1), aug_buf_i32(&b, 0), aug_buf_i32(&b, 0);
    for (int64_t i = 0; i < n; i++) aug_buf_i32(&b, (int32_t)i);
    for (int64_t j = 0; j <= n; j++) aug_buf_i64(&b, j < n ? 2 * j : 2 * n - 1);
    for (int64_t j = 0; j < n; j++) {
        aug_buf_i32(&b, (int32_t)j);
        if (j + 1 < n) aug_buf_i32(&b, (int32_t)(j + 1));
    }
    double d = 4;
    for (int64_t j = 0; j < n; j++) {
        aug_buf_f64(&b, d);
        if (j + 1 < n) aug_buf_f64(&b, -1 / d);
        d = 4 - 1 / d;
    }
    put(w, "FACT", AUG_NOSTEP, &b);
    const char *ck[] = {"lambda_max", "lambda_min", "cond"};
    double cv[] = {6, 2, 3};
    kv(w, "cOND", AUG_NOSTEP, "lanczos", 3, ck, cv);
}

static void field(aug_writer *w, int32_t step, int dim, int64_t count, const int32_t *node,
                  double scale)
{
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, 0), aug_buf_i32(&b, dim), aug_buf_i64(&b, count);
    aug_buf_i32(&b, node != NULL), aug_buf_i32(&b, 0);
    if (node) aug_buf_i32v(&b, node, (size_t)count);
    for (int64_t i = 0; i < count * dim; i++) aug_buf_f64(&b, scale * (double)(i + 1));
    put(w, "fELD", step, &b);
}

/* every record type of formats/stream.md on the two tets; slow scales the times */
static void gen3(FILE *f, int deflate, double slow)
{
    aug_err e;
    aug_writer *w = aug_writer_open(f, "statslib", &e);
    if (!w) exit(1);
    if (deflate) aug_writer_deflate(w, 1);
    char *argv[] = {"statslib", "gen3", "--test"};
    if (aug_write_prov(w, 3, argv, &e)) exit(1);
    if (aug_write(w, "xTRa", AUG_NOSTEP, "hi\0\x01\xff", 5, &e)) exit(1);
    aug_mesh m;
    mesh3(&m, 0);
    static const int32_t base[] = {4, 5, 6}, tip[] = {7}, all[] = {0, 1, 2, 3, 4, 5, 6, 7};
    add_set(&m, "base", base, 3);
    add_set(&m, "tip", tip, 1);
    add_set(&m, "boundary", all, 8);
    static const int32_t fd[] = {12, 13, 14, 15, 16, 17, 18, 19, 20}, ld[] = {0, 23};
    static const double fv[] = {0.001, 0, 0, 0, 0, 0, 0, 0, 0}, lv[] = {2.5, -10};
    m.nfix = 9, m.fix_dof = i32dup(fd, 9), m.fix_val = f64dup(fv, 9);
    m.nload = 2, m.load_dof = i32dup(ld, 2), m.load_val = f64dup(lv, 2);
    m.out_kind = AUG_OUT_SET, m.nout = 1, m.out_nodes = i32dup(tip, 1);
    snprintf(m.out_name, sizeof m.out_name, "tip");
    m.have |= AUG_HAVE_FIXD | AUG_HAVE_LOAD | AUG_HAVE_OUTS;
    if (aug_mesh_write(w, &m, &e)) exit(1);
    matrix_records(w, &m);
    /* step 0: the intact solve */
    field(w, 0, 3, 8, NULL, 1e-3);
    const char *sk[] = {"m", "k", "relres", "iters", "converged", "closure"};
    double a0[] = {0, 0, 1e-16, 1, 1}, p0[] = {0, 0, 1e-9, 12, 1};
    kv(w, "sTAt", 0, "amps", 5, sk, a0);
    kv(w, "sTAt", 0, "pcg", 5, sk, p0);
    const char *tk[] = {"time_ms", "solve_ms"};
    double ta0[] = {1.5 * slow, 1 * slow}, tp0[] = {3 * slow};
    kv(w, "tIMe", 0, "amps", 2, tk, ta0);
    kv(w, "tIMe", 0, "pcg", 1, tk, tp0);
    /* step 1: one new node (copy of the tip), element 1 re-wired to it, one added */
    aug_mdelta d;
    aug_mdelta_init(&d);
    d.step = 1;
    int32_t par[] = {7}, el[] = {1}, cn[] = {4, 5, 6, 8}, ca[] = {4, 5, 6, 7}, ma[] = {1};
    double nx[] = {3, 0, 1.5};
    d.nnew = 1, d.parent = par, d.x = nx;
    d.nmod = 1, d.elem = el, d.conn = cn;
    d.nadd = 1, d.conn_add = ca, d.mat_add = ma;
    d.flags = AUG_STEP_DETACHED;
    if (aug_write_mdelta(w, 3, 4, &d, &e)) exit(1);
    aug_update u;
    aug_update_init(&u);
    int32_t H[] = {0, 2};
    double E[25], df[] = {0, 0, 0, 0, -1};
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 5; j++) E[i + 5 * j] = 1.0 / (1 + i + j);
    u.step = 1, u.m = 2, u.k = 3, u.H = H, u.E = E, u.df = df;
    if (aug_write_update(w, &u, &e)) exit(1);
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, 3), aug_buf_i32(&b, 0), aug_buf_i64(&b, 2);
    for (int i = 0; i < 12; i++) aug_buf_f64(&b, 0.25 * i);
    put(w, "pATH", 1, &b);
    static const int32_t fn[] = {7, 8};
    field(w, 1, 3, 2, fn, -2e-3);
    double a1[] = {2, 3, 2e-16, 1, 1, 7}, p1[] = {2, 3, 0.5, 500, 0};
    double ta1[] = {2.5 * slow}, tp1[] = {9 * slow};
    kv(w, "sTAt", 1, "amps", 6, sk, a1);
    kv(w, "tIMe", 1, "pcg", 1, tk, tp1); /* before its sTAt: matched by (step, tag) */
    kv(w, "sTAt", 1, "pcg", 5, sk, p1);
    kv(w, "tIMe", 1, "amps", 1, tk, ta1);
    const char *qk[] = {"aspect_max", "min_angle"};
    double qv[] = {1.3660254037844386, 54.735610317245346};
    kv(w, "qUAl", 1, "refine", 2, qk, qv);
    aug_buf_init(&b);
    /* MODE (formats 7.5): domain 0, frame 1, 3-D, kind 0, nodes 0 and 3, one mode */
    aug_buf_i32(&b, 0), aug_buf_i32(&b, 1), aug_buf_i32(&b, 3), aug_buf_i32(&b, 0);
    aug_buf_i64(&b, 2), aug_buf_i32(&b, 1), aug_buf_i32(&b, 0);
    aug_buf_i32v(&b, (int32_t[]){0, 3}, 2);
    aug_buf_f64v(&b, (double[]){0.5, 1, 0, 0, 0, 0.25, 0}, 7);
    put(w, "MODE", 1, &b);
    if (aug_write(w, "zNOt", AUG_NOSTEP, "", 0, &e)) exit(1);
    if (aug_writer_close(w, &e)) exit(1);
    aug_writer_free(w);
    aug_mesh_free(&m);
}

static void gen2(FILE *f)
{
    aug_err e;
    aug_writer *w = aug_writer_open(f, "statslib", &e);
    if (!w) exit(1);
    aug_mesh m;
    mesh2(&m);
    static const int32_t fd[] = {0, 1}, ld[] = {9};
    static const double fv[] = {0, 0}, lv[] = {-1};
    m.nfix = 2, m.fix_dof = i32dup(fd, 2), m.fix_val = f64dup(fv, 2);
    m.nload = 1, m.load_dof = i32dup(ld, 1), m.load_val = f64dup(lv, 1);
    m.have |= AUG_HAVE_FIXD | AUG_HAVE_LOAD;
    if (aug_mesh_write(w, &m, &e)) exit(1);
    field(w, 0, 2, 6, NULL, 1e-2);
    if (aug_writer_close(w, &e)) exit(1);
    aug_writer_free(w);
    aug_mesh_free(&m);
}

/* the streams above in memory */

static char *mem_stream(int which, int deflate, size_t *len)
{
    char *p = NULL;
    FILE *f = open_memstream(&p, len);
    if (which == 3) gen3(f, deflate, 1);
    else gen2(f);
    fclose(f);
    return p;
}

static double q_of(const aug_mesh *m, int64_t e, int angle)
{
    aug_quality q;
    aug_elem_quality(m, e, &q);
    return angle ? q.min_angle : q.aspect;
}

static void test_quality_regular_tet(void)
{
    aug_mesh m;
    mesh3(&m, 1);
    aug_qstats s;
    aug_mesh_qstats(&m, &s);
    double dih = acos(1.0 / 3) * DEG;
    T_CHECK(fabs(s.asp_min - 1) < 1e-12 && fabs(s.asp_max - 1) < 1e-12, "aspect %g", s.asp_min);
    T_CHECK(fabs(s.ang_min - dih) < 1e-10, "dihedral %.12g vs %.12g", s.ang_min, dih);
    T_CHECK(fabs(s.ang_min - 70.5288) < 1e-4, "dihedral %.6g", s.ang_min);
    T_CHECK(fabs(s.measure - 8.0 / 3) < 1e-12, "volume %g", s.measure);
    T_CHECK(s.asp_hist[0] == 1 && s.ang_hist[7] == 1, "histogram bins");
    T_CHECK(fabs(s.edge_ratio_max - 1) < 1e-12, "edge ratio %g", s.edge_ratio_max);
    aug_mesh_free(&m);
}

static void test_quality_right_tet(void)
{
    aug_mesh m;
    mesh3(&m, 2);
    /* circumradius sqrt(3)/2, inradius 1/(3+sqrt 3): R/(3r) = (1+sqrt 3)/2;
       dihedrals 90 at the three axis edges, acos(1/sqrt 3) at the slanted face */
    double asp = (1 + sqrt(3)) / 2, dih = acos(1 / sqrt(3)) * DEG;
    T_CHECK(fabs(q_of(&m, 0, 0) - asp) < 1e-12, "aspect %.15g vs %.15g", q_of(&m, 0, 0), asp);
    T_CHECK(fabs(q_of(&m, 0, 1) - dih) < 1e-10, "dihedral %.15g vs %.15g", q_of(&m, 0, 1), dih);
    aug_qstats s;
    aug_mesh_qstats(&m, &s);
    T_CHECK(fabs(s.measure - 1.0 / 6) < 1e-15, "volume %g", s.measure);
    T_CHECK(s.asp_hist[1] == 1 && s.ang_hist[5] == 1, "histogram bins");
    T_CHECK(fabs(s.edge_ratio_max - sqrt(2)) < 1e-12, "edge ratio %g", s.edge_ratio_max);
    aug_mesh_free(&m);
}

static void test_quality_two_tets(void)
{
    aug_mesh m;
    mesh3(&m, 0);
    aug_qstats s;
    aug_mesh_qstats(&m, &s);
    double a1 = (1 + sqrt(3)) / 2;
    T_CHECK(s.ne == 2 && s.nbad == 0, "counts");
    T_CHECK(fabs(s.asp_mean - (1 + a1) / 2) < 1e-12, "mean aspect %g", s.asp_mean);
    T_CHECK(fabs(s.ang_min - acos(1 / sqrt(3)) * DEG) < 1e-10, "min dihedral");
    T_CHECK(fabs(s.ang_max - acos(1.0 / 3) * DEG) < 1e-10, "max of min dihedrals");
    T_CHECK(fabs(s.measure - (8.0 / 3 + 1.0 / 6)) < 1e-12, "volume");
    aug_mesh_free(&m);
}

static void test_quality_triangles(void)
{
    aug_mesh m;
    mesh2(&m);
    T_CHECK(fabs(q_of(&m, 0, 1) - 45) < 1e-12, "right triangle min angle %.15g", q_of(&m, 0, 1));
    T_CHECK(fabs(q_of(&m, 0, 0) - sqrt(2)) < 1e-14, "right triangle edge ratio");
    T_CHECK(fabs(q_of(&m, 1, 1) - 60) < 1e-12, "equilateral min angle %.15g", q_of(&m, 1, 1));
    T_CHECK(fabs(q_of(&m, 1, 0) - 1) < 1e-14, "equilateral edge ratio");
    aug_qstats s;
    aug_mesh_qstats(&m, &s);
    T_CHECK(fabs(s.measure - (0.5 + sqrt(3) / 4)) < 1e-14, "area %g", s.measure);
    T_CHECK(s.ang_hist[4] == 1 && s.ang_hist[6] == 1, "angle bins 45 -> [40,50), 60 -> [60,70)");
    T_CHECK(s.asp_hist[0] == 1 && s.asp_hist[1] == 1, "aspect bins");
    aug_mesh_free(&m);
}

static void test_hist_bins(void)
{
    T_CHECK(aug_qhist_bin(aug_qhist_angle, 59.999999999999993) == 6, "60 minus round-off");
    T_CHECK(aug_qhist_bin(aug_qhist_angle, 59.9) == 5, "59.9");
    T_CHECK(aug_qhist_bin(aug_qhist_angle, -1) == 0, "below the first edge");
    T_CHECK(aug_qhist_bin(aug_qhist_aspect, 1e9) == AUG_QHIST - 1, "huge aspect");
    T_CHECK(aug_qhist_bin(aug_qhist_aspect, 0.9999999999) == 0, "aspect below 1");
}

static void test_median(void)
{
    double a[] = {5, 1, 3}, b[] = {4, 1, 3, 2};
    T_CHECK(aug_median(a, 3) == 3, "odd");
    T_CHECK(aug_median(b, 4) == 2.5, "even");
    T_CHECK(isnan(aug_median(b, 0)), "empty");
}

/* a named-value record in memory, as aug_write_kv lays it out */
static void kvrec(aug_rec *r, aug_buf *b, const char *type, int32_t step, const char *tag,
                  const char *key, double v)
{
    aug_kv k;
    aug_kv_init(&k, tag);
    aug_kv_set(&k, key, v);
    aug_buf_init(b);
    aug_buf_put(b, k.tag, 16);
    aug_buf_i32(b, k.n), aug_buf_i32(b, 0);
    aug_buf_put(b, k.key[0], 16);
    aug_buf_f64(b, v);
    memset(r, 0, sizeof *r);
    memcpy(r->type, type, 5);
    r->step = step;
    r->data = b->p;
    r->len = b->len;
}

static void test_steptab_matching(void)
{
    aug_steptab t;
    aug_steptab_init(&t);
    aug_err e;
    aug_rec r;
    aug_buf b;
    struct { const char *type; int step; const char *tag, *key; double v; } in[] = {
        {"sTAt", 0, "amps", "relres", 1e-16}, {"tIMe", 0, "gmres", "time_ms", 4},
        {"sTAt", 0, "gmres", "iters", 12},    {"tIMe", 0, "amps", "time_ms", 2},
        {"sTAt", 1, "amps", "relres", 3e-16}, {"sTAt", 1, "amps", "relres", 5e-16},
        {"tIMe", 1, "amps", "time_ms", 7},    {"tIMe", 1, "amps", "time_ms", 8},
        {"qUAl", 1, "refine", "x", 1},
    };
    for (size_t i = 0; i < sizeof in / sizeof in[0]; i++) {
        kvrec(&r, &b, in[i].type, in[i].step, in[i].tag, in[i].key, in[i].v);
        T_CHECK(aug_steptab_add(&t, &r, &e) == 0, "add %zu: %s", i, e.msg);
        aug_buf_free(&b);
    }
    T_CHECK(t.n == 4, "rows %zu", t.n);
    int f;
    T_CHECK(t.n == 4 && aug_steprow_get(&t.row[0], "time_ms", &f) == 2 && f, "amps step 0 time");
    T_CHECK(t.n == 4 && aug_steprow_get(&t.row[1], "iters", &f) == 12 && f, "gmres row");
    T_CHECK(t.n == 4 && aug_steprow_get(&t.row[2], "time_ms", &f) == 7 &&
                aug_steprow_get(&t.row[3], "time_ms", &f) == 8 &&
                aug_steprow_get(&t.row[3], "relres", &f) == 5e-16,
            "repeated (step, method) paired in order");
    aug_steprow_get(&t.row[0], "iters", &f);
    T_CHECK(f == 0, "absent key");
    char *p = NULL;
    size_t len;
    FILE *o = open_memstream(&p, &len);
    T_CHECK(aug_steptab_csv(o, &t, &e) == 0, "csv");
    fclose(o);
    const char *want = "step,method,time_ms,relres,m,k,iters\n"
                       "0,amps,2,9.9999999999999998e-17,,,\n"
                       "0,gmres,4,,,,12\n";
    T_CHECK(strncmp(p, want, strlen(want)) == 0, "csv head:\n%s", p);
    int lines = 0;
    for (char *c = p; *c; c++) lines += *c == '\n';
    T_CHECK(lines == 5, "csv lines %d", lines);
    free(p);
    aug_steptab_free(&t);
}

static char *dump_of(const char *s, size_t len, int no_times, int *rc)
{
    char *p = NULL;
    size_t n;
    FILE *in = fmemopen((void *)s, len, "rb"), *o = open_memstream(&p, &n);
    aug_err e;
    aug_reader *r = aug_reader_open(in, "mem", &e);
    *rc = -1;
    if (r) {
        aug_dump d;
        aug_rec rec;
        memset(&rec, 0, sizeof rec);
        aug_dump_init(&d, no_times);
        *rc = aug_dump_head(o, r, &e);
        for (int k = 1; k > 0 && !*rc;) {
            k = aug_read(r, &rec, &e);
            if (k < 0 || aug_dump_record(o, &d, &rec, &e)) *rc = -1;
        }
        aug_rec_free(&rec);
        aug_dump_free(&d);
        aug_reader_free(r);
    }
    fclose(in);
    fclose(o);
    return p;
}

static int count_lines(const char *p, const char *prefix)
{
    int n = 0;
    for (const char *c = p; c && *c;) {
        if (strncmp(c, prefix, strlen(prefix)) == 0) n++;
        c = strchr(c, '\n');
        if (c) c++;
    }
    return n;
}

static void test_dump_every_type(void)
{
    size_t len;
    char *s = mem_stream(3, 0, &len);
    int rc;
    char *d = dump_of(s, len, 0, &rc);
    T_CHECK(rc == 0, "dump failed");
    static const char *types[] = {"HEAD", "pROv", "NODE", "MATL", "ELEM", "nSEt", "FIXD",
                                  "LOAD", "oUTs", "DOFM", "KMAT", "FVEC", "FACT", "cOND",
                                  "MDLT", "UPDT", "pATH", "fELD", "sTAt", "tIMe", "qUAl",
                                  "MODE", "TAIL", "xTRa", "zNOt"};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++) {
        char pat[16];
        snprintf(pat, sizeof pat, " %s step=", types[i]);
        T_CHECK(strstr(d, pat) != NULL, "no %s record in the dump", types[i]);
    }
    /* HEAD pROv xTRa, 9 mesh (3 sets), 5 matrix, 5 of step 0, 10 of step 1, zNOt, TAIL */
    int nrec = count_lines(d, "#");
    T_CHECK(nrec == 3 + 9 + 5 + 5 + 10 + 1 + 1, "%d record headers", nrec);
    T_CHECK(strstr(d, "  count 33\n") != NULL, "TAIL count");
    T_CHECK(strstr(d, "  ordering 0 (natural)\n") != NULL, "FACT ordering");
    T_CHECK(strstr(d, "    relres 0.5\n") != NULL, "sTAt value");
    T_CHECK(strstr(d, "    0: 68 69 00 01 ff\n") != NULL, "unknown record in hex");
    T_CHECK(strstr(d, "  producer \"statslib\"\n") != NULL, "HEAD producer");
    int rc2;
    char *d2 = dump_of(s, len, 0, &rc2);
    T_CHECK(rc2 == 0 && strcmp(d, d2) == 0, "two dumps differ");
    char *d3 = dump_of(s, len, 1, &rc2);
    T_CHECK(rc2 == 0 && count_lines(d3, "#") == nrec - 4 && !strstr(d3, " tIMe "), "--no-times");
    free(d);
    free(d2);
    free(d3);
    free(s);
}

/* deflated and plain streams of the same content: dumps equal but for flags= */
static void test_dump_deflate(void)
{
    size_t l1, l2;
    char *s1 = mem_stream(3, 0, &l1), *s2 = mem_stream(3, 1, &l2);
    int r1, r2;
    char *d1 = dump_of(s1, l1, 0, &r1), *d2 = dump_of(s2, l2, 0, &r2);
    T_CHECK(r1 == 0 && r2 == 0, "dumps failed");
    T_CHECK(l2 < l1, "deflated stream not smaller (%zu vs %zu)", l2, l1);
    T_CHECK(strstr(d2, "flags=1") && !strstr(d1, "flags=1"), "flags");
    for (char *c = d2; (c = strstr(c, "flags=1")); c++) c[6] = '0';
    T_CHECK(strcmp(d1, d2) == 0, "dumps differ beyond the flags");
    free(d1);
    free(d2);
    free(s1);
    free(s2);
}

static aug_summary *summary_of(const char *s, size_t len, int32_t limit, int *rc)
{
    FILE *in = fmemopen((void *)s, len, "rb");
    aug_err e;
    aug_reader *r = aug_reader_open(in, "mem", &e);
    aug_summary *sm = r ? aug_summary_new(r, limit, &e) : NULL;
    *rc = -1;
    if (sm) {
        aug_rec rec;
        memset(&rec, 0, sizeof rec);
        int k;
        while ((k = aug_read(r, &rec, &e)) > 0)
            if (aug_summary_add(sm, &rec, &e)) break;
        if (k == 0) *rc = aug_summary_end(sm, &rec, &e) ? -1 : 0;
        aug_rec_free(&rec);
    }
    aug_reader_free(r);
    fclose(in);
    return sm;
}

static void test_summary_steps(void)
{
    size_t len;
    char *s = mem_stream(3, 0, &len);
    int rc;
    aug_summary *sm = summary_of(s, len, INT32_MAX, &rc);
    T_CHECK(sm && rc == 0, "summary failed");
    if (!sm) return;
    const aug_mesh *m = aug_summary_mesh(sm);
    T_CHECK(aug_summary_last_step(sm) == 1, "last step");
    T_CHECK(m && m->nn == 9 && m->ne == 3, "final mesh %lld nodes %lld elements",
            m ? (long long)m->nn : -1, m ? (long long)m->ne : -1);
    T_CHECK(m && m->conn[7] == 8, "element 1 re-wired to the new node");
    T_CHECK(m && aug_mesh_set(m, "tip")->n == 2, "new node inherits the set");
    int32_t fs;
    double *u;
    unsigned char *mask;
    aug_err e;
    T_CHECK(aug_summary_field(sm, &fs, &u, &mask, &e) == 0 && fs == 1 && u, "field");
    if (u) {
        int nm = 0;
        for (int i = 0; i < 9; i++) nm += mask[i];
        T_CHECK(nm == 2 && mask[7] && mask[8], "mask");
        T_CHECK(u[8 * 3 + 2] == -2e-3 * 6 && u[0] == 0, "scattered values %g", u[8 * 3 + 2]);
    }
    free(u);
    free(mask);
    T_CHECK(aug_summary_steps(sm)->n == 4, "step rows");
    char *p = NULL;
    size_t n;
    FILE *o = open_memstream(&p, &n);
    T_CHECK(aug_summary_print(o, sm, "mem", &e) == 0, "print");
    fclose(o);
    T_CHECK(strstr(p, "final mesh       9 nodes, 3 elements") != NULL, "final mesh line");
    free(p);
    aug_summary_free(sm);
    /* up to step 0: the original mesh and the full field of step 0 */
    sm = summary_of(s, len, 0, &rc);
    m = aug_summary_mesh(sm);
    T_CHECK(m && m->nn == 8 && m->ne == 2, "mesh at step 0");
    T_CHECK(aug_summary_field(sm, &fs, &u, &mask, &e) == 0 && fs == 0 && u && mask[7] && mask[0],
            "field at step 0");
    T_CHECK(u && u[23] == 1e-3 * 24, "u[23] %g", u ? u[23] : 0);
    free(u);
    free(mask);
    aug_summary_free(sm);
    free(s);
}

static void test_vtk_counts(void)
{
    size_t len;
    char *s = mem_stream(2, 0, &len);
    int rc;
    aug_summary *sm = summary_of(s, len, INT32_MAX, &rc);
    const aug_mesh *m = aug_summary_mesh(sm);
    T_CHECK(m != NULL, "mesh");
    char *p = NULL;
    size_t n;
    FILE *o = open_memstream(&p, &n);
    aug_err e;
    int32_t fs;
    double *u;
    unsigned char *mask;
    aug_summary_field(sm, &fs, &u, &mask, &e);
    T_CHECK(m && aug_vtk_write(o, m, u, mask, &e) == 0, "vtk");
    fclose(o);
    T_CHECK(strstr(p, "NumberOfPoints=\"6\" NumberOfCells=\"2\""), "counts");
    T_CHECK(strstr(p, "\n5 5\n") || strstr(p, ">\n5 5\n"), "triangle types");
    T_CHECK(strstr(p, "\n0.01 0.02 0\n") != NULL, "2-D displacement padded with z = 0");
    free(u);
    free(mask);
    free(p);
    aug_summary_free(sm);
    free(s);
}

/* every allocation of reader, summary, dump and table fails once in turn:
   each run ends in AUG_ENOMEM or success, never a crash or leak (ASan build) */
static void test_alloc_failure(void)
{
    size_t len;
    char *s = mem_stream(3, 1, &len);
    int done = 0, bad = 0;
    for (long k = 0; !done && k < 5000; k++) {
        FILE *in = fmemopen(s, len, "rb");
        char *p = NULL;
        size_t n;
        FILE *o = open_memstream(&p, &n);
        aug_err e;
        aug_fail_after(k);
        int rc = -1;
        aug_reader *r = aug_reader_open(in, "mem", &e);
        aug_summary *sm = r ? aug_summary_new(r, INT32_MAX, &e) : NULL;
        aug_dump d;
        aug_dump_init(&d, 0);
        if (sm) {
            aug_rec rec;
            memset(&rec, 0, sizeof rec);
            int q;
            while ((q = aug_read(r, &rec, &e)) > 0)
                if (aug_summary_add(sm, &rec, &e) || aug_dump_record(o, &d, &rec, &e)) break;
            if (q == 0) {
                rc = aug_summary_end(sm, &rec, &e);
                if (!rc) rc = aug_summary_print(o, sm, "mem", &e);
                if (!rc) rc = aug_steptab_csv(o, aug_summary_steps(sm), &e);
                if (!rc) {
                    int32_t fs;
                    double *u;
                    unsigned char *mask;
                    rc = aug_summary_field(sm, &fs, &u, &mask, &e);
                    free(u);
                    free(mask);
                }
            }
            aug_rec_free(&rec);
        }
        if (rc && e.code != AUG_ENOMEM) bad++;
        done = rc == 0;
        aug_fail_after(-1);
        aug_dump_free(&d);
        aug_summary_free(sm);
        aug_reader_free(r);
        fclose(in);
        fclose(o);
        free(p);
    }
    T_CHECK(done, "never succeeded");
    T_CHECK(bad == 0, "%d failures other than out of memory", bad);
    free(s);
}

/* payloads that do not match their layout are reported with their record */
static void test_dump_bad_payload(void)
{
    char *p = NULL;
    size_t len;
    FILE *f = open_memstream(&p, &len);
    aug_err e;
    aug_writer *w = aug_writer_open(f, "statslib", &e);
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i64(&b, 3), aug_buf_i64(&b, 5), aug_buf_i32(&b, 2), aug_buf_i32(&b, 0);
    aug_buf_i32(&b, 0), aug_buf_i32(&b, 1), aug_buf_i32(&b, 1); /* perm not a permutation */
    aug_buf_i64(&b, 0), aug_buf_i64(&b, 2), aug_buf_i64(&b, 4), aug_buf_i64(&b, 5);
    int32_t ri[] = {0, 1, 1, 2, 2};
    aug_buf_i32v(&b, ri, 5);
    for (int i = 0; i < 5; i++) aug_buf_f64(&b, 1);
    put(w, "FACT", AUG_NOSTEP, &b);
    aug_writer_close(w, &e);
    aug_writer_free(w);
    fclose(f);
    int rc;
    char *d = dump_of(p, len, 0, &rc);
    T_CHECK(rc != 0, "bad FACT accepted");
    free(d);
    free(p);
}

/* .pvd series and .mtx export with every allocation failing once in turn:
   each run ends in AUG_ENOMEM or success; a failed run, discarded, leaves no
   file; the run that succeeds writes the steps 0 and 1, the MODE record's
   series and K of step 0 */
static void test_series_alloc_failure(void)
{
    size_t len;
    char *s = mem_stream(3, 0, &len);
    char dir[] = "/tmp/statslib.XXXXXX";
    T_CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    char pvd[64], k[64], prefix[64];
    snprintf(pvd, sizeof pvd, "%s/s.pvd", dir);
    snprintf(prefix, sizeof prefix, "%s/m", dir);
    snprintf(k, sizeof k, "%s/m_K.mtx", dir);
    int done = 0, bad = 0, left = 0;
    for (long n = 0; !done && n < 5000; n++) {
        FILE *in = fmemopen(s, len, "rb");
        aug_err e;
        aug_fail_after(n);
        int rc = -1;
        aug_reader *r = aug_reader_open(in, "mem", &e);
        aug_summary *sm = r ? aug_summary_new(r, INT32_MAX, &e) : NULL;
        aug_pvd *p = sm ? aug_pvd_new(pvd, &e) : NULL;
        aug_mtx *x = p ? aug_mtx_new(&e) : NULL;
        if (x) {
            aug_rec rec;
            memset(&rec, 0, sizeof rec);
            int q;
            while ((q = aug_read(r, &rec, &e)) > 0)
                if (aug_pvd_add(p, sm, &rec, &e) || aug_mtx_add(x, &rec, &e) ||
                    aug_summary_add(sm, &rec, &e))
                    break;
            if (q == 0) {
                rc = aug_pvd_end(p, sm, &e);
                if (!rc) rc = aug_mtx_write(x, 0, aug_summary_mesh(sm), prefix, &e);
            }
            aug_rec_free(&rec);
        }
        aug_fail_after(-1);
        if (rc && e.code != AUG_ENOMEM) bad++;
        done = rc == 0;
        aug_pvd_free(p, !done);
        aug_mtx_free(x, !done);
        if (!done) left += !access(pvd, F_OK) || !access(k, F_OK);
        aug_summary_free(sm);
        aug_reader_free(r);
        fclose(in);
    }
    T_CHECK(done, "never succeeded");
    T_CHECK(bad == 0, "%d failures other than out of memory", bad);
    T_CHECK(left == 0, "%d failed runs left files", left);
    const char *want[] = {"s.pvd", "s_0000.vtu", "s_0001.vtu", "s_modes.pvd", "s_modes_0000.vtu", "m_K.mtx"};
    for (int i = 0; i < 6; i++) {
        char f[96];
        snprintf(f, sizeof f, "%s/%s", dir, want[i]);
        T_CHECK(access(f, F_OK) == 0, "%s not written", want[i]);
        remove(f);
    }
    rmdir(dir);
    free(s);
}

int main(int argc, char **argv)
{
    if (argc >= 3 && (!strcmp(argv[1], "gen3") || !strcmp(argv[1], "gen2"))) {
        int deflate = 0;
        double slow = 1;
        for (int i = 3; i < argc; i++) {
            if (!strcmp(argv[i], "deflate")) deflate = 1;
            else if (!strcmp(argv[i], "slow")) slow = 3;
            else return 2;
        }
        FILE *f = fopen(argv[2], "wb");
        if (!f) return 1;
        if (argv[1][3] == '3') gen3(f, deflate, slow);
        else gen2(f);
        return fclose(f) != 0;
    }
    T_RUN(test_quality_regular_tet);
    T_RUN(test_quality_right_tet);
    T_RUN(test_quality_two_tets);
    T_RUN(test_quality_triangles);
    T_RUN(test_hist_bins);
    T_RUN(test_median);
    T_RUN(test_steptab_matching);
    T_RUN(test_dump_every_type);
    T_RUN(test_dump_deflate);
    T_RUN(test_summary_steps);
    T_RUN(test_vtk_counts);
    T_RUN(test_dump_bad_payload);
    T_RUN(test_alloc_failure);
    T_RUN(test_series_alloc_failure);
    T_EXIT();
}
