/* Reaction forces at the constrained DOFs (paper 000 eq. 9: the unknown at a
   constrained DOF), element by element over the elements that touch them, and
   their resultants per named node set. */
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

/* The elements of m with a node that has a constrained DOF, increasing, into
   *elems (malloc'd): a pass over the connectivity. Returns their count, -1
   when out of memory. */
int64_t aug_react_elements(const aug_mesh *m, int32_t **elems)
{
    *elems = NULL;
    unsigned char *cn = aug_calloc((size_t)m->nn + 1, 1);
    int32_t *el = aug_malloc((size_t)m->ne * sizeof *el + 4);
    if (!cn || !el) {
        free(cn);
        free(el);
        return -1;
    }
    for (int64_t k = 0; k < m->nfix; k++) cn[m->fix_dof[k] / m->dim] = 1;
    int64_t n = 0;
    for (int64_t e = 0; e < m->ne; e++) {
        const int32_t *c = m->conn + e * m->nv;
        int any = 0;
        for (int a = 0; a < m->nv; a++) any |= cn[c[a]];
        if (any) el[n++] = (int32_t)e;
    }
    free(cn);
    *elems = el;
    return n;
}

/* r[k] = (M a + D v + K u - f)_{dof_k}, dof_k = m->fix_dof[k], D = alpha M +
   beta K (Rayleigh), f the nodal loads of m: per element e of elems (increasing,
   every element touching a constrained DOF among them) the rows of its
   constrained DOFs, r += K_e (u + beta v) + M_e (a + alpha v), M_e consistent
   or lumped (aug_elem_mass); then r -= f. Statics (dyn NULL): r = (K u - f)_C.
   u, v, a are nodal (nn*dim) and read at the nodes of elems only. */
void aug_reactions(const aug_mesh *m, const int32_t *elems, int64_t nel, const double *u,
                   const aug_react_dyn *dyn, double *r)
{
    int d = m->dim, nd = m->nv * d;
    double Ke[AUG_MAX_EMAT], Me[AUG_MAX_EMAT], w[AUG_MAX_EDOF], z[AUG_MAX_EDOF], be[AUG_MAX_EDOF];
    int64_t pos[AUG_MAX_EDOF];
    memset(r, 0, (size_t)m->nfix * sizeof *r);
    for (int64_t t = 0; t < nel; t++) {
        const int32_t *c = m->conn + (int64_t)elems[t] * m->nv;
        int any = 0;
        for (int i = 0; i < nd; i++) {
            int64_t g = (int64_t)c[i / d] * d + i % d;
            pos[i] = aug_find_i32(m->fix_dof, m->nfix, (int32_t)g);
            any |= pos[i] >= 0;
            w[i] = u[g] + (dyn ? dyn->beta * dyn->v[g] : 0.0);
            if (dyn) z[i] = dyn->a[g] + dyn->alpha * dyn->v[g];
        }
        if (!any) continue;
        aug_elem_stiffness(m, elems[t], Ke);
        aug_elem_body(m, elems[t], be);
        if (dyn) aug_elem_mass(m, elems[t], dyn->lumped, Me);
        for (int i = 0; i < nd; i++) {
            if (pos[i] < 0) continue;
            double s = 0;
            for (int j = 0; j < nd; j++) s += Ke[(size_t)j * nd + i] * w[j];
            if (dyn)
                for (int j = 0; j < nd; j++) s += Me[(size_t)j * nd + i] * z[j];
            r[pos[i]] += s - be[i];
        }
    }
    for (int64_t k = 0; k < m->nfix; k++) {
        int64_t q = aug_find_i32(m->load_dof, m->nload, m->fix_dof[k]);
        if (q >= 0) r[k] -= m->load_val[q];
    }
}

/* room for n reactions and nset sets in q (contents kept); 0 or -1 */
int aug_reaction_reserve(aug_reaction *q, int64_t n, int64_t nset)
{
    if (n > q->cap) {
        int32_t *dof = aug_realloc(q->dof, (size_t)n * sizeof *dof);
        if (!dof) return -1;
        q->dof = dof;
        double *r = aug_realloc(q->r, (size_t)n * sizeof *r);
        if (!r) return -1;
        q->r = r;
        q->cap = n;
    }
    if (nset > q->setcap) {
        char(*name)[AUG_NAME] = aug_realloc(q->name, (size_t)nset * AUG_NAME);
        if (!name) return -1;
        q->name = name;
        double *res = aug_realloc(q->res, (size_t)nset * 3 * sizeof *res);
        if (!res) return -1;
        q->res = res;
        q->setcap = nset;
    }
    return 0;
}

void aug_reaction_free(aug_reaction *q)
{
    free(q->dof);
    free(q->r);
    free(q->name);
    free(q->res);
    memset(q, 0, sizeof *q);
}

/* q := the reactions of m (aug_reactions) on its constrained DOFs in their
   order, the total per component (sum over every constrained DOF) and, per
   named set of m holding a constrained DOF (in the mesh's set order), the
   resultant: the sum per component of the reactions at its constrained DOFs.
   frame and time are left as they are. */
int aug_reaction_compute(aug_reaction *q, const aug_mesh *m, const int32_t *elems, int64_t nel,
                         const double *u, const aug_react_dyn *dyn, aug_err *e)
{
    aug_err_clear(e);
    int d = m->dim;
    if (aug_reaction_reserve(q, m->nfix, m->nset)) return aug_err_set(e, AUG_ENOMEM, -1, "rEAC", "out of memory");
    q->dim = d;
    q->n = m->nfix;
    memcpy(q->dof, m->fix_dof, (size_t)m->nfix * sizeof *q->dof);
    aug_reactions(m, elems, nel, u, dyn, q->r);
    memset(q->total, 0, sizeof q->total);
    for (int64_t k = 0; k < q->n; k++) q->total[q->dof[k] % d] += q->r[k];
    q->nset = 0;
    for (int s = 0; s < m->nset; s++) {
        const aug_set *S = &m->sets[s];
        double sum[3] = {0, 0, 0};
        int held = 0;
        for (int64_t k = 0; k < q->n; k++) {
            int32_t node = q->dof[k] / d;
            if (aug_find_i32(S->nodes, S->n, node) < 0) continue;
            held = 1;
            sum[q->dof[k] % d] += q->r[k];
        }
        if (!held) continue;
        memcpy(q->name[q->nset], S->name, AUG_NAME);
        memcpy(q->res + q->nset * d, sum, (size_t)d * sizeof *sum);
        q->nset++;
    }
    return 0;
}
