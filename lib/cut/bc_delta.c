/* Boundary conditions that change during the cut: lookups in the mesh's sorted
   constraint and load lists, and the per-step record BDLT (formats/stream.md 7.7). */
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

void aug_bdelta_init(aug_bdelta *b) { memset(b, 0, sizeof *b); }

void aug_bdelta_free(aug_bdelta *b)
{
    free(b->fix_dof);
    free(b->fix_val);
    free(b->load_dof);
    free(b->load_val);
    aug_bdelta_init(b);
}

int aug_bdelta_empty(const aug_bdelta *b) { return b->nfix == 0 && b->nload == 0; }

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

int aug_write_bdelta(aug_writer *w, const aug_bdelta *b, aug_err *e)
{
    aug_buf p;
    aug_buf_init(&p);
    aug_buf_i64(&p, b->nfix);
    aug_buf_i32v(&p, b->fix_dof, (size_t)b->nfix);
    aug_buf_f64v(&p, b->fix_val, (size_t)b->nfix);
    aug_buf_i64(&p, b->nload);
    aug_buf_i32v(&p, b->load_dof, (size_t)b->nload);
    aug_buf_f64v(&p, b->load_val, (size_t)b->nload);
    int rc = p.failed ? aug_err_set(e, AUG_ENOMEM, aug_writer_count(w), "BDLT", "out of memory")
                      : aug_write(w, "BDLT", b->step, p.p, p.len, e);
    aug_buf_free(&p);
    return rc;
}

#define BAD(...) aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type, __VA_ARGS__)

static int read_list(aug_cur *c, const aug_rec *rec, int64_t *n, int32_t **d, double **v,
                     const char *what, aug_err *e)
{
    *n = aug_cur_i64(c);
    if (*n < 0 || *n > INT32_MAX || !aug_cur_has(c, (uint64_t)*n, 12))
        return BAD("bad %s count", what);
    *d = aug_malloc((size_t)*n * sizeof **d + 1);
    *v = aug_malloc((size_t)*n * sizeof **v + 1);
    if (!*d || !*v) return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    aug_cur_i32v(c, *d, (uint64_t)*n);
    aug_cur_f64v(c, *v, (uint64_t)*n);
    for (int64_t i = 0; i < *n; i++) {
        if ((*d)[i] < 0 || (i > 0 && (*d)[i] <= (*d)[i - 1]))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                               "%s dofs not strictly increasing at %lld", what, (long long)i);
        if (!((*v)[i] - (*v)[i] == 0))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "%s value not finite", what);
    }
    return 0;
}

int aug_read_bdelta(const aug_rec *rec, aug_bdelta *b, aug_err *e)
{
    aug_err_clear(e);
    aug_bdelta_init(b);
    aug_cur c;
    aug_cur_init(&c, rec);
    b->step = rec->step;
    int rc = read_list(&c, rec, &b->nfix, &b->fix_dof, &b->fix_val, "constraint", e);
    if (rc) return rc;
    b->capfix = b->nfix;
    rc = read_list(&c, rec, &b->nload, &b->load_dof, &b->load_val, "load", e);
    if (rc) return rc;
    b->capload = b->nload;
    if (!c.ok || c.pos != c.len) return BAD("payload size does not match its counts");
    return 0;
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
