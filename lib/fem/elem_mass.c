/* Element mass matrices of tet4 and tri3: consistent and row-sum lumped
   ([Zienkiewicz]). */
#include <string.h>
#include "aug_fem.h"

/* Consistent: Me[(a,i),(b,j)] = rho delta_ij int N_a N_b, with int N_a N_b =
   V (1 + delta_ab) / 20 (tet4) and t A (1 + delta_ab) / 12 (tri3).
   Lumped (row sums of the consistent matrix): rho w / nv on the diagonal,
   w = V (tet4) or t A (tri3) ([Zienkiewicz]); V, A signed (aug_elem_measure). */
/* The consistent load of the body force rho * m->grav on element e (linear
   elements: each node rho |e| t / nv of it, t the thickness in 2-D): be[a*dim+c].
   Returns 0 when the mesh has no body force (be zeroed). */
int aug_elem_body(const aug_mesh *m, int64_t e, double *be)
{
    int d = m->dim, nv = m->nv;
    memset(be, 0, sizeof(double) * (size_t)(d * nv));
    if (m->grav[0] == 0 && m->grav[1] == 0 && m->grav[2] == 0) return 0;
    const aug_material *mat = &m->mats[m->mat[e]];
    double w = mat->rho * aug_elem_measure(m, e) * (d == 2 ? mat->t : 1.0) / nv;
    for (int a = 0; a < nv; a++)
        for (int c = 0; c < d; c++) be[a * d + c] = w * m->grav[c];
    return 1;
}

void aug_elem_mass(const aug_mesh *m, int64_t e, int lumped, double *Me)
{
    const aug_material *mat = &m->mats[m->mat[e]];
    int d = m->dim, nv = m->nv, n = d * nv;
    double w = mat->rho * aug_elem_measure(m, e) * (d == 2 ? mat->t : 1.0);
    double den = d == 3 ? 20.0 : 12.0;
    memset(Me, 0, sizeof(double) * (size_t)n * n);
    for (int a = 0; a < nv; a++)
        for (int b = 0; b < nv; b++) {
            double v = lumped ? (a == b ? w / nv : 0.0) : w * (a == b ? 2.0 : 1.0) / den;
            for (int i = 0; i < d; i++) Me[(size_t)(b * d + i) * n + (a * d + i)] = v;
        }
}
