/* Element measure and quality (volume/area, aspect ratio: thesis 003 eq. 3.10 and
   [Shewchuk 2002], angles, the hex scaled Jacobian) and boundary detection. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_mesh.h"

static const double *P(const aug_mesh *m, int64_t e, int j)
{
    return m->x + (size_t)m->conn[e * m->nv + j] * m->dim;
}

static void sub3(const double *a, const double *b, double *r)
{
    r[0] = a[0] - b[0], r[1] = a[1] - b[1], r[2] = a[2] - b[2];
}
static void cross3(const double *a, const double *b, double *r)
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double norm3(const double *a) { return sqrt(dot3(a, a)); }

/* V = det[p1-p0, p2-p0, p3-p0] / 6 (tet4);  A = det[p1-p0, p2-p0] / 2 (tri3);
   V = sum of det J over the 2x2x2 Gauss points (hex8: exact, det J being of
   degree 2 in each natural coordinate); signed (positive for a positively
   oriented element) */
double aug_elem_measure(const aug_mesh *m, int64_t e)
{
    if (m->nv == 8) {
        double v = 0, xi[3], N[8];
        for (int q = 0; q < 8; q++) {
            aug_hex_gauss(q, xi);
            v += aug_hex_shape(m, e, xi, N, NULL);
        }
        return v;
    }
    if (m->nv == 4) {
        double a[3], b[3], c[3], n[3];
        sub3(P(m, e, 1), P(m, e, 0), a);
        sub3(P(m, e, 2), P(m, e, 0), b);
        sub3(P(m, e, 3), P(m, e, 0), c);
        cross3(a, b, n);
        return dot3(n, c) / 6.0;
    }
    const double *p0 = P(m, e, 0), *p1 = P(m, e, 1), *p2 = P(m, e, 2);
    if (m->etype == AUG_MEM3) {
        double a[3], b[3], n[3];
        sub3(p1, p0, a);
        sub3(p2, p0, b);
        cross3(a, b, n);
        return 0.5 * norm3(n);
    }
    return 0.5 * ((p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]));
}

/* tri3 (and mem3, in its own plane): aspect = edge_ratio = l_max / l_min
   (thesis 003 eq. 3.10, sec. 3.2.2), min_angle by the law of cosines
   (degrees), measure signed */
static void tri_quality(const aug_mesh *m, int64_t e, aug_quality *q)
{
    double L[3], emin = INFINITY, emax = 0;
    for (int i = 0; i < 3; i++) {
        const double *a = P(m, e, i), *b = P(m, e, (i + 1) % 3);
        L[i] = hypot(b[0] - a[0], b[1] - a[1]);
        if (m->dim == 3) L[i] = hypot(L[i], b[2] - a[2]);
        emin = fmin(emin, L[i]);
        emax = fmax(emax, L[i]);
    }
    double amin = 180;
    for (int i = 0; i < 3; i++) { /* angle opposite edge i: law of cosines */
        double a = L[i], b = L[(i + 1) % 3], c = L[(i + 2) % 3];
        double cs = (b * b + c * c - a * a) / (2 * b * c);
        amin = fmin(amin, acos(fmax(-1, fmin(1, cs))) * 180 / M_PI);
    }
    q->measure = aug_elem_measure(m, e);
    q->edge_ratio = emax / emin;
    q->aspect = q->edge_ratio; /* thesis 003 eq. 3.10, sec. 3.2.2: longest / shortest edge */
    q->min_angle = amin;
}

/* tet4: aspect = R / (3 r), the radius ratio of [Shewchuk 2002] scaled to 1 for
   the regular tet: R = |a^2 (b x c) + b^2 (c x a) + c^2 (a x b)| / (12 |V|),
   r = 3 |V| / (sum of the face areas); min_angle = least dihedral angle (degrees),
   edge_ratio = l_max / l_min */
static void tet_quality(const aug_mesh *m, int64_t e, aug_quality *q)
{
    static const int edges[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                     {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
    double emin = INFINITY, emax = 0, dmin = 180;
    for (int k = 0; k < 6; k++) {
        const double *pi = P(m, e, edges[k][0]), *pj = P(m, e, edges[k][1]);
        const double *pk = P(m, e, edges[k][2]), *pl = P(m, e, edges[k][3]);
        double u[3], vk[3], vl[3];
        sub3(pj, pi, u);
        double len = norm3(u);
        emin = fmin(emin, len);
        emax = fmax(emax, len);
        for (int d = 0; d < 3; d++) u[d] /= len;
        sub3(pk, pi, vk);
        sub3(pl, pi, vl);
        double sk = dot3(vk, u), sl = dot3(vl, u);
        for (int d = 0; d < 3; d++) vk[d] -= sk * u[d], vl[d] -= sl * u[d];
        double cs = dot3(vk, vl) / (norm3(vk) * norm3(vl));
        dmin = fmin(dmin, acos(fmax(-1, fmin(1, cs))) * 180 / M_PI);
    }
    /* R / (3 r) on the tet scaled to a longest edge of 1: R's numerator is
       of degree 4 in the edges and its norm squares that (degree 8), which
       underflowed to 0 below ~1e-38 (stats read aspect 0 for a tet of edge
       1e-50) */
    double a[3], b[3], c[3], t[3], s[3], w = emax > 0 ? 1 / emax : 1;
    sub3(P(m, e, 1), P(m, e, 0), a);
    sub3(P(m, e, 2), P(m, e, 0), b);
    sub3(P(m, e, 3), P(m, e, 0), c);
    for (int d = 0; d < 3; d++) a[d] *= w, b[d] *= w, c[d] *= w;
    cross3(a, b, t);
    double V = dot3(t, c) / 6.0; /* (scaled) */
    double num[3] = {0, 0, 0};
    cross3(b, c, t);
    for (int d = 0; d < 3; d++) num[d] += dot3(a, a) * t[d];
    cross3(c, a, t);
    for (int d = 0; d < 3; d++) num[d] += dot3(b, b) * t[d];
    cross3(a, b, t);
    for (int d = 0; d < 3; d++) num[d] += dot3(c, c) * t[d];
    double R = norm3(num) / (12 * fabs(V));
    double area = 0;
    static const int faces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
    for (int f = 0; f < 4; f++) {
        sub3(P(m, e, faces[f][1]), P(m, e, faces[f][0]), s);
        sub3(P(m, e, faces[f][2]), P(m, e, faces[f][0]), t);
        for (int d = 0; d < 3; d++) s[d] *= w, t[d] *= w;
        double n[3];
        cross3(s, t, n);
        area += 0.5 * norm3(n);
    }
    double r = 3 * fabs(V) / area;
    q->measure = aug_elem_measure(m, e);
    q->edge_ratio = emax / emin;
    q->aspect = R / (3 * r);
    q->min_angle = dmin;
}

/* hex8: the 12 edges (each corner's three neighbours), aspect = edge_ratio =
   l_max / l_min, min_angle = the least angle between two edges at a corner
   (degrees), sjac = aug_hex_scaled_jacobian */
static void hex_quality(const aug_mesh *m, int64_t e, aug_quality *q)
{
    static const int nb[8][3] = {{1, 3, 4}, {0, 2, 5}, {1, 3, 6}, {0, 2, 7},
                                 {0, 5, 7}, {1, 4, 6}, {2, 5, 7}, {3, 4, 6}};
    double emin = INFINITY, emax = 0, amin = 180;
    for (int a = 0; a < 8; a++) {
        double v[3][3], L[3];
        for (int k = 0; k < 3; k++) {
            sub3(P(m, e, nb[a][k]), P(m, e, a), v[k]);
            L[k] = norm3(v[k]);
            emin = fmin(emin, L[k]);
            emax = fmax(emax, L[k]);
        }
        for (int i = 0; i < 3; i++)
            for (int j = i + 1; j < 3; j++) {
                double cs = dot3(v[i], v[j]) / (L[i] * L[j]);
                amin = fmin(amin, acos(fmax(-1, fmin(1, cs))) * 180 / M_PI);
            }
    }
    q->measure = aug_elem_measure(m, e);
    q->edge_ratio = emax / emin;
    q->aspect = q->edge_ratio;
    q->min_angle = amin;
    q->sjac = aug_hex_scaled_jacobian(m, e, NULL);
}

/* measure, aspect, edge ratio and least (dihedral) angle of element e:
   hex_quality (nv = 8), tet_quality (nv = 4) or tri_quality */
void aug_elem_quality(const aug_mesh *m, int64_t e, aug_quality *q)
{
    q->sjac = NAN;
    if (m->nv == 8) hex_quality(m, e, q);
    else if (m->nv == 4) tet_quality(m, e, q);
    else tri_quality(m, e, q);
}

static int cmp_face(const void *a, const void *b)
{
    const int32_t *x = a, *y = b;
    for (int i = 0; i < 4; i++)
        if (x[i] != y[i]) return x[i] < y[i] ? -1 : 1;
    return 0;
}

static void sort_small(int32_t *v, int n)
{
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && v[j - 1] > v[j]; j--) {
            int32_t t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
}

/* a facet (aug_etype_facet: face of a 3-D element, edge of a 2-D one) used by
   exactly one element is boundary */
int64_t aug_mesh_boundary_nodes(const aug_mesh *m, unsigned char *mark)
{
    int nf = aug_etype_nfacet(m->etype), fv = aug_etype_facet_nv(m->etype);
    int32_t *F = aug_malloc((size_t)(m->ne * nf) * 4 * sizeof(int32_t) + 1);
    if (!F) return -1;
    for (int64_t e = 0; e < m->ne; e++)
        for (int f = 0; f < nf; f++) {
            int32_t *t = F + (e * nf + f) * 4;
            const int *l = aug_etype_facet(m->etype, f);
            for (int k = 0; k < 4; k++) t[k] = k < fv ? m->conn[e * m->nv + l[k]] : -1;
            sort_small(t, fv);
        }
    int64_t nt = m->ne * nf;
    qsort(F, (size_t)nt, 4 * sizeof(int32_t), cmp_face);
    memset(mark, 0, (size_t)m->nn);
    for (int64_t i = 0; i < nt;) {
        int64_t j = i + 1;
        while (j < nt && cmp_face(F + 4 * i, F + 4 * j) == 0) j++;
        if (j - i == 1)
            for (int k = 0; k < fv; k++) mark[F[4 * i + k]] = 1;
        i = j;
    }
    free(F);
    int64_t c = 0;
    for (int64_t i = 0; i < m->nn; i++) c += mark[i];
    return c;
}
