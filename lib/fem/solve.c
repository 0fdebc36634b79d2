/* The intact solve a = K^-1 f with its relative residual, and the nodal field. */
#include <math.h>
#include <string.h>
#include "aug_fem.h"

/* A cholmod_dense view of n doubles (no copy). */
static cholmod_dense view(double *x, size_t n)
{
    cholmod_dense d;
    memset(&d, 0, sizeof d);
    d.nrow = n, d.ncol = 1, d.nzmax = n, d.d = n, d.x = x;
    d.xtype = CHOLMOD_REAL, d.dtype = CHOLMOD_DOUBLE;
    return d;
}

/* a = K^-1 f through L (cholmod_solve, [CHOLMOD]); relres = ||K a - f||_2 /
   ||f||_2 (||K a - f||_2 when f = 0). */
int aug_solve(cholmod_sparse *K, cholmod_factor *L, const double *f, double *a, double *relres,
              cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    size_t n = L->n;
    cholmod_dense b = view((double *)f, n);
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
