/* The cut system K_t, f_t assembled from scratch in the cut-matrix numbering
   (formats/stream.md 7.2): the reference the update records must reproduce. */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

/* order of K_t: nfree0 + dim (nn - nn0) (formats/stream.md 7.2) */
int64_t aug_cut_order(const aug_mesh *m, int64_t nn0, int64_t nfree0)
{
    return nfree0 + (m->nn - nn0) * m->dim;
}

/* matrix index of every local dof of element el, -1 outside the matrix;
   con[i] = 1 when the dof is constrained (value in val[i]) */
static void element_dofs(const aug_mesh *m, int64_t el, int64_t nn0, const int32_t *map0,
                         int64_t nfree0, int64_t *gi, int *con, double *val)
{
    int dim = m->dim;
    for (int a = 0; a < m->nv; a++) {
        int32_t node = m->conn[el * m->nv + a];
        for (int c = 0; c < dim; c++) {
            int i = a * dim + c;
            gi[i] = aug_cut_index(m, nn0, map0, nfree0, node, c);
            con[i] = aug_mesh_fixed(m, node * dim + c, &val[i]);
        }
    }
}

typedef struct trip {
    int32_t row, col;
    int64_t seq;
    double v;
} trip;

static int cmp_trip(const void *a, const void *b)
{
    const trip *x = a, *y = b;
    if (x->col != y->col) return x->col < y->col ? -1 : 1;
    if (x->row != y->row) return x->row < y->row ? -1 : 1;
    return (x->seq > y->seq) - (x->seq < y->seq);
}

/* K_t = sum_e scatter(K_e) over free matrix indices + I on constrained matrix
   indices (their columns replaced by identity columns, as J in paper 000 eq. 5);
   upper triangle, duplicates summed in element order (deterministic). */
cholmod_sparse *aug_assemble_cut(const aug_mesh *m, int64_t nn0, const int32_t *map0,
                                 int64_t nfree0, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    int nd = m->nv * m->dim;
    int64_t n = aug_cut_order(m, nn0, nfree0);
    int64_t cap = m->ne * (int64_t)nd * (nd + 1) / 2 + n, nt = 0;
    trip *t = aug_malloc((size_t)cap * sizeof *t);
    double Ke[AUG_MAX_EMAT], val[AUG_MAX_EDOF];
    int64_t gi[AUG_MAX_EDOF];
    int con[AUG_MAX_EDOF];
    cholmod_sparse *A = NULL;
    if (!t) goto nomem;
    for (int64_t el = 0; el < m->ne; el++) {
        aug_elem_stiffness(m, el, Ke);
        element_dofs(m, el, nn0, map0, nfree0, gi, con, val);
        for (int j = 0; j < nd; j++) {
            if (gi[j] < 0 || con[j]) continue;
            for (int i = 0; i < nd; i++) {
                if (gi[i] < 0 || con[i] || gi[i] > gi[j]) continue;
                t[nt].row = (int32_t)gi[i];
                t[nt].col = (int32_t)gi[j];
                t[nt].seq = nt;
                t[nt].v = Ke[i + j * nd];
                nt++;
            }
        }
    }
    for (int64_t node = 0; node < m->nn; node++)
        for (int c = 0; c < m->dim; c++) {
            int64_t g = aug_cut_index(m, nn0, map0, nfree0, node, c);
            if (g >= 0 && aug_mesh_fixed(m, (int32_t)(node * m->dim + c), NULL)) {
                t[nt].row = t[nt].col = (int32_t)g;
                t[nt].seq = nt;
                t[nt].v = 1.0;
                nt++;
            }
        }
    qsort(t, (size_t)nt, sizeof *t, cmp_trip);
    int64_t nz = 0;
    for (int64_t k = 0; k < nt; k++)
        if (k == 0 || t[k].row != t[k - 1].row || t[k].col != t[k - 1].col) nz++;
    A = cholmod_allocate_sparse((size_t)n, (size_t)n, (size_t)nz, 1, 1, 1, CHOLMOD_REAL, cm);
    if (!A) goto nomem;
    int *Ap = A->p, *Ai = A->i;
    double *Ax = A->x;
    int64_t q = -1;
    memset(Ap, 0, (size_t)(n + 1) * sizeof *Ap);
    for (int64_t k = 0; k < nt; k++) {
        if (k == 0 || t[k].row != t[k - 1].row || t[k].col != t[k - 1].col) {
            q++;
            Ai[q] = t[k].row;
            Ax[q] = t[k].v;
            Ap[t[k].col + 1]++;
        } else {
            Ax[q] += t[k].v;
        }
    }
    for (int64_t j = 0; j < n; j++) Ap[j + 1] += Ap[j];
    free(t);
    return A;
nomem:
    free(t);
    aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory assembling the cut matrix");
    return NULL;
}

/* f_t[i] = load_i - sum_j K_ij v_j (i free, j constrained: paper 000 eq. 11, paper
   001 eq. 3.29), f_t[i] = v_i (i constrained: an identity row). */
int aug_load_cut(const aug_mesh *m, int64_t nn0, const int32_t *map0, int64_t nfree0,
                 double *f, aug_err *e)
{
    aug_err_clear(e);
    int nd = m->nv * m->dim;
    int64_t n = aug_cut_order(m, nn0, nfree0);
    double Ke[AUG_MAX_EMAT], val[AUG_MAX_EDOF];
    int64_t gi[AUG_MAX_EDOF];
    int con[AUG_MAX_EDOF];
    memset(f, 0, (size_t)n * sizeof *f);
    for (int64_t k = 0; k < m->nload; k++) {
        int32_t dof = m->load_dof[k];
        int64_t g = aug_cut_index(m, nn0, map0, nfree0, dof / m->dim, dof % m->dim);
        if (g >= 0 && !aug_mesh_fixed(m, dof, NULL)) f[g] += m->load_val[k];
    }
    for (int64_t el = 0; el < m->ne; el++) {
        element_dofs(m, el, nn0, map0, nfree0, gi, con, val);
        int any = 0;
        for (int j = 0; j < nd; j++) any |= con[j] && val[j] != 0;
        if (!any) continue;
        aug_elem_stiffness(m, el, Ke);
        for (int j = 0; j < nd; j++) {
            if (!con[j] || val[j] == 0) continue;
            for (int i = 0; i < nd; i++)
                if (gi[i] >= 0 && !con[i]) f[gi[i]] -= Ke[i + j * nd] * val[j];
        }
    }
    for (int64_t k = 0; k < m->nfix; k++) {
        int32_t dof = m->fix_dof[k];
        int64_t g = aug_cut_index(m, nn0, map0, nfree0, dof / m->dim, dof % m->dim);
        if (g >= 0) f[g] = m->fix_val[k];
    }
    return 0;
}
