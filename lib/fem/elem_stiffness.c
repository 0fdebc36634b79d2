/* Linear-elastic element stiffness: tet4 and hex8 (3-D isotropic) and tri3
   (plane stress) ([Zienkiewicz]; Hughes, The Finite Element Method, ch. 3;
   thesis 003 eqs. 2.19-2.20 give its node-block form). */
#include <string.h>
#include "aug_fem.h"

/* Gradients of the linear shape functions of tet4 element e: g[i*3+c] = dN_i/dx_c.
   J = [p1-p0, p2-p0, p3-p0] (columns); rows of J^-1 are grad N_1..N_3, and
   grad N_0 = -(grad N_1 + grad N_2 + grad N_3). Returns det J = 6 V. */
static double tet_grad(const aug_mesh *m, int64_t e, double g[12])
{
    const int32_t *c = m->conn + e * 4;
    const double *p0 = m->x + (size_t)c[0] * 3;
    double a[3][3]; /* a[r][k] = (p_{k+1} - p0)_r */
    for (int k = 0; k < 3; k++) {
        const double *p = m->x + (size_t)c[k + 1] * 3;
        for (int r = 0; r < 3; r++) a[r][k] = p[r] - p0[r];
    }
    double cof[3][3], det = aug_cofactor3((const double(*)[3])a, cof);
    /* (J^-1)[k][r] = cof[r][k] / det: grad N_{k+1} = row k of J^-1 */
    for (int c0 = 0; c0 < 3; c0++) g[c0] = 0;
    for (int k = 0; k < 3; k++)
        for (int r = 0; r < 3; r++) {
            g[(k + 1) * 3 + r] = cof[r][k] / det;
            g[r] -= g[(k + 1) * 3 + r];
        }
    return det;
}

/* Gradients of tri3 shape functions; returns 2A (det of [p1-p0, p2-p0]). */
static double tri_grad(const aug_mesh *m, int64_t e, double g[6])
{
    const int32_t *c = m->conn + e * 3;
    const double *p0 = m->x + (size_t)c[0] * 2, *p1 = m->x + (size_t)c[1] * 2,
                 *p2 = m->x + (size_t)c[2] * 2;
    double det = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]);
    /* dN_i/dx = (y_j - y_k)/2A, dN_i/dy = (x_k - x_j)/2A, (i j k) cyclic */
    const double *p[3] = {p0, p1, p2};
    for (int i = 0; i < 3; i++) {
        const double *pj = p[(i + 1) % 3], *pk = p[(i + 2) % 3];
        g[i * 2 + 0] = (pj[1] - pk[1]) / det;
        g[i * 2 + 1] = (pk[0] - pj[0]) / det;
    }
    return det;
}

/* Ke += w B' D B at one point with shape gradients g (nv nodes, d dims):
   Ke[(a,i),(b,j)] += w (lambda g_a,i g_b,j + mu g_a,j g_b,i + mu delta_ij g_a.g_b) */
static void add_bdb(double *Ke, const double *g, int nv, int d, double lam, double mu, double w)
{
    int n = d * nv;
    for (int a = 0; a < nv; a++)
        for (int b = 0; b < nv; b++) {
            const double *ga = g + a * d, *gb = g + b * d;
            double gg = 0;
            for (int k = 0; k < d; k++) gg += ga[k] * gb[k];
            for (int i = 0; i < d; i++)
                for (int j = 0; j < d; j++) {
                    double v = lam * ga[i] * gb[j] + mu * ga[j] * gb[i];
                    if (i == j) v += mu * gg;
                    Ke[(size_t)(b * d + j) * n + (a * d + i)] += w * v;
                }
        }
}

/* Ke = V B' D B (tet4), with D the isotropic elasticity matrix of (E, nu):
   lambda = E nu / ((1+nu)(1-2nu)), mu = E / (2(1+nu)); written out as
   Ke[(a,i),(b,j)] = V (lambda g_a,i g_b,j + mu g_a,j g_b,i + mu delta_ij g_a.g_b).
   Ke = t A B' D B (tri3 plane stress), D = E/(1-nu^2) [1 nu 0; nu 1 0; 0 0 (1-nu)/2],
   the same form with lambda* = E nu / (1-nu^2), mu = E / (2(1+nu)) ([Zienkiewicz]).
   V = det J / 6 and A = det / 2 are signed: an inverted element gives -Ke.
   hex8 (Q1, trilinear): Ke = sum_q det J(xi_q) B(xi_q)' D B(xi_q) over the
   2x2x2 Gauss points (full integration; Hughes, The Finite Element Method,
   sec. 3.5-3.8, aug_hex_shape and aug_hex_gauss), 24 x 24.
   mem3: aug_membrane_stiffness (lib/fem/membrane.c), 9 x 9. */
void aug_elem_stiffness(const aug_mesh *m, int64_t e, double *Ke)
{
    const aug_material *mat = &m->mats[m->mat[e]];
    double E = mat->E, nu = mat->nu, mu = E / (2 * (1 + nu)), lam, g[AUG_MAX_EDOF];
    int d = m->dim, nv = m->nv, n = d * nv;
    if (m->etype == AUG_MEM3) {
        aug_membrane_stiffness(m, e, Ke);
        return;
    }
    memset(Ke, 0, sizeof(double) * (size_t)n * n);
    if (nv == 8) {
        double xi[3], N[8];
        lam = E * nu / ((1 + nu) * (1 - 2 * nu));
        for (int q = 0; q < 8; q++) {
            aug_hex_gauss(q, xi);
            double w = aug_hex_shape(m, e, xi, N, g);
            add_bdb(Ke, g, nv, d, lam, mu, w);
        }
        return;
    }
    double w;
    if (d == 3) {
        lam = E * nu / ((1 + nu) * (1 - 2 * nu));
        w = tet_grad(m, e, g) / 6.0;
    } else {
        lam = E * nu / (1 - nu * nu);
        w = mat->t * tri_grad(m, e, g) / 2.0;
    }
    add_bdb(Ke, g, nv, d, lam, mu, w);
}

double aug_elem_grad(const aug_mesh *m, int64_t e, const double *xi, double *g)
{
    static const double centre[3] = {0, 0, 0};
    double N[8];
    if (m->etype == AUG_HEX8) return aug_hex_shape(m, e, xi ? xi : centre, N, g);
    if (m->etype == AUG_MEM3) return aug_membrane_grad(m, e, g, N);
    return m->dim == 3 ? tet_grad(m, e, g) : tri_grad(m, e, g);
}
