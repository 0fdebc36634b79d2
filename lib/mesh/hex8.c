/* The trilinear 8-node hexahedron: shape functions, Jacobian, Gauss points,
   scaled Jacobian. */
#include <math.h>
#include "aug_mesh.h"

/* natural coordinates of the corners, gmsh order */
static const double corner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                    {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

void aug_hex_gauss(int q, double xi[3])
{
    double a = 1 / sqrt(3.0);
    for (int k = 0; k < 3; k++) xi[k] = (q >> k & 1) ? a : -a;
}

/* cyclic indices give the signed cofactors directly; det by the first row */
double aug_cofactor3(const double a[3][3], double cof[3][3])
{
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) {
            int r1 = (r + 1) % 3, r2 = (r + 2) % 3, k1 = (k + 1) % 3, k2 = (k + 2) % 3;
            cof[r][k] = a[r1][k1] * a[r2][k2] - a[r1][k2] * a[r2][k1];
        }
    return a[0][0] * cof[0][0] + a[0][1] * cof[0][1] + a[0][2] * cof[0][2];
}

/* N, dN/dxi at xi; J[r][k] = dx_r/dxi_k; g = J^-T dN/dxi by the cofactors of J */
double aug_hex_shape(const aug_mesh *m, int64_t e, const double xi[3], double N[8], double *g)
{
    const int32_t *c = m->conn + e * 8;
    double dn[8][3], J[3][3] = {{0}};
    for (int a = 0; a < 8; a++) {
        double f[3], d[3];
        for (int k = 0; k < 3; k++) f[k] = 1 + corner[a][k] * xi[k], d[k] = corner[a][k];
        N[a] = f[0] * f[1] * f[2] / 8;
        dn[a][0] = d[0] * f[1] * f[2] / 8;
        dn[a][1] = f[0] * d[1] * f[2] / 8;
        dn[a][2] = f[0] * f[1] * d[2] / 8;
        const double *x = m->x + (size_t)c[a] * 3;
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++) J[r][k] += x[r] * dn[a][k];
    }
    double cof[3][3], det = aug_cofactor3((const double(*)[3])J, cof);
    if (g) /* (J^-1)[k][r] = cof[r][k] / det; dN/dx_r = sum_k dN/dxi_k (J^-1)[k][r] */
        for (int a = 0; a < 8; a++)
            for (int r = 0; r < 3; r++)
                g[a * 3 + r] = (dn[a][0] * cof[r][0] + dn[a][1] * cof[r][1] + dn[a][2] * cof[r][2]) / det;
    return det;
}

/* corner a and its three neighbours, right-handed for a positive hex */
static const int nbr[8][3] = {{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7},
                              {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}};

double aug_hex_scaled_jacobian(const aug_mesh *m, int64_t e, int *where)
{
    const int32_t *c = m->conn + e * 8;
    double best = INFINITY;
    int at = 0;
    for (int a = 0; a < 8; a++) {
        const double *o = m->x + (size_t)c[a] * 3;
        double v[3][3], L = 1;
        for (int k = 0; k < 3; k++) {
            const double *p = m->x + (size_t)c[nbr[a][k]] * 3;
            for (int r = 0; r < 3; r++) v[k][r] = p[r] - o[r];
            L *= sqrt(v[k][0] * v[k][0] + v[k][1] * v[k][1] + v[k][2] * v[k][2]);
        }
        double det = v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[2][1]) -
                     v[0][1] * (v[1][0] * v[2][2] - v[1][2] * v[2][0]) +
                     v[0][2] * (v[1][0] * v[2][1] - v[1][1] * v[2][0]);
        double s = L > 0 ? det / L : 0;
        if (!(s >= best)) best = s, at = a;
    }
    if (where) *where = at;
    return best;
}
