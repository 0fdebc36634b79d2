/* struct aug_mesh: init, free, deep copy, validation, named sets, DOF numbering. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_mesh.h"

void aug_mesh_init(aug_mesh *m) { memset(m, 0, sizeof *m); }

void aug_mesh_free(aug_mesh *m)
{
    free(m->x);
    free(m->conn);
    free(m->mat);
    free(m->mats);
    for (int i = 0; i < m->nset; i++) free(m->sets[i].nodes);
    free(m->sets);
    free(m->fix_dof);
    free(m->fix_val);
    free(m->load_dof);
    free(m->load_val);
    free(m->out_nodes);
    aug_mesh_init(m);
}

/* copy n bytes of src into a new buffer at *dst (NULL when n = 0) */
static int dup_bytes(void **dst, const void *src, size_t n)
{
    *dst = NULL;
    if (n == 0) return 0;
    if (!(*dst = aug_malloc(n))) return -1;
    memcpy(*dst, src, n);
    return 0;
}

int aug_mesh_copy(aug_mesh *t, const aug_mesh *m)
{
    *t = *m;
    t->x = NULL, t->conn = NULL, t->mat = NULL, t->mats = NULL, t->sets = NULL;
    t->fix_dof = NULL, t->fix_val = NULL, t->load_dof = NULL, t->load_val = NULL, t->out_nodes = NULL;
    t->nset = 0;
    if (dup_bytes((void **)&t->x, m->x, (size_t)(m->nn * m->dim) * sizeof(double)) ||
        dup_bytes((void **)&t->conn, m->conn, (size_t)(m->ne * m->nv) * sizeof(int32_t)) ||
        dup_bytes((void **)&t->mat, m->mat, (size_t)m->ne * sizeof(int32_t)) ||
        dup_bytes((void **)&t->mats, m->mats, (size_t)m->nmat * sizeof(aug_material)) ||
        dup_bytes((void **)&t->fix_dof, m->fix_dof, (size_t)m->nfix * sizeof(int32_t)) ||
        dup_bytes((void **)&t->fix_val, m->fix_val, (size_t)m->nfix * sizeof(double)) ||
        dup_bytes((void **)&t->load_dof, m->load_dof, (size_t)m->nload * sizeof(int32_t)) ||
        dup_bytes((void **)&t->load_val, m->load_val, (size_t)m->nload * sizeof(double)) ||
        dup_bytes((void **)&t->out_nodes, m->out_nodes, (size_t)m->nout * sizeof(int32_t)))
        goto fail;
    if (m->nset) {
        if (!(t->sets = aug_calloc((size_t)m->nset, sizeof *t->sets))) goto fail;
        for (int i = 0; i < m->nset; i++) {
            t->sets[i] = m->sets[i];
            t->sets[i].nodes = NULL;
            t->nset = i + 1;
            if (dup_bytes((void **)&t->sets[i].nodes, m->sets[i].nodes,
                          (size_t)m->sets[i].n * sizeof(int32_t)))
                goto fail;
        }
    }
    return 0;
fail:
    aug_mesh_free(t);
    return -1;
}

int aug_mesh_validate(const aug_mesh *m, aug_err *e)
{
    aug_err_clear(e);
    int need = AUG_HAVE_NODE | AUG_HAVE_MATL | AUG_HAVE_ELEM;
    if ((m->have & need) != need)
        return aug_err_set(e, AUG_EDATA, -1, "", "stream has no mesh (NODE, MATL and ELEM needed)");
    if (m->ne == 0) return aug_err_set(e, AUG_EDATA, -1, "ELEM", "mesh has no elements");
    int i = aug_mesh_fndn_misplaced(m);
    if (i >= 0)
        return aug_err_set(e, AUG_EDATA, -1, "FNDN", "material %d (%s) has a foundation: only a membrane "
                           "(mem3) mesh takes one", i, m->mats[i].name);
    return 0;
}

int aug_mesh_fndn_misplaced(const aug_mesh *m)
{
    for (int i = 0; i < m->nmat && m->etype != AUG_MEM3; i++)
        if (m->mats[i].kf != 0) return i;
    return -1;
}

const aug_set *aug_mesh_set(const aug_mesh *m, const char *name)
{
    for (int i = 0; i < m->nset; i++)
        if (strcmp(m->sets[i].name, name) == 0) return &m->sets[i];
    return NULL;
}

/* map[dof] = free index 0, 1, ... in dof order, -1 for constrained (FIXD) dofs; returns nfree */
int64_t aug_dofmap(const aug_mesh *m, int32_t *map)
{
    int64_t nd = m->nn * m->dim, k = 0;
    for (int64_t i = 0; i < nd; i++) map[i] = 0;
    for (int64_t i = 0; i < m->nfix; i++) map[m->fix_dof[i]] = -1;
    for (int64_t i = 0; i < nd; i++)
        if (map[i] == 0) map[i] = (int32_t)k++;
        else map[i] = -1;
    return k;
}
