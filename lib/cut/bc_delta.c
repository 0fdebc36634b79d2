/* Boundary conditions that change during the cut: lookups in the mesh's sorted
   constraint and load lists, building a BDLT and applying it to the mesh. */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"


int aug_mesh_fixed(const aug_mesh *m, int32_t dof, double *v)
{
    int64_t k = aug_find_i32(m->fix_dof, m->nfix, dof);
    if (k < 0) return 0;
    if (v) *v = m->fix_val[k];
    return 1;
}

double aug_mesh_load(const aug_mesh *m, int32_t dof)
{
    int64_t k = aug_find_i32(m->load_dof, m->nload, dof);
    return k < 0 ? 0.0 : m->load_val[k];
}

static int push(int32_t **d, double **v, int64_t *n, int64_t *cap, int32_t dof, double val)
{
    if (*n == *cap) {
        int64_t nc = *cap ? 2 * *cap : 16;
        int32_t *nd = aug_realloc(*d, (size_t)nc * sizeof *nd);
        if (!nd) return -1;
        *d = nd;
        double *nv = aug_realloc(*v, (size_t)nc * sizeof *nv);
        if (!nv) return -1;
        *v = nv;
        *cap = nc;
    }
    (*d)[*n] = dof;
    (*v)[*n] = val;
    (*n)++;
    return 0;
}

int aug_bdelta_fix(aug_bdelta *b, int32_t dof, double v)
{
    return push(&b->fix_dof, &b->fix_val, &b->nfix, &b->capfix, dof, v);
}

int aug_bdelta_load(aug_bdelta *b, int32_t dof, double v)
{
    return push(&b->load_dof, &b->load_val, &b->nload, &b->capload, dof, v);
}

typedef struct pair {
    int32_t dof;
    int64_t seq;
    double v;
} pair;

static int cmp_pair(const void *a, const void *b)
{
    const pair *x = a, *y = b;
    if (x->dof != y->dof) return x->dof < y->dof ? -1 : 1;
    return (x->seq > y->seq) - (x->seq < y->seq);
}

/* sort by dof, keep the last value given for each dof; 0 or -1 (memory) */
static int finish(int32_t *d, double *v, int64_t *n)
{
    if (*n < 2) return 0;
    pair *p = aug_malloc((size_t)*n * sizeof *p);
    if (!p) return -1;
    for (int64_t i = 0; i < *n; i++) p[i] = (pair){d[i], i, v[i]};
    qsort(p, (size_t)*n, sizeof *p, cmp_pair);
    int64_t k = 0;
    for (int64_t i = 0; i < *n; i++) {
        if (k > 0 && d[k - 1] == p[i].dof) k--;
        d[k] = p[i].dof;
        v[k] = p[i].v;
        k++;
    }
    free(p);
    *n = k;
    return 0;
}

int aug_bdelta_finish(aug_bdelta *b)
{
    return finish(b->fix_dof, b->fix_val, &b->nfix) || finish(b->load_dof, b->load_val, &b->nload)
               ? -1 : 0;
}

/* merge sorted (d, v) into the sorted list (*ld, *lv, *ln): new values replace */
static int merge(int32_t **ld, double **lv, int64_t *ln, const int32_t *d, const double *v,
                 int64_t n)
{
    if (n == 0) return 0;
    int64_t cap = *ln + n, i = 0, j = 0, k = 0;
    int32_t *od = aug_malloc((size_t)cap * sizeof *od);
    double *ov = aug_malloc((size_t)cap * sizeof *ov);
    if (!od || !ov) {
        free(od);
        free(ov);
        return -1;
    }
    while (i < *ln || j < n) {
        if (j >= n || (i < *ln && (*ld)[i] < d[j])) {
            od[k] = (*ld)[i];
            ov[k++] = (*lv)[i++];
        } else {
            if (i < *ln && (*ld)[i] == d[j]) i++;
            od[k] = d[j];
            ov[k++] = v[j++];
        }
    }
    free(*ld);
    free(*lv);
    *ld = od;
    *lv = ov;
    *ln = k;
    return 0;
}

int aug_mesh_apply_bc(aug_mesh *m, const aug_bdelta *b, aug_err *e)
{
    aug_err_clear(e);
    int64_t nd = m->nn * m->dim;
    for (int64_t i = 0; i < b->nfix; i++)
        if (b->fix_dof[i] >= nd || (i > 0 && b->fix_dof[i] <= b->fix_dof[i - 1]))
            return aug_err_set(e, AUG_EDATA, -1, "BDLT", "step %d: constraint dof %d invalid",
                               (int)b->step, (int)b->fix_dof[i]);
    for (int64_t i = 0; i < b->nload; i++)
        if (b->load_dof[i] >= nd || (i > 0 && b->load_dof[i] <= b->load_dof[i - 1]))
            return aug_err_set(e, AUG_EDATA, -1, "BDLT", "step %d: load dof %d invalid",
                               (int)b->step, (int)b->load_dof[i]);
    if (merge(&m->fix_dof, &m->fix_val, &m->nfix, b->fix_dof, b->fix_val, b->nfix) ||
        merge(&m->load_dof, &m->load_val, &m->nload, b->load_dof, b->load_val, b->nload))
        return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
    if (b->nfix) m->have |= AUG_HAVE_FIXD;
    if (b->nload) m->have |= AUG_HAVE_LOAD;
    return 0;
}
