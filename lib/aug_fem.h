/* augcut assembly and factor layer: element matrices, global K and M, the
   lifted load, CHOLMOD factorization, condition estimates, and their records
   DOFM KMAT FVEC FACT cOND (formats/stream.md). */
#ifndef AUG_FEM_H
#define AUG_FEM_H

#include <cholmod.h>
#include "aug_mesh.h"

/* Linear elastic element stiffness of element e (tet4: 12x12, tri3 plane
   stress with thickness t: 6x6), column-major, local dof order node*dim+c. */
void aug_elem_stiffness(const aug_mesh *m, int64_t e, double *Ke);
/* Consistent (lumped = 0) or row-sum lumped (lumped = 1) mass matrix of e. */
void aug_elem_mass(const aug_mesh *m, int64_t e, int lumped, double *Me);

enum { AUG_MAT_K = 0, AUG_MAT_M = 1, AUG_MAT_ML = 2 };

/* Global matrix over the free DOFs of map (aug_dofmap): upper triangle,
   sorted columns, stype = 1, deterministic summation order. NULL on failure. */
cholmod_sparse *aug_assemble(const aug_mesh *m, const int32_t *map, int64_t nfree,
                             int which, cholmod_common *cm, aug_err *e);
/* f = loads - K[:,D] a_D over the free DOFs (length nfree). */
int aug_load_vector(const aug_mesh *m, const int32_t *map, int64_t nfree, double *f,
                    aug_err *e);

/* Threading for every tool that calls CHOLMOD / OpenBLAS: sets OpenMP and
   OpenBLAS thread counts (nthreads <= 0: the default, 1). */
void aug_set_threads(int nthreads);
/* cholmod_start plus augcut defaults (error handler off: errors via cm->status). */
void aug_cholmod_start(cholmod_common *cm);

/* Records of this layer. */
int aug_write_dofmap(aug_writer *w, const aug_mesh *m, const int32_t *map, int64_t nfree,
                     aug_err *e);
int aug_read_dofmap(const aug_rec *rec, int *dim, int64_t *ndof, int64_t *nfree,
                    int32_t **map, aug_err *e);
int aug_write_sparse(aug_writer *w, int which, const cholmod_sparse *A, aug_err *e);
cholmod_sparse *aug_read_sparse(const aug_rec *rec, int *which, cholmod_common *cm,
                                aug_err *e);
int aug_write_vector(aug_writer *w, const char *type, int32_t step, int32_t kind,
                     const double *v, int64_t n, aug_err *e);
/* Simplicial LDL' factor as a FACT record (converted copy; L unchanged). */
int aug_write_factor(aug_writer *w, const cholmod_factor *L, cholmod_common *cm,
                     aug_err *e);
/* Rebuild a simplicial LDL' cholmod_factor from a FACT record. */
cholmod_factor *aug_read_factor(const aug_rec *rec, cholmod_common *cm, aug_err *e);

#endif
