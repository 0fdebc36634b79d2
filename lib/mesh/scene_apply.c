/* Scene options applied to an imported mesh: materials, FIXD, LOAD (forces, gravity), oUTs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_scene.h"

/* the set named name, or NULL with a problem when m lacks it or it is empty */
static const aug_set *need_set(aug_sink *k, const aug_mesh *m, const char *opt, const char *arg,
                               const char *name)
{
    const aug_set *s = aug_mesh_set(m, name);
    if (!s) {
        char known[1024] = "";
        size_t n = 0;
        for (int i = 0; i < m->nset && n < sizeof known; i++)
            n += (size_t)snprintf(known + n, sizeof known - n, "%s%s", i ? ", " : "", m->sets[i].name);
        aug_sink_report(k, "%s %s: no physical group or set named '%s' (there are: %s)", opt, arg,
                        name, known);
    } else if (s->n == 0) {
        aug_sink_report(k, "%s %s: set '%s' has no node of the mesh", opt, arg, name);
        return NULL;
    }
    return s;
}

/* each property of each material: --material's, else --default-material's, else its own */
static void materials(const aug_scene_spec *s, aug_mesh *m, aug_sink *k)
{
    int solid = m->dim == 3 && m->etype != AUG_MEM3; /* mem3: a sheet of thickness t */
    if (solid && s->def.has[AUG_PROP_T])
        aug_sink_report(k, "--default-material %s: t= (thickness) applies to 2-D meshes only", s->defarg);
    for (int j = 0; j < s->nmat; j++) {
        const aug_mat_spec *q = &s->mat[j];
        int found = 0;
        for (int i = 0; i < m->nmat; i++) found |= !strcmp(m->mats[i].name, q->group);
        if (!found)
            aug_sink_report(k, "--material %s: '%s' is %s", q->arg, q->group,
                            !aug_mesh_set(m, q->group) ? "no material of the mesh"
                            : solid                    ? "not a physical volume"
                                                       : "not a physical surface");
        if (solid && q->p.has[AUG_PROP_T])
            aug_sink_report(k, "--material %s: t= (thickness) applies to 2-D meshes only", q->arg);
    }
    for (int i = 0; i < m->nmat; i++) {
        aug_material *a = &m->mats[i];
        double *v[AUG_NPROP] = {&a->E, &a->nu, &a->rho, &a->t};
        for (int p = 0; p < AUG_NPROP; p++)
            if (s->def.has[p]) *v[p] = s->def.v[p];
        for (int j = 0; j < s->nmat; j++)
            if (!strcmp(a->name, s->mat[j].group))
                for (int p = 0; p < AUG_NPROP; p++)
                    if (s->mat[j].p.has[p]) *v[p] = s->mat[j].p.v[p];
    }
}

/* mark[i] = 1 for the nodes of every --fix */
static void fixed(const aug_scene_spec *s, const aug_mesh *m, aug_sink *k, unsigned char *mark)
{
    double ext = aug_mesh_extent(m);
    memset(mark, 0, (size_t)m->nn);
    for (int j = 0; j < s->nfix; j++) {
        const aug_fix_spec *f = &s->fix[j];
        if (f->kind == AUG_FIX_GROUP) {
            const aug_set *g = need_set(k, m, "--fix", f->arg, f->group);
            for (int64_t i = 0; g && i < g->n; i++) mark[g->nodes[i]] = 1;
            continue;
        }
        int64_t n = f->kind == AUG_FIX_BOX
                        ? aug_nodes_in_box(m, f->v, f->v + 3, mark)
                        : aug_nodes_on_plane(m, f->v, f->v[3], f->ntol ? f->v[4] : 1e-6 * ext, mark);
        if (n == 0) aug_sink_report(k, "--fix %s: selects no node", f->arg);
    }
}

/* the first --load after which a DOF's sum, or the total force, is not
   finite (each value alone is: 1e308 twice on one node was written as inf,
   a LOAD every reader refuses); 1 when reported */
static int load_overflow(const aug_mesh *m, aug_sink *k, const aug_load_spec *l, const double *f)
{
    int64_t nd = m->nn * m->dim;
    double tot[3] = {0, 0, 0};
    for (int64_t i = 0; i < nd; i++) {
        if (!isfinite(f[i])) {
            aug_sink_report(k, "--load %s: the loads on node %lld add up to a non-finite force", l->arg,
                            (long long)(i / m->dim));
            return 1;
        }
        tot[i % m->dim] += fabs(f[i]);
    }
    for (int c = 0; c < m->dim; c++)
        if (!isfinite(tot[c])) {
            aug_sink_report(k, "--load %s: the loads add up to a non-finite total force", l->arg);
            return 1;
        }
    return 0;
}

/* f[nn*dim] += every --load */
static void loads(const aug_scene_spec *s, const aug_mesh *m, aug_sink *k, double *f)
{
    for (int j = 0, over = 0; j < s->nload; j++) {
        const aug_load_spec *l = &s->load[j];
        if (m->dim == 2 && l->F[2] != 0)
            aug_sink_report(k, "--load %s: a 2-D mesh takes no z force", l->arg);
        /* two numbers on a 3-D mesh would silently mean z = 0 */
        if (m->dim == 3 && l->nF == 2)
            aug_sink_report(k, "--load %s: a 3-D mesh takes fx,fy,fz (three numbers)", l->arg);
        if (m->dim == 3 && l->point && l->np == 2)
            aug_sink_report(k, "--load %s: a 3-D mesh takes point:x,y,z (three numbers)", l->arg);
        if (l->point) {
            int32_t i = (int32_t)aug_nearest_node(m, l->p);
            aug_load_spread(m, &i, 1, l->F, f);
        } else {
            const aug_set *g = need_set(k, m, "--load", l->arg, l->group);
            if (g) aug_load_spread(m, g->nodes, g->n, l->F, f);
        }
        if (!over) over = load_overflow(m, k, l, f);
    }
}

/* the body force of --gravity: GRAV (formats/stream.md 5.8), assembled per
   element wherever loads are (aug_elem_body), so that a cut or refinement
   re-distributes it with the elements; a used material without density is a
   problem when g != 0 */
static void gravity(const aug_scene_spec *s, aug_mesh *m, aug_sink *k)
{
    if (!s->gravity) return;
    if (m->dim == 2 && s->g[2] != 0)
        aug_sink_report(k, "--gravity %s: a 2-D mesh takes no z acceleration", s->garg);
    if (m->dim == 3 && s->gravity == 2)
        aug_sink_report(k, "--gravity %s: a 3-D mesh takes gx,gy,gz (three numbers)", s->garg);
    if (s->g[0] == 0 && s->g[1] == 0 && s->g[2] == 0) return;
    for (int i = 0; i < m->nmat; i++) {
        int used = 0;
        for (int64_t e = 0; e < m->ne && !used; e++) used = m->mat[e] == i;
        if (used && !(m->mats[i].rho > 0))
            aug_sink_report(k, "--gravity %s: material '%s' has density rho = %g (set it with "
                            "--material %s:rho=.. or --default-material rho=..)", s->garg,
                            m->mats[i].name, m->mats[i].rho, m->mats[i].name);
    }
    memcpy(m->grav, s->g, sizeof m->grav);
    if (m->dim == 2) m->grav[2] = 0;
    m->have |= AUG_HAVE_GRAV;
}

/* oUTs := the output set (mark: workspace of nn bytes) */
static int output(const aug_scene_spec *s, aug_mesh *m, aug_sink *k, unsigned char *mark, aug_err *e)
{
    const char *name = s->output ? s->output : "all";
    if (!strcmp(name, "all")) return aug_mesh_set_output(m, AUG_OUT_ALL, "all", NULL, 0, e);
    if (strcmp(name, "surface") != 0) {
        const aug_set *g = need_set(k, m, "--output", name, name);
        return g ? aug_mesh_set_output(m, AUG_OUT_SET, name, g->nodes, g->n, e) : 0;
    }
    int32_t *v = aug_malloc((size_t)(m->nn ? m->nn : 1) * sizeof *v);
    if (!v || aug_mesh_boundary_nodes(m, mark) < 0) {
        free(v);
        return aug_err_set(e, AUG_ENOMEM, -1, "oUTs", "out of memory");
    }
    int64_t n = 0;
    for (int64_t i = 0; i < m->nn; i++)
        if (mark[i]) v[n++] = (int32_t)i;
    int rc = aug_mesh_set_output(m, AUG_OUT_SURFACE, "surface", v, n, e);
    free(v);
    return rc;
}

/* materials, FIXD, LOAD, oUTs of m from s, each problem to k */
int aug_scene_spec_apply(const aug_scene_spec *s, aug_mesh *m, aug_sink *k, aug_err *e)
{
    aug_err_clear(e);
    size_t nn = (size_t)(m->nn ? m->nn : 1);
    unsigned char *mark = aug_malloc(nn);
    double *f = aug_calloc(nn * (size_t)m->dim, sizeof *f);
    int rc = AUG_ENOMEM;
    if (!mark || !f) {
        aug_err_set(e, rc, -1, "", "out of memory");
    } else {
        materials(s, m, k);
        fixed(s, m, k, mark);
        loads(s, m, k, f);
        gravity(s, m, k);
        rc = aug_mesh_fix_marked(m, mark, e);
        if (!rc) rc = aug_mesh_set_load(m, f, e);
        if (!rc) rc = output(s, m, k, mark, e);
    }
    free(mark);
    free(f);
    return rc;
}
