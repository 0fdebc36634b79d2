/* augcut assembly and factor layer: element matrices, global K and M, the
   lifted load, CHOLMOD factorization, condition estimates, and their records
   DOFM KMAT FVEC FACT cOND (formats/stream.md). */
#ifndef AUG_FEM_H
#define AUG_FEM_H

#include <cholmod.h>
#include "aug_dyn.h"
#include "aug_mesh.h"

/* Linear elastic element stiffness of element e (hex8 Q1 with 2x2x2 Gauss:
   24x24, tet4: 12x12, tri3 plane stress with thickness t: 6x6, mem3: 9x9; at most
   AUG_MAX_EMAT entries), column-major, local dof order node*dim+c. */
void aug_elem_stiffness(const aug_mesh *m, int64_t e, double *Ke);
/* Shape-function gradients of element e, g[a*dim+c] = dN_a/dx_c: tet4 and tri3
   the constant ones, hex8 at natural coordinates xi (NULL: the centre).
   Returns det J (tet4: 6 V, tri3: 2 A, hex8: at xi); mem3: the surface
   gradients of aug_membrane_grad, 2 A. */
double aug_elem_grad(const aug_mesh *m, int64_t e, const double *xi, double *g);
/* mem3 (lib/fem/membrane.c): surface gradients g[a*3+c] of N_a and the unit
   normal nrm of element e, returns 2 A; the 9 x 9 membrane stiffness (plane
   stress in the triangle's plane, 3 DOFs per node). */
double aug_membrane_grad(const aug_mesh *m, int64_t e, double g[9], double nrm[3]);
void aug_membrane_stiffness(const aug_mesh *m, int64_t e, double *Ke);
/* Consistent load of the body force rho * m->grav (GRAV) on element e;
   0 (be zeroed) when the mesh has none. */
int aug_elem_body(const aug_mesh *m, int64_t e, double *be);
/* Consistent (lumped = 0) or row-sum lumped (lumped = 1) mass matrix of e. */
void aug_elem_mass(const aug_mesh *m, int64_t e, int lumped, double *Me);

enum { AUG_MAT_K = 0, AUG_MAT_M = 1, AUG_MAT_ML = 2, AUG_MAT_A = 3 };

/* Global matrix over the free DOFs of map (aug_dofmap): upper triangle,
   sorted columns, stype = 1, deterministic summation order. NULL on failure. */
cholmod_sparse *aug_assemble(const aug_mesh *m, const int32_t *map, int64_t nfree,
                             int which, cholmod_common *cm, aug_err *e);
/* f = loads - K[:,D] a_D over the free DOFs (length nfree). */
int aug_load_vector(const aug_mesh *m, const int32_t *map, int64_t nfree, double *f,
                    aug_err *e);

/* Threading for every tool that calls CHOLMOD / OpenBLAS: OpenBLAS gets
   nthreads threads (<= 0: the default, 1), OpenMP (CHOLMOD's assembly loops)
   a team of 1, so that the two never wait on each other's spinning threads
   (lib/fem/threads.c). CHOLMOD's fixed OpenMP teams are capped only by
   OMP_THREAD_LIMIT at start-up: tools call aug_tool_threads
   (lib/cli/aug_tool.h), which sees to that first. */
void aug_set_threads(int nthreads);
/* OpenBLAS's thread count for the calls that follow (n < 1: unchanged);
   returns the count before. */
int aug_blas_threads(int n);
/* cholmod_start plus augcut defaults (error handler off: errors via cm->status;
   blocks >= 2 MiB allocated on transparent huge pages). */
void aug_cholmod_start(cholmod_common *cm);

/* Records of this layer: matrix family (lib/fem/matrix_rec.c), factor
   (lib/fem/factor_rec.c), field (lib/fem/field_rec.c). Every read checks the
   payload (sizes, orders, finite values) before it fills anything. */
int aug_write_dofmap(aug_writer *w, const aug_mesh *m, const int32_t *map, int64_t nfree,
                     aug_err *e);
int aug_read_dofmap(const aug_rec *rec, int *dim, int64_t *ndof, int64_t *nfree,
                    int32_t **map, aug_err *e);
int aug_write_sparse(aug_writer *w, int which, const cholmod_sparse *A, aug_err *e);
cholmod_sparse *aug_read_sparse(const aug_rec *rec, int *which, cholmod_common *cm,
                                aug_err *e);
int aug_write_vector(aug_writer *w, const char *type, int32_t step, int32_t kind,
                     const double *v, int64_t n, aug_err *e);
/* Any numeric factor as a FACT record in simplicial LDL' form (a supernodal
   LL' is written as D = diag(L)^2, L diag(L)^-1; L itself is not changed). */
int aug_write_factor(aug_writer *w, const cholmod_factor *L, cholmod_common *cm,
                     aug_err *e);
/* Rebuild a simplicial LDL' cholmod_factor from a FACT record. */
cholmod_factor *aug_read_factor(const aug_rec *rec, cholmod_common *cm, aug_err *e);
/* Read a vector record of the FVEC layout (kind, n, v[n]); *v is malloc'd. */
int aug_read_vector(const aug_rec *rec, int32_t *kind, int64_t *n, double **v, aug_err *e);
/* Header fields of a KMAT / FACT record that aug_check_payload accepted. */
int aug_kmat_info(const aug_rec *rec, int32_t *which, int32_t *stype, int64_t *n, int64_t *nnz);
int aug_fact_info(const aug_rec *rec, int64_t *n, int64_t *nnz, int32_t *ordering);

/* Connected components of the element graph (nodes sharing an element):
   comp[node] = 0, 1, ... in the order of each component's smallest node, -1
   for nodes in no element. Returns the count, -1 when out of memory. */
int64_t aug_mesh_components(const aug_mesh *m, int32_t *comp);
/* Singular scenes: every component's constraints must remove its rigid-body
   modes (6 in 3-D, 3 in 2-D); otherwise AUG_ESINGULAR naming the component. */
int aug_check_support(const aug_mesh *m, aug_err *e);
/* The rigid motions its constraints leave free (a dynamic scene need not be
   held), on the free DOFs of map: *R nfree x k (column-major, malloc'ed; at
   most kmax columns). Returns k, -1 when out of memory. */
int64_t aug_free_rigid_modes(const aug_mesh *m, const int32_t *map, int64_t nfree, int64_t kmax, double **R);
/* mem3 (lib/fem/membrane_support.c): a free direction of a node with no
   stiffness (a flat part of the sheet: its normal), checked by
   aug_check_support; after the factorization, a zero-stiffness mode of K
   found by inverse iteration (a flexing free edge). AUG_ESINGULAR naming the
   node. */
int aug_membrane_support(const aug_mesh *m, aug_err *e);
int aug_membrane_flex(cholmod_sparse *K, cholmod_factor *L, const aug_mesh *m, const int32_t *map,
                      cholmod_common *cm, aug_err *e);

/* Ordering choice (--ordering) and factor kind for CHOLMOD. */
enum { AUG_ORDER_AUTO = 0, AUG_ORDER_AMD = 1, AUG_ORDER_METIS = 2 };
void aug_factor_options(cholmod_common *cm, int ordering, int simplicial);
const char *aug_ordering_name(int cholmod_ordering);
/* cholmod_analyze with errors as aug_err. */
cholmod_factor *aug_analyze(cholmod_sparse *K, cholmod_common *cm, aug_err *e);
/* The symbolic factor of K for augmented solves: with AUG_ORDER_AUTO, a
   supernodal factor and >= 2,000 DOFs, AMD or METIS by the least lnz + 4
   mean closure work (aug_closure_work); otherwise aug_analyze. cm->lnz and
   cm->fl describe the factor returned. */
cholmod_factor *aug_analyze_steps(cholmod_sparse *K, int ordering, cholmod_common *cm, aug_err *e);
/* Mean over columns j of the entries of L on the etree path of j (the
   work of a sparse substitution from e_j) for a supernodal symbolic L;
   -1 if L is simplicial. */
double aug_closure_work(const cholmod_factor *L);
/* Numeric factorization; not positive definite -> AUG_ESINGULAR naming the
   pivot column and (m, map non-NULL) its node and connected component. */
int aug_factorize(cholmod_sparse *K, cholmod_factor *L, const aug_mesh *m, const int32_t *map,
                  cholmod_common *cm, aug_err *e);
/* A cholmod_dense view of n doubles (no copy). */
cholmod_dense aug_dense_view(double *x, size_t n);
/* y = A x for a symmetric CHOLMOD matrix (cholmod_sdmult): 0 or -1. */
int aug_sym_mult(cholmod_sparse *A, double *x, double *y, cholmod_common *cm);
/* y = A^-1 x through its factor L (cholmod_solve2 with the caller's kept
   workspaces X, Y, E): 0 or -1. */
int aug_factor_apply_inv(cholmod_factor *L, double *x, double *y, cholmod_dense **X,
                         cholmod_dense **Y, cholmod_dense **E, cholmod_common *cm);
/* a = K^-1 f through L; relres = ||K a - f|| / ||f|| (may be NULL). */
int aug_solve(cholmod_sparse *K, cholmod_factor *L, const double *f, double *a, double *relres,
              cholmod_common *cm, aug_err *e);
/* Nodal field u[nn*dim]: free DOFs from a, constrained ones at their value. */
void aug_expand_field(const aug_mesh *m, const int32_t *map, const double *a, double *u);

/* Condition estimate cond_2(K) = lambda_max / lambda_min (cond.c). */
typedef struct aug_cond {
    double lambda_max, lambda_min, cond;
    int iters_max, iters_min;   /* operator applications (K x, resp. K^-1 x) */
    int converged;              /* 0: NAN in the values that did not converge */
} aug_cond;
int aug_cond_estimate(cholmod_sparse *K, cholmod_factor *L, double tol, aug_cond *c,
                      cholmod_common *cm, aug_err *e);
/* y = A x of a symmetric operator: 0, or -1 on failure */
typedef int (*aug_symop)(void *ctx, double *x, double *y);
/* Extreme eigenvalue theta of op by ARPACK Lanczos (which "LA" or "LM", cond.c):
   1 converged, 0 not within maxit restarts, -1 failure. */
int aug_lanczos_extreme(int n, aug_symop op, void *ctx, const char *which, double tol, int maxit,
                        double *theta, int *nops);

/* The nev lowest eigenvalues of K x = lambda M x (lib/fem/modes.c), by
   ARPACK shift-invert on the factor L of F = cM M + cK K (statics: cM = 0,
   cK = 1 and L the factor of K), to ARPACK's tolerance tol; unconverged:
   converged = 0 and NAN, never a number. */
#define AUG_MODES_MAX 24
typedef struct aug_modes {
    int nev, converged, iters;
    double lambda[AUG_MODES_MAX];
} aug_modes;
/* R (n x k, column-major; NULL, 0: none): modes known to have lambda = 0
   (aug_free_rigid_modes), deflated: lambda_1..k = 0, the rest found in
   their M-orthogonal complement. */
int aug_modes_lowest(cholmod_sparse *M, cholmod_factor *L, double cM, double cK, int nev,
                     double tol, const double *R, int k, aug_modes *r, cholmod_common *cm, aug_err *e);
/* As aug_modes_lowest, and X (n x nev, column-major) the eigenvectors in the
   order of lambda, M-orthonormal (X'MX = I; ARPACK dseupd with rvec = 1);
   X NULL: eigenvalues only; unconverged: X all NAN. */
int aug_modes_lowest_vec(cholmod_sparse *M, cholmod_factor *L, double cM, double cK, int nev,
                         double tol, const double *R, int k, aug_modes *r, double *X,
                         cholmod_common *cm, aug_err *e);
/* The same with K possibly singular (free rigid motions, floating
   sub-domains): its own factor of K + alpha M, alpha = 1e-8 max K_jj / M_jj
   (modes.c); K and M stored as the same triangle. X NULL: no vectors. */
int aug_modes_shifted(cholmod_sparse *K, cholmod_sparse *M, int nev, double tol, const double *R, int k,
                      aug_modes *r, double *X, cholmod_common *cm, aug_err *e);

/* fELD (field of one step): nodes == NULL means nodes 0..count-1 (not indexed).
   aug_read_field: *nodes is NULL when the record is not indexed; both malloc'd. */
int aug_write_field(aug_writer *w, int32_t step, int32_t kind, int dim, int64_t count,
                    const int32_t *nodes, const double *u, aug_err *e);
int aug_read_field(const aug_rec *rec, int32_t *kind, int *dim, int64_t *count,
                   int32_t **nodes, double **u, aug_err *e);

/* fRAM (one time frame of a dynamic stream, formats/stream.md 7.9): nodal
   displacement u and velocity v, nodes == NULL for nodes 0..count-1. */
typedef struct aug_frame {
    int32_t frame;
    double time;
    int dim;
    int64_t count;
    int32_t *nodes;
    double *u, *v;
} aug_frame;
int aug_write_frame(aug_writer *w, int32_t step, const aug_frame *f, aug_err *e);
/* fills f (malloc'd arrays; aug_frame_free also on error) */
int aug_read_frame(const aug_rec *rec, aug_frame *f, aug_err *e);
void aug_frame_free(aug_frame *f);
/* Reaction forces (lib/fem/reaction.c; paper 000 eq. 9: the unknown at a
   constrained DOF), r = (M a + D v + K u - f) on the constrained DOFs of m,
   D = alpha M + beta K. Statics: dyn = NULL, r = (K u - f)_C. */
typedef struct aug_react_dyn {
    const double *v, *a;        /* nodal velocity and acceleration (nn*dim) */
    double alpha, beta;         /* Rayleigh damping D = alpha M + beta K */
    int lumped;                 /* M row-sum lumped (1) or consistent (0) */
} aug_react_dyn;
/* Elements with a node that has a constrained DOF, increasing (*elems
   malloc'd); their count, -1 when out of memory. */
int64_t aug_react_elements(const aug_mesh *m, int32_t **elems);
/* r[k] at dof m->fix_dof[k], summed element by element over elems[0..nel)
   (increasing, a superset of the elements touching a constrained DOF); u (and
   dyn's v, a) are read at the nodes of elems only. */
void aug_reactions(const aug_mesh *m, const int32_t *elems, int64_t nel, const double *u,
                   const aug_react_dyn *dyn, double *r);
/* rEAC (formats/stream.md 7.10): the reactions of one step (frame): every
   constrained DOF, increasing, with its reaction, the total per component,
   and per named set holding a constrained DOF its resultant (dim values). */
typedef struct aug_reaction {
    int dim;
    int32_t frame;              /* 0 in statics */
    double time;                /* 0 in statics */
    int64_t n;
    int32_t *dof;               /* node*dim + c, strictly increasing */
    double *r;
    double total[3];
    int64_t nset;
    char (*name)[AUG_NAME];
    double *res;                /* nset*dim */
    int64_t cap, setcap;        /* allocated entries of dof/r and name/res */
} aug_reaction;
void aug_reaction_free(aug_reaction *q);
/* Room for n DOFs and nset sets in q, contents kept: 0, or -1 (memory). */
int aug_reaction_reserve(aug_reaction *q, int64_t n, int64_t nset);
/* q := the reactions of m (aug_reactions), their total and the resultant of
   every set of m holding a constrained DOF (set order of m); q's arrays are
   reused; frame and time are not touched. */
int aug_reaction_compute(aug_reaction *q, const aug_mesh *m, const int32_t *elems, int64_t nel,
                         const double *u, const aug_react_dyn *dyn, aug_err *e);
/* Codec (lib/fem/reaction_rec.c): the read checks sizes, dimension, frame,
   increasing DOFs, finite values and set names before it fills q (zeroed or
   from an earlier read; free with aug_reaction_free). */
int aug_write_reaction(aug_writer *w, int32_t step, const aug_reaction *q, aug_err *e);
int aug_read_reaction(const aug_rec *rec, aug_reaction *q, aug_err *e);

/* Node -> element incidence (CSR, elements increasing): elements of node i are
   ind[ptr[i] .. ptr[i+1]-1]. Both malloc'd; -1 on allocation failure. */
int aug_node_elements(const aug_mesh *m, int64_t **ptr, int32_t **ind);

/* factor's computation on the intact scene (lib/fem/factor_scene.c): K (M,
   lumped M), f, the factor L of K with CHOLMOD, a = K^-1 f with its relres,
   cond(K) by ARPACK unless no_cond; then its records DOFM KMAT FVEC FACT cOND
   fELD (step 0), rEAC (step 0, unless no_reactions) sTAt tIMe. */
typedef struct aug_factor_opts {
    int ordering, simplicial, threads, mass, lumped, no_factor, no_cond;
    double cond_tol;
    const aug_dynp *dyn;       /* factor --dynamic: the integrator (NULL: statics) */
    int modes;                 /* factor --modes N: the N lowest of K x = lambda M x */
    int no_reactions;
} aug_factor_opts;
/* With dyn set (factor --dynamic), the factored matrix is the integrator's
   A = cM M + cK K (aug_dyn.h) instead of K, with M of dyn->mass; a piece
   without supports is not singular (its mass holds it), a material without
   density is; a = A^-1 f only checks the factor (no field: the scene starts
   at rest, written as frame 0). */
typedef struct aug_factored {
    int32_t *map;
    int64_t nfree;
    cholmod_sparse *K, *M, *ML, *A;
    double *f, *a;
    cholmod_factor *L;
    double relres;
    aug_cond cond;
    aug_modes modes;
    double lnz, fl;            /* CHOLMOD's analysis: nnz(L) and flop count */
    double t_asm, t_an, t_fac, t_sol, t_cond;  /* seconds */
} aug_factored;
int aug_factored_compute(aug_factored *r, const aug_mesh *m, const aug_factor_opts *o,
                         cholmod_common *cm, aug_err *e);
int aug_factored_write(aug_writer *w, const aug_factored *r, const aug_mesh *m,
                       const aug_factor_opts *o, cholmod_common *cm, aug_err *e);
void aug_factored_free(aug_factored *r, cholmod_common *cm);

#endif
