/* Two-core supernodal triangular solves: a persistent thread pool, the split
   of the supernodal elimination tree into a top part and two independent
   subtree sets, and the solves over it (lib/solve/par_*.c). */
#ifndef AUG_PAR_H
#define AUG_PAR_H
#include <stdint.h>
#include <cholmod.h>
#include "aug_solve.h"

/* ---- persistent pool (par_pool.c) --------------------------------------- */

typedef struct aug_par aug_par;
/* one job: fn(arg, t) for every thread t = 0..n-1 (t = 0: the caller) */
typedef void (*aug_par_fn)(void *arg, int t);
/* A pool of nthreads threads, the caller included (nthreads - 1 workers that
   wait on a condition variable between jobs); NULL when nthreads < 2 or the
   threads cannot be started. */
aug_par *aug_par_new(int nthreads);
void aug_par_free(aug_par *p);
int aug_par_nthreads(const aug_par *p);
/* runs the job on all threads, returns when every one has finished */
void aug_par_run(aug_par *p, aug_par_fn fn, void *arg);
/* the pool's scratch block k (0 <= k < AUG_PAR_NBUF) of at least n doubles,
   kept across jobs; NULL when out of memory. Caller's thread only. */
enum { AUG_PAR_NBUF = 4 };
double *aug_par_buf(aug_par *p, int k, size_t n);

/* ---- etree split (par_split.c) ------------------------------------------ */

/* The supernodes of Ls in three sets: top (the supernodes above the split,
   the ancestors of everything else) and two bins of whole subtrees, no
   supernode of one bin an ancestor or descendant of one of the other. Each
   list is in increasing supernode order. w*: entries of Ls each set reads.
   The solves hand the subtrees out as tasks, not as the fixed bins: a
   thread the system does not schedule then leaves its share to the other. */
typedef struct aug_par_plan {
    int64_t nsuper;
    int32_t ntop, nbin[2];
    int32_t *top, *bin[2];
    /* per supernode of a bin: its rows below the diagonal block from
       defer_i0[s] on lie in top supernodes (a suffix: ancestors ascend), and
       their updates of the forward solve wait at defer_at[s] in a buffer of
       ndefer entries; -1 for top supernodes */
    int32_t *defer_i0;
    int64_t *defer_at;
    int64_t ndefer;
    int64_t tmpmax;      /* max rows below the diagonal block of a supernode */
    double wtop, wbin[2];
    /* the tasks the threads take in turn (par_solve.c): the subtrees below
       top, heaviest first; task k is task_s[task_p[k] .. task_p[k+1]),
       ascending. bin[] is the static two-way estimate the split minimizes. */
    int32_t ntask;
    int64_t *task_p;
    int32_t *task_s;
} aug_par_plan;

/* The split that minimizes wtop + max(wbin) by expanding the heaviest
   subtree root into the top part (a greedy of nested dissection trees);
   NULL when Ls is not supernodal, out of memory, or no split gains. */
aug_par_plan *aug_par_plan_new(const cholmod_factor *Ls);
/* b->par_plan = the split of b->Ls, once, for a base solved on a pool (its
   greedy costs 3-6 ms on the 2-D square's 5k DOFs: a one-thread run never
   builds it); a NULL plan (no split, or out of memory): serial solves */
void aug_base_split(aug_base *b);
void aug_par_plan_free(aug_par_plan *pl);

/* ---- solves (par_solve.c) ----------------------------------------------- */

enum { AUG_PAR_L = 0, AUG_PAR_LT = 1 };
/* x := Ls^-1 x (AUG_PAR_L) or Ls^-T x (AUG_PAR_LT), supernode by supernode
   as cholmod_super_lsolve / ltsolve do for one right-hand side; with p (and a
   plan) the subtrees below top on the pool's threads, bitwise the same
   result for Ls' (for Ls, updates of top rows from below are summed in
   another order: equal to rounding). p or pl NULL:
   on the caller alone. 0, or -1 when out of memory (x unchanged). */
int aug_par_super_solve(aug_par *p, const aug_par_plan *pl, const cholmod_factor *Ls, int sys,
                        double *x);
/* x := L^-T x = Ls^-T (D^1/2 x) (aug_ldl_ltsolve_all) on the pool with the
   base's plan: 0, -1 out of memory (x untouched), 1 no pool, Ls or plan
   (x untouched: the caller solves serially) */
int aug_par_ltsolve_all(aug_par *p, const aug_base *b, double *x);
/* x := L^-T y off an etree closure C of the base's Ls whose final values
   x_C are given; pre[s]: the leading columns of supernode s outside C
   (aug_ldl_closure_pre). On the pool (with the base's plan) when p is set,
   else serially; 0 or -1 (memory) */
int aug_par_ltsolve_rest(aug_par *p, const aug_base *b, const int *pre, const double *y, double *x);
/* x = K_b^-1 rhs with both supernodal solves on the pool: 0, -1, 1 as above */
int aug_par_full_solve(aug_par *p, const aug_base *b, const double *rhs, double *x);

#endif
