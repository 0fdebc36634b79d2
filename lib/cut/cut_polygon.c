/* Bounded planar cuts: restrict a planned plane cut to the nodes whose
   projection onto the plane lies inside a polygon (a partial cut whose front
   stops at the polygon's edges). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

/* u, v: an orthonormal basis of the plane with unit normal n */
static void plane_basis(const double *n, double *u, double *v)
{
    int ax = fabs(n[0]) < fabs(n[1]) ? (fabs(n[0]) < fabs(n[2]) ? 0 : 2) : (fabs(n[1]) < fabs(n[2]) ? 1 : 2);
    double a[3] = {0, 0, 0};
    a[ax] = 1;
    double s = a[0] * n[0] + a[1] * n[1] + a[2] * n[2], l = 0;
    for (int k = 0; k < 3; k++) u[k] = a[k] - s * n[k], l += u[k] * u[k];
    for (int k = 0; k < 3; k++) u[k] /= sqrt(l);
    v[0] = n[1] * u[2] - n[2] * u[1];
    v[1] = n[2] * u[0] - n[0] * u[2];
    v[2] = n[0] * u[1] - n[1] * u[0];
}

/* distance of p to segment ab (2-D) */
static double seg_dist(const double *a, const double *b, const double *p)
{
    double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return hypot(a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
}

/* p inside the polygon q by the even-odd (crossing-number) rule; points within
   tol of an edge count as inside */
static int inside(const double *q, int nq, const double *p, double tol)
{
    int in = 0;
    for (int i = 0, j = nq - 1; i < nq; j = i++) {
        const double *a = q + 2 * i, *b = q + 2 * j;
        if (seg_dist(a, b, p) <= tol) return 1;
        if ((a[1] > p[1]) != (b[1] > p[1]) &&
            p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0])
            in = !in;
    }
    return in;
}

/* keep the planned cut nodes whose projection onto the plane (orthonormal basis
   u, v) lies inside the projected polygon, within 1e-9 of its size */
int aug_plane_restrict(aug_plane_cut *pc, const aug_mesh *m, const double *poly, int npoly,
                       aug_err *e)
{
    aug_err_clear(e);
    if (m->dim != 3 || npoly < 3)
        return aug_err_set(e, AUG_EUSAGE, -1, "", "a bounding polygon needs a 3-D mesh and 3 or more vertices");
    double u[3], v[3], *q = aug_malloc((size_t)npoly * 2 * sizeof *q), scale = 0;
    if (!q) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    plane_basis(pc->n, u, v);
    for (int i = 0; i < npoly; i++) {
        const double *x = poly + 3 * i;
        q[2 * i] = x[0] * u[0] + x[1] * u[1] + x[2] * u[2];
        q[2 * i + 1] = x[0] * v[0] + x[1] * v[1] + x[2] * v[2];
        if (i > 0) scale = fmax(scale, hypot(q[2 * i] - q[0], q[2 * i + 1] - q[1]));
    }
    int64_t k = 0;
    for (int64_t i = 0; i < pc->ncut; i++) {
        const double *x = m->x + (int64_t)pc->nodes[i] * 3;
        double p[2] = {x[0] * u[0] + x[1] * u[1] + x[2] * u[2], x[0] * v[0] + x[1] * v[1] + x[2] * v[2]};
        if (inside(q, npoly, p, 1e-9 * scale)) pc->nodes[k++] = pc->nodes[i];
    }
    free(q);
    if (k == 0) return aug_err_set(e, AUG_EDATA, -1, "", "no cut node lies inside the polygon");
    pc->ncut = k;
    pc->next = 0;
    return 0;
}
