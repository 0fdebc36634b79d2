/* augcut modal simulation (paper 004, Yang et al. CAGD 2016): the scene cut
   into sub-domains, each simulated in full (FE) or in the subspace of its own
   displacement snapshots (reduced), coupled at duplicated interface nodes by
   Lagrange multipliers (eq. 15), switching between the two (eqs. 12-14), and
   followed through the cut steps of a dynamic stream. The numerics it stands
   on are in aug_modal.h (incremental SVD, projection error, Galerkin) and
   aug_saddle.h (the saddle-point solvers). */
#ifndef AUG_MSIM_H
#define AUG_MSIM_H

#include <cholmod.h>
#include "aug_dyn.h"
#include "aug_fem.h"
#include "aug_modal.h"

/* ---- Sub-domains (lib/modal/partition.c) ----
   Element e belongs to domain group[mat[e]] (default: one per material), and
   with split > 1 each group is cut into `split` slabs of equal width along
   the longest side of its bounding box on the original mesh (centroids), so
   an element made by a cut or a refinement falls where its parent was. */
typedef struct aug_mpart {
    int ngroup, split, nd;      /* groups, slabs per group, domains = ngroup * split */
    int32_t *group;             /* per material index: group */
    int *axis;                  /* per group: slab axis */
    double *lo, *width;         /* per group: slab origin and width */
    int dim, nv;
} aug_mpart;
/* spec: NULL or "material" (one group per material), "one" (a single
   domain), or groups of material names or ids: "a,b/c" = {a, b} and {c};
   every material must be in exactly one group. AUG_EUSAGE naming the problem. */
int aug_mpart_init(aug_mpart *p, const aug_mesh *m, const char *spec, int split, aug_err *e);
void aug_mpart_free(aug_mpart *p);
int aug_mpart_domain(const aug_mpart *p, const aug_mesh *m, int64_t e);

/* ---- One sub-domain (lib/modal/domain.c) ---- */
enum { AUG_MD_FE = 0, AUG_MD_RED = 1 };
typedef struct aug_mdomain {
    int id, mode;
    int64_t nel, nn;
    int32_t *elems;             /* its elements (global), increasing */
    int32_t *nodes;             /* its nodes (global), increasing */
    aug_mesh sub;               /* its elements over local nodes 0..nn-1 */
    int32_t *map;               /* local DOF -> free index, -1 constrained */
    int64_t nf;                 /* free DOFs */
    int32_t *free_dof;          /* nf: local DOF of each free index */
    cholmod_sparse *Kall, *Mall, *Aall; /* over every local DOF (upper) */
    cholmod_sparse *K, *M, *A;  /* over the free DOFs */
    double *fext;               /* nodal loads (master copies) + body force, every local DOF */
    double *u, *v;              /* local nodal state (nn*dim) */
    double *uf, *b, *du, *tmp, *tmp2; /* free-DOF work vectors */
    /* the subspace */
    aug_isvd svd;
    aug_galerkin gK, gM;
    int have_svd;
    int r;                      /* reduced: rank */
    double *W;                  /* nf x r explicit basis while reduced */
    double *MW, *KW, *flift;    /* reduced: M W, K W, f - K[F,C] u_C (its residual) */
    double *mvc;                /* reduced: M[F,C] v_C this frame (nf), when vc */
    int vc;                     /* reduced: some constrained DOF moves (v_C != 0) this frame */
    double *dinv;               /* 1 / diag(A) over the free DOFs */
    const double *res;          /* the frame's full-order residual (du reduced, tmp FE; not owned) */
    unsigned char *iface;       /* nf: free DOF on an interface row */
    cholmod_sparse *Afull;      /* A with both triangles (fe_residual's rows), NULL until needed */
    double acc, last_res;       /* accumulated error estimate of its reduced frames (whole run), its last increment */
    int spent;                  /* a stretch ended on the budget: it does not switch again */
    int over;                   /* past its budget in this frame's first solve (aug_msim_frame) */
    double *Kr, *Mr, *Ar, *fr, *q, *qd, *br, *dq;
    double err_switch;          /* projection error at the switch */
    double last_err, last_est, last_ratio;
    int moved;                  /* constrained DOFs moved this frame */
    uint64_t version;           /* bumped when A (or the basis) changes */
    int since;                  /* snapshots since the last re-wiring or return to FE */
    int ready, wait;            /* passed the switch tests this frame; frames waited for the others */
    int switched;               /* this frame: +1 to reduced, -1 to FE, 0 */
    int rebuilt;                /* re-wired this step */
    int hold;                   /* returned to FE by this step (a neighbour re-wired) */
    double *lmaX;               /* --lma: its lowest modes (nf x nlma, M-orthonormal) */
    int nlma;
    double lmaL[AUG_MODES_MAX];
} aug_mdomain;

/* ---- The simulation (lib/modal/msim.c) ---- */
enum { AUG_COUPLE_DIRECT = 0, AUG_COUPLE_SCHUR = 1, AUG_COUPLE_PPCG = 2 };
enum { AUG_BASIS_SVD = 0, AUG_BASIS_IDENTITY = 1 };
enum { AUG_AFTER_CUT_ALL = 0, AUG_AFTER_CUT_NEIGHBOURS = 1, AUG_AFTER_CUT_TOUCHED = 2 };
typedef struct aug_msim_opts {
    const char *domains;        /* aug_mpart_init spec */
    int split;
    int reduce_all, reduce_none;/* every domain may reduce (default) / none */
    int32_t *reduce;            /* or the listed domains only (nreduce) */
    int nreduce;
    int rank;                   /* rank cap per domain */
    double svd_tol;             /* drop s_k <= svd_tol s_1 */
    double tau_svd;             /* eq. 12's singular-value sum ratio threshold (0.9, 1) */
    double err_tol, acc_tol;    /* eq. 13 threshold, accumulation budget (relative) */
    int min_snap;               /* snapshots before a domain may switch */
    int sync;                   /* frames a ready domain waits for the other FE domains */
    int probes;                 /* random probes of eq. 14's estimate */
    int gate_estimate;          /* switch on the estimate instead of the exact error */
    int coupling;               /* AUG_COUPLE_* */
    double tol;                 /* ppcg */
    int maxit;
    int basis;                  /* AUG_BASIS_* (identity: a check of the machinery) */
    int warp;                   /* write warped fields (eqs. 16-17) */
    int after_cut;              /* AUG_AFTER_CUT_*: reduced domains a cut returns to FE */
    uint64_t seed;
} aug_msim_opts;
void aug_msim_opts_default(aug_msim_opts *o);

typedef struct aug_direct aug_direct;   /* lib/modal/direct.c */

/* An external solver of the whole-mesh FE system, used by the direct
   coupling whenever every domain is FE (the shared-node system is then the
   stream's A_t): A_t x = b in its own numbering of n(ctx) unknowns, index(ctx,
   node, c) the unknown of a free DOF (-1: none; its other unknowns are
   decoupled identity rows). modal passes the AMPS solver of the stream
   (paper 001: the cut steps as principal-submatrix updates of the factor
   factor wrote, no re-factorization). */
typedef struct aug_mext {
    void *ctx;
    int64_t (*n)(void *ctx);
    int64_t (*index)(void *ctx, int64_t node, int c);
    int (*solve)(void *ctx, const double *b, double *x, aug_err *e);
} aug_mext;

typedef struct aug_msim {
    aug_msim_opts o;
    aug_dynp p;
    cholmod_common *cm;
    aug_mpart part;
    int nd;
    aug_mdomain *d;
    int dim;
    int64_t nn;                 /* nodes of the mesh */
    int32_t *edom;              /* per element: domain */
    int64_t ne;                 /* elements of the mesh edom was made for */
    int32_t *conn;              /* their connectivity then (ne*nv): the parents of a step's added elements */
    int32_t *owner;             /* per node: lowest domain holding it (-1: none) */
    int32_t *ownloc;            /* per node: its local index in the owner */
    double *u, *v;              /* global nodal state (the owner's copy) */
    double *uw;                 /* warped output (nn*dim) when o.warp */
    int32_t frame;
    double time;
    /* coupling: interface rows */
    int64_t m, mcap;
    int32_t *ca, *cb, *cdof;    /* row k: slave domain, master domain, component-node DOF (global) */
    int32_t *cia, *cib;         /* local free index of the slave, master copy */
    cholmod_sparse *C;          /* saddle C (m x N) for schur / ppcg */
    double *g, *lam, *x, *rhs;
    int64_t N, xcap;
    int64_t *off;               /* block offsets */
    struct aug_saddle *sad;     /* schur / ppcg (aug_saddle.h) */
    struct aug_sblock *blk;
    aug_direct *dir;
    const aug_mext *ext;        /* NULL: the FE union is always factored */
    int dirty;                  /* coupled system to rebuild */
    int returned;               /* a reduced domain returned to FE this frame */
    double *rsum, *dsum;        /* per global DOF on an interface: residual and diag(A) summed over the copies */
    uint64_t rng;
    /* last frame's figures */
    double gap, relres, t_rhs, t_solve, t_adv, t_svd, t_build;
    int iters, converged, rank_c, events, step_events;
    int redo;                   /* this frame was solved again with domains back in FE (aug_msim_frame) */
    int64_t nsys;
} aug_msim;

/* Start on the original mesh m (a dynamic stream's, p its integrator) at the
   state u0, v0 (nn*dim; NULL: rest, constrained DOFs at their value). */
int aug_msim_init(aug_msim *s, const aug_msim_opts *o, const aug_dynp *p, const aug_mesh *m,
                  const double *u0, const double *v0, cholmod_common *cm, aug_err *e);
void aug_msim_free(aug_msim *s);
/* A cut step happened: m is the mesh after it, nn_old nodes before it, the
   new nodes' parents parent[nn - nn_old] (a parent may be an earlier new
   node), chg[nchg] the elements the step re-wired or added. Every domain with
   a changed element, node, constraint or load is rebuilt from m and switched
   to FE, its snapshots padded (new nodes take their parent's rows); the
   other reduced domains return to FE as o.after_cut says. */
int aug_msim_step(aug_msim *s, const aug_mesh *m, int64_t nn_old, const int32_t *parent,
                  const int32_t *chg, int64_t nchg, aug_err *e);
/* One frame: right-hand sides, the coupled solve (rebuilt after a switch or
   a step), the states advanced, snapshots and switches (ready domains
   together, o.sync). */
int aug_msim_frame(aug_msim *s, aug_err *e);
/* Interface row k's gap: its master copy's value minus its slave copy's now
   (the g of C du = g that makes the copies agree after the frame). */
double aug_msim_row_gap(const aug_msim *s, int64_t k);
/* The frame's figures as sTAt / tIMe (tag modal). */
void aug_msim_stats(const aug_msim *s, aug_kv *st, aug_kv *tm);

/* ---- What modal writes besides the frames (lib/modal/mode_out.c) ---- */
/* Domain d's current basis (reduced) as a MODE record's content (kind 0):
   W over its nodes, node-major, constrained DOFs 0, sigma its singular values;
   arrays malloc'd into *mr (aug_moderec_free). */
int aug_msim_mode(const aug_msim *s, int d, aug_moderec *mr, aug_err *e);
/* The k lowest modes of domain d (paper 004 fig. 3: LMA), kept in the domain,
   as a MODE record of kind 1 (mr->r = 0: the domain is too small for k). */
int aug_msim_lma(aug_msim *s, int d, int k, aug_moderec *mr, aug_err *e);
/* rel[j] = ||x_j - W W'x_j|| / ||x_j|| of the kept modes against the current
   basis of domain d; their count (0: none or not reduced), -1 out of memory. */
int aug_msim_lma_fit(const aug_msim *s, int d, double *rel);
/* The field to write: u, or with o.warp R~(w) u (eqs. 16-17) in s->uw. NULL
   on error. */
const double *aug_msim_output(aug_msim *s, const aug_mesh *m, aug_err *e);

/* ---- Domain internals shared by msim.c and direct.c (lib/modal/domain.c) ---- */
int aug_mdomain_build(aug_mdomain *d, int id, const aug_mesh *m, const int32_t *edom,
                      const int32_t *owner, const aug_dynp *p, cholmod_common *cm, aug_err *e);
void aug_mdomain_free(aug_mdomain *d, cholmod_common *cm);
/* the right-hand side of the integrator (aug_dyn.h) over the free DOFs (FE)
   or the basis (reduced): b = h M v0 + gamma h^2 (f - K u0), the prescribed
   motion of constrained DOFs (the targets of its sub-mesh) lifted */
int aug_mdomain_rhs(aug_mdomain *d, const aug_dynp *p, cholmod_common *cm, aug_err *e);
/* the state advanced by the solution (du over the free DOFs, or dq); a
   reduced domain leaves the full-order residual of its frame in res */
void aug_mdomain_advance(aug_mdomain *d, const aug_dynp *p);
/* after the advance, an FE domain's residual b - A du in res, on its
   interface rows only when iface is set (elsewhere it is zero up to the
   solve's rounding, and the estimate reads only those rows), else on all
   its free DOFs */
int aug_mdomain_fe_residual(aug_mdomain *d, cholmod_common *cm, aug_err *e);
/* FE -> reduced on the current basis (state projected), reduced -> FE */
int aug_mdomain_reduce(aug_mdomain *d, const aug_dynp *p, cholmod_common *cm, aug_err *e);
void aug_mdomain_unreduce(aug_mdomain *d);
/* the value of free index i of domain d now (FE: u; reduced: W q, kept
   expanded in u after every frame) */
double aug_mdomain_value(const aug_mdomain *d, int64_t i);

/* The rows and columns of the upper-stored symmetric A kept by map (old
   index -> new index 0..n-1 or -1; increasing on the kept ones, so columns
   stay sorted), upper stored. NULL when out of memory. */
cholmod_sparse *aug_sym_restrict(const cholmod_sparse *A, const int32_t *map, int64_t n,
                                 cholmod_common *cm);
/* The snapshots of a re-wired sub-domain (a cut): X' = P X with row i of P X
   row src[i] of X (-1: zero, a DOF no snapshot saw), n the new length; the
   thin SVD of P U S by a QR of P U S and the SVD of its R factor (O(n r^2));
   the basis compacted (Up = I). */
int aug_isvd_remap(aug_isvd *s, int64_t n, const int32_t *src, aug_err *e);

/* ---- The direct coupled solve (lib/modal/direct.c) ----
   Paper 004 eq. 15 solved by eliminating the slave DOFs: nodes shared by FE
   domains are one unknown (the shared-node FE system), an FE copy of a node
   whose master copy is reduced follows it (u = W q), reduced-reduced rows stay
   constraints (least squares on their row space); the FE part is factored once
   per change of the coupled system and its Schur complement onto the reduced
   coordinates is dense. */
int aug_direct_new(aug_direct **dp, aug_err *e);
void aug_direct_free(aug_direct *dr, cholmod_common *cm);
/* rebuild for s's current domains and rows */
int aug_direct_build(aug_direct *dr, aug_msim *s, aug_err *e);
/* solve the frame: every domain's b in, du / dq out; gap rows g */
int aug_direct_solve(aug_direct *dr, aug_msim *s, aug_err *e);
int64_t aug_direct_size(const aug_direct *dr);

#endif
