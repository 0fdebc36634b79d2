/* augcut modal layer (paper 004, Yang et al. CAGD 2016): the incremental SVD
   of displacement snapshots, the projection error of a state onto the basis
   (exact and by random probes), the Galerkin projection kept up to date, and
   the reduced implicit step of one sub-domain. Dense column-major storage. */
#ifndef AUG_MODAL_H
#define AUG_MODAL_H

#include <cholmod.h>
#include "aug_dyn.h"
#include "aug_mesh.h"

/* Incremental thin SVD X ~ U diag(S) V' of the snapshots seen so far (paper
   004 eqs. 4-11; Brand, LAA 415 (2006) sec. 3-4). The basis is kept in
   Brand's factored form U = U0 Up: U0 (n x q, orthonormal columns) only ever
   grows by the normalised new residual direction, Up (q x r, orthonormal
   columns) absorbs every rotation of eq. 9 at O(q r^2) cost; eq. 9's big
   rotation U0 <- U0 Up (O(n q r)) is deferred until q reaches qcap (or the
   caller asks: aug_isvd_compact). V is not kept: neither U nor S needs it. */
typedef struct aug_isvd {
    int64_t n;          /* snapshot length */
    int rmax;           /* rank cap (>= 1) */
    int qcap;           /* U0 columns before an automatic compaction (>= rmax + 1) */
    double rtol;        /* drop s_k <= rtol * s_1 (0: only numerically zero ones) */
    int q, r;           /* U0 columns, rank */
    double *U0;         /* n x qcap */
    double *Up;         /* qcap x (rmax + 1), leading dimension qcap */
    double *S;          /* rmax + 1, descending */
    int64_t nsnap;      /* snapshots added */
    /* what the last aug_isvd_add did (for the Galerkin projections) */
    int grew;           /* 1 when U0 gained column q-1 */
    int compacted;      /* 1 when U0 <- U0 Pc first (Pc = the old Up, qold x rold) */
    int unit_up;        /* 1 when Up = I (q = r): the deferred rotation is trivial */
    int qold, rold;
    double *Pc;         /* qcap x (rmax + 1), leading dimension qcap */
    double ratio;       /* sum S before / sum S after the add (eq. 12's switch test) */
    double resid;       /* ||u - U U'u|| of the snapshot before the add */
    double dropped2;    /* sum over adds of the largest singular value dropped */
    double *work;       /* internal */
} aug_isvd;

/* Allocate an empty state; rtol in [0, 1), rmax >= 1, qcap >= rmax + 1
   (qcap = 0: 2 rmax + 2). AUG_EUSAGE / AUG_ENOMEM. */
int aug_isvd_init(aug_isvd *s, int64_t n, int rmax, int qcap, double rtol, aug_err *e);
void aug_isvd_free(aug_isvd *s);
/* The state whose basis is W = I_n: U0 = I, Up = I, S = 1, rank n (what n
   unit snapshots give, set in O(n^2) instead of n adds at O(n^2 + r^3) each;
   modal --basis identity). AUG_EUSAGE / AUG_ENOMEM. */
int aug_isvd_identity(aug_isvd *s, int64_t n, aug_err *e);
/* Add snapshot u (length n): Brand's rank-one column update of the thin SVD,
   truncated to rmax and rtol. Cost O(n q + q r^2 + r^3), plus O(n q r) when
   q reaches qcap (amortised O(n r) per snapshot with qcap = 2 rmax + 2). */
int aug_isvd_add(aug_isvd *s, const double *u, aug_err *e);
/* U0 <- U0 Up, Up <- I (eq. 9's deferred rotation; O(n q r)); sets compacted,
   Pc, qold, rold like an add does (grew = 0). Nothing (compacted = 0) when Up
   is already I. */
int aug_isvd_compact(aug_isvd *s, aug_err *e);
/* The basis U = U0 Up explicitly (n x r into Uout, leading dimension n):
   O(n q r), O(n r) when Up = I; for tests and for the records that write the
   modes. */
void aug_isvd_basis(const aug_isvd *s, double *Uout);

/* Relative projection error ||u - U (U'u)|| / ||u|| with U = U0 Up (paper 004
   eq. 13) without forming U U': O(n q); work >= n + 2 q + r. ||u|| = 0 gives 0. */
double aug_proj_err(const aug_isvd *s, const double *u, double *work);

/* Wallis factor W_m = E|z_1| for z uniform on the unit sphere of R^m (paper
   004 eq. 14; Kenney & Laub, SIAM J. Sci. Comput. 15 (1994) eq. 2.4). */
double aug_wallis(int64_t m);
/* Small-sample statistical estimate (Kenney & Laub 1994 sec. 2; the correct
   form of paper 004 eq. 14) of ||e||, e = u - U (U'u): with k random
   orthonormal probes z_j (uniform on the Stiefel manifold of R^n, drawn from
   *seed, which advances), nu = (W_k / W_n) sqrt(sum_j (z_j'e)^2), E nu = ||e||.
   Returns nu / ||u|| (0 when u = 0), or -1 (e: memory, k not in [1, n]).
   Cost O(n q + n k^2). */
double aug_proj_err_estimate(const aug_isvd *s, const double *u, int k, uint64_t *seed,
                             aug_err *e);

/* Galerkin projection G = U0' A U0 of a sparse symmetric A (CHOLMOD, as
   aug_assemble gives, upper stored) kept along with an aug_isvd (paper 004
   eq. 3 and the decomposition after eq. 8): A_r = U' A U = Up' G Up. */
typedef struct aug_galerkin {
    int qcap, q;
    double *G;          /* qcap x qcap, leading dimension qcap, symmetric */
    double *Aw;         /* n: A times the newest U0 column */
    double *work;       /* qcap x (rmax + 1) */
} aug_galerkin;
/* G for s's current U0 (one sparse product per column: for the start or a
   re-wired sub-domain). A: n x n, stype != 0. */
int aug_galerkin_init(aug_galerkin *g, const aug_isvd *s, cholmod_sparse *A, cholmod_common *cm,
                      aug_err *e);
/* G = A densely for the state of aug_isvd_identity (U0 = I): O(n^2 + nnz),
   not n sparse products and O(n^3). */
int aug_galerkin_identity(aug_galerkin *g, const aug_isvd *s, const cholmod_sparse *A, aug_err *e);
void aug_galerkin_free(aug_galerkin *g);
/* Follow the last aug_isvd_add / aug_isvd_compact of s: on compaction
   G <- Pc' G Pc (O(q^2 r)); on growth, w = U0(:, q-1), G gains the row and
   column U0' (A w) (one sparse product and O(n q): O(nnz + n q)). */
int aug_galerkin_sync(aug_galerkin *g, const aug_isvd *s, cholmod_sparse *A,
                      cholmod_common *cm, aug_err *e);
/* A_r = Up' G Up (r x r, leading dimension r): O(q^2 r + q r^2), O(r^2) when
   Up = I. */
void aug_galerkin_reduced(aug_galerkin *g, const aug_isvd *s, double *Ar);

/* A basis W = U0 Up of one sub-domain (n x q times q x r; Up == NULL: the
   identity, r = q), e.g. an aug_isvd's or W = I. */
typedef struct aug_basis {
    int64_t n;
    int q, r;
    const double *U0;   /* n x q, leading dimension n */
    const double *Up;   /* q x r, leading dimension ldp, or NULL */
    int ldp;
} aug_basis;
/* The basis of s's current state. */
aug_basis aug_isvd_view(const aug_isvd *s);
/* y = W' x (length r; work q): O(n q + q r). */
void aug_basis_project(const aug_basis *W, const double *x, double *y, double *work);
/* x = W y (length n; work q): O(n q + q r). */
void aug_basis_expand(const aug_basis *W, const double *y, double *x, double *work);
/* res = u - W (W'u) (length n; work 2 q + r): O(n q + q r). */
void aug_basis_residual(const aug_basis *W, const double *u, double *res, double *work);

/* One reduced implicit step of paper 004 eq. 2 with the integrators of
   aug_dyn.h: A_r dq = h M_r q' + gamma h^2 (f_r - K_r q), A_r = cM M_r + cK K_r
   (D_r = alpha M_r + beta K_r is inside cM, cK), f_r = W'f; then q += dq and
   q' from aug_dynp_velocity. Kr, Mr: r x r SPD (leading dimension r). q, qd
   updated in place. AUG_ESINGULAR when A_r is not positive definite. Cost
   O(r^3). */
int aug_reduced_step(const aug_dynp *p, int r, const double *Kr, const double *Mr,
                     const double *fr, double *q, double *qd, aug_err *e);

/* ---- Modal warping (lib/modal/warp.c; paper 004 sec. 5.1, eqs. 16-17;
   Mueller et al. 2002, Choi & Ko 2005) ---- */
/* Per-node rotation vectors w_i = (1/2) curl u, the unweighted mean over the
   listed elements around node i (elems NULL: all ne elements, nel ignored;
   else nel of them) of each element's (1/2) curl: tet4 and tri3 from their
   constant gradient, hex8 from the gradient at the element centre; 2-D:
   w = (0, 0, (du_y/dx - du_x/dy) / 2). A linear u is reproduced exactly (for
   u = theta n x X, w = theta n). Nodes in no listed element get w = 0.
   u: nn*dim nodal displacements; w: nn*3. AUG_EUSAGE (listed element out of
   range, nel < 0), AUG_ENOMEM. */
int aug_warp_rotations(const aug_mesh *m, const int32_t *elems, int64_t nel, const double *u,
                       double *w, aug_err *e);
/* R~(w) of eq. 17, row-major 3x3: with t = |w|, W = [w]x,
   R~ = I + W (1 - cos t) / t^2 + W^2 (t - sin t) / t^3
   (eq. 17 as printed, with the unit w^ = w / t). Both coefficients by their
   Taylor series for t < 2 (11 terms) and the closed forms above; relative
   error of each coefficient a few ulps on both sides of t = 2 (measured in
   tests/unit/modal_warp.c). For u = theta n x X, R~(theta n) u = R X - X
   with R the finite rotation by theta about n, for every X (Rodrigues). */
void aug_warp_matrix(const double w[3], double R[9]);
/* eq. 16: out_i = R~(w_i) u_i for the nn nodes (w: nn*3, u, out: nn*dim;
   out == u allowed); 2-D: the upper-left 2x2 block (rotation about z). */
void aug_warp_apply(const double *w, const double *u, double *out, int64_t nn, int dim);

/* ---- The MODE record (lib/modal/mode_rec.c, formats/stream.md 7.5) ----
   One sub-domain's modal basis at a cut step (the record's step): kind 0
   (AUG_MODE_SNAPSHOT) sigma = the singular values of its snapshot matrix
   (descending, >= 0), phi = the orthonormal left singular vectors; kind 1
   (AUG_MODE_LMA) sigma = the eigenvalues of K x = lambda M x (ascending),
   phi = M-orthonormal modes. phi node-major over the listed nodes:
   phi[j*count*dim + k*dim + c] (constrained DOFs 0). */
enum { AUG_MODE_SNAPSHOT = 0, AUG_MODE_LMA = 1 };
typedef struct aug_moderec {
    int32_t domain, frame, dim, kind;
    int64_t count;
    int32_t r;
    int32_t *nodes;   /* count, strictly increasing, >= 0 */
    double *sigma;    /* r */
    double *phi;      /* r*count*dim */
} aug_moderec;
/* Checks m as aug_read_mode does (AUG_EDATA naming the field), then writes. */
int aug_write_mode(aug_writer *w, int32_t step, const aug_moderec *m, aug_err *e);
/* Checks everything first (exact length, dim, kind, count >= 1,
   1 <= r <= count*dim, increasing nodes, finite values, the sigma order and
   sign of the kind), then fills m (malloc'd arrays; empty on error). */
int aug_read_mode(const aug_rec *rec, aug_moderec *m, aug_err *e);
void aug_moderec_free(aug_moderec *m);

#endif
