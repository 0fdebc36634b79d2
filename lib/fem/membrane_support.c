/* Singular membrane scenes: a sheet carries no load out of its plane where it
   is flat, and a free edge of a curved sheet can flex without stretching. */
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

/* A node's own block K_ii = sum over its triangles of the (a,a) block of
   aug_membrane_stiffness restricted to its free components must be
   nonsingular: K is positive semi-definite, so v' K_ii v = 0 for a free v
   means K (v at node i) = 0, a zero-energy motion of node i alone. Where all
   triangles at i are coplanar (a flat sheet) K_ii n = 0 for their normal n
   exactly. Tested as lambda_min(K_ii restricted) <= 1e-9 trace(K_ii)
   (LAPACK dsyev); the first such node is reported (AUG_ESINGULAR) with the
   direction. Meshes other than mem3 pass. */
int aug_membrane_support(const aug_mesh *m, aug_err *e)
{
    aug_err_clear(e);
    if (m->etype != AUG_MEM3) return 0;
    double *B = aug_calloc((size_t)(m->nn ? m->nn : 1) * 9, sizeof *B);
    unsigned char *fixed = aug_calloc((size_t)(m->nn ? m->nn : 1) * 3, 1);
    if (!B || !fixed) {
        free(B);
        free(fixed);
        return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    }
    for (int64_t t = 0; t < m->nfix; t++) fixed[m->fix_dof[t]] = 1;
    double Ke[81];
    for (int64_t el = 0; el < m->ne; el++) {
        aug_elem_stiffness(m, el, Ke); /* the foundation's part included */
        for (int a = 0; a < 3; a++) {
            double *b = B + (size_t)m->conn[el * 3 + a] * 9;
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) b[i * 3 + j] += Ke[(size_t)(a * 3 + j) * 9 + a * 3 + i];
        }
    }
    for (int64_t i = 0; i < m->nn; i++) {
        const double *b = B + i * 9;
        int fr[3], nf = 0;
        for (int c = 0; c < 3; c++)
            if (!fixed[i * 3 + c]) fr[nf++] = c;
        double tr = b[0] + b[4] + b[8];
        if (nf == 0 || tr == 0) continue; /* tr == 0: in no element, aug_check_support's case */
        double S[9], w[3];
        for (int p = 0; p < nf; p++)
            for (int q = 0; q < nf; q++) S[q * nf + p] = b[fr[p] * 3 + fr[q]];
        if (LAPACKE_dsyev(LAPACK_COL_MAJOR, 'V', 'U', nf, S, nf, w) != 0 || w[0] > 1e-9 * tr) continue;
        double v[3] = {0, 0, 0};
        for (int p = 0; p < nf; p++) v[fr[p]] = S[p];
        aug_err_set(e, AUG_ESINGULAR, -1, "",
                    "singular scene: membrane node %lld has no stiffness along (%.3g, %.3g, %.3g) "
                    "(its triangles are coplanar: a flat sheet carries no load out of its plane); "
                    "constrain it or curve the sheet",
                    (long long)i, v[0], v[1], v[2]);
        break;
    }
    free(B);
    free(fixed);
    return e->code;
}

/* The flexes no node shows alone (an inextensional motion of a curved sheet's
   free edge): after K = L D L', 8 steps of inverse iteration x <- K^-1 x / |.|
   from a fixed start give the Rayleigh quotient rho = x' K x >= lambda_min
   (Golub & Van Loan, Matrix Computations, sec. 7.6.1; it converges at once
   when lambda_min is a round-off zero); with g the largest absolute row sum
   of K (Gershgorin: >= lambda_max), rho <= 1e-12 g reports AUG_ESINGULAR
   naming the free DOF where x is largest. */
int aug_membrane_flex(cholmod_sparse *K, cholmod_factor *L, const aug_mesh *m, const int32_t *map,
                      cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    int64_t n = (int64_t)K->nrow;
    double *x = aug_malloc((size_t)(n ? n : 1) * sizeof *x), *y = aug_malloc((size_t)(n ? n : 1) * sizeof *y);
    double *rs = aug_calloc((size_t)(n ? n : 1), sizeof *rs);
    cholmod_dense *X = NULL, *Y = NULL, *E = NULL;
    int rc = !x || !y || !rs;
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    for (int64_t j = 0; !rc && j < n; j++)
        for (int p = Kp[j]; p < Kp[j + 1]; p++) {
            rs[j] += fabs(Kx[p]);
            if (Ki[p] != j) rs[Ki[p]] += fabs(Kx[p]);
        }
    double g = 0, rho = 0;
    for (int64_t j = 0; !rc && j < n; j++) g = fmax(g, rs[j]), x[j] = 1 + 0.5 * sin(1.0 + (double)j);
    for (int it = 0; !rc && it < 8; it++) {
        double s = 0;
        for (int64_t j = 0; j < n; j++) s += x[j] * x[j];
        s = sqrt(s);
        for (int64_t j = 0; j < n; j++) x[j] /= s;
        if (aug_factor_apply_inv(L, x, y, &X, &Y, &E, cm)) rc = 1;
        else memcpy(x, y, (size_t)n * sizeof *x);
    }
    if (!rc) {
        double s = 0;
        for (int64_t j = 0; j < n; j++) s += x[j] * x[j];
        s = sqrt(s);
        for (int64_t j = 0; j < n; j++) x[j] /= s;
        rc = aug_sym_mult(K, x, y, cm) != 0;
        for (int64_t j = 0; !rc && j < n; j++) rho += x[j] * y[j];
    }
    if (rc) aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    else if (!(rho > 1e-12 * g)) {
        int64_t big = 0, dof = -1;
        for (int64_t j = 1; j < n; j++)
            if (fabs(x[j]) > fabs(x[big])) big = j;
        for (int64_t d = 0; d < m->nn * 3 && dof < 0; d++)
            if (map[d] == big) dof = d;
        aug_err_set(e, AUG_ESINGULAR, -1, "",
                    "singular scene: the membrane has a zero-stiffness mode (x' K x = %.3g of "
                    "max row sum %.3g), largest at node %lld %c: a sheet that flexes without "
                    "stretching (a free edge, a flat part); constrain it",
                    rho, g, (long long)(dof / 3), "xyz"[dof % 3]);
    }
    cholmod_free_dense(&X, cm);
    cholmod_free_dense(&Y, cm);
    cholmod_free_dense(&E, cm);
    free(x);
    free(y);
    free(rs);
    return e->code;
}
