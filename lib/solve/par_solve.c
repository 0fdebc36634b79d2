/* Supernodal triangular solves Ls x = b and Ls' x = b for one right-hand
   side on two threads over the split of par_split.c, each supernode computed
   as cholmod_super_lsolve / ltsolve compute it: Ls' x = b is bitwise the
   serial solve (a supernode reads only its ancestors' final x), Ls x = b
   equal to rounding (the top rows' updates from below are summed from zero,
   then added). Paper 001 sec. 3.6 parallelizes AMPS steps 1-4 and leaves the
   final back-substitution (step 6, ~80% of a brain step by its fig. 8, the
   c |L| of eq. 3.34) serial; this is its two-core form (issue 15 item 4). */
#include <stdatomic.h>
#include <stdlib.h>
#include <cblas.h>
#include "aug_par.h"
#include "aug_solve.h"


/* x1 := L1^-T (x1 - L2' x(rows)): supernode s of L' x = b, which reads x only
   on the supernode's rows, its etree ancestors (paper 000 thm 2). pre: its
   first pre columns only, the others given (final) as rows of the first
   pre: x(0:pre) := T^-T (x(0:pre) - A(pre:nscol, 0:pre)' x(pre:nscol) -
   L2(:, 0:pre)' x(rows)); pre = nscol is the whole supernode, 0 nothing */
static void lt_super(const cholmod_factor *L, int32_t s, int pre, double *x, double *e)
{
    const int *sup = L->super, *pi = L->pi, *px = L->px, *rows = L->s;
    const double *A = (const double *)L->x + px[s];
    int k1 = sup[s], nscol = sup[s + 1] - k1, nsrow = pi[s + 1] - pi[s], nb = nsrow - nscol;
    if (pre <= 0) return;
    const int *rs = rows + pi[s] + nscol;
    for (int i = 0; i < nb; i++) e[i] = x[rs[i]];
    cblas_dgemv(CblasColMajor, CblasTrans, nb, pre, -1.0, A + nscol, nsrow, e, 1, 1.0, x + k1, 1);
    if (pre < nscol)
        cblas_dgemv(CblasColMajor, CblasTrans, nscol - pre, pre, -1.0, A + pre, nsrow, x + k1 + pre, 1,
                    1.0, x + k1, 1);
    cblas_dtrsv(CblasColMajor, CblasLower, CblasTrans, CblasNonUnit, pre, A, nsrow, x + k1, 1);
}

/* x1 := L1^-1 x1, x(rows) := x(rows) - L2 x1: supernode s of L x = b. The
   rows from i0 on (in top, shared by all tasks) are not touched: their
   update 0 - L2 x1 goes to dst, added later in supernode order. */
static void l_super(const cholmod_factor *L, int32_t s, double *x, double *e, int i0, double *dst)
{
    const int *sup = L->super, *pi = L->pi, *px = L->px, *rows = L->s;
    const double *A = (const double *)L->x + px[s];
    int k1 = sup[s], nscol = sup[s + 1] - k1, nsrow = pi[s + 1] - pi[s], nb = nsrow - nscol;
    const int *rs = rows + pi[s] + nscol;
    for (int i = 0; i < i0; i++) e[i] = x[rs[i]];
    for (int i = i0; i < nb; i++) e[i] = 0;
    cblas_dtrsv(CblasColMajor, CblasLower, CblasNoTrans, CblasNonUnit, nscol, A, nsrow, x + k1, 1);
    cblas_dgemv(CblasColMajor, CblasNoTrans, nb, nscol, -1.0, A + nscol, nsrow, x + k1, 1, 1.0, e, 1);
    for (int i = 0; i < i0; i++) x[rs[i]] = e[i];
    for (int i = i0; i < nb; i++) dst[i - i0] = e[i];
}

typedef struct job {
    const aug_par_plan *pl;
    const cholmod_factor *L;
    double *x, *e, *defer;
    int64_t elen;        /* per-thread length of e */
    const int *pre;      /* L': columns of each supernode to compute (NULL: all) */
    int sys;
    atomic_int next;     /* the next task to take */
} job;

/* thread t takes tasks (subtrees below top) until none is left, each as
   the serial solve does it: L' in decreasing, L in increasing supernode
   order; a task's supernodes read and write x only on the task's columns
   and their ancestors in top (read for L', deferred for L) */
static void run_tasks(void *arg, int t)
{
    job *j = arg;
    const aug_par_plan *pl = j->pl;
    const int *sup = j->L->super, *pi = j->L->pi;
    double *e = j->e + (int64_t)t * j->elen;
    for (;;) {
        int k = atomic_fetch_add(&j->next, 1);
        if (k >= pl->ntask) return;
        const int32_t *list = pl->task_s + pl->task_p[k];
        int64_t len = pl->task_p[k + 1] - pl->task_p[k];
        if (j->sys == AUG_PAR_LT) {
            for (int64_t q = len - 1; q >= 0; q--) {
                int32_t s = list[q];
                lt_super(j->L, s, j->pre ? j->pre[s] : sup[s + 1] - sup[s], j->x, e);
            }
            continue;
        }
        for (int64_t q = 0; q < len; q++) {
            int32_t s = list[q];
            int nb = pi[s + 1] - pi[s] - (sup[s + 1] - sup[s]);
            int i0 = pl->defer_i0[s] >= 0 ? pl->defer_i0[s] : nb;
            l_super(j->L, s, j->x, e, i0, i0 < nb ? j->defer + pl->defer_at[s] : NULL);
        }
    }
}

/* after the tasks of L x = b: every supernode in increasing order, a top
   one computed, a task one's deferred updates x(rows) += dst added (x(rows)
   - L2 x1 = x(rows) + (0 - L2 x1): the order and operands of the serial
   solve) */
static void l_top(const job *j)
{
    const aug_par_plan *pl = j->pl;
    const int *sup = j->L->super, *pi = j->L->pi, *rows = j->L->s;
    int64_t next = 0;
    for (int64_t s = 0; s < pl->nsuper; s++) {
        if (next < pl->ntop && pl->top[next] == s) {
            l_super(j->L, (int32_t)s, j->x, j->e, pi[s + 1] - pi[s] - (sup[s + 1] - sup[s]), NULL);
            next++;
            continue;
        }
        if (pl->defer_i0[s] < 0) continue;
        int nscol = sup[s + 1] - sup[s], nb = pi[s + 1] - pi[s] - nscol, i0 = pl->defer_i0[s];
        const int *rs = rows + pi[s] + nscol;
        const double *d = j->defer + pl->defer_at[s];
        for (int i = i0; i < nb; i++) j->x[rs[i]] += d[i - i0];
    }
}

/* aug_par_super_solve with pre (AUG_PAR_LT: per supernode the leading
   columns computed, the rest given; NULL: all) */
static int super_solve(aug_par *p, const aug_par_plan *pl, const cholmod_factor *Ls, int sys,
                       const int *pre, double *x)
{
    int ns = (int)Ls->nsuper;
    const int *sup = Ls->super, *pi = Ls->pi;
    if (!p || !pl) {
        double *e = aug_malloc(((size_t)Ls->maxesize + 1) * sizeof *e);
        if (!e) return -1;
        if (sys == AUG_PAR_LT)
            for (int s = ns - 1; s >= 0; s--) lt_super(Ls, s, pre ? pre[s] : sup[s + 1] - sup[s], x, e);
        else
            for (int s = 0; s < ns; s++) l_super(Ls, s, x, e, pi[s + 1] - pi[s] - (sup[s + 1] - sup[s]), NULL);
        free(e);
        return 0;
    }
    job j = {pl, Ls, x, NULL, NULL, pl->tmpmax + 1, pre, sys, 0};
    int nt = aug_par_nthreads(p);
    j.e = aug_par_buf(p, 0, (size_t)nt * (size_t)j.elen);
    if (sys == AUG_PAR_L) j.defer = aug_par_buf(p, 2, (size_t)pl->ndefer + 1);
    if (!j.e || (sys == AUG_PAR_L && !j.defer)) return -1;
    atomic_init(&j.next, 0);
    /* one BLAS thread inside each worker: a threaded dgemv would split the
       sums differently from the serial solve's */
    int nblas = aug_blas_threads(1);
    if (sys == AUG_PAR_LT) {
        /* the top part first (the ancestors of every task), then the tasks */
        for (int64_t k = pl->ntop - 1; k >= 0; k--) {
            int32_t s = pl->top[k];
            lt_super(Ls, s, pre ? pre[s] : sup[s + 1] - sup[s], x, j.e);
        }
        aug_par_run(p, run_tasks, &j);
    } else {
        aug_par_run(p, run_tasks, &j);
        l_top(&j);
    }
    aug_blas_threads(nblas);
    return 0;
}

int aug_par_super_solve(aug_par *p, const aug_par_plan *pl, const cholmod_factor *Ls, int sys,
                        double *x)
{
    return super_solve(p, pl, Ls, sys, NULL, x);
}

/* x := L^-T y off an etree closure C whose values x_C are given (final):
   the columns outside C are the leading pre[s] of each supernode s
   (aug_ldl_closure_pre); there x = Ls^-T (D^1/2 y) with x_C read where
   their rows meet (paper 000 thm 2: the rest of the back-substitution
   needs C only through its final values). On the pool when p and the
   base's plan are there, else on the caller; 0 or -1 (memory) */
int aug_par_ltsolve_rest(aug_par *p, const aug_base *b, const int *pre, const double *y, double *x)
{
    const int *sup = b->Ls->super;
    for (int64_t s = 0; s < (int64_t)b->Ls->nsuper; s++)
        for (int j = sup[s]; j < sup[s] + pre[s]; j++) x[j] = y[j] * b->sqrtd[j];
    return super_solve(p, p ? b->par_plan : NULL, b->Ls, AUG_PAR_LT, pre, x);
}

/* x := L^-T x = Ls^-T (D^1/2 x), as aug_ldl_ltsolve_all, over the split of
   b->par_plan on the pool p; 1 (x untouched) without a pool, Ls or plan */
int aug_par_ltsolve_all(aug_par *p, const aug_base *b, double *x)
{
    const aug_par_plan *pl = b->par_plan;
    if (!p || !b->Ls || !pl) return 1;
    if (!aug_par_buf(p, 0, (size_t)aug_par_nthreads(p) * ((size_t)pl->tmpmax + 1))) return -1;
    for (int64_t k = 0; k < b->n; k++) x[k] *= b->sqrtd[k];
    return aug_par_super_solve(p, pl, b->Ls, AUG_PAR_LT, x);
}

/* x = K_b^-1 rhs = P' Ls^-T Ls^-1 P rhs (cholmod_solve2's CHOLMOD_A on Ls)
   with both solves over the split; 1 without a pool, Ls or plan */
int aug_par_full_solve(aug_par *p, const aug_base *b, const double *rhs, double *x)
{
    const aug_par_plan *pl = b->par_plan;
    if (!p || !b->Ls || !pl) return 1;
    double *w = aug_par_buf(p, 3, (size_t)b->n + 1);
    if (!w) return -1;
    for (int64_t k = 0; k < b->n; k++) w[k] = rhs[b->perm[k]];
    if (aug_par_super_solve(p, pl, b->Ls, AUG_PAR_L, w) || aug_par_super_solve(p, pl, b->Ls, AUG_PAR_LT, w))
        return -1;
    for (int64_t k = 0; k < b->n; k++) x[b->perm[k]] = w[k];
    return 0;
}
