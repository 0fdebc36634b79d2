/* augcut coupled saddle-point solvers (paper 004 eq. 15 and 18): sub-domain
   blocks A_b (sparse FE or dense reduced) coupled by Lagrange multipliers,
   solved by the dual Schur complement (direct) or by projected PCG with the
   Schilders constraint preconditioner (paper 004 sec. 5.3). No mesh knowledge. */
#ifndef AUG_SADDLE_H
#define AUG_SADDLE_H

#include <cholmod.h>
#include "aug_stream.h"

/* The system. Unknowns x = [x_0; ...; x_{nb-1}], block b of size n_b,
   N = sum n_b; multipliers lambda (m = C->nrow):
       A x + C' lambda = r,   C x = g,   A = blockdiag(A_b), A_b SPD.
   Contract on C (m x N). A column is "private" when it holds exactly one
   nonzero of C; a row holding a private column is a private row. Private rows
   are linearly independent of each other and of all other rows and are kept
   exactly. The remaining rows D (in the modal tool: rows between two reduced
   blocks, dense over reduced columns) may be dependent, even inconsistent:
   they are replaced by their row space. With the thin SVD C_D = U S V' of
   that row block, the kept rank k counts s_i > AUG_SADDLE_RTOL * s_1 and the
   compressed constraints are C_k x = U_k' g_D, C_k = U_k' C_D = S_k V_k'.
   The solvers solve the compressed system (mc = m_private + k rows, full row
   rank) exactly: constraints exact where independent, least squares on D,
   and minimum-energy over the rest. lambda is returned in the original rows:
   lambda_P as solved, lambda_D = U_k mu (the minimum-norm multiplier with
   C' lambda = C_k' mu). */
/* 1e-8, not round-off: between two snapshot bases the interface rows have
   singular values trailing off to 1e-12 and below (measured on the cube of
   paper 004: 1, ..., 5.8e-5, 2.6e-12, 1.2e-14); a direction at s_i ~ 1e-12 s_1
   is one the bases cannot follow without amplifying rounding by 1/s_i, and a
   cut there would make the rank (and the frames) depend on the last bits. */
#define AUG_SADDLE_RTOL 1e-8

typedef struct aug_sblock {
    int64_t n;
    cholmod_sparse *A;   /* FE block: n x n, stype > 0 (upper stored), sorted, packed; or NULL */
    const double *Ad;    /* reduced block: n x n dense SPD, column-major (lower triangle read); or NULL */
    uint64_t version;    /* the caller changes it whenever A/Ad or this block's columns of C change */
} aug_sblock;

typedef struct aug_saddle_stats {
    int iters, converged, rank;  /* iters: ppcg iterations (schur: 0); rank: k, rows of D kept */
    int mc;                      /* compressed rows m_private + k */
    double relres;               /* ||[A C_c';C_c 0][x;mu] - [r;g_c]|| / ||[r;g_c]|| (compressed) */
    double gap;                  /* ||C x - g|| with the original C, g */
    double prep_ms, solve_ms;    /* lazy factorisation / Schur build in this call; the solve */
    int64_t nfactor;             /* block factorisations done since init (cumulative) */
    int64_t ncontrib;            /* block Schur contributions computed since init (cumulative) */
} aug_saddle_stats;

/* Per-block state (internal). */
typedef struct aug_sblk {
    aug_sblock d;                /* the descriptor of the last set */
    int64_t off;                 /* first unknown in x */
    int have;                    /* a descriptor has been seen */
    int fact_ok;                 /* L / Lc hold the factor of version d.version */
    cholmod_factor *L;           /* FE: CHOLMOD factor */
    double *Lc;                  /* reduced: lower Cholesky factor, n x n */
    double *diag;                /* diag(A_b), n */
    cholmod_dense *X, *Y, *E;    /* cholmod_solve2 workspaces */
    int sc_ok;                   /* Sb valid for the current compressed rows */
    int nr;                      /* compressed rows touching the block */
    int *rows;                   /* their compressed indices, ascending */
    double *Sb;                  /* nr x nr: C_c,b A_b^-1 C_c,b' */
    int touches_d;               /* the block has columns in the compressed rows */
    int *sig_p, *sig_c;          /* signature of the block's private-row entries: */
    double *sig_x;               /* row-wise (col - off, value), rows in C's order */
    int sig_n;                   /* rows in the signature */
} aug_sblk;

typedef struct aug_saddle {
    cholmod_common *cm;
    int nb, nbcap;
    aug_sblk *blk;
    int64_t N;
    int m;                       /* rows of C */
    cholmod_sparse *C;
    int c_ok;                    /* the analysis below belongs to C */
    /* private rows (compressed rows 0..mp-1, in C's row order) */
    int mp;
    int *prow;                   /* their row in C */
    int64_t *pslave;             /* slave column (largest |entry| among the private ones) */
    double *pdiag;               /* C(prow, pslave) */
    int *pp; int64_t *pj; double *px;   /* CSR of the private rows */
    /* remaining rows D, compressed to k rows (compressed rows mp..mp+k-1) */
    int md, nd, k;
    int *drow;                   /* their row in C */
    int64_t *dcol;               /* columns of C touched by D, ascending */
    double *Uk;                  /* md x k */
    double *Ck;                  /* k x nd: S_k V_k' */
    int64_t *dslave;             /* k slave columns (QR column pivoting of Ck) */
    double *Rq, *Rr;             /* R = Ck(:, dslave) = Rq Rr: Rq k x k orthogonal, Rr upper */
    int nx; int *xi, *xj; double *xv;   /* X = entries of private rows on dense slave columns */
    int mc;                      /* mp + k */
    int64_t *slave_of;           /* N: C1 index of a slave column, -1 otherwise */
    double *ginv;                /* N: 1 / diag(A) on non-slaves, 0 on slaves */
    /* Schur complement (lazy) */
    int S_ok;
    double *S;                   /* mc x mc lower Cholesky factor */
    /* workspaces */
    double *w[8];                /* N each */
    double *u[6];                /* max(m, mc) each */
    int64_t nfactor, ncontrib;
} aug_saddle;

/* Empty state; cm started by the caller (aug_cholmod_start), kept by pointer. */
int aug_saddle_init(aug_saddle *s, cholmod_common *cm, aug_err *e);
void aug_saddle_free(aug_saddle *s);
/* The system for the next solves: nb block descriptors (copied; matrices stay
   the caller's and must live until the next set), C (m x N, stype 0, kept by
   pointer; NULL means m = 0). c_changed = 1 when C's pattern or values changed
   (a different pointer counts as changed). Blocks whose version (and n) is
   unchanged keep their factorisation and, when the block's entries in the
   private rows are the same (rows may be renumbered) and it has no column in
   D, their Schur contribution. The compression and slave selection are
   redone when C or a block descriptor changes (a block's columns of C may
   have): O(nnz(C) + md nd min(md, nd) + k^2 nd). On failure the state needs
   a new successful set before the next solve. Checks sizes
   (AUG_EUSAGE) and diag(A_b) > 0 (AUG_ESINGULAR); factorisations are done by
   the first aug_saddle_schur that needs them. */
int aug_saddle_set(aug_saddle *s, int nb, const aug_sblock *b, cholmod_sparse *C, int c_changed,
                   aug_err *e);
/* Direct solve by the dual Schur complement S = sum_b C_c,b A_b^-1 C_c,b'
   (dense mc x mc; per-block contributions cached; FE blocks by chunked
   multi-right-hand-side CHOLMOD solves over the block's rows of C_c), dense
   Cholesky of S, mu = S^-1 (C_c A^-1 r - g_c), x = A^-1 (r - C_c' mu).
   Per solve after the first: two solves per block, O(nnz(C) + mc^2) (and
   one A apply for st->relres). g may be NULL (0); lambda (m) may be NULL.
   AUG_ESINGULAR when a block or S is not positive definite. */
int aug_saddle_schur(aug_saddle *s, const double *r, const double *g, double *x, double *lambda,
                     aug_saddle_stats *st, aug_err *e);
/* Projected PCG (Gould, Hribar & Nocedal, SIAM J. Sci. Comput. 23 (2001),
   with their residual update; paper 004 sec. 5.3, algorithms 1-3) with the
   constraint preconditioner P = [G C_c'; C_c 0], G = diag(A) except G11 = 0 on
   the slave unknowns (Schilders factorisation, Dollar, Gould, Schilders &
   Wathen, SIMAX 28 (2006)). warm = 0: start from x = 0, lambda = 0; warm = 1:
   from the given x and lambda (NULL: 0; x need not be feasible). g may be
   NULL (0), lambda NULL when not wanted. Every iterate satisfies
   C_c x = g_c up to round-off. Stops at relres <= tol (checked on the true residual) or after
   maxit iterations: then x, lambda hold the last iterate, st->converged = 0
   and AUG_ENOCONV is returned. Per iteration: one A apply (sparse product
   per FE block, dense symv per reduced block) and O(nnz(C) + k nd + k^2).
   AUG_ESINGULAR when A is not positive definite on the constraint null space. */
int aug_saddle_ppcg(aug_saddle *s, const double *r, const double *g, double *x, double *lambda,
                    double tol, int maxit, int warm, aug_saddle_stats *st, aug_err *e);

/* Shared by lib/modal/saddle*.c (not for tools). */
/* y = A x (all blocks); 0 or AUG_ENOMEM */
int aug_saddle_apply_A(aug_saddle *s, const double *x, double *y, aug_err *e);
/* y (mc) = C_c x */
void aug_saddle_cc(const aug_saddle *s, const double *x, double *y);
/* x (N) += C_c' y */
void aug_saddle_cct(const aug_saddle *s, const double *y, double *x);
/* g_c (mc) from g (m); lambda (m) from mu (mc) and back (mu = T lambda) */
void aug_saddle_compress(const aug_saddle *s, const double *g, double *gc);
void aug_saddle_expand(const aug_saddle *s, const double *mu, double *lambda);
/* stats->relres (compressed) and ->gap (original) of (x, mu); uses the
   workspaces w[6], u[4], u[5] of s (one A apply, O(nnz(C))) */
int aug_saddle_residuals(aug_saddle *s, const double *r, const double *g, const double *gc,
                         const double *x, const double *mu, aug_saddle_stats *st, aug_err *e);

#endif
