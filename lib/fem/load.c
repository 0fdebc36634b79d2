/* The lifted load over the free DOFs: nodal forces minus the coupling to the
   prescribed displacements, f = loads_F - K[F,D] a_D. */
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

/* f_F = l_F + b_F - K_FD a_D (paper 000 eq. 11, paper 001 eq. 3.29, on the free
   rows; b the body force of GRAV, element by element),
   K_FD accumulated element by element (element order): f[map[r]] -= Ke(r, d) a_d
   for every free r and constrained d of each element. */
int aug_load_vector(const aug_mesh *m, const int32_t *map, int64_t nfree, double *f,
                    aug_err *e)
{
    aug_err_clear(e);
    int d = m->dim, nv = m->nv, n = d * nv;
    int64_t nd = m->nn * d;
    memset(f, 0, (size_t)nfree * sizeof *f);
    for (int64_t t = 0; t < m->nload; t++) {
        int32_t q = map[m->load_dof[t]];
        if (q >= 0) f[q] += m->load_val[t];
    }
    double be[AUG_MAX_EDOF];
    for (int64_t el = 0; el < m->ne && aug_elem_body(m, el, be); el++)
        for (int k = 0; k < n; k++) {
            int32_t q = map[(int64_t)m->conn[el * nv + k / d] * d + k % d];
            if (q >= 0) f[q] += be[k];
        }
    if (m->nfix == 0) return 0;
    double *a = aug_calloc((size_t)(nd ? nd : 1), sizeof *a);
    if (!a) return aug_err_set(e, AUG_ENOMEM, -1, "FVEC", "out of memory");
    int any = 0;
    for (int64_t t = 0; t < m->nfix; t++) {
        a[m->fix_dof[t]] = m->fix_val[t];
        any |= m->fix_val[t] != 0;
    }
    if (!any) {
        free(a);
        return 0;
    }
    double Ke[AUG_MAX_EMAT];
    for (int64_t el = 0; el < m->ne; el++) {
        const int32_t *cn = m->conn + el * nv;
        int need = 0;
        for (int k = 0; k < n && !need; k++) {
            int64_t g = (int64_t)cn[k / d] * d + k % d;
            need = map[g] < 0 && a[g] != 0;
        }
        if (!need) continue;
        aug_elem_stiffness(m, el, Ke);
        for (int s = 0; s < n; s++) {
            int64_t gs = (int64_t)cn[s / d] * d + s % d;
            if (map[gs] >= 0 || a[gs] == 0) continue;
            for (int r = 0; r < n; r++) {
                int32_t q = map[(int64_t)cn[r / d] * d + r % d];
                if (q >= 0) f[q] -= Ke[(size_t)s * n + r] * a[gs];
            }
        }
    }
    free(a);
    return 0;
}
