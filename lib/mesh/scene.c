/* Scene options on a mesh: node predicates, Dirichlet constraints, nodal loads, output set. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_scene.h"

/* coordinate d of node i, z = 0 in 2-D */
static double X(const aug_mesh *m, int64_t i, int d)
{
    return d < m->dim ? m->x[i * m->dim + d] : 0.0;
}

/* lo <= x_i <= hi componentwise over the mesh's dimensions */
int64_t aug_nodes_in_box(const aug_mesh *m, const double lo[3], const double hi[3],
                         unsigned char *mark)
{
    int64_t n = 0;
    for (int64_t i = 0; i < m->nn; i++) {
        int in = 1;
        for (int d = 0; d < m->dim; d++) {
            double x = X(m, i, d);
            in &= x >= lo[d] && x <= hi[d];
        }
        if (in) mark[i] = 1, n++;
    }
    return n;
}

/* |n.x_i - d| <= tol |n| */
int64_t aug_nodes_on_plane(const aug_mesh *m, const double nrm[3], double d, double tol,
                           unsigned char *mark)
{
    double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    int64_t n = 0;
    for (int64_t i = 0; i < m->nn; i++) {
        double s = nrm[0] * X(m, i, 0) + nrm[1] * X(m, i, 1) + nrm[2] * X(m, i, 2);
        if (fabs(s - d) <= tol * len) mark[i] = 1, n++;
    }
    return n;
}

/* argmin_i |x_i - p|, the lowest index among equals */
int64_t aug_nearest_node(const aug_mesh *m, const double p[3])
{
    int64_t best = -1;
    double bd = INFINITY;
    for (int64_t i = 0; i < m->nn; i++) {
        double s = 0;
        for (int d = 0; d < m->dim; d++) {
            double h = X(m, i, d) - p[d];
            s += h * h;
        }
        if (s < bd) bd = s, best = i;
    }
    return best;
}

/* |max x - min x| over the nodes */
double aug_mesh_extent(const aug_mesh *m)
{
    double s = 0;
    for (int d = 0; d < m->dim; d++) {
        double lo = INFINITY, hi = -INFINITY;
        for (int64_t i = 0; i < m->nn; i++) {
            lo = fmin(lo, X(m, i, d));
            hi = fmax(hi, X(m, i, d));
        }
        if (m->nn) s += (hi - lo) * (hi - lo);
    }
    return sqrt(s);
}

/* FIXD: dofs i*dim + c of the marked nodes, value 0 */
int aug_mesh_fix_marked(aug_mesh *m, const unsigned char *mark, aug_err *e)
{
    int64_t n = 0;
    for (int64_t i = 0; i < m->nn; i++) n += mark[i] != 0;
    int32_t *dof = aug_malloc((size_t)(n ? n : 1) * m->dim * sizeof *dof);
    double *val = aug_calloc((size_t)(n ? n : 1) * m->dim, sizeof *val);
    if (!dof || !val) {
        free(dof);
        free(val);
        return aug_err_set(e, AUG_ENOMEM, -1, "FIXD", "out of memory");
    }
    int64_t k = 0;
    for (int64_t i = 0; i < m->nn; i++)
        if (mark[i])
            for (int c = 0; c < m->dim; c++) dof[k++] = (int32_t)(i * m->dim + c);
    free(m->fix_dof);
    free(m->fix_val);
    m->fix_dof = dof;
    m->fix_val = val;
    m->nfix = k;
    m->have |= AUG_HAVE_FIXD;
    return 0;
}

/* f_i += F / n for each listed node i */
void aug_load_spread(const aug_mesh *m, const int32_t *nodes, int64_t n, const double F[3],
                     double *f)
{
    for (int64_t j = 0; j < n; j++)
        for (int c = 0; c < m->dim; c++) f[(int64_t)nodes[j] * m->dim + c] += F[c] / (double)n;
}

/* LOAD: the nonzero entries of f, in dof order */
int aug_mesh_set_load(aug_mesh *m, const double *f, aug_err *e)
{
    int64_t nd = m->nn * m->dim, n = 0;
    for (int64_t i = 0; i < nd; i++) n += f[i] != 0;
    int32_t *dof = aug_malloc((size_t)(n ? n : 1) * sizeof *dof);
    double *val = aug_malloc((size_t)(n ? n : 1) * sizeof *val);
    if (!dof || !val) {
        free(dof);
        free(val);
        return aug_err_set(e, AUG_ENOMEM, -1, "LOAD", "out of memory");
    }
    int64_t k = 0;
    for (int64_t i = 0; i < nd; i++)
        if (f[i] != 0) dof[k] = (int32_t)i, val[k++] = f[i];
    free(m->load_dof);
    free(m->load_val);
    m->load_dof = dof;
    m->load_val = val;
    m->nload = k;
    m->have |= AUG_HAVE_LOAD;
    return 0;
}

/* oUTs: kind, name and a copy of the node list */
int aug_mesh_set_output(aug_mesh *m, int kind, const char *name, const int32_t *nodes,
                        int64_t n, aug_err *e)
{
    if (kind == AUG_OUT_ALL) n = 0;
    int32_t *v = aug_malloc((size_t)(n ? n : 1) * sizeof *v);
    if (!v) return aug_err_set(e, AUG_ENOMEM, -1, "oUTs", "out of memory");
    if (n) memcpy(v, nodes, (size_t)n * sizeof *v);
    free(m->out_nodes);
    m->out_nodes = v;
    m->nout = n;
    m->out_kind = kind;
    memset(m->out_name, 0, sizeof m->out_name);
    strncpy(m->out_name, name, AUG_NAME - 1);
    m->have |= AUG_HAVE_OUTS;
    return 0;
}
