/* Element mass matrices of tet4, tri3 and hex8: consistent and row-sum lumped
   ([Zienkiewicz]; Hughes, The Finite Element Method, sec. 7.3). */
#include <string.h>
#include "aug_fem.h"

/* hex8: m_ab = rho sum_q det J(xi_q) N_a N_b (2x2x2 Gauss, exact for Q1), the
   lumped diagonal its row sums rho sum_q det J N_a (sum_b N_b = 1) */
static void hex_mass(const aug_mesh *m, int64_t e, int lumped, double rho, double *Me)
{
    double xi[3], N[8], mab[8][8] = {{0}};
    for (int q = 0; q < 8; q++) {
        aug_hex_gauss(q, xi);
        double w = rho * aug_hex_shape(m, e, xi, N, NULL);
        for (int a = 0; a < 8; a++)
            for (int b = 0; b < 8; b++) mab[a][b] += lumped ? (a == b ? w * N[a] : 0.0) : w * N[a] * N[b];
    }
    for (int a = 0; a < 8; a++)
        for (int b = 0; b < 8; b++)
            for (int i = 0; i < 3; i++) Me[(size_t)(b * 3 + i) * 24 + (a * 3 + i)] = mab[a][b];
}

/* Consistent: Me[(a,i),(b,j)] = rho delta_ij int N_a N_b, with int N_a N_b =
   V (1 + delta_ab) / 20 (tet4) and t A (1 + delta_ab) / 12 (tri3, and mem3
   with its 3 components).
   Lumped (row sums of the consistent matrix): rho w / nv on the diagonal,
   w = V (tet4) or t A (tri3) ([Zienkiewicz]); V, A signed (aug_elem_measure).
   hex8: hex_mass. */
void aug_elem_mass(const aug_mesh *m, int64_t e, int lumped, double *Me)
{
    const aug_material *mat = &m->mats[m->mat[e]];
    int d = m->dim, nv = m->nv, n = d * nv;
    memset(Me, 0, sizeof(double) * (size_t)n * n);
    if (nv == 8) {
        hex_mass(m, e, lumped, mat->rho, Me);
        return;
    }
    double w = mat->rho * aug_elem_measure(m, e) * (d == 2 || m->etype == AUG_MEM3 ? mat->t : 1.0);
    double den = nv == 4 ? 20.0 : 12.0; /* tet4; tri3 and mem3 */
    for (int a = 0; a < nv; a++)
        for (int b = 0; b < nv; b++) {
            double v = lumped ? (a == b ? w / nv : 0.0) : w * (a == b ? 2.0 : 1.0) / den;
            for (int i = 0; i < d; i++) Me[(size_t)(b * d + i) * n + (a * d + i)] = v;
        }
}

/* The consistent load of the body force rho * m->grav (GRAV) on element e:
   be[a*dim+c] = grav_c rho int N_a (t in 2-D and mem3), the row sums of the consistent
   mass (sum_b N_b = 1), i.e. the lumped mass times grav. Returns 0 when the
   mesh has no body force (be zeroed). */
int aug_elem_body(const aug_mesh *m, int64_t e, double *be)
{
    int d = m->dim, n = d * m->nv;
    memset(be, 0, sizeof(double) * (size_t)n);
    if (m->grav[0] == 0 && m->grav[1] == 0 && m->grav[2] == 0) return 0;
    double Ml[AUG_MAX_EMAT];
    aug_elem_mass(m, e, 1, Ml);
    for (int k = 0; k < n; k++) be[k] = Ml[(size_t)k * n + k] * m->grav[k % d];
    return 1;
}
