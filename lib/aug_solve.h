/* augcut solver layer: the cut matrix K_t as K_0 plus accumulated principal
   submatrix updates (UPDT), sparse-RHS solves on a simplicial LDL' factor, AMPS
   (paper 001), the unsymmetric augmented GMRES method (paper 000), the baselines
   (re-factorization, CHOLMOD row updates, Jacobi PCG), background
   re-factorization, and the solver session that runs them side by side. */
#ifndef AUG_SOLVE_H
#define AUG_SOLVE_H

#include <cholmod.h>
#include "aug_fem.h"
#include "aug_update.h"

/* ---- cumulative update (cutmat.c) -------------------------------------- */

/* a column of Ebar: positions i[0..nz) increasing, values x (capacity cap) */
typedef struct aug_ecol {
    int32_t *i;
    double *x;
    int32_t nz, cap;
} aug_ecol;

/* K_t = Kbar - P_S Ebar P_S', f_t = [f_b; 0] + P_S dF, relative to a base
   matrix K_b of order nb: Kbar = blkdiag(K_b, I), S the union of every step's
   Hbar (AMPS eq. 3.1 composed over steps), in insertion order. */
typedef struct aug_cum {
    int64_t nb;          /* order of the base */
    int64_t n;           /* order of K_t */
    int64_t ns, cap;     /* |S| and capacity */
    int32_t *S;          /* S[p]: matrix index at position p */
    int32_t *pos;        /* pos[i]: position of index i in S, -1 if none (size pcap) */
    int64_t pcap;
    /* Ebar = Kbar - K_t on S x S by sparse columns E[p]: an entry is kept
       once an update touched it (its value may have cancelled to 0), an
       entry never touched is 0 */
    aug_ecol *E;
    int64_t nnzE;        /* entries kept, all columns */
    int64_t enzmax;      /* entries of the longest column */
    double *dF;          /* f_t - [f_b; 0] on S */
    int64_t *mod;        /* mod[p]: value of napply when Ebar(:, p) last changed */
    unsigned char *keep; /* keep[p]: K_t's unit row at p is not the base's
                            methods' (an update's keep, solver.c keep_blocks) */
    int64_t napply;      /* number of updates composed */
} aug_cum;

int aug_cum_init(aug_cum *c, int64_t nb, aug_err *e);
void aug_cum_free(aug_cum *c);
/* Compose one step: K_t = [K_{t-1} 0; 0 I_k] - Hbar (E + [0 0; 0 I_k]) Hbar'
   (formats/stream.md 7.2) into (S, Ebar, dF). Validates H against n. */
int aug_cum_apply(aug_cum *c, const aug_update *u, aug_err *e);
/* 1 when Ebar(:, p) has a nonzero entry (position p couples to others);
   0: a load-only position, or a copy of a constrained DOF (amps_schur.c
   activate: no column of S2; amps_reach.c: no memo column) */
static inline int aug_cum_coupled(const aug_cum *c, int64_t p)
{
    for (int32_t t = 0; t < c->E[p].nz; t++)
        if (c->E[p].x[t] != 0) return 1;
    return 0;
}
/* Number of positions of S that are base DOFs (index < nb). */
int64_t aug_cum_morig(const aug_cum *c);

/* The explicit cut matrix: K_0 (both triangles) plus the cumulative update
   relative to K_0. */
typedef struct aug_cutmat {
    cholmod_sparse *K0;  /* full symmetric (stype 0), sorted */
    int64_t n0;
    double *f0;
    aug_cum cum;
    double *work, *rwork; /* n-sized scratch */
    int64_t wcap, rcap;
    /* unit[i]: row (and column) i of K_t is exactly e_i', a constrained DOF
       kept in the matrix (formats/stream.md 7.2), x_i = f_t(i) in any
       solution; kept by aug_cutmat_apply for the indices each step touches */
    unsigned char *unit;
    int64_t unitcap, k0colmax, ubufcap;
    double *uscr, *uval; /* column extraction: n-sized zero scratch, values */
    int32_t *uidx;
} aug_cutmat;

int aug_cutmat_init(aug_cutmat *m, const cholmod_sparse *K0, const double *f0,
                    cholmod_common *cm, aug_err *e);
void aug_cutmat_free(aug_cutmat *m, cholmod_common *cm);
int aug_cutmat_apply(aug_cutmat *m, const aug_update *u, aug_err *e);
static inline int64_t aug_cutmat_n(const aug_cutmat *m) { return m->cum.n; }
/* 1 when row i of K_t is exactly the unit row e_i' (then x_i = f_t(i)) */
static inline int aug_cutmat_unit(const aug_cutmat *m, int64_t i)
{
    return i >= 0 && i < m->unitcap && m->unit[i];
}
/* f_t(i) */
double aug_cutmat_f(const aug_cutmat *m, int64_t i);
/* y = K_t x */
void aug_cutmat_mult(const aug_cutmat *m, const double *x, double *y);
/* f = f_t */
void aug_cutmat_rhs(const aug_cutmat *m, double *f);
/* r[t] = (f_t - K_t x)(rows[t]), ka[t] = (|K_t||x| + |f_t|)(rows[t]) (ka may
   be NULL); x is read on aug_cutmat_pattern(rows) only. */
void aug_cutmat_rows_residual(const aug_cutmat *m, const int32_t *rows, int64_t nr, const double *x,
                              double *r, double *ka);
/* The union of the patterns of K_t's rows rows[0..nr) into out (unordered);
   mark: n bytes, 0 on entry and exit. Returns its size. */
int64_t aug_cutmat_pattern(const aug_cutmat *m, const int32_t *rows, int64_t nr, int32_t *out,
                           unsigned char *mark);
/* ||K_t x - f_t|| / ||f_t|| (2-norms; absolute residual when f_t = 0). */
double aug_cutmat_relres(aug_cutmat *m, const double *x);
/* The part of relres on the rows where K_t differs from K0 (S): O(|S| row
   length + nnz(Ebar)) instead of a product with all of K_t. */
double aug_cutmat_relres_changed(aug_cutmat *m, const double *x);
/* ||f_t||_2, in O(n0 + |S|) */
double aug_cutmat_fnorm(const aug_cutmat *m);
/* r = f_t - K_t x; returns ||r|| / ||f_t|| (absolute when f_t = 0). */
double aug_cutmat_residual(aug_cutmat *m, const double *x, double *r);
/* The same against a right-hand side b (NULL: f_t). */
double aug_cutmat_residual_b(aug_cutmat *m, const double *x, const double *b, double *r);
/* The same over the rows that are not unit rows (aug_cutmat_unit), both
   norms: the relres of a dynamic frame (formats/stream.md 7.9). */
double aug_cutmat_residual_free(aug_cutmat *m, const double *x, const double *b, double *r);
/* K_t as a CHOLMOD matrix, upper triangle (stype 1), sorted; exact zeros of
   changed entries are dropped. pad extra identity columns are appended. */
cholmod_sparse *aug_cutmat_sparse(const aug_cutmat *m, int64_t pad, cholmod_common *cm);
/* Column j of K_t (both triangles): nnz entries into idx/val (capacity from
   aug_cutmat_colmax), rows increasing. */
int64_t aug_cutmat_column(const aug_cutmat *m, int64_t j, int32_t *idx, double *val,
                          double *scratch);
int64_t aug_cutmat_colmax(const aug_cutmat *m);

/* ---- base factor and sparse triangular solves (ldl_sparse.c) ----------- */

/* Bases of at least this order also get a supernodal factor for full
   back-substitutions (below it the simplicial loop is as fast). */
#define AUG_SUPERNODAL_MIN 2000

/* A simplicial LDL' factor P K_b P' = L D L' with its elimination tree and the
   base solution a_b = K_b^-1 f_b. Columns hold D(j,j) first, then L below. */
typedef struct aug_base {
    cholmod_factor *L;   /* owned; simplicial LDL', int indices */
    int64_t n;
    const int *Lp, *Li, *Lnz;
    const double *Lx;
    int32_t *parent;     /* etree parent of permuted column j, -1 at a root */
    int32_t *perm;       /* perm[k]: original index of permuted position k */
    int32_t *pinv;       /* pinv[i]: permuted position of original index i */
    double *a;           /* a_b (original order) */
    double rnorm, anorm; /* ||f_b - K_b a_b||_2 (NAN: K_b not given), ||a_b||_2 */
    int32_t step;        /* step whose matrix K_b is (-1: K_0) */
    int refs;            /* shared by methods: freed when it drops to 0 */
    cholmod_factor *Ls;  /* supernodal L L' with the same permutation, for
                            full back-substitutions (NULL: none) */
    double *sqrtd;       /* sqrt(D(j,j)), permuted order, when Ls is set */
    int32_t *super_of;   /* supernode of each column of Ls */
    struct aug_par_plan *par_plan; /* Ls's two-core split (aug_par.h; NULL: none,
                            or not asked for: aug_base_split) */
    int split_done;      /* aug_base_split ran */
} aug_base;

/* Take L (simplicial or supernodal: converted to simplicial LDL'), check
   that its pattern is closed under its elimination tree (struct L(:,j) minus
   the parent lies in struct L(:,parent)), and solve a_b = K_b^-1 f_b. A
   pattern that fails the check is re-factored from K_b with the same
   permutation. Returns NULL on failure (L is freed). */
aug_base *aug_base_new(cholmod_factor *L, const cholmod_sparse *Kb, const double *fb,
                       int32_t step, cholmod_common *cm, aug_err *e);
void aug_base_release(aug_base *b, cholmod_common *cm);
static inline double aug_base_d(const aug_base *b, int64_t j) { return b->Lx[b->Lp[j]]; }

/* Elimination-tree path of permuted column p to its root (paper 000 thm 3):
   writes it ascending into path, returns its length. */
int64_t aug_ldl_path(const aug_base *b, int32_t p, int32_t *path);
/* Closure in G(L) of the permuted indices start[0..ns): the union of their
   etree paths, ascending, into out; mark (size n, all 0 on entry and exit) is
   workspace. Returns the size. */
int64_t aug_ldl_closure(const aug_base *b, const int32_t *start, int64_t ns, int32_t *out,
                        unsigned char *mark);
/* x := L^-1 x over the closed set set[0..k) (ascending); x is zero outside it.
   set = NULL: all columns. */
void aug_ldl_lsolve(const aug_base *b, const int32_t *set, int64_t k, double *x);
/* x := D^-1 x over set (NULL: all). */
void aug_ldl_dsolve(const aug_base *b, const int32_t *set, int64_t k, double *x);
/* r columns of V at once (BLAS 3 where their paths share supernodes, as
   the paths of one node's DOFs and the top of the tree always do):
   outs[q][t] = V(paths[q][t], p[q]), lens[q] = path lengths from
   aug_ldl_path. Returns 0 or -1 (out of memory). */
int aug_ldl_paths_solve_super(const aug_base *b, int r, const int32_t *p, int32_t *const *paths,
                              const int64_t *lens, double *const *outs);
/* x := L^-T x on the rows of set[0..k) only (an etree closure, ascending, as
   from aug_ldl_closure), through the supernodes of Ls (BLAS 2 per supernode);
   rows outside it are left as they are. tmp: n-sized workspace. */
void aug_ldl_ltsolve_closure_super(const aug_base *b, const int32_t *set, int64_t k, double *x,
                                   double *tmp);
/* pre[s] = the leading columns of supernode s of Ls outside the ascending
   etree closure set[0..k) (aug_par_ltsolve_rest); 0, or -1 when a
   supernode's rows in the set are not a suffix of its columns (or no Ls) */
int aug_ldl_closure_pre(const aug_base *b, const int32_t *set, int64_t k, int *pre);
/* x := L^-1 x on the etree closure set[0..k) (ascending) only, x zero
   outside it, through the supernodes of Ls (BLAS 2 per supernode), column
   by column without Ls. tmp: n-sized workspace. */
void aug_ldl_lsolve_closure_super(const aug_base *b, const int32_t *set, int64_t k, double *x,
                                  double *tmp);
/* x := L^-T x over all columns, given x = D^-1 z: through the supernodal
   factor Ls = L D^1/2 when the base has one (BLAS), else column by column.
   X/Yw/Ew are cholmod_solve2 workspaces kept by the caller. Returns 0 or -1. */
int aug_ldl_ltsolve_all(const aug_base *b, double *x, cholmod_dense **X, cholmod_dense **Yw,
                        cholmod_dense **Ew, cholmod_common *cm);
/* x := L^-T x computed only on the closed set (NULL: all); components outside
   it are left untouched and are never read. */
void aug_ldl_ltsolve(const aug_base *b, const int32_t *set, int64_t k, double *x);
/* x = K_b^-1 b (original order, full; work of size n). */
void aug_ldl_solve_full(const aug_base *b, const double *rhs, double *x, double *work);

/* ---- work arrays growing with the steps (mapped.c) --------------------- */

/* p (old bytes, NULL when old = 0) as an array of n >= old bytes, contents
   kept, page-aligned: from the heap up to 64 MiB, above it mapped from the
   system (no copy on growth); NULL when out of memory (p unchanged). Freed
   by aug_map_free with its size. */
void *aug_map_grow(void *p, size_t old, size_t n);
void aug_map_free(void *p, size_t n);
/* a (cap x cap doubles, column-major, leading dim cap, from aug_map_grow or
   NULL) grown in place to ncap x ncap, leading dim ncap, keeping its leading
   keep x keep block (keep <= cap < ncap); NULL when out of memory. */
double *aug_sq_grow(double *a, int64_t cap, int64_t ncap, int64_t keep);
/* capacity for order need of a square array of capacity cap (>= need, grown
   by a quarter at least, in multiples of 256; AUG_SCHUR_CAP0 at first) */
int64_t aug_sq_cap(int64_t cap, int64_t need);
/* bytes of heap touched once and kept by the allocator, for the arrays
   above to grow into without first-touch page faults (mapped.c says why);
   milliseconds, or -1 (out of memory) */
double aug_prefault(size_t bytes);

/* ---- AMPS (paper 001) -------------------------------------------------- */

/* V = L^-1 P H, one column per base DOF of S, each only over its etree
   path (amps_reach.c); G = H'K^-1H = V'D^-1V grown by trapezoidal
   augmentation (amps_memo.c, eqs. 3.23-3.27). */
typedef struct aug_memo {
    int64_t m, mcap;     /* columns (base DOFs of S, in S order) */
    int64_t *vp;         /* column c: entries vp[c] .. vp[c+1]-1 */
    int64_t *vt;         /* vt[c]: start of the tail of column c whose rows are
                            consecutive (the top of the tree, dense) */
    int32_t *vi;         /* permuted row indices (ascending: the etree path) */
    double *vx;          /* values; vx and then vi share one aug_map_grow array */
    int64_t vnz, vcap;
    int32_t *col;        /* col[c]: position in S of memo column c */
    int32_t *cpos;       /* cpos[pos in S]: memo column or -1 (size pcap) */
    int64_t pcap;
    double *G;           /* m x m symmetric, column-major, leading dim mcap
                            (aug_sq_grow) */
    int use_cholmod;     /* 1: V by cholmod_solve2 with Bset (for comparison) */
    int all;             /* 1: a column for every base DOF of S (the field's
                            memo way needs them); 0: only for those whose
                            column of Ebar is nonzero (amps_reach.c) */
    int64_t reach_new;   /* sum of path lengths computed in the last grow */
    int64_t m_new;
} aug_memo;

void aug_memo_init(aug_memo *M);
void aug_memo_free(aug_memo *M);
/* V columns for the base DOFs of S not yet in the memo (amps_reach.c); a
   group of 8 or more in two halves on the pool par when not NULL (a column
   then rounds as in its half's BLAS calls: equal to rounding). */
struct aug_par;
int aug_memo_reach(aug_memo *M, const aug_base *b, const aug_cum *c, struct aug_par *par,
                   cholmod_common *cm, aug_err *e);
/* Trapezoidal augmentation of G for the columns added by aug_memo_reach
   (eq. 3.27): G[i,j] = V_i' D^-1 V_j, summed over the common etree suffix;
   on the pool par when not NULL (the same bits as without). */
int aug_memo_grow(aug_memo *M, const aug_base *b, struct aug_par *par, aug_err *e);

/* S2 of eq. 3.21 on the active positions A of S (Ebar column nonzero: the
   Dirichlet/load-only positions drop out, sec. 3.4), LU-factored by LAPACK
   and kept across steps (amps_schur.c): A only grows, in activation order,
   and a step changes the columns of Ebar on its own positions only, so the
   factorization is updated from the first changed column on (block LU:
   the leading columns keep their pivots, the new rows are solved against
   U11, the trailing block is re-eliminated), not re-done. */
/* initial capacity (positions) of S2's and the memo's dense arrays */
#define AUG_SCHUR_CAP0 1024
typedef struct aug_schur {
    int64_t na, acap;
    int32_t *A;          /* active positions of S, in activation order */
    unsigned char *act;  /* act[pos] */
    int64_t pcap;
    int32_t *gi;         /* gi[a]: memo column of A[a], -1 for a new DOF */
    double *rs;          /* rs[a]: scale of row a of S2 (1 / sigma for a new DOF) */
    double *S2;          /* LU factors of S2, leading dim scap (aug_sq_grow);
                            S2 itself is formed from the memo's G and Ebar_AA
                            column by column where the factorization needs it */
    double *cs;          /* column sums of |S2| (when rcond is estimated) */
    int *ipiv;
    int64_t scap;
    int64_t *ep;         /* Ebar_AA by columns: rows ei, values ex */
    int32_t *ei;
    double *ex;
    int64_t ecap;
    int64_t nlu;         /* order of the valid factorization, 0: none */
    int64_t stamp;       /* aug_cum napply it reflects */
    int64_t k0;          /* last step: first re-eliminated column (0: full) */
    int64_t nkept;       /* last step: columns from k0 on carried by the old L22 U22 */
    int want_rcond;      /* estimate rcond (dgecon, O(na^2)) */
    double rcond;        /* NaN unless estimated */
    int detsign;
    int singular;
    int64_t nnzE;
    double flops;        /* of the last aug_schur_factor (formed columns and LU) */
} aug_schur;

void aug_schur_init(aug_schur *s);
void aug_schur_free(aug_schur *s);
/* Bring S2 = I - Gbar_AA Ebar_AA and its factorization up to date with c;
   singular is set when LU fails, rcond < rcond_min (when estimated), or
   det(S2) <= 0 (K_t not positive definite: S2 = Gbar M with M the Schur
   complement of K_t on A). */
int aug_schur_factor(aug_schur *s, const aug_memo *M, const aug_cum *c, double rcond_min,
                     aug_err *e);
/* x := S2^-1 x (length na). */
void aug_schur_solve(const aug_schur *s, double *x);
/* x := S2'^-1 x (length na): the matrix of eq. 3.16 is -S2'. */
void aug_schur_solve_t(const aug_schur *s, double *x);

/* The AMPS solution (amps_solve.c): rhs of eq. 3.21 extended to loads changed
   on H, S2 solve, and eq. 3.20: a on A from a2, elsewhere
   a_b + P'L^-T D^-1 V (dF + Ebar a2) over the closure of the requested DOFs. */
typedef struct aug_amps {
    aug_memo memo;
    aug_schur schur;
    double *x;           /* a2 on A */
    double *w, *y;       /* scratch: S-sized and n_b-sized */
    int64_t xcap, wcap;
    int32_t *q;          /* output closure (permuted, ascending) */
    unsigned char *mark;
    int64_t nq;
    int64_t closure_v;   /* |union of V paths| (closure of H in L) */
    int32_t *ca;         /* closure of A's base DOFs in L' (permuted, ascending) */
    double *t2;          /* n_b-sized scratch */
    double *zlo;         /* n_b-sized, zero between uses (lo_times) */
    int32_t *lset;       /* n_b-sized: lo_times's closure */
    cholmod_dense *X, *Yw, *Ew; /* cholmod_solve2 workspaces (supernodal path) */
    /* the correction on H (amps_solve.c, correct_on_h): set kt to K_t */
    const aug_cutmat *kt; /* K_t (NULL: no correction) */
    int correct_max;     /* sweeps at most */
    int ncorrect;        /* sweeps the last step applied */
    double berr_h0, berr_h; /* componentwise backward error on the rows of H
                            before the first and after the last sweep measured */
    double floor_k;      /* no sweep once relres_h <= floor_k times the base's
                            residual scaled to the step (0: berr alone) */
    double relres_h0, relres_h, relres_floor; /* ||r_H|| / ||f_t|| before
                            and after, and that floor */
    double t_correct;    /* ms the last step's correction took */
    struct aug_hcorr *hc; /* its workspace */
    /* the field's Kbar^-1 Hbar w (amps_solve.c, v_times): 0 by a forward
       solve of H w over the closure of H in L (hcl), 1 by the memo's V w */
    int field_memo;
    int32_t *hcl;        /* closure of H in L (permuted, ascending), nhcl long */
    int64_t nhcl, hcl_m; /* ... for the first hcl_m positions of S */
    const void *hcl_b;   /* ... of this base */
    int pivot;           /* AUG_PIVOT_S2, _ALT (eqs. 3.16-3.17) or _AUTO */
    int pivot_used;      /* the last step's: S2 or ALT */
    double berr_piv[2];  /* berr_h0 of S2 and ALT when last used (AUTO) */
    struct aug_par *par; /* borrowed two-core pool for the full L^-T (NULL: serial) */
    double xnorm;        /* ||x_t|| on base DOFs of the last full field ... */
    const void *xnorm_b; /* ... on this base (relres_floor of a deferred L^-T) */
    double cancel;       /* (||a_b|| + ||Kbar^-1 P_S w||) / ||x_t|| of the last full
                            field (NaN: an output set): how far the rows outside S
                            may carry more than a fresh solve's rounding */
    double floor_end;    /* relres_floor with this step's ||x_t|| (full field) */
    /* the reference field (aug_amps_set_ref): a step's field is xref + delta,
       delta = K_t^-1 (f_t - K_t xref) through the same S2 and memo */
    double *xref;        /* a refined full field of this base, nref DOFs (the
                            DOFs added since at 0, extended in place) */
    int64_t nref, refcap;
    const void *xref_b;  /* ... of this base */
    int32_t xref_step;   /* ... and its step (the caller's number, stat ref_step) */
    double *rref, *kref; /* xref's residual and |K||x| on the rows of S */
    int64_t rrcap;
    int ref_used;        /* the last field was xref + delta */
    const double *ab_cur, *dF_cur, *xnew_cur; /* the field's offsets (b->a, or xref)
                            and load on S (c->dF, or rref) in aug_amps_field */
} aug_amps;

/* Schur pivots of AMPS (paper 001): S2 of eq. 3.8, the (1,2) block of S1 as
   pivot; ALT of eqs. 3.16-3.17, the (2,1) block; AUTO per step */
enum { AUG_PIVOT_S2 = 0, AUG_PIVOT_ALT = 1, AUG_PIVOT_AUTO = 2 };

void aug_amps_init(aug_amps *a);
void aug_amps_free(aug_amps *a);
/* One step. out[0..nout) are requested DOFs of K_t (NULL: all); u receives
   the solution (length c->n, valid at least at the requested DOFs and on S).
   times[0..4]: reach, memo, schur, solve (ms). */
int aug_amps_step(aug_amps *a, const aug_base *b, const aug_cum *c, const int32_t *out,
                  int64_t nout, double rcond_min, double *u, double times[4],
                  cholmod_common *cm, aug_err *e);
/* The solution part of aug_amps_step alone, on the S2 and memo the last
   aug_amps_step or aug_amps_prepare left (same arguments): e.g. the whole
   field of a step whose output set was solved (the rest of it, for the
   step's relres), computed as a full-field step computes it. */
int aug_amps_field(aug_amps *a, const aug_base *b, const aug_cum *c, const int32_t *out,
                   int64_t nout, double *u, cholmod_common *cm, aug_err *e);
/* The per-step work of aug_amps_step without a solve (reach, memo, schur:
   times[0..2] in ms); then any number of aug_amps_solve_general (the frames
   of a dynamic step). */
int aug_amps_prepare(aug_amps *a, const aug_base *b, const aug_cum *c, double rcond_min,
                     double times[3], cholmod_common *cm, aug_err *e);
/* Keep the full field x (n DOFs) of step step on base b, refined to a fresh
   solve's residual, as the reference of the later steps on b: their field
   is x + delta (amps_solve.c, aug_amps_field). 0, or -1 (memory: no
   reference kept). */
int aug_amps_set_ref(aug_amps *a, const aug_base *b, const double *x, int64_t n, int32_t step);
/* Solve K_t x = r for a general r with the current factorization (used by
   iterative refinement and by the frames of a dynamic step; full vectors). */
int aug_amps_solve_general(aug_amps *a, const aug_base *b, const aug_cum *c,
                           const double *r, double *x, cholmod_common *cm, aug_err *e);

/* ---- unsymmetric augmented GMRES (gmres_aug.c, paper 000) -------------- */

enum { AUG_PREC_NONE = 0, AUG_PREC_D = 1, AUG_PREC_SPAI = 2 };

typedef struct aug_gmres aug_gmres;
aug_gmres *aug_gmres_new(int prec, int restart, int maxit, double tol, aug_err *e);
void aug_gmres_free(aug_gmres *g);
/* Tridiagonal SPAI of K_b (min ||K_b S - I||_F over tridiagonal S, paper 000
   sec. 3.5), computed once per base. */
int aug_gmres_set_base(aug_gmres *g, const aug_base *b, const cholmod_sparse *Kbfull,
                       aug_err *e);
/* One step: (Hbar' Kbar^-1 J) a2 = Hbar' Kbar^-1 f_t (eq. 17) with J = K_t Hbar,
   then a1 = Kbar^-1 (f_t - J a2) (eq. 16). times: setup, rhs, iter, solve. */
int aug_gmres_step(aug_gmres *g, const aug_base *b, const aug_cum *c, aug_cutmat *cm_t,
                   const int32_t *out, int64_t nout, double *u, double times[4], aug_err *e);
/* K_t x = r for a general r (refinement, dynamic frames, an output set's
   rest): the same steps with full solves, warm rounds at a tighter Schur
   tolerance until m's relative residual against r meets tol (m NULL: one
   round at tol); converged as for a step. */
int aug_gmres_solve_general(aug_gmres *g, const aug_base *b, const aug_cum *c, aug_cutmat *m,
                            const double *r, double *x, aug_err *e);
/* The per-step set-up of aug_gmres_step (J = K_t Hbar, closures) without a
   solve: then aug_gmres_solve_general per right-hand side. */
int aug_gmres_prepare(aug_gmres *g, const aug_base *b, const aug_cum *c, const aug_cutmat *m,
                      aug_err *e);
int aug_gmres_iters(const aug_gmres *g);
int aug_gmres_converged(const aug_gmres *g);
/* the last aug_gmres_step's output set: 1 when the step computed the whole
   field for it (its round at the learnt Schur tolerance stalled, or none
   learnt yet), 0 the output values only, -1 no output set */
int aug_gmres_whole(const aug_gmres *g);
int64_t aug_gmres_closure_j(const aug_gmres *g);
int64_t aug_gmres_closure_h(const aug_gmres *g);

/* ---- baselines --------------------------------------------------------- */

/* refactor.c: CHOLMOD re-factorization of K_t: with an ordering given
   (aug_refactor_order) the ordering of K0 extended to the new DOFs, analysed
   anew (no re-ordering) only when the pattern changed and re-ordered by
   CHOLMOD only past AUG_REFACTOR_FILL times the fill of its last ordering;
   the factor's memory kept across steps; numeric-only factorization whenever
   the pattern holds. Without an ordering: cholmod_analyze (a fresh analysis)
   whenever the pattern changed. */
#define AUG_REFACTOR_FILL 1.2
typedef struct aug_refactor {
    cholmod_factor *L;
    int64_t n, nnz;
    int *Kp, *Ki;        /* pattern of the last analyzed matrix */
    int64_t pcap, icap;
    int *perm;           /* the ordering to extend (NULL: CHOLMOD's each time) */
    int64_t nperm;
    double lnz, lnz_ref; /* nnz(L) now / of CHOLMOD's last ordering */
    int analyzed;        /* 1 if the last step ran the symbolic analysis */
    int reordered;       /* 1 if it also ran CHOLMOD's ordering */
    int kept;            /* 1 if the factor's numeric storage was kept */
    int singular;
    cholmod_dense *X, *Y, *E; /* cholmod_solve2 workspaces */
    const void *given;   /* the base aug_refactor_take_base gave its factor to */
    int step_cost;       /* re-order by aug_analyze_steps (a base for AMPS),
                            not CHOLMOD's least fill */
    int nblas;           /* > 1: OpenBLAS's threads for the factorize, the
                            count before restored after it (solver.c) */
} aug_refactor;
void aug_refactor_init(aug_refactor *r);
void aug_refactor_free(aug_refactor *r, cholmod_common *cm);
/* the fill-reducing ordering (perm[k]: original index at position k) of the
   first n DOFs to extend from now on; 0, or -1 out of memory */
int aug_refactor_order(aug_refactor *r, const int32_t *perm, int64_t n);
/* P K_t P' = L L' by the step of aug_refactor_step, the factor moved into a
   new base of step (aug_base_new: Ls = L, its simplicial LDL', a_b = K_t^-1
   f_t); old (the base replaced, or NULL) hands its supernodal factor back
   first when only the caller holds it (its storage, and its symbolic
   analysis when r made it). NULL with r->singular = 1 when K_t is not
   positive definite (e not set), NULL with e on other failures. times:
   assemble, analyze, factor, base. */
aug_base *aug_refactor_take_base(aug_refactor *r, const aug_cutmat *m, int32_t step, aug_base *old,
                                 double times[4], cholmod_common *cm, aug_err *e);
/* times: assemble, analyze, factor, solve */
int aug_refactor_step(aug_refactor *r, const aug_cutmat *m, double *u, double times[4],
                      cholmod_common *cm, aug_err *e);
int aug_refactor_solve(aug_refactor *r, const double *rhs, double *x, cholmod_common *cm,
                       aug_err *e);

/* rowupdate.c: cholmod_rowdel / cholmod_rowadd of every changed row of a
   simplicial LDL' of blkdiag(K_t, I_spare); new DOFs take spare rows. */
typedef struct aug_rowupd aug_rowupd;
aug_rowupd *aug_rowupd_new(const aug_cutmat *m, const aug_base *b0, int64_t spare,
                           cholmod_common *cm, aug_err *e);
void aug_rowupd_free(aug_rowupd *r, cholmod_common *cm);
/* times: update, solve; rows = rows changed this step */
int aug_rowupd_step(aug_rowupd *r, const aug_cutmat *m, const aug_update *u, double *x,
                    double times[2], int64_t *rows, int *rebuilt, int *singular,
                    cholmod_common *cm, aug_err *e);
int aug_rowupd_solve(aug_rowupd *r, int64_t n, const double *rhs, double *x, cholmod_common *cm,
                     aug_err *e);

/* pcg.c: Jacobi-preconditioned CG on K_t (upper-stored), from x (warm start)
   to ||f - K x|| <= tol ||f||. Returns iterations; *converged, *breakdown
   (p'Kp <= 0: not positive definite). */
int aug_pcg(const cholmod_sparse *K, const double *f, double *x, double tol, int maxit,
            int *converged, int *breakdown, double *relres, cholmod_common *cm);
/* The same with preconditioner prec: none (M = I), Jacobi (M = diag(K)) or IC
   (M = R'R, IC(0) of K, ichol.c); *shift (may be NULL): the IC diagonal shift
   used. AUG_PCG_IC_AMD: IC(0) of P'KP, P the AMD ordering of K's pattern
   (ichol_amd.c), M = P R'R P'. *prec_ms (may be NULL): the wall-clock time
   of building M (the IC(0) factorization with its shifts and ordering; 0
   for none and Jacobi). unit (may be NULL): unit[i] != 0 (i < nunit) marks
   a row and column of K that are e_i (a constrained DOF, aug_cutmat_unit):
   x_i := f_i at the start, and the tolerance, relres and convergence are of
   the other rows alone (||f|| over them). Returns iterations, -1 out of
   memory or no IC(0) exists. */
enum { AUG_PCG_NONE, AUG_PCG_JACOBI, AUG_PCG_IC, AUG_PCG_IC_AMD };
int aug_pcg_prec(const cholmod_sparse *K, const double *f, const unsigned char *unit, int64_t nunit,
                 double *x, int prec, double tol,
                 int maxit, int *converged, int *breakdown, double *relres, double *shift,
                 double *prec_ms, cholmod_common *cm);

/* ichol.c: IC(0) R'R ~ K + shift diag(K), R upper with the pattern of K's
   upper triangle, the smallest shift of 0, 1e-3, 2e-3, ... without breakdown
   (0; 1 none of 40 worked; -1 out of memory). */
typedef struct aug_ichol {
    int n;
    int *p, *i;          /* columns of R, rows ascending, the diagonal last */
    double *x, *k;       /* R, and K's values while factoring */
    double shift;
    int *perm;           /* NULL, or row k of R is K's row perm[k] (ichol_amd.c) */
    double *w;           /* n doubles of workspace when perm is set */
} aug_ichol;
int aug_ichol_factor(const cholmod_sparse *K, aug_ichol *R);
/* ichol_amd.c: the same IC(0) of P'KP, P the AMD fill-reducing ordering of
   K's pattern (SuiteSparse AMD through cholmod_amd), R->perm = P: R'R ~
   P'(K + shift diag(K))P. 0, -1 out of memory or no ordering, 1 no shift
   worked. */
int aug_ichol_factor_amd(const cholmod_sparse *K, aug_ichol *R, cholmod_common *cm);
/* z = (R'R)^-1 r, or z = P (R'R)^-1 P' r when R->perm is set */
void aug_ichol_apply(const aug_ichol *R, const double *r, double *z);
void aug_ichol_free(aug_ichol *R);

/* ---- background re-factorization (bgfactor.c, paper 000 sec. 3.6) ------ */

typedef struct aug_bg aug_bg;
/* stepwise: the thread catches AMPS up one queued update at a time (with a
   --bg-lag schedule), not in batches of what queued meanwhile, whose
   grouping, and so the rounding of the new base's memo, depends on timing */
aug_bg *aug_bg_new(int nthreads, int stepwise);
void aug_bg_free(aug_bg *bg);
/* Start re-factoring K (taken) with load f (copied) in a thread; step is the
   step whose matrix K is. perm (may be NULL): a fill-reducing ordering of K to
   reuse (the old base's permutation extended by the DOFs added since), saving
   CHOLMOD's ordering while its fill stays within 10% of the fill of the
   ordering last chosen (the first job's sets it); beyond that CHOLMOD orders
   K anew (given, AMD, METIS: the least fill), so that the factors, which the
   new DOFs placed last would fill more with every step, stay bounded.
   amps (0: no, 1: own path solve, 2: cholmod_solve2
   reach): once factored, the thread also catches AMPS up with the updates
   pushed since the start (aug_bg_push): their composed update and the memo
   of V columns and H'K^-1H for the new base, so that the swap step does not
   pay for them. 0 or error (a job is running). */
int aug_bg_start(aug_bg *bg, cholmod_sparse *K, const double *f, const int32_t *perm,
                 int32_t step, int amps, aug_err *e);
/* Queue a copy of the update of a step taken while the job runs. */
int aug_bg_push(aug_bg *bg, const aug_update *u, aug_err *e);
int aug_bg_running(const aug_bg *bg);
/* 1 when the job finished (without waiting), 0 otherwise. */
int aug_bg_done(aug_bg *bg);
/* Wait for the job; returns the new base (caller owns a reference), or NULL
   with e filled (e.g. the matrix was not positive definite; the queue is
   dropped). */
aug_base *aug_bg_join(aug_bg *bg, aug_err *e);
/* After a successful join: the composed update of the queued steps relative
   to the new base into c (uninitialized on entry), and the AMPS state the
   thread prepared into a (freed or never initialized on entry; a fresh one
   when the thread prepared none, with use_cholmod set as started). The memory
   the caller freed with the old base and state is then given back to the
   system (malloc_trim). */
int aug_bg_take(aug_bg *bg, int64_t nb, aug_cum *c, aug_amps *a, aug_err *e);
int32_t aug_bg_step(const aug_bg *bg);

/* ---- thesis 003 sec. 3.5: conditioning transforms (cgm_*.c) ----------- */

/* The variants: the covariance matrix COV of K_t (eq. 3.21); ES-CGM, the
   recomposition L F(D + eps I) L' of COV = L D L' with F = D^p (eqs.
   3.22-3.23, 3.25) or F = log (eq. 3.24); AS-CGM, the Newton-Schulz square
   root of COV + eps I (eq. 3.27). Each is a dense n x n matrix T; the variant
   solves T x = f_t by Jacobi PCG and x is reported as the displacement. */
enum { AUG_CGM_COV, AUG_CGM_ES, AUG_CGM_LOG, AUG_CGM_AS, AUG_CGM_COUNT };
typedef struct aug_cgm_opts {
    double eps;          /* D' = D + eps I (eq. 3.22); AS: Y = COV + eps I (default 1e-6) */
    double p;            /* ES exponent of eq. 3.25 (default 1/2) */
    double ns_tol;       /* AS: stop when ||I - Q_k P_k||_F <= ns_tol (default 1e-10) */
    int ns_maxit;        /* AS: iteration cap (default 100) */
    int64_t max_n;       /* dense limit: larger K_t is refused (default 8400) */
    double cond_tol;     /* ARPACK relative Ritz residual (default 1e-6) */
} aug_cgm_opts;
typedef struct aug_cgm_res {
    double cond, lambda_max, lambda_min; /* of T: largest / smallest |eigenvalue|, signed */
    int cond_converged;
    int spd;             /* T positive definite (by its inertia) */
    int zero_pivots;     /* pivots of COV = L D L' taken as 0 */
    double cond_k;       /* cond(K_t), the true cut system (cond.c) */
    int iters, converged, breakdown;
    double relres_t;     /* ||f - T x|| / ||f|| of the system CG solved */
    int ref_spd;         /* the fresh CHOLMOD factor of K_t exists */
    double err;          /* ||x - u|| / ||u||, u = K_t^-1 f_t by a fresh CHOLMOD solve */
    double err_scaled;   /* min over alpha of ||alpha x - u|| / ||u|| */
    int ns_iters, ns_converged;
    double ns_scale, ns_resid; /* AS: c = ||Y||_F, ||P^2 - Y/c||_F / ||Y/c||_F */
    double t_cov, t_decomp, t_norm, t_recomp, t_cg, t_diag; /* ms */
} aug_cgm_res;
void aug_cgm_opts_default(aug_cgm_opts *o);
/* cgm_cov.c: C (n x n, column-major) = COV of eq. 3.21 of the symmetric K
   (upper-stored). 0 or AUG_ENOMEM. */
int aug_cgm_cov(const cholmod_sparse *K, double *C, cholmod_common *cm, aug_err *e);
/* cgm_es.c: M = L D L' in place (unit L strictly below the diagonal of M, the
   rest of M destroyed), no pivoting; pivots <= n macheps max|M_jj| are 0 with
   a zero column of L (M positive semidefinite). Returns the count of such
   pivots. */
int aug_cgm_ldl(double *M, int n, double *d);
/* cgm_es.c: T = L diag(F) L' (eq. 3.23), L from aug_cgm_ldl. */
void aug_cgm_recompose(const double *L, const double *F, int n, double *T);
/* cgm_as.c: P ~ (Y/c)^(1/2), c = ||Y||_F, by the coupled Newton-Schulz
   iteration (eq. 3.27) from P_0 = Y/c, Q_0 = I; 1 converged (||I - Q P||_F <=
   tol), 0 not within maxit, -1 allocation failure. */
int aug_cgm_newton_schulz(const double *Y, int n, double tol, int maxit, double *P, int *iters,
                          double *scale);
/* cgm_solve.c: the variant's T of K_t, T x = f by Jacobi PCG (tol, maxit) from
   x = 0, and the figures of r (cond of T by ARPACK, the error against a fresh
   CHOLMOD solve of K_t). n > o->max_n: AUG_EUSAGE. */
/* cgm_solve.c: the sTAt and tIMe entries of a variant's result */
void aug_cgm_put(int variant, const aug_cgm_res *r, const aug_cgm_opts *o, aug_kv *st, aug_kv *tm);
int aug_cgm_solve(int variant, const cholmod_sparse *K, const double *f, const aug_cgm_opts *o,
                  double tol, int maxit, double *x, aug_cgm_res *r, cholmod_common *cm,
                  aug_err *e);

/* auto_policy.c: the cost model of --method auto (the choice per step from
   the measured times; the session runs the choice and reports it). */
enum { AUG_AUTO_AMPS, AUG_AUTO_REFACTOR };
/* reasons (sTAt key reason of tag auto, formats/stream.md 7.4) */
enum {
    AUG_AUTO_CHEAPER,      /* AMPS: its growth has cost less than a re-factorization */
    AUG_AUTO_FIRST,        /* AMPS: a warm-up step on a base (measures it) */
    AUG_AUTO_BG_RUNNING,   /* AMPS: a background re-factorization is running */
    AUG_AUTO_BG_START,     /* AMPS, and a background re-factorization starts */
    AUG_AUTO_STEP,         /* refactor: the next AMPS step costs more than it */
    AUG_AUTO_AMORTIZED,    /* refactor: the growth has cost more than it */
    AUG_AUTO_FIRST_DEARER, /* refactor: warm-up AMPS steps cost more than it */
    AUG_AUTO_SINGULAR,     /* refactor: AMPS called the step singular */
    AUG_AUTO_SWAPPED,      /* AMPS on the background factor swapped in this step */
    AUG_AUTO_HORIZON,      /* AMPS: the growth has cost more than a re-factorization,
                              but the steps left (--horizon) would not pay it back */
    AUG_AUTO_DYNAMIC       /* AMPS: a dynamic stream, whose frames the cost model does not run on */
};
/* AMPS steps on a new base whose excess over the cheapest later step counts
   as its warm-up; after this many re-factorizations in a row chosen because
   the first AMPS step on a new base was predicted dearer (FIRST_DEARER, by
   less than twice) one AMPS step is measured again (the interval doubling
   after each); the prior of a re-factorization step, in full
   solves of the base, until one is measured */
#define AUG_AUTO_WARM 2
#define AUG_AUTO_PROBE 8
#define AUG_AUTO_PRIOR 50
/* the ms per S2 flop assumed until one is fitted (10 Gflop/s, one core of
   dense LU on this kind of machine) */
#define AUG_AUTO_CFLOP_PRIOR 1e-7
#define AUG_AUTO_CFLOP_MIN 1e-7 /* 10 Gflop/s: no faster than the prior */
#define AUG_AUTO_CFLOP_MAX 2e-6 /* 0.5 Gflop/s */
typedef struct aug_auto {
    int bg_allowed;        /* a second core: background jobs may run */
    int on_base;           /* AMPS steps on the current base */
    int64_t na;            /* order of S2 after the last AMPS step on the base */
    double a1, w1;         /* the first AMPS step on the base: ms, S2 flops */
    double a_last, w_last; /* the last AMPS step on the base: ms, S2 flops */
    double a_first, w_first; /* first AMPS steps on the bases (running means) */
    double c_flop;         /* ms per S2 flop, fitted on the last base where S2 grew
                              (AUG_AUTO_CFLOP_PRIOR until then), clamped to
                              AUG_AUTO_CFLOP_MIN .. MAX */
    double warm_sum;       /* the warm-up steps on this base, ms */
    double t_warm;         /* their excess over a_ref (running mean), ms */
    double a_ref;          /* the first steady AMPS step on the base, ms */
    double ls[5];          /* sums of 1, j, a_j, j^2, j a_j over the steady steps */
    double excess;         /* the growth's cost on the base (trend over a_ref), ms */
    double g, trend0;      /* the trend's slope (ms per step, >= 0) and intercept */
    double t_factor;       /* a re-factorization step (running mean), ms; 0: none yet */
    double t_prior;        /* its prior before one is measured, ms */
    int nsync_run;         /* re-factorizations in a row for FIRST_DEARER */
    int probe_every;       /* ... after which one AMPS step is measured again */
    int nbase;             /* bases made since the session's (re-factored or swapped in) */
    int choice, reason, want_bg;
    double est_amps, est_factor, w_next; /* the estimates the choice compared,
                                            the S2 flops predicted for the step */
} aug_auto;
void aug_auto_init(aug_auto *a, int bg_allowed);
/* the choice for the next step; s_step: the positions the step's update adds
   to S2 (its m + k); left: the steps the stream still brings, this one
   included (solve-aug --horizon), <= 0 when unknown */
int aug_auto_decide(aug_auto *a, int bg_running, int64_t s_step, int64_t left);
/* the step's measured time ms and, for AMPS, its S2 flops and order */
void aug_auto_observe(aug_auto *a, double ms, double s2_flops, int64_t na);
void aug_auto_rebased(aug_auto *a);
/* the flops of the LU of S2 brought from order n0 to n1, re-eliminated from
   column k0 (0: from scratch), formed columns included (amps_schur.c) */
double aug_s2_flops(int64_t n0, int64_t n1, int64_t k0);

/* ---- the session (solver.c) -------------------------------------------- */

enum { AUG_M_AMPS, AUG_M_GMRES, AUG_M_REFACTOR, AUG_M_ROWUPDATE, AUG_M_PCG, AUG_M_AUTO,
       AUG_M_CGM_COV, AUG_M_CGM_ES, AUG_M_CGM_LOG, AUG_M_CGM_AS, AUG_M_COUNT };
extern const char *const aug_method_names[AUG_M_COUNT];
/* the method named by the len bytes of name, -1 when none */
int aug_method_index(const char *name, size_t len);
/* "amps,gmres,..." into order[] (returns count, -1 on an unknown, empty or
   repeated name; aug_methods_parse then says which in why). */
int aug_parse_methods(const char *s, int order[AUG_M_COUNT]);
int aug_methods_parse(const char *s, int order[AUG_M_COUNT], char why[64]);

typedef struct aug_solver_opts {
    int nmeth;
    int order[AUG_M_COUNT];
    double tol;          /* iterative methods */
    int maxit;           /* pcg / gmres iteration cap */
    int restart;         /* gmres restart */
    int refine_iter;     /* > 0: exactly this many refinement steps */
    double refine_tol;   /* refine_iter = 0: refine while relres > refine_tol ... */
    int refine_max;      /* ... at most this many steps, while each halves relres */
    double fail_tol;     /* a direct method whose relres stays above this failed */
    int fail_tol_fixed;  /* fail_tol as given (--fail-tol), not raised to the base's relres (sys0_rec.c) */
    double amps_target;  /* amps refines (once) above this relres even below refine_tol */
    int check;           /* err_direct against a fresh CHOLMOD solve */
    int background;      /* background re-factorization for amps/gmres */
    int bg_lag;          /* > 0: swap exactly bg_lag steps after the start (deterministic) */
    int gmres_prec;
    int64_t spare;       /* rowupdate spare rows */
    double rcond_min;
    int reach_cholmod;   /* amps V columns by cholmod_solve2 with Bset */
    int nthreads;
    int dynamic;         /* the matrix is a dynamic stream's A (aug_solver_frame) */
    aug_cgm_opts cgm;    /* the cgm-* methods (thesis 003 sec. 3.5) */
    int pcg_prec;        /* AUG_PCG_NONE, AUG_PCG_JACOBI (default) or AUG_PCG_IC */
    double auto_prior;   /* auto: the re-factorization time (ms) assumed until one
                            is measured; 0: AUG_AUTO_PRIOR full solves */
    int64_t horizon;     /* auto: the steps the stream brings (0: unknown, the
                            stream's pLAN ignored; < 0: the pLAN's, the default) */
    int amps_correct;    /* amps: correction sweeps on H at most (0: none) */
    int amps_pivot;      /* amps: AUG_PIVOT_S2 (default), _ALT or _AUTO */
    int amps_field_memo; /* amps: Kbar^-1 Hbar w by the memo's V (1) or a forward solve (0) */
} aug_solver_opts;
void aug_solver_opts_default(aug_solver_opts *o);
/* the message of a method list that cannot run in one session (auto with
   amps or gmres: auto re-factors their base), or NULL; the tools check it
   before reading input, aug_solver_new again */
const char *aug_solver_opts_conflict(const aug_solver_opts *o);

/* The original system read from a stream (lib/solve/sys0_rec.c): K0, f0 and
   the factor L0 of KMAT/FVEC/FACT, in one cholmod_common that the struct owns,
   and the solver made from them at the first update, once they agree: orders
   equal to DOFM's free count, and L0 a factor of K0 (the relres of its solve
   of f0 at most AUG_SYS0_TOL, or what cond(K0) allows, below), else an
   error naming both records. */
typedef struct aug_sys0 {
    cholmod_common *cm;
    cholmod_sparse *K0;
    double *f0;
    int64_t nf0;
    cholmod_factor *L0;
    long k_index, f_index, l_index; /* their record indices */
    struct aug_solver *solver;
    /* a dynamic stream (DYNP): the solver's matrix is A0 (KMAT which 3) and
       FACT its factor; K0 and M0 (KMAT of DYNP's mass kind) drive the frames */
    int dynamic;
    aug_dynp dyn;
    cholmod_sparse *A0, *Mk[2];
    long a_index;
} aug_sys0;
/* largest relres of K0 L0^-1 f0 that lets a FACT pass as K0's factor */
#define AUG_SYS0_TOL 1e-4
/* ... or AUG_SYS0_COND cond(K0) eps (estimated when the relres passes
   AUG_SYS0_TOL), at most 1e-2; unless fail_tol_fixed, a step's direct solve
   fails above max(fail_tol, AUG_SYS0_COND x that relres), at most 1e-2 */
#define AUG_SYS0_COND 100.0
int aug_sys0_init(aug_sys0 *s, aug_err *e);
void aug_sys0_free(aug_sys0 *s);
int aug_sys0_add(aug_sys0 *s, const aug_rec *rec, aug_err *e);
int aug_sys0_solver(aug_sys0 *s, int64_t nfree, const aug_solver_opts *o, const aug_rec *rec,
                    aug_err *e);

typedef struct aug_solver aug_solver;
/* K0 upper (stype 1), f0, the FACT factor of K0 (taken). */
aug_solver *aug_solver_new(const cholmod_sparse *K0, const double *f0, cholmod_factor *L0,
                           const aug_solver_opts *o, cholmod_common *cm, aug_err *e);
void aug_solver_free(aug_solver *s);
/* One cut step: apply u, run every method. out: requested DOFs of K_t (NULL:
   all). Returns 0, or an error (data errors, out of memory, a failed background
   re-factorization); a singular step is not an error: see aug_solver_singular
   (nor is the background's failure to factor the matrix of a step some method
   reported singular or not converged: the base stays). */
int aug_solver_step(aug_solver *s, const aug_update *u, const int32_t *out, int64_t nout,
                    int flags, aug_err *e);
/* The number of the stream's last cut step (its pLAN; 0: unknown): auto's
   horizon when --horizon is not given */
void aug_solver_plan(aug_solver *s, int32_t last_step);
int64_t aug_solver_n(const aug_solver *s);
const double *aug_solver_field(const aug_solver *s, int method);
const aug_kv *aug_solver_stat(const aug_solver *s, int method);
const aug_kv *aug_solver_time(const aug_solver *s, int method);
/* Median wall time (ms) of `reps` full solves K_b^-1 f_b with the current base
   factor (supernodal when the base has one): the unit the per-step times of
   the methods are compared with, measured in the same process. */
double aug_solver_full_solve_ms(aug_solver *s, int reps);
int aug_solver_singular(const aug_solver *s, int method);
int aug_solver_converged(const aug_solver *s, int method);
/* Dynamic streams (opts.dynamic): aug_solver_step does each method's
   per-step work only (AMPS: V, H'A^-1H and S2; gmres: J; refactor and
   rowupdate: the factor; pcg: A_t assembled); a detached piece is no longer
   singular (its mass holds A_t definite). Then per time frame one right-hand
   side b: every method solves A_t x = b with what its step left (refined as
   in a step, pcg warm-started from its previous frame), its field, sTAt
   (frame, relres, iters, refine, converged, singular, err_direct with
   --check) and tIMe (time_ms) replaced. */
int aug_solver_frame(aug_solver *s, const double *b, int32_t frame, aug_err *e);
/* --check, after aug_solver_frame: err_out of every method on the output
   DOFs out[0..nout) (a frame solves every DOF: the integrator needs them) */
void aug_solver_frame_err_out(aug_solver *s, const int32_t *out, int64_t nout);
int aug_solver_frame_singular(const aug_solver *s, int method);

/* ---- time integration of a dynamic stream (dyn_sim.c) ----------------- */

struct aug_replay;
/* State over the nodes of the step's mesh (u, v, the acceleration estimate
   (v1 - v0) / h), K_t and M_t in the cut-matrix numbering (K_0, M_0 and the
   UPKM updates; Kc's load is the static f_t of the UPDTs), the integrator. */
typedef struct aug_dynsim {
    aug_dynp p;
    cholmod_common *cm;
    aug_cutmat Kc, Mc;
    int64_t nn, n, cap, ncap;
    int dim;
    double *u, *v, *acc, *du, *cval;   /* nodal (nn*dim); cval: prescribed value or NAN */
    double *xu, *xv, *zero;            /* matrix-numbered scratch (n) */
    double *Mv, *Ku;                   /* M_t v, K_t u of the state (n) ... */
    int fresh;                         /* ... valid: no step since the last advance */
    int32_t *idof;                     /* matrix index -> DOF */
    int64_t *ep;                       /* node -> element incidence */
    int32_t *ei;
    int32_t *elist, *estamp, stamp;    /* elements holding a moving constrained DOF */
    int32_t frame;
    double time, kinetic, potential, work;
} aug_dynsim;
int aug_dynsim_init(aug_dynsim *d, const aug_dynp *p, const cholmod_sparse *K0,
                    const cholmod_sparse *M0, const double *f0, cholmod_common *cm, aug_err *e);
void aug_dynsim_free(aug_dynsim *d);
/* At rest on the replay's mesh (u = the prescribed values, v = 0) or from a
   frame over every node (init). */
int aug_dynsim_start(aug_dynsim *d, const struct aug_replay *rp, const aug_frame *init, aug_err *e);
/* A step: K and M updated by u->EK, u->EM (AMPS eq. 3.1 form), the nnew new
   nodes of the replay's mesh take the state of their parents. */
int aug_dynsim_step(aug_dynsim *d, const aug_update *u, const struct aug_replay *rp,
                    const int32_t *parent, int64_t nnew, aug_err *e);
/* b (order of A_t) of one frame (aug_dyn.h): h M_t v0 + gamma h^2 (f_t - K_t u0)
   on free rows, the increment to the prescribed value on constrained ones, and
   the coupling to constrained DOFs that move (value != u0, or v0 != 0) added
   element by element. */
int aug_dynsim_rhs(aug_dynsim *d, const struct aug_replay *rp, double *b, aug_err *e);
/* The frame's solution dx of A_t dx = b: u, v advanced (aug_dynp_velocity),
   frame and time counted, kinetic (1/2 v'Mv), potential (1/2 u'Ku) and the
   load's work f'u over the free DOFs. */
int aug_dynsim_advance(aug_dynsim *d, const struct aug_replay *rp, const double *dx, aug_err *e);

#endif
