/* Structured test meshes built in code for the fem_* unit tests: a box of
   hexahedra split into 6 tets each (around the main diagonal) or kept as
   trilinear hexahedra, and a rectangle
   of squares split into 2 triangles each; plus small dense helpers. */
#ifndef FEM_MESH_H
#define FEM_MESH_H
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

static inline void tm_material(aug_mesh *m, int nmat, double E, double nu, double rho, double t)
{
    m->nmat = nmat;
    m->mats = calloc((size_t)nmat, sizeof *m->mats);
    for (int i = 0; i < nmat; i++) {
        m->mats[i].id = i + 1;
        snprintf(m->mats[i].name, sizeof m->mats[i].name, "mat%d", i);
        m->mats[i].E = E;
        m->mats[i].nu = nu;
        m->mats[i].rho = rho;
        m->mats[i].t = t;
    }
    m->have |= AUG_HAVE_MATL;
}

/* nx*ny*nz cells on [0,lx]x[0,ly]x[0,lz]; node (i,j,k) = i + (nx+1)(j + (ny+1) k). */
static inline void tm_box(aug_mesh *m, int nx, int ny, int nz, double lx, double ly, double lz,
                   double E, double nu)
{
    aug_mesh_init(m);
    m->dim = 3, m->etype = AUG_TET4, m->nv = 4;
    m->nn = (int64_t)(nx + 1) * (ny + 1) * (nz + 1);
    m->x = malloc((size_t)m->nn * 3 * sizeof(double));
    for (int k = 0; k <= nz; k++)
        for (int j = 0; j <= ny; j++)
            for (int i = 0; i <= nx; i++) {
                int64_t v = i + (int64_t)(nx + 1) * (j + (int64_t)(ny + 1) * k);
                m->x[v * 3] = lx * i / nx, m->x[v * 3 + 1] = ly * j / ny, m->x[v * 3 + 2] = lz * k / nz;
            }
    m->ne = (int64_t)nx * ny * nz * 6;
    m->conn = malloc((size_t)m->ne * 4 * sizeof(int32_t));
    m->mat = calloc((size_t)m->ne, sizeof(int32_t));
    /* the 6 tets of the cube around the diagonal 0-7 (corner bits x=1,y=2,z=4) */
    static const int path[6][2] = {{1, 2}, {1, 4}, {2, 1}, {2, 4}, {4, 1}, {4, 2}};
    int64_t e = 0;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++)
                for (int t = 0; t < 6; t++) {
                    int c[4] = {0, path[t][0], path[t][0] | path[t][1], 7};
                    for (int a = 0; a < 4; a++) {
                        int ii = i + (c[a] & 1), jj = j + ((c[a] >> 1) & 1), kk = k + ((c[a] >> 2) & 1);
                        m->conn[e * 4 + a] = ii + (nx + 1) * (jj + (ny + 1) * kk);
                    }
                    if (aug_elem_measure(m, e) < 0) {
                        int32_t s = m->conn[e * 4 + 1];
                        m->conn[e * 4 + 1] = m->conn[e * 4 + 2], m->conn[e * 4 + 2] = s;
                    }
                    e++;
                }
    m->have = AUG_HAVE_NODE | AUG_HAVE_ELEM;
    tm_material(m, 1, E, nu, 0.0, 1.0);
}

/* The same box as nx*ny*nz trilinear hexahedra (same nodes, gmsh node order:
   corner bits x=1, y=2, z=4 at 0 1 3 2 4 5 7 6). */
static inline void tm_hexbox(aug_mesh *m, int nx, int ny, int nz, double lx, double ly, double lz,
                             double E, double nu)
{
    tm_box(m, nx, ny, nz, lx, ly, lz, E, nu);
    free(m->conn);
    free(m->mat);
    m->etype = AUG_HEX8, m->nv = 8;
    m->ne = (int64_t)nx * ny * nz;
    m->conn = malloc((size_t)m->ne * 8 * sizeof(int32_t));
    m->mat = calloc((size_t)m->ne, sizeof(int32_t));
    static const int bits[8] = {0, 1, 3, 2, 4, 5, 7, 6};
    int64_t e = 0;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++, e++)
                for (int a = 0; a < 8; a++) {
                    int ii = i + (bits[a] & 1), jj = j + ((bits[a] >> 1) & 1), kk = k + ((bits[a] >> 2) & 1);
                    m->conn[e * 8 + a] = ii + (nx + 1) * (jj + (ny + 1) * kk);
                }
}

/* nx*ny squares on [0,lx]x[0,ly], each split along its diagonal, CCW. */
static inline void tm_rect(aug_mesh *m, int nx, int ny, double lx, double ly, double E, double nu,
                    double t)
{
    aug_mesh_init(m);
    m->dim = 2, m->etype = AUG_TRI3, m->nv = 3;
    m->nn = (int64_t)(nx + 1) * (ny + 1);
    m->x = malloc((size_t)m->nn * 2 * sizeof(double));
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) {
            int64_t v = i + (int64_t)(nx + 1) * j;
            m->x[v * 2] = lx * i / nx, m->x[v * 2 + 1] = ly * j / ny;
        }
    m->ne = (int64_t)nx * ny * 2;
    m->conn = malloc((size_t)m->ne * 3 * sizeof(int32_t));
    m->mat = calloc((size_t)m->ne, sizeof(int32_t));
    int64_t e = 0;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            int32_t a = i + (nx + 1) * j, b = a + 1, c = a + nx + 1, d = c + 1;
            int32_t t1[3] = {a, b, d}, t2[3] = {a, d, c};
            memcpy(m->conn + e * 3, t1, sizeof t1), e++;
            memcpy(m->conn + e * 3, t2, sizeof t2), e++;
        }
    m->have = AUG_HAVE_NODE | AUG_HAVE_ELEM;
    tm_material(m, 1, E, nu, 0.0, t);
}

/* Fix every component of the nodes with x[axis] == value (within 1e-12) to
   val(x, c) (NULL: zero). Replaces the mesh's FIXD. */
typedef double (*tm_field)(const double *x, int c);
static inline void tm_fix_nodes(aug_mesh *m, const unsigned char *sel, tm_field val)
{
    free(m->fix_dof);
    free(m->fix_val);
    int64_t n = 0;
    for (int64_t i = 0; i < m->nn; i++) n += sel[i] ? m->dim : 0;
    m->fix_dof = malloc((size_t)(n ? n : 1) * sizeof(int32_t));
    m->fix_val = malloc((size_t)(n ? n : 1) * sizeof(double));
    m->nfix = 0;
    for (int64_t i = 0; i < m->nn; i++)
        if (sel[i])
            for (int c = 0; c < m->dim; c++) {
                m->fix_dof[m->nfix] = (int32_t)(i * m->dim + c);
                m->fix_val[m->nfix++] = val ? val(m->x + i * m->dim, c) : 0.0;
            }
    m->have |= AUG_HAVE_FIXD;
}

static inline void tm_fix_plane(aug_mesh *m, int axis, double value, tm_field val)
{
    unsigned char *sel = calloc((size_t)m->nn, 1);
    for (int64_t i = 0; i < m->nn; i++) sel[i] = fabs(m->x[i * m->dim + axis] - value) < 1e-12;
    tm_fix_nodes(m, sel, val);
    free(sel);
}

/* y = A x for a symmetric matrix stored as its upper triangle (stype 1). */
static inline void tm_symv(const cholmod_sparse *A, const double *x, double *y)
{
    const int *Ap = A->p, *Ai = A->i;
    const double *Ax = A->x;
    memset(y, 0, A->nrow * sizeof *y);
    for (size_t j = 0; j < A->ncol; j++)
        for (int p = Ap[j]; p < Ap[j + 1]; p++) {
            int i = Ai[p];
            y[i] += Ax[p] * x[j];
            if ((size_t)i != j) y[j] += Ax[p] * x[i];
        }
}

/* Dense full copy (column-major n x n) of a stype-1 sparse matrix. */
static inline double *tm_dense(const cholmod_sparse *A)
{
    size_t n = A->nrow;
    double *D = calloc(n * n, sizeof *D);
    const int *Ap = A->p, *Ai = A->i;
    const double *Ax = A->x;
    for (size_t j = 0; j < n; j++)
        for (int p = Ap[j]; p < Ap[j + 1]; p++) {
            D[j * n + Ai[p]] += Ax[p];
            if ((size_t)Ai[p] != j) D[(size_t)Ai[p] * n + j] += Ax[p];
        }
    return D;
}

static inline double tm_norm(const double *v, int64_t n)
{
    double s = 0;
    for (int64_t i = 0; i < n; i++) s += v[i] * v[i];
    return sqrt(s);
}
#endif
