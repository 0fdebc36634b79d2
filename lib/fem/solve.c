/* The intact solve a = K^-1 f with its relative residual, and the nodal field;
   the dense views, products and factor solves the eigensolvers share. */
#include <math.h>
#include <string.h>
#include "aug_fem.h"

cholmod_dense aug_dense_view(double *x, size_t n)
{
    cholmod_dense d;
    memset(&d, 0, sizeof d);
    d.nrow = n, d.ncol = 1, d.nzmax = n, d.d = n, d.x = x;
    d.xtype = CHOLMOD_REAL, d.dtype = CHOLMOD_DOUBLE;
    return d;
}

int aug_sym_mult(cholmod_sparse *A, double *x, double *y, cholmod_common *cm)
{
    cholmod_dense xv = aug_dense_view(x, A->nrow), yv = aug_dense_view(y, A->nrow);
    double one[2] = {1, 0}, zero[2] = {0, 0};
    return cholmod_sdmult(A, 0, one, zero, &xv, &yv, cm) ? 0 : -1;
}

int aug_factor_apply_inv(cholmod_factor *L, double *x, double *y, cholmod_dense **X,
                         cholmod_dense **Y, cholmod_dense **E, cholmod_common *cm)
{
    cholmod_dense b = aug_dense_view(x, L->n);
    if (!cholmod_solve2(CHOLMOD_A, L, &b, NULL, X, NULL, Y, E, cm)) return -1;
    memcpy(y, (*X)->x, L->n * sizeof *y);
    return 0;
}

/* a = K^-1 f through L (cholmod_solve, [CHOLMOD]); relres = ||K a - f||_2 /
   ||f||_2 (||K a - f||_2 when f = 0). */
int aug_solve(cholmod_sparse *K, cholmod_factor *L, const double *f, double *a, double *relres,
              cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    size_t n = L->n;
    cholmod_dense b = aug_dense_view((double *)f, n);
    cholmod_dense *x = cholmod_solve(CHOLMOD_A, L, &b, cm);
    cholmod_dense *r = cholmod_copy_dense(&b, cm);
    if (!x || !r) {
        cholmod_free_dense(&x, cm);
        cholmod_free_dense(&r, cm);
        return aug_err_set(e, AUG_ENOMEM, -1, "", "CHOLMOD solve failed (status %d)", cm->status);
    }
    memcpy(a, x->x, n * sizeof *a);
    double one[2] = {1, 0}, mone[2] = {-1, 0};
    cholmod_sdmult(K, 0, one, mone, x, r, cm); /* r = K a - f */
    double rn = 0, fn = 0;
    for (size_t i = 0; i < n; i++) {
        rn += ((double *)r->x)[i] * ((double *)r->x)[i];
        fn += f[i] * f[i];
    }
    if (relres) *relres = fn > 0 ? sqrt(rn / fn) : sqrt(rn);
    cholmod_free_dense(&x, cm);
    cholmod_free_dense(&r, cm);
    return 0;
}

/* u[dof] = a[map[dof]] for free DOFs, the prescribed value for constrained ones. */
void aug_expand_field(const aug_mesh *m, const int32_t *map, const double *a, double *u)
{
    int64_t nd = m->nn * m->dim;
    for (int64_t i = 0; i < nd; i++) u[i] = map[i] >= 0 ? a[map[i]] : 0.0;
    for (int64_t t = 0; t < m->nfix; t++) u[m->fix_dof[t]] = m->fix_val[t];
}
