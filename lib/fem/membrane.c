/* The membrane triangle (mem3): plane stress in each triangle's own plane with
   3 DOFs per node, for thin sheets in 3-D (thesis 003 sec. 2.5.1, table 5.4). */
#include <math.h>
#include <string.h>
#include "aug_fem.h"

/* Surface gradients of the linear shape functions of mem3 element e:
   G_a = n x (p_c - p_b) / (2A), (a b c) cyclic, n the unit normal
   (p1-p0) x (p2-p0) / (2A) -- the in-plane gradient of N_a written in 3-D,
   tangent to the triangle (in the x-y plane it is tri3's (y_b - y_c,
   x_c - x_b) / 2A). g[a*3+c] = (G_a)_c, nrm the unit normal; returns 2A. */
double aug_membrane_grad(const aug_mesh *m, int64_t e, double g[9], double nrm[3])
{
    const int32_t *c = m->conn + e * 3;
    const double *p[3];
    for (int a = 0; a < 3; a++) p[a] = m->x + (size_t)c[a] * 3;
    double u[3], v[3];
    for (int k = 0; k < 3; k++) u[k] = p[1][k] - p[0][k], v[k] = p[2][k] - p[0][k];
    double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    double det = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++) nrm[k] = n[k] / det;
    for (int a = 0; a < 3; a++) {
        const double *pb = p[(a + 1) % 3], *pc = p[(a + 2) % 3];
        double d[3] = {pc[0] - pb[0], pc[1] - pb[1], pc[2] - pb[2]};
        g[a * 3 + 0] = (nrm[1] * d[2] - nrm[2] * d[1]) / det;
        g[a * 3 + 1] = (nrm[2] * d[0] - nrm[0] * d[2]) / det;
        g[a * 3 + 2] = (nrm[0] * d[1] - nrm[1] * d[0]) / det;
    }
    return det;
}

/* Ke = t A T' B' D B T, the 2-D plane-stress triangle (elem_stiffness.c,
   D = E/(1-nu^2) [1 nu 0; nu 1 0; 0 0 (1-nu)/2]) in the triangle's local axes
   E = [e1 e2] rotated to 3-D by T = diag(E', E', E'), in the 3 x 3 node
   blocks of thesis 003 eq. 2.19 (there 2 x 2) with 3 DOFs per vertex
   (table 5.4). With g_a = E' G_a it reads, frame-free,
     Ke[(a,i),(b,j)] = t A (lam* G_a,i G_b,j + mu G_a,j G_b,i + mu P_ij G_a.G_b),
   lam* = E nu / (1-nu^2), mu = E / (2(1+nu)), P = I - n n' the projector on
   the plane. Its null space is the 6 rigid motions of 3-D: the in-plane
   strain of u vanishes exactly for the 2 in-plane translations, the in-plane
   rotation and the 3 out-of-plane motions w = linear (which are the normal
   translation and the 2 tilts), 9 - 3 strains = 6 ([Zienkiewicz] vol. 1
   ch. 4 and 11: a flat shell facet without its bending part).
   With a Winkler foundation of modulus k (FNDN: force per unit area and unit
   normal displacement, the tissue under a skin) it adds
   k int N_a N_b dA n_i n_j = k A (1 + delta_ab) / 12 n_i n_j, the energy
   k/2 int (u.n)^2 dA ([Zienkiewicz] vol. 2, beams and plates on elastic
   foundations; Hetenyi 1946): the 3 out-of-plane modes are then held and
   3 in-plane ones remain. */
void aug_membrane_stiffness(const aug_mesh *m, int64_t e, double *Ke)
{
    const aug_material *mat = &m->mats[m->mat[e]];
    double E = mat->E, nu = mat->nu, mu = E / (2 * (1 + nu)), lam = E * nu / (1 - nu * nu);
    double g[9], n[3], A = aug_membrane_grad(m, e, g, n) / 2.0, w = mat->t * A, kf = mat->kf * A;
    memset(Ke, 0, sizeof(double) * 81);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            const double *ga = g + a * 3, *gb = g + b * 3;
            double gg = ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2];
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) {
                    double P = (i == j) - n[i] * n[j];
                    Ke[(size_t)(b * 3 + j) * 9 + (a * 3 + i)] =
                        w * (lam * ga[i] * gb[j] + mu * ga[j] * gb[i] + mu * P * gg) +
                        kf * (1.0 + (a == b)) / 12.0 * n[i] * n[j];
                }
        }
}
