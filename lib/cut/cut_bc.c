/* Boundary conditions a cut step adds: constraints on a set or a box (the
   augmented-matrix paper eq. 3, AMPS sec. 3.4) and the pull forces that open
   the cut (AMPS sec. 4.3.2). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

/* BDLT += u_c = v_c (0 when v is NULL) for each component of node (also
   where m has that constraint already: aug_constrain_step drops those once
   the step's constraints are composed) */
static int fix_node(const aug_mesh *m, int32_t node, const double *v, aug_bdelta *b)
{
    for (int c = 0; c < m->dim; c++)
        if (aug_bdelta_fix(b, node * m->dim + c, v ? v[c] : 0.0)) return -1;
    return 0;
}

/* new Dirichlet constraints u = v on the nodes of set (paper 000 eq. 3; the
   matrix takes them as identity rows, formats/stream.md 7.2) */
int aug_cut_constrain_set(const aug_mesh *m, const char *set, const double *v, aug_bdelta *b,
                          aug_err *e)
{
    aug_err_clear(e);
    const aug_set *s = aug_mesh_set(m, set);
    if (!s) return aug_err_set(e, AUG_EDATA, -1, "nSEt", "no node set named '%s'", set);
    for (int64_t i = 0; i < s->n; i++)
        if (fix_node(m, s->nodes[i], v, b))
            return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
    return 0;
}

/* new Dirichlet constraints u = v on the nodes with lo <= x <= hi (as
   aug_cut_constrain_set); AUG_EDATA when the box holds no node */
int aug_cut_constrain_box(const aug_mesh *m, const double *lo, const double *hi,
                          const double *v, aug_bdelta *b, aug_err *e)
{
    aug_err_clear(e);
    int64_t hit = 0;
    for (int64_t i = 0; i < m->nn; i++) {
        int in = 1;
        for (int k = 0; k < m->dim && in; k++) {
            double x = m->x[i * m->dim + k];
            in = x >= lo[k] && x <= hi[k];
        }
        if (!in) continue;
        hit++;
        if (fix_node(m, (int32_t)i, v, b))
            return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
    }
    if (!hit) return aug_err_set(e, AUG_EDATA, -1, "", "the constraint box holds no node");
    return 0;
}

/* centroid of the elements around node p */
static void star_centroid(const aug_mesh *m, const aug_adj *adj, int32_t p, double *c)
{
    int dim = m->dim, nv = m->nv;
    for (int k = 0; k < dim; k++) c[k] = 0;
    for (int32_t i = 0; i < adj->cnt[p]; i++) {
        const int32_t *cn = m->conn + (int64_t)adj->list[p][i] * nv;
        for (int a = 0; a < nv; a++)
            for (int k = 0; k < dim; k++) c[k] += m->x[(int64_t)cn[a] * dim + k];
    }
    if (adj->cnt[p])
        for (int k = 0; k < dim; k++) c[k] /= (double)adj->cnt[p] * nv;
}

/* current total force on dof: b's latest entry, else the mesh's */
static double current(const aug_mesh *m, const aug_bdelta *b, int32_t dof)
{
    for (int64_t i = b->nload - 1; i >= 0; i--)
        if (b->load_dof[i] == dof) return b->load_val[i];
    return aug_mesh_load(m, dof);
}

/* Opposing pull forces (paper 001 sec. 4.3.2): for every copy q made by d (at its
   parent p's place), force F along u = centroid(star q) - centroid(star p) (or
   +-dir, the sign of u.dir) added to q's total load and subtracted from p's; nodes
   a split inserted get none */
int aug_cut_pull(const aug_mesh *m, const aug_adj *adj, const aug_mdelta *d, double F,
                 const double *dir, aug_bdelta *b, aug_err *e)
{
    aug_err_clear(e);
    int dim = m->dim;
    int64_t nnb = m->nn - d->nnew;
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t q = (int32_t)(nnb + i), p = d->parent[i];
        if (memcmp(m->x + (int64_t)q * dim, m->x + (int64_t)p * dim, (size_t)dim * sizeof(double)))
            continue; /* a node inserted by a split, not a copy */
        double cq[3], cp[3], u[3], s = 0;
        star_centroid(m, adj, q, cq);
        star_centroid(m, adj, p, cp);
        for (int k = 0; k < dim; k++) {
            u[k] = cq[k] - cp[k];
            s += u[k] * u[k];
        }
        if (dir) {
            double sg = 0;
            s = 0;
            for (int k = 0; k < dim; k++) sg += u[k] * dir[k];
            for (int k = 0; k < dim; k++) {
                u[k] = sg >= 0 ? dir[k] : -dir[k];
                s += u[k] * u[k];
            }
        }
        s = sqrt(s);
        if (!(s > 0)) continue;
        for (int k = 0; k < dim; k++) {
            double f = F * u[k] / s;
            if (f == 0) continue;
            if (aug_bdelta_load(b, q * dim + k, current(m, b, q * dim + k) + f) ||
                aug_bdelta_load(b, p * dim + k, current(m, b, p * dim + k) - f))
                return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
        }
    }
    return 0;
}
