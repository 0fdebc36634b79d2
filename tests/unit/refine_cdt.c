/* Local constrained Delaunay triangulation (lib/refine/cdt_local.c): Bowyer-Watson
   insertion, segment recovery, Lawson flips, checked against brute-force
   definitions (empty circumcircles, conformity, area, visibility). */
#include <gsl/gsl_rng.h>
#include <math.h>
#include <string.h>
#include "aug_refine.h"
#include "t.h"

static double area_of(const aug_cdt *c, int32_t t)
{
    const int32_t *v = c->tri + 3 * t;
    return 0.5 * aug_orient2d(c->xy + 2 * v[0], c->xy + 2 * v[1], c->xy + 2 * v[2]);
}

/* every live triangle positive; every edge shared by <= 2 triangles with opposite
   orientations; total area */
static int valid(const aug_cdt *c, double *area)
{
    *area = 0;
    aug_edgemap dir;
    aug_edgemap_init(&dir, 64);
    int ok = 1;
    for (int32_t t = 0; t < c->nt; t++) {
        const int32_t *v = c->tri + 3 * t;
        if (v[0] < 0) continue;
        double a = area_of(c, t);
        if (!(a > 0)) ok = 0;
        *area += a;
        for (int i = 0; i < 3; i++) {
            int32_t p = v[i], q = v[(i + 1) % 3];
            int32_t *s = aug_edgemap_put(&dir, p, q);
            int slot = p < q ? 0 : 1; /* each direction at most once */
            if (s[slot] >= 0) ok = 0;
            s[slot] = t;
        }
    }
    aug_edgemap_free(&dir);
    return ok;
}

/* no vertex strictly inside the circumcircle of a triangle it can see across a
   non-fixed edge chain: checked as local Delaunay on every non-fixed interior edge */
static int locally_delaunay(const aug_cdt *c)
{
    for (int32_t t = 0; t < c->nt; t++) {
        const int32_t *v = c->tri + 3 * t;
        if (v[0] < 0) continue;
        for (int i = 0; i < 3; i++) {
            int32_t p = v[i], q = v[(i + 1) % 3];
            if (aug_cdt_is_fixed(c, p, q)) continue;
            int32_t n = aug_cdt_across(c, t, p, q);
            if (n < 0) continue;
            const int32_t *u = c->tri + 3 * n;
            int32_t y = u[0] != p && u[0] != q ? u[0] : u[1] != p && u[1] != q ? u[1] : u[2];
            if (aug_incircle(c->xy + 2 * v[0], c->xy + 2 * v[1], c->xy + 2 * v[2], c->xy + 2 * y,
                             1e-9) > 0)
                return 0;
        }
    }
    return 1;
}

static int has_edge(const aug_cdt *c, int32_t a, int32_t b)
{
    return aug_edgemap_get(&c->edges, a, b) != NULL;
}

static void square(aug_cdt *c)
{
    aug_cdt_reset(c);
    aug_cdt_vertex(c, 0, 0);
    aug_cdt_vertex(c, 1, 0);
    aug_cdt_vertex(c, 1, 1);
    aug_cdt_vertex(c, 0, 1);
    aug_cdt_tri(c, 0, 1, 2, 0);
    aug_cdt_tri(c, 0, 2, 3, 0);
}

static int insert_xy(aug_cdt *c, double x, double y)
{
    int32_t at, t = aug_cdt_locate(c, x, y, -1, &at);
    if (t < 0) return -1;
    if (at >= 0) return at;
    int32_t v = aug_cdt_vertex(c, x, y);
    if (aug_cdt_insert(c, v, t)) return -2;
    return v;
}

static void bw_random_points(void)
{
    aug_cdt c;
    aug_cdt_init(&c);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 7);
    square(&c);
    for (int i = 0; i < 400; i++) {
        int v = insert_xy(&c, gsl_rng_uniform(r), gsl_rng_uniform(r));
        T_CHECK(v >= 0, "insert %d failed (%d)", i, v);
    }
    double a;
    T_CHECK(valid(&c, &a), "invalid triangulation");
    T_CHECK(fabs(a - 1) < 1e-12, "area %.17g", a);
    T_CHECK(locally_delaunay(&c), "not Delaunay");
    int live = 0;
    for (int32_t t = 0; t < c.nt; t++) live += c.tri[3 * t] >= 0;
    /* Euler: 2 n - h - 2 triangles with 4 hull vertices */
    T_CHECK(live == 2 * c.nv - 4 - 2, "%d triangles for %d vertices", live, c.nv);
    gsl_rng_free(r);
    aug_cdt_free(&c);
}

static void bw_boundary_and_grid_points(void)
{
    aug_cdt c;
    aug_cdt_init(&c);
    square(&c);
    /* points on the boundary edges and on the diagonal, then a co-circular grid */
    double pts[][2] = {{0.5, 0}, {1, 0.25}, {0.5, 0.5}, {0, 0.75}, {0.25, 0.25}, {0.75, 1}};
    for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++)
        T_CHECK(insert_xy(&c, pts[i][0], pts[i][1]) >= 0, "insert %zu", i);
    for (int i = 0; i <= 8; i++)
        for (int j = 0; j <= 8; j++) T_CHECK(insert_xy(&c, i / 8.0, j / 8.0) >= 0, "grid %d %d", i, j);
    double a;
    T_CHECK(valid(&c, &a), "invalid");
    T_CHECK(fabs(a - 1) < 1e-12, "area %.17g", a);
    T_CHECK(locally_delaunay(&c), "not Delaunay");
    T_CHECK(c.nv == 81, "vertices %d (grid points on inserted ones must merge)", c.nv);
    aug_cdt_free(&c);
}

static void recover_segments(void)
{
    aug_cdt c;
    aug_cdt_init(&c);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 11);
    int crossed = 0;
    for (int rep = 0; rep < 20; rep++) {
        square(&c);
        for (int i = 0; i < 200; i++) insert_xy(&c, gsl_rng_uniform(r), gsl_rng_uniform(r));
        /* a polyline of new vertices, inserted then recovered */
        int32_t prev = -1;
        double x0 = 0.05 + 0.1 * gsl_rng_uniform(r), y0 = 0.1 + 0.8 * gsl_rng_uniform(r);
        int32_t chain[12];
        for (int k = 0; k < 12; k++) {
            double x = x0 + k * 0.07, y = y0 + 0.05 * sin(3.0 * k + rep);
            y = fmin(0.95, fmax(0.05, y));
            int32_t v = insert_xy(&c, x, y);
            T_CHECK(v >= 0, "insert chain");
            chain[k] = v;
            if (prev >= 0) T_CHECK(aug_cdt_recover(&c, prev, v) == 0, "recover %d", k);
            prev = v;
        }
        for (int k = 1; k < 12; k++)
            T_CHECK(has_edge(&c, chain[k - 1], chain[k]) && aug_cdt_is_fixed(&c, chain[k - 1], chain[k]),
                    "segment %d missing", k);
        T_CHECK(aug_cdt_legalize(&c) == 0, "legalize");
        for (int k = 1; k < 12; k++)
            T_CHECK(has_edge(&c, chain[k - 1], chain[k]), "segment %d flipped away", k);
        double a;
        T_CHECK(valid(&c, &a), "invalid after recovery (rep %d)", rep);
        T_CHECK(fabs(a - 1) < 1e-12, "area %.17g", a);
        T_CHECK(locally_delaunay(&c), "not constrained Delaunay (rep %d)", rep);
        /* a long segment through many triangles between two existing vertices:
           the square's diagonal y = x, refused exactly when the fixed chain
           crosses it (a chain vertex on it splits it instead) */
        int cross = 0;
        for (int k = 1; k < 12; k++) {
            const double *p = c.xy + 2 * chain[k - 1], *q = c.xy + 2 * chain[k];
            cross |= (p[1] - p[0] > 0 && q[1] - q[0] < 0) || (p[1] - p[0] < 0 && q[1] - q[0] > 0);
        }
        int rc = aug_cdt_recover(&c, 0, 2);
        T_CHECK(rc == (cross ? AUG_EDATA : 0), "rep %d: diagonal %s: rc %d", rep,
                cross ? "crosses the chain" : "free", rc);
        if (rc == 0)
            T_CHECK(has_edge(&c, 0, 2) && aug_cdt_is_fixed(&c, 0, 2), "rep %d: the diagonal is no fixed edge", rep);
        T_CHECK(valid(&c, &a) && fabs(a - 1) < 1e-12, "rep %d: invalid after the diagonal (area %.17g)", rep, a);
        crossed += cross;
    }
    T_CHECK(crossed > 0 && crossed < 20, "%d of 20 chains cross the diagonal: both cases wanted", crossed);
    gsl_rng_free(r);
    aug_cdt_free(&c);
}

static void fixed_edges_block_cavities(void)
{
    aug_cdt c;
    aug_cdt_init(&c);
    square(&c);
    int32_t a = insert_xy(&c, 0.5, 0.02), b = insert_xy(&c, 0.5, 0.98);
    T_CHECK(aug_cdt_recover(&c, a, b) == 0, "recover");
    /* points right next to the constraint, on both sides, and one on it */
    T_CHECK(insert_xy(&c, 0.49, 0.5) >= 0 && insert_xy(&c, 0.51, 0.5) >= 0, "near");
    int32_t m = insert_xy(&c, 0.5, 0.3);
    T_CHECK(m >= 0, "on the constraint");
    T_CHECK(aug_cdt_is_fixed(&c, a, m) && has_edge(&c, a, m), "lower half of the split constraint");
    T_CHECK(aug_cdt_legalize(&c) == 0, "legalize");
    double ar;
    T_CHECK(valid(&c, &ar) && fabs(ar - 1) < 1e-12, "invalid / area");
    T_CHECK(locally_delaunay(&c), "not constrained Delaunay");
    /* a segment crossing a fixed one is refused */
    int32_t p = insert_xy(&c, 0.2, 0.6), q = insert_xy(&c, 0.8, 0.6);
    T_CHECK(aug_cdt_recover(&c, p, q) == AUG_EDATA, "crossing constraints accepted");
    aug_cdt_free(&c);
}

/* a slit: two coincident vertices on each side of a cut line; insertion on one
   side leaves the other untouched */
static void slit_sides(void)
{
    aug_cdt c;
    aug_cdt_init(&c);
    aug_cdt_reset(&c);
    /* square split by the slit (0,0.5)-(0.6,0.5); the slit's end (0.6,0.5) shared */
    int32_t v0 = aug_cdt_vertex(&c, 0, 0), v1 = aug_cdt_vertex(&c, 1, 0), v2 = aug_cdt_vertex(&c, 1, 1),
            v3 = aug_cdt_vertex(&c, 0, 1), lo = aug_cdt_vertex(&c, 0, 0.5), up = aug_cdt_vertex(&c, 0, 0.5),
            tip = aug_cdt_vertex(&c, 0.6, 0.5);
    aug_cdt_tri(&c, v0, v1, tip, 0);
    aug_cdt_tri(&c, v0, tip, lo, 0);
    aug_cdt_tri(&c, v1, v2, tip, 0);
    aug_cdt_tri(&c, v2, v3, tip, 0);
    aug_cdt_tri(&c, v3, up, tip, 0);
    double a;
    T_CHECK(valid(&c, &a) && fabs(a - 1) < 1e-12, "set-up");
    /* insert a point on the lower slit edge lo-tip (from the lower side) */
    int32_t t = aug_cdt_locate(&c, 0.3, 0.49, -1, NULL);
    int32_t p = aug_cdt_vertex(&c, 0.3, 0.5);
    T_CHECK(aug_cdt_insert(&c, p, t) == 0, "insert on slit");
    T_CHECK(has_edge(&c, lo, p) && has_edge(&c, p, tip), "lower slit edge split");
    T_CHECK(has_edge(&c, up, tip), "upper slit edge untouched");
    T_CHECK(aug_cdt_legalize(&c) == 0, "legalize");
    T_CHECK(valid(&c, &a) && fabs(a - 1) < 1e-12, "area %.17g", a);
    aug_cdt_free(&c);
}

int main(void)
{
    T_RUN(bw_random_points);
    T_RUN(bw_boundary_and_grid_points);
    T_RUN(recover_segments);
    T_RUN(fixed_edges_block_cavities);
    T_RUN(slit_sides);
    T_EXIT();
}
