/* Singular scenes: connected components of the element graph and whether the
   Dirichlet constraints of each remove all its rigid-body modes. */
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

/* root of i in the union-find forest up, with path halving */
static int32_t find(int32_t *up, int32_t i)
{
    while (up[i] != i) {
        up[i] = up[up[i]];
        i = up[i];
    }
    return i;
}

/* Nodes sharing an element are in one component (union-find); components are
   numbered 0, 1, ... in the order of their smallest node; comp = -1 for nodes
   in no element. Returns the component count, -1 when out of memory. */
int64_t aug_mesh_components(const aug_mesh *m, int32_t *comp)
{
    int64_t nn = m->nn;
    int32_t *up = aug_malloc((size_t)(nn ? nn : 1) * sizeof *up);
    if (!up) return -1;
    for (int64_t i = 0; i < nn; i++) up[i] = (int32_t)i, comp[i] = -1;
    for (int64_t e = 0; e < m->ne; e++) {
        const int32_t *c = m->conn + e * m->nv;
        int32_t r = find(up, c[0]);
        comp[c[0]] = 0;
        for (int a = 1; a < m->nv; a++) {
            int32_t s = find(up, c[a]);
            comp[c[a]] = 0;
            if (s != r) { /* the smaller root wins, so roots are smallest nodes */
                if (s < r) up[r] = s, r = s;
                else up[s] = r;
            }
        }
    }
    int64_t nc = 0;
    for (int64_t i = 0; i < nn; i++) {
        if (comp[i] < 0) continue;
        int32_t r = find(up, (int32_t)i);
        comp[i] = r == i ? (int32_t)nc++ : comp[r];
    }
    free(up);
    return nc;
}

/* Rigid mode j at DOF (y, k), y = (x - centre) / radius: translations
   r_j = e_j (j < dim), rotations r = w x y (3-D: w = e_0, e_1, e_2; 2-D: w = e_z). */
static void rigid_row(int dim, const double *y, int k, double *row)
{
    if (dim == 3) {
        double rot[3][3] = {{0, -y[2], y[1]}, {y[2], 0, -y[0]}, {-y[1], y[0], 0}};
        for (int j = 0; j < 3; j++) row[j] = j == k, row[3 + j] = rot[j][k];
    } else {
        double rot[2] = {-y[1], y[0]};
        row[0] = k == 0, row[1] = k == 1, row[2] = rot[k];
    }
}

/* Per component c of comp (nc of them), acc[c*40 + 0..2]: the centre of its
   nodes, acc[c*40 + 3]: their largest distance from it, acc[c*40 + 4..39]:
   G = sum over its constrained DOFs d of r_d r_d' (nr x nr, rigid_row of the
   coordinates centred and scaled), with each mem3 triangle on a foundation
   (FNDN) holding n.r at its centroid; size[c]: its node count. acc and size
   zero on entry. */
static void support_gram(const aug_mesh *m, const int32_t *comp, int64_t nc, double *acc, int64_t *size)
{
    int d = m->dim, nr = d == 3 ? 6 : 3;
    int64_t nn = m->nn;
    for (int64_t i = 0; i < nn; i++)
        if (comp[i] >= 0) {
            size[comp[i]]++;
            for (int k = 0; k < d; k++) acc[comp[i] * 40 + k] += m->x[i * d + k];
        }
    for (int64_t c = 0; c < nc; c++)
        for (int k = 0; k < d; k++) acc[c * 40 + k] /= (double)size[c];
    for (int64_t i = 0; i < nn; i++)
        if (comp[i] >= 0) {
            double *a = acc + comp[i] * 40, r2 = 0;
            for (int k = 0; k < d; k++) r2 += pow(m->x[i * d + k] - a[k], 2);
            a[3] = fmax(a[3], sqrt(r2));
        }
    for (int64_t t = 0; t < m->nfix; t++) {
        int64_t i = m->fix_dof[t] / d;
        int k = (int)(m->fix_dof[t] % d);
        if (comp[i] < 0) continue;
        double *a = acc + comp[i] * 40, y[3] = {0, 0, 0}, row[6];
        double s = a[3] > 0 ? a[3] : 1;
        for (int q = 0; q < d; q++) y[q] = (m->x[i * d + q] - a[q]) / s;
        rigid_row(d, y, k, row);
        for (int p = 0; p < nr; p++)
            for (int q = 0; q < nr; q++) a[4 + p * nr + q] += row[p] * row[q];
    }
    /* mem3 on a foundation (FNDN): each such triangle holds the normal
       component n.r of a rigid motion at its centroid, like a constraint on n */
    for (int64_t el = 0; m->etype == AUG_MEM3 && el < m->ne; el++) {
        if (!(m->mats[m->mat[el]].kf > 0)) continue;
        const int32_t *c = m->conn + el * 3;
        double g[9], n[3], y[3] = {0, 0, 0}, row[6], rn[6] = {0, 0, 0, 0, 0, 0};
        aug_membrane_grad(m, el, g, n);
        double *a = acc + comp[c[0]] * 40, s = a[3] > 0 ? a[3] : 1;
        for (int q = 0; q < 3; q++)
            y[q] = ((m->x[c[0] * 3 + q] + m->x[c[1] * 3 + q] + m->x[c[2] * 3 + q]) / 3 - a[q]) / s;
        for (int k = 0; k < 3; k++) {
            rigid_row(3, y, k, row);
            for (int p = 0; p < 6; p++) rn[p] += n[k] * row[p];
        }
        for (int p = 0; p < 6; p++)
            for (int q = 0; q < 6; q++) a[4 + p * 6 + q] += rn[p] * rn[q];
    }
}

/* The rigid motions a component's G (support_gram, nr x nr, overwritten)
   leaves free: its null space, the eigenvectors (LAPACK dsyev) whose
   eigenvalue is at most 1e-9 lambda_max(G), or every motion when G is 0
   (*held 0: nothing constrains the component). Z (nr x nr, may be NULL):
   the null vectors, column by column. Returns their count, -1 when dsyev
   fails. */
static int gram_null(int nr, double *G, double *Z, int *held)
{
    *held = 0;
    for (int p = 0; p < nr; p++) *held |= G[p * nr + p] > 0;
    if (!*held) {
        for (int p = 0; Z && p < nr * nr; p++) Z[p] = p % (nr + 1) == 0;
        return nr;
    }
    double w[6];
    if (LAPACKE_dsyev(LAPACK_COL_MAJOR, Z ? 'V' : 'N', 'U', nr, G, nr, w) != 0) return -1;
    int k = 0;
    for (int p = 0; p < nr; p++) /* ascending: the null vectors first */
        if (w[p] <= 1e-9 * w[nr - 1]) {
            if (Z) memcpy(Z + k * nr, G + p * nr, (size_t)nr * sizeof *Z);
            k++;
        }
    return k;
}

/* A component is held when no rigid motion r (dim 3: 6 modes, dim 2: 3; the null
   space of an unsupported linear-elastic K, [Zienkiewicz]) vanishes at all its
   constrained DOFs, i.e. G = sum_{constrained d} r_d r_d' (nr x nr) is
   nonsingular: its eigenvalues (LAPACK dsyev) all above 1e-9 lambda_max(G),
   with coordinates centred and scaled per component. The first component that
   is not held is reported (AUG_ESINGULAR) with its size, smallest node and the
   material of its first element; so is a node in no element with a free DOF.
   mem3: a triangle on a foundation (FNDN) holds n.r at its centroid as a
   constraint would; then aug_membrane_support (a flat sheet's normals). */
int aug_check_support(const aug_mesh *m, aug_err *e)
{
    aug_err_clear(e);
    int d = m->dim, nr = d == 3 ? 6 : 3;
    int64_t nn = m->nn;
    int32_t *comp = aug_malloc((size_t)(nn ? nn : 1) * sizeof *comp);
    unsigned char *fixed = aug_calloc((size_t)(nn > 0 ? nn * d : 1), 1);
    if (!comp || !fixed) {
        free(comp);
        free(fixed);
        return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    }
    int64_t nc = aug_mesh_components(m, comp);
    double *acc = nc > 0 ? aug_calloc((size_t)nc * (4 + 36), sizeof *acc) : NULL;
    int64_t *first_el = nc > 0 ? aug_malloc((size_t)nc * sizeof *first_el) : NULL;
    int64_t *size = nc > 0 ? aug_calloc((size_t)nc, sizeof *size) : NULL;
    if (nc < 0 || (nc > 0 && (!acc || !first_el || !size))) {
        aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        goto done;
    }
    for (int64_t t = 0; t < m->nfix; t++) fixed[m->fix_dof[t]] = 1;
    /* a node in no element with a free DOF makes a zero column of K */
    for (int64_t i = 0; i < nn; i++)
        if (comp[i] < 0)
            for (int c = 0; c < d; c++)
                if (!fixed[i * d + c]) {
                    aug_err_set(e, AUG_ESINGULAR, -1, "",
                                "singular scene: node %lld belongs to no element and is not "
                                "fully constrained",
                                (long long)i);
                    goto done;
                }
    for (int64_t c = 0; c < nc; c++) first_el[c] = -1;
    for (int64_t el = m->ne - 1; el >= 0; el--) first_el[comp[m->conn[el * m->nv]]] = el;
    support_gram(m, comp, nc, acc, size);
    for (int64_t c = 0; c < nc; c++) {
        int any, freem = gram_null(nr, acc + c * 40 + 4, NULL, &any);
        if (freem < 0) freem = nr;
        if (freem == 0) continue;
        int64_t node = 0;
        while (comp[node] != c) node++;
        const char *mat = m->mats[m->mat[first_el[c]]].name;
        if (!any)
            aug_err_set(e, AUG_ESINGULAR, -1, "",
                        "singular scene: component of %lld nodes (node %lld, material %s) has "
                        "no Dirichlet support",
                        (long long)size[c], (long long)node, mat);
        else
            aug_err_set(e, AUG_ESINGULAR, -1, "",
                        "singular scene: component of %lld nodes (node %lld, material %s) has "
                        "too little Dirichlet support: its constraints leave %d of %d rigid-body "
                        "modes free",
                        (long long)size[c], (long long)node, mat, freem, nr);
        goto done;
    }
done:
    free(comp);
    free(fixed);
    free(acc);
    free(first_el);
    free(size);
    return e->code ? e->code : aug_membrane_support(m, e);
}

/* The rigid motions the constraints leave free, on the free DOFs (map: node
   DOF -> free index or < 0, aug_dofmap): per component, the null space of its
   G (gram_null), each null vector z giving the motion
   sum_j z_j r_j, which vanishes at the component's constrained DOFs and is
   zero off the component. These are exact null vectors of a linear-elastic
   K (zero strain), eigenvectors of K x = lambda M x with lambda = 0
   (aug_modes_lowest_vec deflates them). *R: nfree x k column-major
   (malloc'ed, NULL when k = 0), at most kmax columns kept. Returns k, or
   -1 (out of memory). */
int64_t aug_free_rigid_modes(const aug_mesh *m, const int32_t *map, int64_t nfree, int64_t kmax, double **R)
{
    int d = m->dim, nr = d == 3 ? 6 : 3;
    int64_t nn = m->nn, k = 0;
    *R = NULL;
    int32_t *comp = aug_malloc((size_t)(nn ? nn : 1) * sizeof *comp);
    if (!comp) return -1;
    int64_t nc = aug_mesh_components(m, comp);
    double *acc = nc > 0 ? aug_calloc((size_t)nc * 40, sizeof *acc) : NULL;
    int64_t *size = nc > 0 ? aug_calloc((size_t)nc, sizeof *size) : NULL;
    double *Z = nc > 0 ? aug_malloc((size_t)nc * 36 * sizeof *Z) : NULL;
    int *nz = nc > 0 ? aug_calloc((size_t)nc, sizeof *nz) : NULL;
    if (nc < 0 || (nc > 0 && (!acc || !size || !Z || !nz))) {
        k = -1;
        goto done;
    }
    if (nc > 0) support_gram(m, comp, nc, acc, size);
    int64_t total = 0;
    for (int64_t c = 0; c < nc; c++) {
        int held, k0 = gram_null(nr, acc + c * 40 + 4, Z + c * 36, &held);
        nz[c] = k0 > 0 ? k0 : 0;
        total += nz[c];
    }
    if (total > kmax) total = kmax;
    if (total == 0) goto done;
    if (!(*R = aug_calloc((size_t)(nfree * total), sizeof **R))) {
        k = -1;
        goto done;
    }
    int64_t *col0 = aug_malloc((size_t)nc * sizeof *col0);
    if (!col0) {
        free(*R), *R = NULL, k = -1;
        goto done;
    }
    for (int64_t c = 0, j = 0; c < nc; c++) col0[c] = j, j += nz[c];
    for (int64_t i = 0; i < nn; i++) {
        int64_t c = comp[i];
        if (c < 0) continue;
        const double *a = acc + c * 40;
        double s = a[3] > 0 ? a[3] : 1, y[3] = {0, 0, 0}, row[6];
        for (int q = 0; q < d; q++) y[q] = (m->x[i * d + q] - a[q]) / s;
        for (int kk = 0; kk < d; kk++) {
            int32_t f = map[i * d + kk];
            if (f < 0) continue;
            rigid_row(d, y, kk, row);
            for (int t = 0; t < nz[c] && col0[c] + t < total; t++) {
                double v = 0;
                for (int p = 0; p < nr; p++) v += Z[c * 36 + t * nr + p] * row[p];
                (*R)[(col0[c] + t) * nfree + f] = v;
            }
        }
    }
    free(col0);
    k = total;
done:
    free(comp), free(acc), free(size), free(Z), free(nz);
    return k;
}
