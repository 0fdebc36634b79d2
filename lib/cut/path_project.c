/* Cut paths projected onto a membrane (mem3) sheet along a view direction
   (thesis 003 sec. 3.1.1, figs. 3.2-3.3): the 2-D path cut runs on the
   sheet's image in the view plane, its edits lifted back onto the sheet. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_update.h"

/* view = (u, v): both non-zero and finite, u.v <= 1e-9 |u| |v|; normalised in place */
int aug_view_axes(double view[6], aug_err *e)
{
    aug_err_clear(e);
    double nu = sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
    double nv = sqrt(view[3] * view[3] + view[4] * view[4] + view[5] * view[5]);
    if (!(nu > 0) || !(nv > 0) || !isfinite(nu) || !isfinite(nv))
        return aug_err_set(e, AUG_EUSAGE, -1, "", "u and v must be finite and non-zero");
    double d = (view[0] * view[3] + view[1] * view[4] + view[2] * view[5]) / (nu * nv);
    if (fabs(d) > 1e-9) return aug_err_set(e, AUG_EUSAGE, -1, "", "u and v are not orthogonal (u.v = %.3g |u||v|)", d);
    for (int k = 0; k < 3; k++) view[k] /= nu, view[3 + k] /= nv;
    return 0;
}

void aug_view_free(aug_view *vw)
{
    aug_edit_free(&vw->ed);
    aug_adj_free(&vw->adj);
    aug_mesh_free(&vw->img);
    memset(vw, 0, sizeof *vw);
}

/* The image of m under the orthographic view (u, v): node x -> (u.x, v.x)
   (thesis 003 sec. 3.1.1: the model multiplied by the view matrix, the cut
   detected in 2-D), the triangles as in m (all reversed, flip = 1, when the
   sheet faces away from w = u x v). Every triangle must face the same way,
   its image's area above 1e-12 of its own: a sheet seen edge-on, or folded
   over itself along the view, is refused naming the triangle. The image's
   FIXD fixes min(k, 2) components of a node with k fixed in m, so that the
   2-D split code chooses the same parents (the less constrained end). */
int aug_view_init(aug_view *vw, const aug_mesh *m, const double u[3], const double v[3], aug_err *e)
{
    aug_err_clear(e);
    memset(vw, 0, sizeof *vw);
    if (m->etype != AUG_MEM3) return aug_err_set(e, AUG_EUSAGE, -1, "ELEM", "a view needs a membrane (mem3) mesh");
    memcpy(vw->u, u, sizeof vw->u);
    memcpy(vw->v, v, sizeof vw->v);
    vw->w[0] = u[1] * v[2] - u[2] * v[1], vw->w[1] = u[2] * v[0] - u[0] * v[2], vw->w[2] = u[0] * v[1] - u[1] * v[0];
    aug_mesh *g = &vw->img;
    if (aug_mesh_copy(g, m)) goto nomem;
    free(g->x), free(g->load_dof), free(g->load_val), free(g->fix_dof), free(g->fix_val);
    g->load_dof = g->fix_dof = NULL, g->load_val = g->fix_val = NULL, g->nload = g->nfix = 0;
    g->dim = 2, g->etype = AUG_TRI3;
    memset(g->grav, 0, sizeof g->grav);
    g->x = aug_malloc((size_t)(m->nn ? m->nn : 1) * 2 * sizeof *g->x);
    g->fix_dof = aug_malloc((size_t)(m->nn ? m->nn : 1) * 2 * sizeof *g->fix_dof);
    g->fix_val = aug_calloc((size_t)(m->nn ? m->nn : 1) * 2, sizeof *g->fix_val);
    if (!g->x || !g->fix_dof || !g->fix_val) goto nomem;
    for (int64_t i = 0; i < m->nn; i++) {
        const double *p = m->x + i * 3;
        g->x[i * 2] = u[0] * p[0] + u[1] * p[1] + u[2] * p[2];
        g->x[i * 2 + 1] = v[0] * p[0] + v[1] * p[1] + v[2] * p[2];
    }
    for (int64_t t = 0, k = 0; t < m->nfix; t = k) {
        int32_t node = m->fix_dof[t] / 3;
        for (k = t; k < m->nfix && m->fix_dof[k] / 3 == node; k++) {}
        for (int64_t c = 0; c < k - t && c < 2; c++) g->fix_dof[g->nfix++] = node * 2 + (int32_t)c;
    }
    int sign = 0;
    for (int64_t t = 0; t < g->ne; t++) {
        double a2 = aug_elem_measure(g, t), a3 = aug_elem_measure(m, t);
        int s = a2 > 1e-12 * a3 ? 1 : a2 < -1e-12 * a3 ? -1 : 0;
        if (t == 0) sign = s;
        if (s == 0 || s != sign) {
            aug_view_free(vw);
            return aug_err_set(e, AUG_EDATA, -1, "ELEM",
                               "triangle %lld is %s along the view (image area %.3g of %.3g): a projected "
                               "cut needs a sheet seen as one layer, every triangle facing the same way",
                               (long long)t, s == 0 ? "seen edge-on" : "facing the other way than triangle 0",
                               a2, a3);
        }
    }
    vw->flip = sign < 0;
    for (int64_t t = 0; vw->flip && t < g->ne; t++) {
        int32_t s = g->conn[t * 3 + 1];
        g->conn[t * 3 + 1] = g->conn[t * 3 + 2], g->conn[t * 3 + 2] = s;
    }
    if (aug_adj_build(&vw->adj, g) || aug_edit_init(&vw->ed, g, &vw->adj)) goto nomem;
    return 0;
nomem:
    aug_view_free(vw);
    return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
}

/* the image's triangle t as it was when the step began */
static const int32_t *begin_conn(const aug_edit *ed, int64_t t)
{
    if (t < ed->capslot && ed->slot[t] >= 0) return ed->mod_old + (int64_t)ed->slot[t] * 3;
    return ed->m->conn + t * 3;
}

/* x3 = sum_k l_k X_k in the triangle of the image at the step's begin that
   holds q best (the largest least barycentric coordinate l): the point of
   the sheet seen at q, back through the inverse of the view (thesis 003
   sec. 3.1.1, fig. 3.2) onto the flat triangle, so that a cut leaves the
   sheet's shape (and area) as it was. -1 when q is outside the image. */
static int lift_point(const aug_view *vw, const aug_mesh *m, const double *q, double *x3)
{
    const aug_edit *ed = &vw->ed;
    double best = -INFINITY, bl[3] = {0, 0, 0};
    const int32_t *bc = NULL;
    const double *X = ed->m->x;
    for (int64_t t = 0; t < ed->ne0; t++) {
        const int32_t *c = begin_conn(ed, t);
        const double *p0 = X + c[0] * 2, *p1 = X + c[1] * 2, *p2 = X + c[2] * 2;
        double det = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]);
        double l1 = ((q[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (q[1] - p0[1])) / det;
        double l2 = ((p1[0] - p0[0]) * (q[1] - p0[1]) - (q[0] - p0[0]) * (p1[1] - p0[1])) / det;
        double l[3] = {1 - l1 - l2, l1, l2}, mn = fmin(l[0], fmin(l[1], l[2]));
        if (mn > best) best = mn, bc = c, memcpy(bl, l, sizeof bl);
    }
    if (!bc || best < -1e-9) return -1;
    for (int r = 0; r < 3; r++)
        x3[r] = bl[0] * m->x[bc[0] * 3 + r] + bl[1] * m->x[bc[1] * 3 + r] + bl[2] * m->x[bc[2] * 3 + r];
    return 0;
}

/* The path cut of one step on the image (aug_path_step on vw->ed), then
   replayed onto ed3, the cutter's edit of the sheet m: each new node lifted
   (lift_point) with the image's parent, the re-wired and added triangles
   with the image's connectivity (flip undone), the step's segments (*seg
   empty on entry; 2-D from aug_path_step) lifted to 3-D points (6 doubles
   each, as pATH wants in dim 3); then the image completes its step (aug_edit_end, aug_mesh_apply). */
int aug_view_path_step(aug_view *vw, aug_path_cut *pc, aug_edit *ed3, int32_t step, double s_to,
                       double **seg, int64_t *nseg, aug_err *e)
{
    aug_edit *ed = &vw->ed;
    const aug_mesh *m = ed3->m;
    if (*nseg != 0) return aug_err_set(e, AUG_EUSAGE, -1, "pATH", "a view's step starts with no segments");
    int rc = aug_path_step(pc, ed, s_to, seg, nseg, e);
    if (rc) return rc;
    if (ed->nn0 != ed3->nn0 + ed3->nnew || ed->ne0 != ed3->ne0 + ed3->nadd)
        return aug_err_set(e, AUG_EUSAGE, -1, "MDLT", "the view's image is out of step with the sheet");
    double x3[3];
    for (int64_t j = 0; j < ed->nnew; j++) {
        if (lift_point(vw, m, ed->xnew + j * 2, x3))
            return aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: new node %lld lies outside the sheet's image",
                               (int)step, (long long)(ed->nn0 + j));
        if (aug_edit_node(ed3, x3, ed->parent[j]) != (int32_t)(ed->nn0 + j)) goto nomem;
    }
    int32_t c[3];
    for (int64_t i = 0; i < ed->nmod + ed->nadd; i++) {
        int64_t el = i < ed->nmod ? ed->mod_elem[i] : ed->ne0 + (i - ed->nmod);
        memcpy(c, aug_edit_conn(ed, el), sizeof c);
        if (vw->flip) {
            int32_t s = c[1];
            c[1] = c[2], c[2] = s;
        }
        if (i < ed->nmod ? aug_edit_set(ed3, el, c) != 0 : aug_edit_elem(ed3, c, ed->mat_add[i - ed->nmod]) != el)
            goto nomem;
    }
    double *q = aug_malloc((size_t)(*nseg ? *nseg : 1) * 6 * sizeof *q);
    if (!q) goto nomem;
    for (int64_t i = 0; i < *nseg; i++)
        for (int k = 0; k < 2; k++)
            if (lift_point(vw, m, *seg + i * 4 + k * 2, q + i * 6 + k * 3)) {
                free(q);
                return aug_err_set(e, AUG_EDATA, -1, "pATH", "step %d: a cut segment lies outside the sheet's image",
                                   (int)step);
            }
    free(*seg);
    *seg = q;
    aug_mdelta d;
    int32_t *old = NULL;
    rc = aug_edit_end(ed, step, &d, &old, e);
    if (!rc) rc = aug_mesh_apply(&vw->img, &d, e);
    aug_mdelta_free(&d);
    free(old);
    aug_edit_begin(ed);
    return rc;
nomem:
    return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
}
