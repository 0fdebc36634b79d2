/* Modal warping (paper 004 eqs. 16-17): the rotation field of a linear
   infinitesimal rotation on distorted tet, hex and tri meshes, the warp of it
   against Rodrigues' finite rotation, the coefficients of R~ against long
   double series across the series switch, and the error cases. */
#include "t.h"
#include "fem_mesh.h"
#include "modal_gen.h"

static double worst_w, worst_rot, worst_coef, worst_jump;

/* shift the mesh off the origin and move every node by up to 5% of a cell */
static void distort(aug_mesh *m, double h)
{
    for (int64_t i = 0; i < m->nn; i++)
        for (int c = 0; c < m->dim; c++)
            m->x[i * m->dim + c] += -0.45 + 0.1 * h * (g_unif() - 0.5);
}

static void random_axis(int dim, double n[3])
{
    if (dim == 2) {
        n[0] = n[1] = 0, n[2] = g_unif() < 0.5 ? -1 : 1;
        return;
    }
    double s;
    do {
        for (int c = 0; c < 3; c++) n[c] = g_normal();
        s = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    } while (s < 1e-3);
    for (int c = 0; c < 3; c++) n[c] /= s;
}

static void cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static const double thetas[] = {1e-9, 1e-6, 1e-3, 0.1, 0.5, 1.0, 1.9999999, 2.0, 2.0000001, 2.5};

/* u = theta n x X: w = theta n at every node (elements listed: those of the
   first half, the others' nodes w = 0), R~(w) u = R X - X with R the finite
   rotation (Rodrigues: sin t n x X + (1 - cos t) n x (n x X)) for every X,
   also X not perpendicular to n */
static void rigid(aug_mesh *m)
{
    int d = m->dim;
    int64_t nn = m->nn, half = m->ne / 2;
    double *u = malloc(nn * d * sizeof *u), *w = malloc(nn * 3 * sizeof *w),
           *out = malloc(nn * d * sizeof *out);
    int32_t *el = malloc(half * sizeof *el);
    unsigned char *in = calloc(nn, 1);
    for (int64_t k = 0; k < half; k++) {
        el[k] = (int32_t)(2 * k);
        for (int a = 0; a < m->nv; a++) in[m->conn[el[k] * m->nv + a]] = 1;
    }
    aug_err e;
    double maxpar = 0;
    for (size_t it = 0; it < sizeof thetas / sizeof *thetas; it++)
        for (int rep = 0; rep < 4; rep++) {
            double th = thetas[it], n[3];
            random_axis(d, n);
            for (int64_t i = 0; i < nn; i++) {
                double X[3] = {0, 0, 0}, v[3];
                for (int c = 0; c < d; c++) X[c] = m->x[i * d + c];
                cross(n, X, v);
                for (int c = 0; c < d; c++) u[i * d + c] = th * v[c];
                double p = fabs(n[0] * X[0] + n[1] * X[1] + n[2] * X[2]);
                if (p > maxpar) maxpar = p;
            }
            for (int pass = 0; pass < 2; pass++) {
                int rc = aug_warp_rotations(m, pass ? el : NULL, pass ? half : -7, u, w, &e);
                T_CHECK(rc == 0, "rotations: %s", e.msg);
                for (int64_t i = 0; i < nn; i++) {
                    int on = !pass || in[i];
                    for (int c = 0; c < 3; c++) {
                        double dw = fabs(w[i * 3 + c] - (on ? th * n[c] : 0)) / th;
                        if (!on) T_CHECK(w[i * 3 + c] == 0, "node %lld off the elements: w %g", (long long)i, w[i * 3 + c]);
                        if (dw > worst_w) worst_w = dw;
                        T_CHECK(dw < 1e-12, "theta %g node %lld: w error %.2e", th, (long long)i, dw);
                    }
                }
            }
            aug_warp_rotations(m, NULL, 0, u, w, &e);
            memcpy(out, u, nn * d * sizeof *out);
            aug_warp_apply(w, out, out, nn, d); /* in place */
            double err = 0, ref = 0, s = sin(th), c1 = 2 * sin(th / 2) * sin(th / 2);
            for (int64_t i = 0; i < nn; i++) {
                double X[3] = {0, 0, 0}, a[3], b[3];
                for (int c = 0; c < d; c++) X[c] = m->x[i * d + c];
                cross(n, X, a);
                cross(n, a, b);
                for (int c = 0; c < d; c++) {
                    double r = s * a[c] + c1 * b[c];
                    err = fmax(err, fabs(out[i * d + c] - r));
                    ref = fmax(ref, fabs(r));
                }
            }
            err /= ref;
            if (err > worst_rot) worst_rot = err;
            T_CHECK(err < 1e-12, "theta %g: |R~u - (RX - X)| / |RX - X| = %.2e", th, err);
        }
    if (d == 3) T_CHECK(maxpar > 0.1, "X never far from perpendicular to n (%g)", maxpar);
    free(u), free(w), free(out), free(el), free(in);
}

static void rigid_tet(void)
{
    aug_mesh m;
    tm_box(&m, 3, 2, 2, 1.0, 0.8, 0.9, 1, 0.3);
    distort(&m, 0.3);
    for (int64_t e = 0; e < m.ne; e++) T_CHECK(aug_elem_measure(&m, e) > 0, "tet %lld inverted", (long long)e);
    rigid(&m);
    aug_mesh_free(&m);
}

static void rigid_hex(void)
{
    aug_mesh m;
    tm_hexbox(&m, 3, 2, 2, 1.0, 0.8, 0.9, 1, 0.3);
    distort(&m, 0.3);
    for (int64_t e = 0; e < m.ne; e++) T_CHECK(aug_hex_scaled_jacobian(&m, e, NULL) > 0, "hex %lld inverted", (long long)e);
    rigid(&m);
    aug_mesh_free(&m);
}

static void rigid_tri(void)
{
    aug_mesh m;
    tm_rect(&m, 4, 3, 1.0, 0.9, 1, 0.3, 1);
    distort(&m, 0.25);
    for (int64_t e = 0; e < m.ne; e++) T_CHECK(aug_elem_measure(&m, e) > 0, "tri %lld inverted", (long long)e);
    rigid(&m);
    aug_mesh_free(&m);
}

/* (1 - cos t) / t^2 and (t - sin t) / t^3 in long double by 40 terms of
   their series (no cancellation below t = 3: the terms' sum of moduli is
   under twice the value) */
static void ref_coef(long double t, long double *a, long double *b)
{
    long double x = t * t, ta = 0.5L, tb = 1.0L / 6, sa = 0, sb = 0;
    for (int k = 0; k < 40; k++) {
        sa += ta, sb += tb;
        ta *= -x / ((2 * k + 3) * (2 * k + 4));
        tb *= -x / ((2 * k + 4) * (2 * k + 5));
    }
    *a = sa, *b = sb;
}

/* a from R~((0,0,t)) (entry (1,0) = a t), b from R~((s,s,0)) (entry (0,1) =
   b s^2), both against ref_coef */
static void coef_at(double t, double *ea, double *eb, double *a, double *b)
{
    double R[9], w[3] = {0, 0, t};
    aug_warp_matrix(w, R);
    *a = R[3] / t;
    long double ra, rb;
    ref_coef(t, &ra, &rb);
    *ea = (double)fabsl((*a - ra) / ra);
    double s = t / sqrt(2.0), w2[3] = {s, s, 0};
    aug_warp_matrix(w2, R);
    *b = R[1] / (s * s);
    ref_coef(sqrtl((long double)s * s * 2), &ra, &rb);
    *eb = (double)fabsl((*b - rb) / rb);
}

static void coefficients(void)
{
    for (int i = 0; i <= 400; i++) {
        double t = 1e-9 * pow(3e9, i / 400.0), ea, eb, a, b; /* 1e-9 .. 3 */
        coef_at(t, &ea, &eb, &a, &b);
        double er = fmax(ea, eb);
        if (er > worst_coef) worst_coef = er;
        T_CHECK(er < 2e-15, "t %.17g: relative errors a %.2e b %.2e", t, ea, eb);
    }
    double R[9], z[3] = {0, 0, 0};
    aug_warp_matrix(z, R);
    for (int k = 0; k < 9; k++) T_CHECK(R[k] == (k % 4 == 0), "R~(0) entry %d = %g", k, R[k]);
}

/* the switch at t = 2: the 2 x 40 angles within 40 ulps either side, each
   coefficient within round-off of the reference, and the step from the last
   series value to the first closed-form one no larger than the exact change */
static void switch_continuity(void)
{
    double lo = 2.0, pa = 0, pb = 0;
    for (int k = 0; k < 40; k++) lo = nextafter(lo, 0);
    double t = lo;
    for (int k = 0; k < 80; k++, t = nextafter(t, 3)) {
        double ea, eb, a, b;
        coef_at(t, &ea, &eb, &a, &b);
        T_CHECK(fmax(ea, eb) < 2e-15, "t %.17g: relative errors a %.2e b %.2e", t, ea, eb);
        if (fmax(ea, eb) > worst_coef) worst_coef = fmax(ea, eb);
        if (k > 0) {
            double j = fmax(fabs(a - pa) / a, fabs(b - pb) / b);
            if (j > worst_jump) worst_jump = j;
            T_CHECK(j < 2e-15, "t %.17g: jump %.2e from the previous ulp", t, j);
        }
        pa = a, pb = b;
    }
}

/* 2-D: the 2x2 block of the 3-D operator */
static void plane_block(void)
{
    double w[6] = {0, 0, 0.7, 0, 0, -2.2}, u2[4] = {0.3, -0.4, 1.5, 0.25}, u3[6] = {0.3, -0.4, 0, 1.5, 0.25, 0};
    double o2[4], o3[6];
    aug_warp_apply(w, u2, o2, 2, 2);
    aug_warp_apply(w, u3, o3, 2, 3);
    for (int i = 0; i < 2; i++) {
        T_CHECK(o3[i * 3 + 2] == 0, "z component %g", o3[i * 3 + 2]);
        for (int c = 0; c < 2; c++) T_CHECK(o2[i * 2 + c] == o3[i * 3 + c], "node %d c %d", i, c);
    }
}

static void errors(void)
{
    aug_mesh m;
    tm_box(&m, 1, 1, 1, 1, 1, 1, 1, 0.3);
    double u[8 * 3] = {0}, w[8 * 3];
    aug_err e;
    int32_t bad[2] = {0, 6};
    T_CHECK(aug_warp_rotations(&m, bad, 2, u, w, &e) == AUG_EUSAGE, "element 6 of 6 accepted");
    T_CHECK(strstr(e.msg, "element 6") != NULL, "message: %s", e.msg);
    bad[1] = -1;
    T_CHECK(aug_warp_rotations(&m, bad, 2, u, w, &e) == AUG_EUSAGE, "element -1 accepted");
    T_CHECK(aug_warp_rotations(&m, bad, -1, u, w, &e) == AUG_EUSAGE, "nel -1 accepted");
    T_CHECK(aug_warp_rotations(&m, bad, 0, u, w, &e) == 0, "no elements: %s", e.msg);
    for (int i = 0; i < 24; i++) T_CHECK(w[i] == 0, "w with no elements");
    aug_fail_after(0);
    T_CHECK(aug_warp_rotations(&m, NULL, 0, u, w, &e) == AUG_ENOMEM, "allocation failure not reported");
    aug_fail_after(-1);
    m.etype = 99;
    T_CHECK(aug_warp_rotations(&m, NULL, 0, u, w, &e) == AUG_EUSAGE, "element type 99 accepted");
    aug_mesh_free(&m);
}

int main(void)
{
    T_RUN(rigid_tet);
    T_RUN(rigid_hex);
    T_RUN(rigid_tri);
    T_RUN(coefficients);
    T_RUN(switch_continuity);
    T_RUN(plane_block);
    T_RUN(errors);
    printf("measured: w rel %.2e, warp vs finite rotation rel %.2e, coefficients rel %.2e, "
           "step at the switch %.2e\n", worst_w, worst_rot, worst_coef, worst_jump);
    T_EXIT();
}
