/* The solve-aug session: every requested method on the same update stream,
   the shared base factor and its background replacement, per-step figures. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include "aug_solve.h"
#include "aug_par.h"

const char *const aug_method_names[AUG_M_COUNT] = {"amps", "gmres", "refactor", "rowupdate", "pcg",
                                                   "auto", "cgm-cov", "cgm-es", "cgm-log", "cgm-as"};

int aug_method_index(const char *name, size_t len)
{
    for (int m = 0; m < AUG_M_COUNT; m++)
        if (strlen(aug_method_names[m]) == len && !strncmp(name, aug_method_names[m], len)) return m;
    return -1;
}

int aug_methods_parse(const char *s, int order[AUG_M_COUNT], char why[64])
{
    int n = 0;
    for (const char *p = s;; p += strcspn(p, ",") + 1) {
        size_t len = strcspn(p, ",");
        int found = aug_method_index(p, len);
        if (!len) return snprintf(why, 64, "an empty method name"), -1; /* "amps," or ",amps" */
        if (found < 0) return snprintf(why, 64, "an unknown method"), -1;
        for (int i = 0; i < n; i++)
            if (order[i] == found) return snprintf(why, 64, "%s given twice", aug_method_names[found]), -1;
        order[n++] = found; /* at most AUG_M_COUNT: a repeat is refused above */
        if (!p[len]) return n;
    }
}

int aug_parse_methods(const char *s, int order[AUG_M_COUNT])
{
    char why[64];
    return aug_methods_parse(s, order, why);
}

const char *aug_solver_opts_conflict(const aug_solver_opts *o)
{
    int has_auto = 0, has_based = 0;
    for (int i = 0; i < o->nmeth; i++) {
        has_auto |= o->order[i] == AUG_M_AUTO;
        has_based |= o->order[i] == AUG_M_AMPS || o->order[i] == AUG_M_GMRES;
    }
    return has_auto && has_based ? "--method auto re-factors the base of amps and gmres: run it apart" : NULL;
}

void aug_solver_opts_default(aug_solver_opts *o)
{
    memset(o, 0, sizeof *o);
    o->nmeth = 1;
    o->order[0] = AUG_M_AUTO;
    o->horizon = -1; /* the stream's pLAN */
    o->tol = 1e-8;
    o->maxit = 10000;
    o->restart = 100;
    o->gmres_prec = AUG_PREC_D;
    o->spare = 3000;
    /* rcond(S2) scales with cond(K): on a cantilever of cond 1e12 a regular
       step has rcond ~1e-17, so singularity is judged by det S2 <= 0 and by
       the residual reached, not by rcond */
    o->rcond_min = 0;
    o->refine_tol = 1e-8;
    o->refine_max = 3;
    o->fail_tol = 1e-6;
    o->amps_target = 1e-12;
    o->nthreads = 1;
    aug_cgm_opts_default(&o->cgm);
    o->pcg_prec = AUG_PCG_JACOBI;
    o->amps_correct = 2;
}

struct aug_solver {
    aug_solver_opts o;
    cholmod_common *cm;
    aug_cutmat cut;
    aug_base *base;
    aug_cum cum;
    aug_amps amps;
    aug_gmres *gm;
    aug_refactor rf;
    aug_rowupd *ru;
    aug_bg *bg;
    int use[AUG_M_COUNT];
    double *field[AUG_M_COUNT];
    int64_t fcap, pcg_n;
    double *pcg_x, *f, *ref, *tmp, *tmp2;
    aug_kv stat[AUG_M_COUNT], time[AUG_M_COUNT];
    cholmod_dense *fB, *fX, *fY, *fE; /* full-solve timing workspaces */
    int singular[AUG_M_COUNT], converged[AUG_M_COUNT], frame_singular[AUG_M_COUNT];
    int32_t step;
    int bg_unsolved;     /* a method did not solve the background job's step */
    /* dynamics (aug_solver_frame): pcg's assembled A_t, the --check reference
       factor and AMPS's fallback factor of the step */
    cholmod_sparse *pcg_K;
    aug_refactor chk, amps_fb;
    int chk_ok, amps_fb_ok, prepped;
    aug_cgm_res cgm[AUG_CGM_COUNT]; /* the cgm-* methods' figures of the step */
    double pcg_shift;               /* pcg --pcg-prec ic: the IC(0) shift used */
    /* --method auto: its cost model and re-factorizations (AMPS on the
       session's base, which it re-factors) */
    aug_auto au;
    aug_refactor au_rf;
    int au_swapped;      /* the background factor became the base this step */
    aug_par *par;        /* --threads >= 2: the two-core L^-T of AMPS (aug_par.h) */
    int nblas;           /* OpenBLAS's threads outside the steps (0: not lowered) */
    int64_t nstep;       /* steps taken (aug_solver_step calls), this one included */
    int32_t plan_last;   /* the stream's last cut step (pLAN), 0: unknown */
    double *ue;          /* keep_blocks: the step's E with its unit block kept */
    int64_t uecap;
    unsigned char *ukeep; /* keep_blocks: the update's keep (m bytes) */
    int64_t ukcap;
};

/* nnz(L) of the base's factor: the fill of K0's ordering, which the
   re-factorizations' extended orderings are held to (AUG_REFACTOR_FILL) */
static double base_lnz(const aug_base *b)
{
    double nz = 0;
    for (int64_t j = 0; j < b->n; j++) nz += b->Lnz[j];
    return nz;
}

aug_solver *aug_solver_new(const cholmod_sparse *K0, const double *f0, cholmod_factor *L0,
                           const aug_solver_opts *o, cholmod_common *cm, aug_err *e)
{
    aug_solver *s = aug_calloc(1, sizeof *s);
    if (!s) {
        cholmod_free_factor(&L0, cm);
        aug_err_set(e, AUG_ENOMEM, -1, "FACT", "out of memory");
        return NULL;
    }
    s->o = *o;
    s->cm = cm;
    aug_amps_init(&s->amps);
    aug_refactor_init(&s->rf);
    aug_refactor_init(&s->chk);
    aug_refactor_init(&s->amps_fb);
    aug_refactor_init(&s->au_rf);
    s->amps.memo.use_cholmod = o->reach_cholmod;
    s->amps.schur.want_rcond = o->check; /* a diagnostic: O(na^2) per step */
    s->par = aug_par_new(o->nthreads < 2 ? 1 : 2); /* NULL: serial */
    for (int i = 0; i < o->nmeth; i++) s->use[o->order[i]] = 1;
    for (int m = AUG_M_CGM_COV; m <= AUG_M_CGM_AS; m++)
        if (s->use[m] && o->dynamic) {
            cholmod_free_factor(&L0, cm);
            aug_err_set(e, AUG_EUSAGE, -1, "FACT", "%s solves static steps only, not a dynamic stream",
                        aug_method_names[m]);
            goto fail;
        }
    if ((int64_t)L0->n != (int64_t)K0->nrow) {
        cholmod_free_factor(&L0, cm);
        aug_err_set(e, AUG_EDATA, -1, "FACT", "factor order %lld differs from KMAT order %lld",
                    (long long)L0->n, (long long)K0->nrow);
        goto fail;
    }
    if (aug_cutmat_init(&s->cut, K0, f0, cm, e)) {
        cholmod_free_factor(&L0, cm);
        goto fail;
    }
    double tb0 = 1e3 * aug_now();
    s->base = aug_base_new(L0, K0, f0, -1, cm, e);
    if (s->base && s->par) aug_base_split(s->base);
    /* With a pool, the steps' BLAS calls (the memo, S2, small dense solves)
       run on one OpenBLAS thread: a second one would spin (sched_yield)
       between calls on the core the pool's worker needs (the brain of
       bench/organs.sh, 64 one-node AMPS steps at --threads 2: 46 ms median
       with OpenBLAS at 2, 22-25 ms with it at 1); the re-factorizations
       (aug_refactor nblas) take the threads back for their factorize. */
    if (s->par) {
        s->nblas = aug_blas_threads(1);
        s->rf.nblas = s->chk.nblas = s->amps_fb.nblas = s->au_rf.nblas = s->nblas;
    }
    double t_base0 = 1e3 * aug_now() - tb0;
    if (!s->base || aug_cum_init(&s->cum, s->base->n, e)) goto fail;
    if (aug_solver_opts_conflict(o)) {
        aug_err_set(e, AUG_EUSAGE, -1, "", "%s", aug_solver_opts_conflict(o));
        goto fail;
    }
    if (s->use[AUG_M_AUTO]) {
        /* a background job needs a free core: --background or --threads >= 2 */
        aug_auto_init(&s->au, o->background || o->nthreads >= 2);
        /* the prior of a re-factorization step: AUG_AUTO_PRIOR full solves,
           or the time the first base took when more (from a simplicial
           stream factor it is a numeric factorization of K0 on its
           ordering and the base's set-up, what a re-factor step repeats:
           sphere3 of bench/organs.sh, 50 full solves 170 ms against a
           re-factor step of 332 ms, so that the growth rule re-factored
           on too low a price) */
        s->au.t_prior = o->auto_prior > 0 ? o->auto_prior : AUG_AUTO_PRIOR * aug_solver_full_solve_ms(s, 3);
        if (!(o->auto_prior > 0) && t_base0 > s->au.t_prior) s->au.t_prior = t_base0;
        if (!(s->au.t_prior > 0)) s->au.t_prior = 0;
        if (aug_refactor_order(&s->au_rf, s->base->perm, s->base->n)) {
            aug_err_set(e, AUG_ENOMEM, -1, "FACT", "out of memory");
            goto fail;
        }
        s->au_rf.lnz_ref = base_lnz(s->base);
        s->au_rf.step_cost = 1;
    }
    /* refactor extends the ordering of K0 (README: the baselines' configuration) */
    if (s->use[AUG_M_REFACTOR] && aug_refactor_order(&s->rf, s->base->perm, s->base->n)) {
        aug_err_set(e, AUG_ENOMEM, -1, "FACT", "out of memory");
        goto fail;
    }
    s->rf.lnz_ref = base_lnz(s->base);
    if (s->use[AUG_M_GMRES]) {
        s->gm = aug_gmres_new(o->gmres_prec, o->restart, o->maxit, o->tol, e);
        if (!s->gm || aug_gmres_set_base(s->gm, s->base, s->cut.K0, e)) goto fail;
    }
    if (s->use[AUG_M_ROWUPDATE]) {
        s->ru = aug_rowupd_new(&s->cut, s->base, o->spare, cm, e);
        if (!s->ru) goto fail;
    }
    if ((o->background && (s->use[AUG_M_AMPS] || s->use[AUG_M_GMRES])) ||
        (s->use[AUG_M_AUTO] && s->au.bg_allowed)) {
        s->bg = aug_bg_new(o->nthreads, o->bg_lag > 0);
        if (!s->bg) {
            aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
            goto fail;
        }
    }
    return s;
fail:
    aug_solver_free(s);
    return NULL;
}

void aug_solver_free(aug_solver *s)
{
    if (!s) return;
    aug_bg_free(s->bg);
    aug_par_free(s->par);
    if (s->nblas > 1) aug_blas_threads(s->nblas);
    aug_amps_free(&s->amps);
    aug_gmres_free(s->gm);
    aug_refactor_free(&s->rf, s->cm);
    aug_refactor_free(&s->chk, s->cm);
    aug_refactor_free(&s->amps_fb, s->cm);
    aug_refactor_free(&s->au_rf, s->cm);
    if (s->pcg_K) cholmod_free_sparse(&s->pcg_K, s->cm);
    aug_rowupd_free(s->ru, s->cm);
    aug_base_release(s->base, s->cm);
    aug_cum_free(&s->cum);
    aug_cutmat_free(&s->cut, s->cm);
    free(s->ue);
    free(s->ukeep);
    for (int m = 0; m < AUG_M_COUNT; m++) free(s->field[m]);
    free(s->pcg_x), free(s->f), free(s->ref), free(s->tmp), free(s->tmp2);
    cholmod_dense **fw[] = {&s->fB, &s->fX, &s->fY, &s->fE};
    for (int i = 0; i < 4; i++)
        if (*fw[i]) cholmod_free_dense(fw[i], s->cm);
    free(s);
}

int64_t aug_solver_n(const aug_solver *s) { return s->cut.cum.n; }
const double *aug_solver_field(const aug_solver *s, int m) { return s->field[m]; }
const aug_kv *aug_solver_stat(const aug_solver *s, int m) { return &s->stat[m]; }
const aug_kv *aug_solver_time(const aug_solver *s, int m) { return &s->time[m]; }

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* median wall time of min(reps, 16) full solves K_b^-1 a_b with the base factor
   (cholmod_solve2 on Ls when present, else aug_ldl_solve_full): the unit of the
   "x solve" figures; NAN on failure */
double aug_solver_full_solve_ms(aug_solver *s, int reps)
{
    const aug_base *b = s->base;
    double t[16], *x = NULL, *w = NULL;
    if (reps > 16) reps = 16;
    if (b->Ls) {
        /* workspaces kept across calls, as AMPS keeps its own: the time is the
           two triangular solves, not allocation */
        if (s->fB && s->fB->nrow != (size_t)b->n) cholmod_free_dense(&s->fB, s->cm);
        if (!s->fB) {
            s->fB = cholmod_allocate_dense((size_t)b->n, 1, (size_t)b->n, CHOLMOD_REAL, s->cm);
            if (s->fB) memcpy(s->fB->x, b->a, (size_t)b->n * sizeof *x); /* any right-hand side */
        }
        if (!s->fB) reps = 0;
    } else {
        x = aug_malloc((size_t)(b->n + 1) * sizeof *x);
        w = aug_malloc((size_t)(b->n + 1) * sizeof *w);
        if (!x || !w) reps = 0;
    }
    for (int r = 0; r < reps; r++) {
        double t0 = 1e3 * aug_now();
        if (s->par && b->par_plan) { /* as AMPS solves with --threads 2 */
            if (s->fX && s->fX->nrow != (size_t)b->n) cholmod_free_dense(&s->fX, s->cm);
            if (!s->fX) s->fX = cholmod_allocate_dense((size_t)b->n, 1, (size_t)b->n, CHOLMOD_REAL, s->cm);
            if (!s->fX || aug_par_full_solve(s->par, b, s->fB->x, s->fX->x)) {
                reps = 0;
                break;
            }
        } else if (b->Ls) {
            if (!cholmod_solve2(CHOLMOD_A, b->Ls, s->fB, NULL, &s->fX, NULL, &s->fY, &s->fE, s->cm)) {
                reps = 0;
                break;
            }
        } else {
            aug_ldl_solve_full(b, b->a, x, w);
        }
        t[r] = 1e3 * aug_now() - t0;
    }
    free(x);
    free(w);
    if (reps == 0) return NAN;
    qsort(t, (size_t)reps, sizeof *t, cmp_double);
    return reps % 2 ? t[reps / 2] : 0.5 * (t[reps / 2 - 1] + t[reps / 2]);
}
int aug_solver_singular(const aug_solver *s, int m) { return s->singular[m]; }
int aug_solver_converged(const aug_solver *s, int m) { return s->converged[m]; }

static int buffers(aug_solver *s, int64_t n)
{
    if (n <= s->fcap) return 0;
    int64_t c = n * 2;
    for (int m = 0; m < AUG_M_COUNT; m++) {
        double *p = aug_realloc(s->field[m], (size_t)c * sizeof *p);
        if (!p) return -1;
        s->field[m] = p;
    }
    double **v[] = {&s->f, &s->ref, &s->tmp, &s->tmp2};
    for (int i = 0; i < 4; i++) {
        double *p = aug_realloc(*v[i], (size_t)c * sizeof *p);
        if (!p) return -1;
        *v[i] = p;
    }
    s->fcap = c;
    return 0;
}

/* a finished background factor becomes the base: the cumulative update
   shrinks to the steps after its snapshot (paper 000 fig. 1), and AMPS takes
   the state the thread prepared for them */
static int swap_base(aug_solver *s, aug_base *nb, aug_err *e)
{
    aug_base_release(s->base, s->cm);
    s->base = nb;
    if (s->par) aug_base_split(nb); /* the job split it already */
    aug_cum_free(&s->cum);
    int wr = s->amps.schur.want_rcond;
    aug_amps_free(&s->amps);
    int rc = aug_bg_take(s->bg, nb->n, &s->cum, &s->amps, e);
    s->amps.schur.want_rcond = wr;
    return rc;
}

/* the power of 2 at or above v (1 for 0 or non-finite v): dividing by it is
   exact, so a scaled norm has the bits of the unscaled one where that
   neither underflows nor overflows */
static double pow2_scale(double v)
{
    if (!(v > 0) || !isfinite(v)) return 1;
    int ex;
    frexp(v, &ex);
    return ldexp(1.0, ex);
}

/* ||x - r||_2 / ||r||_2 (||x - r||_2 when r = 0) over the entries idx[0..n)
   (idx NULL: 0..n-1), err_direct and err_out against the fresh solve; scaled
   by the largest |r_i| and |x_i|: fields of 1e-300 (E = 1e300 Pa) would
   square to 0 and read as no difference, of 1e200 to inf */
static double reldiff(const double *x, const double *r, const int32_t *idx, int64_t n)
{
    double sc = 0;
    for (int64_t t = 0; t < n; t++) {
        int64_t i = idx ? idx[t] : t;
        if (fabs(r[i]) > sc) sc = fabs(r[i]);
        if (fabs(x[i]) > sc) sc = fabs(x[i]);
    }
    sc = pow2_scale(sc);
    double d = 0, q = 0;
    for (int64_t t = 0; t < n; t++) {
        int64_t i = idx ? idx[t] : t;
        double xi = x[i] / sc, ri = r[i] / sc;
        d += (xi - ri) * (xi - ri), q += ri * ri;
    }
    return q > 0 ? sqrt(d / q) : sc * sqrt(d);
}

static void put(aug_kv *kv, const char *k, double v) { aug_kv_set(kv, k, v); }

/* ---- the methods: one row each of {step, solve, stats} ---- */

/* what the session asks of one method's step */
typedef struct step_req {
    const aug_update *u;
    const int32_t *out;  /* the output set, or NULL */
    int64_t nout;
    int full;            /* every DOF is wanted (no output set, or refinement) */
} step_req;

/* what one method's step gave */
typedef struct step_res {
    double *x;           /* the solution (its field) */
    double t[4];         /* its phase times (ms) */
    int ran;             /* the step ran (0: the step was known singular) */
    int iters, conv, sing;
    int64_t rows;        /* rowupdate: rows changed */
    int rebuilt;         /* rowupdate: factor rebuilt */
} step_res;

enum {
    M_DIRECT = 1,        /* a direct solve: refined, and failed when it stays above fail_tol */
    M_BASED = 2,         /* on the shared base factor: swaps, partial (output-set) solves */
    M_TARGET = 4         /* its residual lies on the rows K_t changed: amps_target applies */
};

typedef struct method {
    /* x = K_t^-1 f_t (on the output set when !full, for the based methods) */
    int (*step)(aug_solver *s, const step_req *q, step_res *r, aug_err *e);
    /* x = K_t^-1 b with the operator the step left (refinement, the rest of x);
       NULL: none */
    int (*solve)(aug_solver *s, const double *b, double *x, aug_err *e);
    /* the method's own sTAt and tIMe entries of the step */
    void (*stats)(const aug_solver *s, const step_res *r, aug_kv *st, aug_kv *tm);
    int flags;
    /* the per-step work of a dynamic step, without a solve (NULL: step) */
    int (*prep)(aug_solver *s, const step_req *q, step_res *r, aug_err *e);
} method;

/* the problem size of a method on the whole cut matrix: m = DOFs of K0
   changed, k = DOFs added */
static void cut_size(const aug_solver *s, aug_kv *st)
{
    put(st, "m", (double)aug_cum_morig(&s->cut.cum));
    put(st, "k", (double)(s->cut.cum.n - s->cut.n0));
}

/* The correction on H stops, and the refinement solve of --amps-target is
   not taken, once the part of the relres on the rows of H is at most
   AMPS_FLOOR times the part the other rows carry by the rounding of the
   base's back-substitution (amps_solve.c, relres_floor): the step's relres
   is then within sqrt(1 + AMPS_FLOOR^2) of what the factor allows. On the
   liver of the organs bench (base relres 6.5e-12) a fixed 4e-16 backward
   error and 1e-12 target cost a sweep on 54 of 64 steps and a refinement
   solve on many, for a relres of 1.1e-11 with or without them. */
#define AMPS_FLOOR 2.0

/* ... unless the field's cancellation (amps_solve.c, field_norms) exceeds
   AMPS_CANCEL: the rows outside S may then carry more than the floor, and the
   relres is measured (one product with K_t, no solve); the refinement solve
   is taken when it exceeds AMPS_CANCEL_REFINE times the floor with this
   step's ||x_t|| (floor_end, twice a fresh factorization's expected relres):
   within 10x of refactor's with room for the estimate's error. */
#define AMPS_CANCEL 4.0
#define AMPS_CANCEL_REFINE 2.0

/* ... and an AMPS step whose relres, refined, still exceeds AMPS_FAR times
   that floor (floor_end: twice a fresh factorization's expected relres) is
   taken by a fresh factorization, as one whose S2 is singular (run_method,
   fallback): S2 near singular (rcond 3.5e-18: a stack of E 1e3 / 1e9 / 10
   layers, nu up to 0.4999, cond(K0) 2.7e10, a piece dropped at step 6) left
   a raw relres of 3e-5 and, refined 3 times at a contraction of 0.36 each,
   1.9e-6 and 3.9e-9 on the next step, 220x that floor and 14x refactor's,
   reported as converged; with --refine-iter 3, 9.3e-7 (below fail_tol) with
   a difference of 1e-4 to a fresh solve. On the organs of bench/organs.sh
   and the armadillo the ratio stays at or below 1.9. */
#define AMPS_FAR 10.0

/* AMPS (paper 001 eqs. 3.8, 3.20-3.21): V over the reach, memoized H'K^-1H,
   dense S2, the solution on the output closure */
static int amps_step(aug_solver *s, const step_req *q, step_res *r, aug_err *e)
{
    s->amps.kt = &s->cut, s->amps.correct_max = s->o.amps_correct; /* the correction on H */
    s->amps.floor_k = AMPS_FLOOR;
    s->amps.par = s->par;
    s->amps.pivot = s->o.amps_pivot, s->amps.field_memo = s->o.amps_field_memo;
    int rc = aug_amps_step(&s->amps, s->base, &s->cum, q->full ? NULL : q->out, q->nout, s->o.rcond_min,
                           r->x, r->t, s->cm, e);
    r->sing = s->amps.schur.singular;
    return rc;
}

static int amps_prep(aug_solver *s, const step_req *q, step_res *r, aug_err *e)
{
    (void)q;
    s->amps.par = s->par;
    s->amps.pivot = s->o.amps_pivot, s->amps.field_memo = s->o.amps_field_memo;
    int rc = aug_amps_prepare(&s->amps, s->base, &s->cum, s->o.rcond_min, r->t, s->cm, e);
    r->sing = s->amps.schur.singular;
    return rc;
}

static int amps_solve(aug_solver *s, const double *b, double *x, aug_err *e)
{
    if (s->amps_fb_ok) return aug_refactor_solve(&s->amps_fb, b, x, s->cm, e);
    return aug_amps_solve_general(&s->amps, s->base, &s->cum, b, x, s->cm, e);
}

static void amps_stats(const aug_solver *s, const step_res *r, aug_kv *st, aug_kv *tm)
{
    if (!r->ran) return;
    const aug_amps *a = &s->amps;
    put(st, "m", (double)aug_cum_morig(&s->cum));
    put(st, "k", (double)(s->cum.n - s->cum.nb));
    put(st, "m_active", (double)a->schur.na);
    put(st, "m_new", (double)a->memo.m_new);
    put(st, "reach_new", (double)a->memo.reach_new);
    put(st, "closure_v", (double)a->closure_v);
    put(st, "closure_out", (double)a->nq);
    put(st, "s2_from", (double)a->schur.k0);
    if (!isnan(a->schur.rcond)) put(st, "rcond", a->schur.rcond);
    if (a->kt && a->correct_max > 0 && !isnan(a->berr_h0)) {
        put(st, "correct", a->ncorrect);
        put(st, "berr_h0", a->berr_h0), put(st, "berr_h", a->berr_h);
        put(st, "relres_h0", a->relres_h0), put(st, "relres_h", a->relres_h);
        put(st, "relres_floor", a->relres_floor);
        if (!isnan(a->cancel)) put(st, "cancel", a->cancel);
        if (a->ref_used) put(st, "ref_step", a->xref_step);
        put(tm, "correct_ms", a->t_correct);
    }
    put(st, "pivot", a->pivot_used);
    put(tm, "reach", r->t[0]), put(tm, "memo", r->t[1]), put(tm, "schur", r->t[2]), put(tm, "solve", r->t[3]);
}

/* unsymmetric augmented GMRES (paper 000) on the implicit Schur complement */
static int gmres_step(aug_solver *s, const step_req *q, step_res *r, aug_err *e)
{
    int rc = aug_gmres_step(s->gm, s->base, &s->cum, &s->cut, q->full ? NULL : q->out, q->nout, r->x, r->t, e);
    r->iters = aug_gmres_iters(s->gm);
    r->conv = aug_gmres_converged(s->gm);
    return rc;
}

static int gmres_prep(aug_solver *s, const step_req *q, step_res *r, aug_err *e)
{
    (void)q, (void)r;
    return aug_gmres_prepare(s->gm, s->base, &s->cum, &s->cut, e);
}

static int gmres_solve(aug_solver *s, const double *b, double *x, aug_err *e)
{
    return aug_gmres_solve_general(s->gm, s->base, &s->cum, &s->cut, b, x, e);
}

static void gmres_stats(const aug_solver *s, const step_res *r, aug_kv *st, aug_kv *tm)
{
    if (!r->ran) return;
    put(st, "m", (double)s->cum.ns);
    put(st, "k", (double)(s->cum.n - s->cum.nb));
    put(st, "closure_j", (double)aug_gmres_closure_j(s->gm));
    put(st, "closure_h", (double)aug_gmres_closure_h(s->gm));
    if (aug_gmres_whole(s->gm) >= 0) put(st, "whole", (double)aug_gmres_whole(s->gm));
    put(tm, "setup", r->t[0]), put(tm, "rhs", r->t[1]), put(tm, "iter", r->t[2]), put(tm, "solve", r->t[3]);
}

/* CHOLMOD re-factorization of K_t (numeric only when the pattern allows) */
static int refactor_step(aug_solver *s, const step_req *q, step_res *r, aug_err *e)
{
    (void)q;
    int rc = aug_refactor_step(&s->rf, &s->cut, r->x, r->t, s->cm, e);
    r->sing = s->rf.singular;
    return rc;
}

static int refactor_solve(aug_solver *s, const double *b, double *x, aug_err *e)
{
    return aug_refactor_solve(&s->rf, b, x, s->cm, e);
}

static void refactor_stats(const aug_solver *s, const step_res *r, aug_kv *st, aug_kv *tm)
{
    if (r->ran)
        put(st, "analyzed", s->rf.analyzed), put(st, "reordered", s->rf.reordered),
            put(st, "kept", s->rf.kept),
            put(st, "lnz", s->rf.lnz);
    cut_size(s, st);
    if (r->ran)
        put(tm, "assemble", r->t[0]), put(tm, "analyze", r->t[1]), put(tm, "factor", r->t[2]),
            put(tm, "solve", r->t[3]);
}

/* CHOLMOD row deletions / additions of the rows the step changed */
static int rowupdate_step(aug_solver *s, const step_req *q, step_res *r, aug_err *e)
{
    return aug_rowupd_step(s->ru, &s->cut, q->u, r->x, r->t, &r->rows, &r->rebuilt, &r->sing, s->cm, e);
}

static int rowupdate_solve(aug_solver *s, const double *b, double *x, aug_err *e)
{
    return aug_rowupd_solve(s->ru, s->cut.cum.n, b, x, s->cm, e);
}

static void rowupdate_stats(const aug_solver *s, const step_res *r, aug_kv *st, aug_kv *tm)
{
    if (r->ran) put(st, "rows", (double)r->rows), put(st, "rebuilt", r->rebuilt);
    cut_size(s, st);
    if (r->ran) put(tm, "update", r->t[0]), put(tm, "solve", r->t[1]);
}

/* PCG on K_t assembled, warm-started from the previous step's x (new DOFs
   0, the first step from the base solution); times: assembly, the CG
   iterations, the IC(0) factorization */
static int pcg_step(aug_solver *s, const step_req *q, step_res *r, aug_err *e)
{
    (void)q;
    int64_t n = s->cut.cum.n;
    double ta = 1e3 * aug_now();
    cholmod_sparse *K = aug_cutmat_sparse(&s->cut, 0, s->cm);
    if (!K) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    double tb = 1e3 * aug_now();
    double *xp = aug_realloc(s->pcg_x, (size_t)n * sizeof *xp);
    if (!xp) {
        cholmod_free_sparse(&K, s->cm);
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    }
    s->pcg_x = xp;
    if (s->pcg_n == 0) memcpy(xp, s->base->a, (size_t)s->base->n * sizeof *xp), s->pcg_n = s->base->n;
    for (int64_t i = s->pcg_n; i < n; i++) xp[i] = 0;
    s->pcg_n = n;
    double rr, tic;
    r->iters = aug_pcg_prec(K, s->f, NULL, 0, xp, s->o.pcg_prec, s->o.tol, s->o.maxit, &r->conv, &r->sing,
                            &rr, &s->pcg_shift, &tic, s->cm);
    cholmod_free_sparse(&K, s->cm);
    if (r->iters < 0) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "pcg: out of memory or no IC(0)");
    memcpy(r->x, xp, (size_t)n * sizeof *r->x);
    r->t[0] = tb - ta, r->t[2] = tic, r->t[1] = 1e3 * aug_now() - tb - tic;
    return 0;
}

/* a dynamic step: A_t assembled once for the step's frames */
static int pcg_prep(aug_solver *s, const step_req *q, step_res *r, aug_err *e)
{
    (void)q;
    double ta = 1e3 * aug_now();
    if (s->pcg_K) cholmod_free_sparse(&s->pcg_K, s->cm);
    if (!(s->pcg_K = aug_cutmat_sparse(&s->cut, 0, s->cm)))
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    r->t[0] = 1e3 * aug_now() - ta;
    return 0;
}

static void pcg_stats(const aug_solver *s, const step_res *r, aug_kv *st, aug_kv *tm)
{
    cut_size(s, st);
    put(st, "prec", s->o.pcg_prec);
    if (s->o.pcg_prec == AUG_PCG_IC || s->o.pcg_prec == AUG_PCG_IC_AMD) put(st, "ic_shift", s->pcg_shift);
    if (r->ran) put(tm, "assemble", r->t[0]), put(tm, "iter", r->t[1]);
    if (r->ran && (s->o.pcg_prec == AUG_PCG_IC || s->o.pcg_prec == AUG_PCG_IC_AMD)) put(tm, "ic_factor", r->t[2]);
}

/* the thesis 003 sec. 3.5 transforms (cgm_solve.c): T of K_t assembled, CG on
   T x = f_t from 0; x is the step's field, whatever it solves */
static int cgm_step(aug_solver *s, int v, step_res *r, aug_err *e)
{
    double ta = 1e3 * aug_now();
    cholmod_sparse *K = aug_cutmat_sparse(&s->cut, 0, s->cm);
    if (!K) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    r->t[0] = 1e3 * aug_now() - ta;
    int rc = aug_cgm_solve(v, K, s->f, &s->o.cgm, s->o.tol, s->o.maxit, r->x, &s->cgm[v], s->cm, e);
    cholmod_free_sparse(&K, s->cm);
    r->iters = s->cgm[v].iters, r->conv = s->cgm[v].converged;
    return rc;
}

static void cgm_stats(const aug_solver *s, int v, const step_res *r, aug_kv *st, aug_kv *tm)
{
    cut_size(s, st);
    if (!r->ran) return;
    put(tm, "assemble", r->t[0]);
    aug_cgm_put(v, &s->cgm[v], &s->o.cgm, st, tm);
}

static int cov_step(aug_solver *s, const step_req *q, step_res *r, aug_err *e) { (void)q; return cgm_step(s, AUG_CGM_COV, r, e); }
static int es_step(aug_solver *s, const step_req *q, step_res *r, aug_err *e) { (void)q; return cgm_step(s, AUG_CGM_ES, r, e); }
static int log_step(aug_solver *s, const step_req *q, step_res *r, aug_err *e) { (void)q; return cgm_step(s, AUG_CGM_LOG, r, e); }
static int as_step(aug_solver *s, const step_req *q, step_res *r, aug_err *e) { (void)q; return cgm_step(s, AUG_CGM_AS, r, e); }
static void cov_stats(const aug_solver *s, const step_res *r, aug_kv *st, aug_kv *tm) { cgm_stats(s, AUG_CGM_COV, r, st, tm); }
static void es_stats(const aug_solver *s, const step_res *r, aug_kv *st, aug_kv *tm) { cgm_stats(s, AUG_CGM_ES, r, st, tm); }
static void log_stats(const aug_solver *s, const step_res *r, aug_kv *st, aug_kv *tm) { cgm_stats(s, AUG_CGM_LOG, r, st, tm); }
static void as_stats(const aug_solver *s, const step_res *r, aug_kv *st, aug_kv *tm) { cgm_stats(s, AUG_CGM_AS, r, st, tm); }

/* --method auto: the step by the choice of the cost model (auto_policy.c),
   AMPS on the base or a synchronous re-factorization of K_t that becomes the
   base (aug_refactor_take_base; also when AMPS calls S2 singular); the background
   job, when the model asks for it, starts after the step */
static int auto_rebase(aug_solver *s, step_res *r, aug_err *e)
{
    aug_base *nb = aug_refactor_take_base(&s->au_rf, &s->cut, s->step, s->base, r->t, s->cm, e);
    if (!nb) {
        if (!s->au_rf.singular) return e->code;
        r->sing = 1;
        return 0;
    }
    aug_base_release(s->base, s->cm);
    s->base = nb;
    if (s->par) aug_base_split(nb);
    aug_cum_free(&s->cum);
    int wr = s->amps.schur.want_rcond, uc = s->amps.memo.use_cholmod;
    aug_amps_free(&s->amps);
    aug_amps_init(&s->amps);
    s->amps.schur.want_rcond = wr, s->amps.memo.use_cholmod = uc;
    if (aug_cum_init(&s->cum, nb->n, e)) return e->code;
    memcpy(r->x, nb->a, (size_t)nb->n * sizeof *r->x);
    return 0;
}

void aug_solver_plan(aug_solver *s, int32_t last_step) { s->plan_last = last_step > 0 ? last_step : 0; }

/* the steps left, this one included, when the stream's length is known:
   --horizon (a count of steps; a longer stream than said: unknown from
   there on), else the stream's pLAN (its last step number); 0: unknown */
static int64_t steps_left(const aug_solver *s)
{
    if (s->o.horizon > 0) return s->nstep <= s->o.horizon ? s->o.horizon - s->nstep + 1 : 0;
    if (s->o.horizon == 0) return 0;
    return s->plan_last >= s->step ? (int64_t)s->plan_last - s->step + 1 : 0;
}

static int auto_step(aug_solver *s, const step_req *q, step_res *r, aug_err *e)
{
    int bgr = s->bg && aug_bg_running(s->bg);
    s->amps.relres_h = s->amps.cancel = NAN; /* a re-factoring step leaves no AMPS residual */
    int64_t left = steps_left(s);
    if (aug_auto_decide(&s->au, bgr, (int64_t)q->u->m + q->u->k, left) == AUG_AUTO_AMPS) {
        if (s->au_swapped) s->au.reason = AUG_AUTO_SWAPPED;
        int rc = amps_step(s, q, r, e);
        if (rc || !r->sing || bgr) return rc; /* singular with a job running: the fallback */
        s->au.choice = AUG_AUTO_REFACTOR, s->au.reason = AUG_AUTO_SINGULAR;
        r->sing = 0;
    }
    return auto_rebase(s, r, e);
}

static void auto_stats(const aug_solver *s, const step_res *r, aug_kv *st, aug_kv *tm)
{
    const aug_auto *a = &s->au;
    if (!r->ran) return;
    /* a dynamic stream: AMPS on K0's base per step (prep_method), no model
       ran, none of its keys */
    int dyn = s->o.dynamic;
    put(st, "choice", dyn ? AUG_AUTO_AMPS : a->choice);
    put(st, "reason", dyn ? AUG_AUTO_DYNAMIC : a->reason);
    if (!dyn) {
        put(st, "on_base", a->on_base);
        /* estimates from measured times: tIMe, not sTAt (formats 7.4) */
        put(tm, "est_amps_ms", a->est_amps);
        put(tm, "est_factor_ms", a->est_factor);
        put(tm, "excess_ms", a->excess);
        if (s->o.horizon > 0 || (s->o.horizon < 0 && s->plan_last > 0)) put(st, "steps_left", (double)steps_left(s));
        put(st, "bg_start", a->want_bg);
        put(st, "est_s2_flops", a->w_next);
        put(st, "base_no", a->nbase + (a->choice == AUG_AUTO_REFACTOR));
    }
    if (dyn || a->choice == AUG_AUTO_AMPS) {
        put(st, "s2_flops", s->amps.schur.flops);
        amps_stats(s, r, st, tm);
    } else {
        put(st, "reordered", s->au_rf.reordered);
        put(st, "lnz", s->au_rf.lnz);
        put(tm, "assemble", r->t[0]), put(tm, "analyze", r->t[1]), put(tm, "factor", r->t[2]),
            put(tm, "base", r->t[3]);
    }
}

static const method methods[AUG_M_COUNT] = {
    [AUG_M_AMPS] = {amps_step, amps_solve, amps_stats, M_DIRECT | M_BASED | M_TARGET, amps_prep},
    [AUG_M_GMRES] = {gmres_step, gmres_solve, gmres_stats, M_BASED, gmres_prep},
    [AUG_M_REFACTOR] = {refactor_step, refactor_solve, refactor_stats, M_DIRECT, NULL},
    [AUG_M_ROWUPDATE] = {rowupdate_step, rowupdate_solve, rowupdate_stats, M_DIRECT, NULL},
    [AUG_M_PCG] = {pcg_step, NULL, pcg_stats, 0, pcg_prep},
    [AUG_M_CGM_COV] = {cov_step, NULL, cov_stats, 0, NULL},
    [AUG_M_CGM_ES] = {es_step, NULL, es_stats, 0, NULL},
    [AUG_M_CGM_LOG] = {log_step, NULL, log_stats, 0, NULL},
    [AUG_M_CGM_AS] = {as_step, NULL, as_stats, 0, NULL},
    [AUG_M_AUTO] = {auto_step, amps_solve, auto_stats, M_DIRECT | M_BASED | M_TARGET, amps_prep},
};

/* ---- one step of the session ---- */

/* Iterative refinement x += K_t^-1 (f_t - K_t x) with the method's own solve:
   refine_iter steps when set, else while relres > refine_tol (at most
   refine_max steps, stopping when a step does not halve it). Returns the
   number of steps or -1; *rr: the final relres. */
/* r = b - K_t x, returns ||r|| / ||b|| (absolute when b = 0); b NULL: f_t */
static double residual(aug_solver *s, const double *b, const double *x, double *r)
{
    return aug_cutmat_residual_b(&s->cut, x, b, r);
}

static int refine(aug_solver *s, const method *op, int target, const double *b, double *x, double *rr,
                  aug_err *e)
{
    int64_t n = s->cut.cum.n;
    int fixed = s->o.refine_iter > 0, it;
    if (!fixed && s->o.refine_max == 0) { /* --refine-tol 0: never */
        *rr = NAN;
        return 0;
    }
    double tol = s->o.refine_tol, once = 0; /* once: a single step above this */
    double measured = NAN;                   /* the relres, when the gate took it */
    if (!fixed && !b && target) {
        /* the residual AMPS promises on well-conditioned meshes (amps_target):
           one step when it is missed (near-detached pieces), more only above
           refine_tol. AMPS's solution is one back-substitution off the rows of
           S, so its residual lies on the rows where K_t differs from K0: below
           the limit there, no product with all of K_t is taken, unless the
           field cancels (AMPS_CANCEL: measured, refined above check) */
        once = s->o.amps_target < tol ? s->o.amps_target : 0;
        const aug_amps *a = &s->amps;
        double check = NAN; /* measured: refine above this */
        if (once > 0 && a->kt && a->correct_max > 0 && a->relres_h <= a->relres_floor) {
            if (a->cancel > AMPS_CANCEL && a->floor_end > 0) check = AMPS_CANCEL_REFINE * a->floor_end;
            once = 0;
        }
        if (check > 0) {
            measured = residual(s, b, x, s->tmp);
            if (!(measured > check)) {
                *rr = measured;
                return 0;
            }
            once = check; /* one step; more only above tol */
        } else if (aug_cutmat_relres_changed(&s->cut, x) <= (once > 0 ? once : 0.1 * tol)) {
            *rr = NAN;
            return 0;
        }
    }
    /* the residual vector (s->tmp) and its relative norm in one product */
    double r = isnan(measured) ? residual(s, b, x, s->tmp) : measured;
    for (it = 0; fixed ? it < s->o.refine_iter
                       : (r > tol || (it == 0 && once > 0 && r > once)) && it < s->o.refine_max;
         it++) {
        if (op->solve(s, s->tmp, s->tmp2, e)) return -1;
        for (int64_t i = 0; i < n; i++) x[i] += s->tmp2[i];
        double r2 = residual(s, b, x, s->tmp);
        int better = r2 < 0.5 * r;
        if (!fixed && !(r2 <= r)) { /* a step that raised the residual is taken back (auto's
                                       re-factored sphere3 step: 4.8e-11 -> 5.7e-11, err 1e-13 -> 1e-8) */
            for (int64_t i = 0; i < n; i++) x[i] -= s->tmp2[i];
            it++;
            break;
        }
        r = r2;
        if (!fixed && !better) {
            it++;
            break;
        }
    }
    *rr = r;
    return it;
}

/* method m's step was an AMPS step (amps, or auto when it chose AMPS) */
static int on_amps(const aug_solver *s, int m)
{
    return m == AUG_M_AMPS || (m == AUG_M_AUTO && s->au.choice == AUG_AUTO_AMPS);
}

/* an iterative method (pcg, gmres) is converged only where K_t's relres rr
   says so too (its own may be of another scaling: pcg at E = 1e-13 Pa with
   K_t's unit rows called 0.02 converged); 10x for the two residuals'
   rounding */
static int iter_agrees(const aug_solver *s, int m, double rr)
{
    return !(m == AUG_M_PCG || m == AUG_M_GMRES) || rr <= 10 * s->o.tol;
}

/* a solve on the output set only: the rest of x from the method's whole-vector
   solve (untimed, for the residual), the output-set values kept as solved */
static int fill_rest(aug_solver *s, int m, const method *op, const step_req *q, double *x, aug_err *e)
{
    int rc;
    if (on_amps(s, m) && !s->amps_fb_ok) {
        /* AMPS's rest as its full-field step computes it (eq. 3.20 with the
           correction on H), not by aug_amps_solve_general, which has no
           correction: on the soft armadillo of tests/solve_amps_cancel.test
           with a one-node output set the step's relres read 5e-9 and
           err_direct 9e-9 while the output itself was within 7e-12 of a
           fresh solve and a full-field step within 6e-12. The pivot history
           the output-set step left is kept. */
        aug_amps *a = &s->amps;
        double bp[2] = {a->berr_piv[0], a->berr_piv[1]};
        rc = aug_amps_field(a, s->base, &s->cum, NULL, 0, s->tmp2, s->cm, e);
        a->berr_piv[0] = bp[0], a->berr_piv[1] = bp[1];
    } else
        rc = op->solve(s, s->f, s->tmp2, e);
    if (rc) return rc;
    for (int64_t t = 0; t < q->nout; t++) s->tmp[t] = x[q->out[t]];
    memcpy(x, s->tmp2, (size_t)s->cut.cum.n * sizeof *x);
    for (int64_t t = 0; t < q->nout; t++) x[q->out[t]] = s->tmp[t];
    return 0;
}

/* x = K_t^-1 f_t by a fresh CHOLMOD factorization (the --check reference when
   refactor ran): 0 with *rr its relres when K_t is positive definite and the
   solve reaches fail_tol, 1 when it does not, -1 on error */
static int fallback(aug_solver *s, double *x, double *rr, aug_err *e)
{
    aug_refactor r;
    aug_refactor_init(&r);
    double t[4];
    int rc = aug_refactor_step(&r, &s->cut, x, t, s->cm, e);
    int sing = r.singular;
    aug_refactor_free(&r, s->cm);
    if (rc) return -1;
    if (sing) return 1;
    *rr = aug_cutmat_relres(&s->cut, x);
    return *rr <= s->o.fail_tol ? 0 : 1;
}

/* the minor page faults of the calling thread so far (tIMe minflt: the
   first touch of memory, which a step that grows arrays pays, mapped.c) */
static double minflt(void)
{
    struct rusage u;
#ifdef RUSAGE_THREAD
    if (getrusage(RUSAGE_THREAD, &u)) return NAN;
#else
    if (getrusage(RUSAGE_SELF, &u)) return NAN;
#endif
    return (double)u.ru_minflt;
}

/* method m on the step: its solution, refined where it refines, judged
   singular when detached, when its solve says so, or (a direct method) when
   its relres stays above fail_tol; its sTAt and tIMe entries */
static int run_method(aug_solver *s, int m, const step_req *q, int detached, int swapped, aug_err *e)
{
    const method *op = &methods[m];
    aug_kv *st = &s->stat[m], *tm = &s->time[m];
    int64_t n = s->cut.cum.n;
    step_res r = {.x = s->field[m], .conv = 1, .sing = detached};
    double t0 = 1e3 * aug_now(), f0 = minflt();
    int rc;
    aug_kv_init(st, aug_method_names[m]);
    aug_kv_init(tm, aug_method_names[m]);
    memset(r.x, 0, (size_t)n * sizeof *r.x);
    put(st, "n", (double)n);
    put(st, "m_step", q->u->m);
    put(st, "k_step", q->u->k);
    if (!detached) {
        r.ran = 1;
        if ((rc = op->step(s, q, &r, e))) return rc;
    }
    op->stats(s, &r, st, tm);
    int nref = 0;
    double rref = NAN; /* the relres refine() computed for x, if it did */
    if (!r.sing && q->full && op->solve && ((op->flags & M_DIRECT) || s->o.refine_iter > 0)) {
        double tr = 1e3 * aug_now();
        /* amps_target is AMPS's promise: not for auto's re-factored steps */
        if ((nref = refine(s, op, (op->flags & M_TARGET) && on_amps(s, m), NULL, r.x, &rref, e)) < 0) return e->code;
        if (nref) put(tm, "refine", 1e3 * aug_now() - tr);
        /* a refined AMPS field becomes the reference of the base's later
           steps (amps_solve.c, ref_setup): they solve for their change from
           it, whose rounding does not carry the cancellation that made this
           step refine; not with --amps-correct 0, the raw steps */
        if (nref > 0 && on_amps(s, m) && s->o.amps_correct > 0 && !s->amps_fb_ok && !s->o.dynamic && isfinite(rref) &&
            aug_amps_set_ref(&s->amps, s->base, r.x, n, s->step))
            return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    }
    double total = 1e3 * aug_now() - t0;
    if (m == AUG_M_AUTO && r.ran) aug_auto_observe(&s->au, total, s->amps.schur.flops, s->amps.schur.na);
    put(st, "iters", r.iters);
    put(st, "refine", nref);
    /* (gmres: not when its output set's round stalled and the step went
       on to the whole field, aug_gmres_whole) */
    int whole = m == AUG_M_GMRES && aug_gmres_whole(s->gm) == 1;
    double t_fill = 1e3 * aug_now();
    if (!r.sing && !q->full && !whole && (op->flags & M_BASED) && (rc = fill_rest(s, m, op, q, r.x, e))) return rc;
    t_fill = 1e3 * aug_now() - t_fill;
    double rr = r.sing ? NAN : !isnan(rref) ? rref : aug_cutmat_relres(&s->cut, r.x);
    /* a direct method that cannot reach fail_tol, even refined, met a
       numerically singular K_t: report it, never the number; a non-finite
       residual (a breakdown) is never a solution of any method */
    if (!r.sing && (((op->flags & M_DIRECT) && !(rr <= s->o.fail_tol)) || !isfinite(rr))) r.sing = 1;
    /* with an output set rr is of the field filled in apart (fill_rest):
       the method's own whole solve around the output values the step gave,
       whose error shows as residual on the rows near them (gmres on the
       liver, one round at the Schur tolerance: relres 1e-5, err_out 2e-4,
       was converged) */
    if (!r.sing && r.conv && !iter_agrees(s, m, rr)) r.conv = 0;
    /* gmres's output-set round met the Schur tolerance learnt on an earlier
       whole field, yet the field filled in around its values misses 10 tol:
       S grew since, and the values cannot be told converged (the liver of
       bench/organs.sh, 8-node steps 11 and 15 with a 7-node output set:
       relres 1.3e-7 and 4.2e-7 at tol 1e-8, called not converged, while the
       whole-field run converged every step). The rest fill_rest solved is
       then a whole field solved to tol (aug_gmres_solve_general, learning
       the Schur tolerance anew): it is the step's field, and its time and
       iterations count, as after a stalled round (gmres_aug.c) */
    if (m == AUG_M_GMRES && !r.sing && !r.conv && !q->full && !whole && aug_gmres_converged(s->gm)) {
        memcpy(r.x, s->tmp2, (size_t)n * sizeof *r.x);
        total += t_fill;
        r.iters += aug_gmres_iters(s->gm);
        put(st, "whole", 1);
        put(st, "iters", r.iters);
        rr = aug_cutmat_relres(&s->cut, r.x);
        r.conv = iter_agrees(s, m, rr);
    }
    /* AMPS far above a fresh factorization's residual, refined (AMPS_FAR) */
    int far = !r.sing && !detached && on_amps(s, m) && !s->amps_fb_ok && s->amps.floor_end > 0 && rr > AMPS_FAR * s->amps.floor_end;
    if (far) r.sing = 1;
    /* AMPS calls K_t singular where S2 is too ill-conditioned (nu -> 0.5):
       a fresh CHOLMOD factorization of K_t decides; when it is positive
       definite its solution is the step's, and sTAt says so (fallback 1) */
    if (r.sing && !detached && (m == AUG_M_AMPS || m == AUG_M_AUTO)) {
        double tf = 1e3 * aug_now();
        int fs = fallback(s, r.x, &rr, e);
        if (fs < 0) return e->code;
        if (!fs) {
            r.sing = 0, r.conv = 1;
            put(st, "fallback", far ? 2 : 1);
            put(tm, "fallback", 1e3 * aug_now() - tf);
            total += 1e3 * aug_now() - tf;
        }
    }
    put(st, "relres", r.sing ? NAN : rr);
    put(st, "converged", r.sing ? 0 : r.conv);
    put(st, "singular", r.sing);
    if (op->flags & M_BASED) {
        put(st, "swapped", swapped);
        put(st, "base_step", s->base->step);
    }
    put(tm, "time_ms", total);
    put(tm, "minflt", minflt() - f0);
    s->singular[m] = r.sing;
    s->converged[m] = !r.sing && r.conv;
    return 0;
}

/* The background job is joined once its factor is ready, or with bg_lag
   exactly bg_lag steps after its start, waiting for it if need be (a lag of
   11 swapped at step 7, 8 or 9 from run to run when the job was done sooner:
   --bg-lag promises deterministic output), and its factor becomes the base
   (*swapped). A job that
   failed because the matrix of its step is not positive definite, on a step
   some method reported singular or not converged, leaves the base as it is:
   the step said so already. Any other failure (the matrix of a step every
   method solved is not positive definite, or out of memory) is the caller's
   error. */
static int join_background(aug_solver *s, int *swapped, aug_err *e)
{
    *swapped = 0;
    if (!s->bg || !aug_bg_running(s->bg)) return 0;
    if (s->o.bg_lag > 0 ? s->step - aug_bg_step(s->bg) < s->o.bg_lag : !aug_bg_done(s->bg)) return 0;
    aug_err be;
    aug_base *nb = aug_bg_join(s->bg, &be);
    if (!nb) {
        if (be.code == AUG_ESINGULAR && s->bg_unsolved) return 0;
        *e = be;
        return e->code;
    }
    if (swap_base(s, nb, e)) return e->code;
    *swapped = 1;
    return 0;
}

/* the next background job starts from this step's matrix, with the base's
   ordering extended by the DOFs added since it ordered last; unsolved: some
   method did not solve this step (singular or not converged) */
static int start_background(aug_solver *s, int unsolved, aug_err *e)
{
    double tb = 1e3 * aug_now();
    cholmod_sparse *K = aug_cutmat_sparse(&s->cut, 0, s->cm);
    if (!K) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    int64_t nk = (int64_t)K->nrow, nb = s->base->n;
    int32_t *perm = aug_malloc((size_t)(nk + 1) * sizeof *perm);
    if (!perm) {
        cholmod_free_sparse(&K, s->cm);
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    }
    memcpy(perm, s->base->perm, (size_t)nb * sizeof *perm);
    for (int64_t i = nb; i < nk; i++) perm[i] = (int32_t)i;
    int amps = s->use[AUG_M_AMPS] || s->use[AUG_M_AUTO] ? 1 + s->o.reach_cholmod : 0;
    int rc = aug_bg_start(s->bg, K, s->f, perm, s->step, amps, e);
    free(perm);
    if (rc) {
        cholmod_free_sparse(&K, s->cm);
        return e->code;
    }
    s->bg_unsolved = unsolved;
    double tsnap = 1e3 * aug_now() - tb;
    for (int oi = 0; oi < s->o.nmeth; oi++) {
        int m = s->o.order[oi];
        if (methods[m].flags & M_BASED) put(&s->time[m], "bg_snapshot", tsnap);
    }
    return 0;
}

/* fresh CHOLMOD solve of K_t (the --check reference); 1 if K_t is not SPD */
static int direct_ref(aug_solver *s, aug_err *e)
{
    /* always its own (fresh analysis, fresh factor): refactor's field taken
       as the reference made refactor's err_direct 0 by construction and the
       others' figures depend on the method list (a sweep: amps 1.7e-14 alone,
       0 beside refactor, its field the same bits) */
    aug_refactor r;
    aug_refactor_init(&r);
    double t[4];
    int rc = aug_refactor_step(&r, &s->cut, s->ref, t, s->cm, e);
    int sing = r.singular;
    aug_refactor_free(&r, s->cm);
    return rc ? -1 : sing;
}

/* --check: every method's solution against a fresh direct solve of K_t;
   with an output set (out, the DOFs the step solved) also on those DOFs
   alone (err_out): the rest of an output-set solution is filled in for the
   residual by a wider solve (fill_rest), and err_direct mixes the two */
/* err_out of method m: its difference to s->ref on the DOFs out[0..nout) */
static void put_err_out(aug_solver *s, int m, const int32_t *out, int64_t nout, int bad)
{
    put(&s->stat[m], "err_out", bad ? NAN : reldiff(s->field[m], s->ref, out, nout));
}

static int check_direct(aug_solver *s, const int32_t *out, int64_t nout, aug_err *e)
{
    int ds = direct_ref(s, e);
    if (ds < 0) return e->code;
    for (int oi = 0; oi < s->o.nmeth; oi++) {
        int m = s->o.order[oi];
        int bad = ds || s->singular[m];
        put(&s->stat[m], "err_direct", bad ? NAN : reldiff(s->field[m], s->ref, NULL, s->cut.cum.n));
        if (out) put_err_out(s, m, out, nout, bad);
        put(&s->stat[m], "direct_spd", !ds);
    }
    return 0;
}

void aug_solver_frame_err_out(aug_solver *s, const int32_t *out, int64_t nout)
{
    if (!s->o.check) return;
    for (int oi = 0; oi < s->o.nmeth; oi++) {
        int m = s->o.order[oi];
        put_err_out(s, m, out, nout, !s->chk_ok || s->frame_singular[m]);
    }
}

/* A dynamic step (aug_solver_opts.dynamic): method m's per-step work for the
   effective matrix A_t, no solve; AMPS whose S2 it calls singular falls back
   to a CHOLMOD factorization of A_t for the step's frames (fallback 1) */
static int prep_method(aug_solver *s, int m, const step_req *q, int swapped, aug_err *e)
{
    const method *op = &methods[m];
    aug_kv *st = &s->stat[m], *tm = &s->time[m];
    step_res r = {.x = s->field[m], .conv = 1, .ran = 1};
    double t0 = 1e3 * aug_now();
    int rc;
    aug_kv_init(st, aug_method_names[m]);
    aug_kv_init(tm, aug_method_names[m]);
    put(st, "n", (double)s->cut.cum.n);
    put(st, "m_step", q->u->m);
    put(st, "k_step", q->u->k);
    memset(r.x, 0, (size_t)s->cut.cum.n * sizeof *r.x);
    if ((rc = op->prep ? op->prep(s, q, &r, e) : op->step(s, q, &r, e))) return rc;
    op->stats(s, &r, st, tm);
    s->amps_fb_ok = 0;
    if ((m == AUG_M_AMPS || m == AUG_M_AUTO) && r.sing) {
        aug_refactor_free(&s->amps_fb, s->cm);
        aug_refactor_init(&s->amps_fb);
        double t[4];
        if (aug_refactor_step(&s->amps_fb, &s->cut, s->tmp, t, s->cm, e)) return e->code;
        s->amps_fb_ok = !s->amps_fb.singular;
        r.sing = s->amps_fb.singular;
        put(st, "fallback", s->amps_fb_ok);
    }
    if (op->flags & M_BASED) {
        put(st, "swapped", swapped);
        put(st, "base_step", s->base->step);
    }
    put(st, "singular", r.sing);
    put(tm, "time_ms", 1e3 * aug_now() - t0);
    s->singular[m] = r.sing;
    s->converged[m] = !r.sing;
    return 0;
}

/* one method on one frame: x = A_t^-1 b by its solve (pcg warm-started from
   its previous frame), refined as in a step, judged by its relres */
static int frame_method(aug_solver *s, int m, const double *b, int32_t frame, aug_err *e)
{
    const method *op = &methods[m];
    aug_kv *st = &s->stat[m], *tm = &s->time[m];
    int64_t n = s->cut.cum.n;
    double *x = s->field[m], t0 = 1e3 * aug_now(), rr = NAN;
    int sing = s->singular[m], conv = 1, iters = 0, nref = 0, rc;
    aug_kv_init(st, aug_method_names[m]);
    aug_kv_init(tm, aug_method_names[m]);
    put(st, "frame", frame);
    put(st, "n", (double)n);
    if (!sing && m == AUG_M_PCG) {
        double *xp = aug_realloc(s->pcg_x, (size_t)n * sizeof *xp);
        if (!xp) return aug_err_set(e, AUG_ENOMEM, -1, "fRAM", "out of memory");
        s->pcg_x = xp;
        for (int64_t i = s->pcg_n; i < n; i++) xp[i] = 0;
        s->pcg_n = n;
        double tic;
        iters = aug_pcg_prec(s->pcg_K, b, s->cut.unit, s->cut.unitcap, xp, s->o.pcg_prec, s->o.tol,
                             s->o.maxit, &conv, &sing, &rr, &s->pcg_shift, &tic, s->cm);
        if (iters < 0) return aug_err_set(e, AUG_ENOMEM, -1, "fRAM", "pcg: out of memory or no IC(0)");
        memcpy(x, xp, (size_t)n * sizeof *x);
        if (s->o.pcg_prec == AUG_PCG_IC || s->o.pcg_prec == AUG_PCG_IC_AMD) put(tm, "ic_factor", tic);
    } else if (!sing) {
        if ((rc = op->solve(s, b, x, e))) return rc;
        if (m == AUG_M_GMRES) iters = aug_gmres_iters(s->gm), conv = aug_gmres_converged(s->gm);
        double tr = 1e3 * aug_now();
        if (((op->flags & M_DIRECT) || s->o.refine_iter > 0) && (nref = refine(s, op, 0, b, x, &rr, e)) < 0)
            return e->code;
        if (nref) put(tm, "refine", 1e3 * aug_now() - tr);
    }
    double total = 1e3 * aug_now() - t0;
    /* relres over the rows that are not unit rows (formats/stream.md 7.9):
       those hold the constrained DOFs' jumps, displacements, where the others
       hold forces times h^2 */
    if (!sing) rr = aug_cutmat_residual_free(&s->cut, x, b, s->tmp);
    if (!sing && (((op->flags & M_DIRECT) && !(rr <= s->o.fail_tol)) || !isfinite(rr))) sing = 1;
    if (!sing && conv && !iter_agrees(s, m, rr)) conv = 0;
    put(st, "iters", iters);
    put(st, "refine", nref);
    put(st, "relres", sing ? NAN : rr);
    put(st, "converged", sing ? 0 : conv);
    put(st, "singular", sing);
    put(tm, "time_ms", total);
    s->converged[m] = !sing && conv;
    s->frame_singular[m] = sing;
    return 0;
}

static int dynamic_step(aug_solver *s, const aug_update *u, int swapped, aug_err *e);

int aug_solver_frame(aug_solver *s, const double *b, int32_t frame, aug_err *e)
{
    int rc;
    if (!s->prepped) { /* frames before any step: the per-step work of A_0 */
        static const int32_t none[1] = {0};
        static const double zero[1] = {0};
        aug_update u0 = {0, 0, 0, (int32_t *)none, (double *)zero, (double *)zero, NULL, NULL, NULL};
        if (buffers(s, s->cut.cum.n)) return aug_err_set(e, AUG_ENOMEM, -1, "fRAM", "out of memory");
        if ((rc = dynamic_step(s, &u0, 0, e))) return rc;
    }
    for (int oi = 0; oi < s->o.nmeth; oi++)
        if ((rc = frame_method(s, s->o.order[oi], b, frame, e))) return rc;
    if (!s->o.check) return 0;
    int64_t n = s->cut.cum.n;
    if (s->chk_ok && aug_refactor_solve(&s->chk, b, s->ref, s->cm, e)) return e->code;
    for (int oi = 0; oi < s->o.nmeth; oi++) {
        int m = s->o.order[oi];
        put(&s->stat[m], "err_direct", !s->chk_ok || s->frame_singular[m] ? NAN : reldiff(s->field[m], s->ref, NULL, n));
        put(&s->stat[m], "direct_spd", s->chk_ok);
    }
    return 0;
}

int aug_solver_frame_singular(const aug_solver *s, int m) { return s->frame_singular[m]; }

/* the per-step work of every method on a dynamic step, and the --check
   reference factor of A_t */
static int dynamic_step(aug_solver *s, const aug_update *u, int swapped, aug_err *e)
{
    step_req q = {u, NULL, 0, 1};
    int rc, unsolved = 0;
    s->prepped = 1;
    for (int oi = 0; oi < s->o.nmeth; oi++) {
        if ((rc = prep_method(s, s->o.order[oi], &q, swapped, e))) return rc;
        unsolved |= !s->converged[s->o.order[oi]];
    }
    if (s->o.check) {
        aug_refactor_free(&s->chk, s->cm);
        aug_refactor_init(&s->chk);
        double t[4];
        if (aug_refactor_step(&s->chk, &s->cut, s->ref, t, s->cm, e)) return e->code;
        s->chk_ok = !s->chk.singular;
    }
    if (s->bg && !aug_bg_running(s->bg)) return start_background(s, unsolved, e);
    return 0;
}

/* The update the base's methods (AMPS and its background job) compose when
   old DOFs P of the step become unit rows of K_t with f_t = 0 (a piece
   dropped, formats/stream.md 7.7; a pin's supports; --constrain at 0).
   K_t holds the identity on P x P; AMPS takes instead
   K'_t = blockdiag(B, K_t(R, R)): the same zero coupling between P and the
   rest R, and B = K'_{t-1}(P, P) + G, G a diagonal of springs. On R the
   solution is K_t's (R does not see P), on P it is 0 = f_t(P), which AMPS
   takes exactly (amps_solve.c unit_rows; its correction leaves those rows
   out, cum->keep). E' is E with its P x P block replaced by -G: E(P, P) =
   K_{t-1}(P, P) - I, whose pattern is B's graph. A DOF inside a piece has
   no coupling across it, so its column of E' is zero: it never joins S2
   nor the memo (its load reaches them by one forward solve, amps_solve.c
   lo_times). Dropping a piece costs AMPS the positions of its boundary,
   which the cut that frees it changes anyway, and G's, not 3 unit rows per
   node: the bunny of bench/organs.sh, 8-node steps, drops a 514-node piece
   at step 6 (1,542 DOFs); S2 grew from 453 to 510 positions instead of
   1,578, that step took 20 ms instead of 802, the median AMPS step
   127 -> 34 ms (refactor 93), relres within 3.4x refactor's as before.
   G holds each connected component of P x P still: K_{t-1}(P, P) alone is
   as near singular as the piece was near detached (it hung by a thin
   bridge), and with it AMPS's relres rose from 8e-10 to 7e-7 there. G puts
   springs equal to the diagonal entries on three sites of the component,
   far apart in its graph (a DOF, the farthest from it, the farthest from
   both), each with the DOFs of the same pattern (its node's other
   components). A component of at most SPRING_ALL DOFs, or with fewer DOFs
   inside than on its boundary (a constrained face), stays as E has it.
   Only AMPS's composition changes; K_t itself (cutmat: residuals, the
   correction's rows, refactor, rowupdate, pcg, --check) is the stream's.
   Only when amps or auto runs; not with gmres, which shares the
   composition and checks its residual against K_t, nor in dynamics, whose
   right-hand side is not f_t.
   A later step that prescribes other values there (--drag of the dropped
   piece) changes only f_t(P), which R does not see, and the values are
   still taken exactly (tests/solve_amps_drop.test).
   Returns u, or the copy with s->ue and s->ukeep; NULL: out of memory. */
#define SPRING_ALL 12
static const aug_update *keep_blocks(aug_solver *s, const aug_update *u, aug_update *tmp)
{
    if (s->o.dynamic || s->gm || u->m < 2 || !(s->use[AUG_M_AMPS] || s->use[AUG_M_AUTO])) return u;
    int64_t m = u->m, w = (int64_t)u->m + u->k;
    const double *E = u->E;
    if (m > s->ukcap) {
        unsigned char *q = aug_realloc(s->ukeep, (size_t)m);
        if (!q) return NULL;
        s->ukeep = q, s->ukcap = m;
    }
    /* in[t]: H[t] in P (a row E changes that becomes a unit row at f_t = 0) */
    unsigned char *in = s->ukeep;
    int64_t np = 0;
    for (int64_t t = 0; t < m; t++) {
        in[t] = 0;
        if (!aug_cutmat_unit(&s->cut, u->H[t]) || aug_cutmat_f(&s->cut, u->H[t]) != 0.0) continue;
        for (int64_t j = 0; j < w && !in[t]; j++) in[t] = E[t + j * w] != 0;
        np += in[t];
    }
    if (np < 2) return u;
    int64_t need = w * w + 2 * m + 1;
    if (need > s->uecap) {
        double *q = aug_realloc(s->ue, (size_t)need * sizeof *q);
        if (!q) return NULL;
        s->ue = q, s->uecap = need;
    }
    double *ue = s->ue;
    int32_t *seen = (int32_t *)(ue + w * w), *dist = seen + m, *queue = dist + m, *dmin = queue + m;
    memcpy(ue, E, (size_t)(w * w) * sizeof *ue);
    for (int64_t j = 0; j < m; j++)
        if (in[j])
            for (int64_t i = 0; i < m; i++)
                if (in[i]) ue[i + j * w] = 0;
    for (int64_t t = 0; t < m; t++) seen[t] = 0;
    int64_t nkept = 0;
    for (int64_t t0 = 0; t0 < m; t0++) { /* per connected component of E(P, P) */
        if (!in[t0] || seen[t0]) continue;
        int64_t site[3] = {t0, -1, -1}, size = 0;
        for (int k = 0; k < 3; k++) {
            /* breadth-first distances from site k in the graph of E(P, P);
               the component's DOFs in queue[0..size) */
            int64_t src = site[k], qh = 0, qt = 0;
            if (k == 0)
                for (int64_t j = 0; j < m; j++) dist[j] = -1;
            else
                for (int64_t q = 0; q < size; q++) dist[queue[q]] = -1;
            queue[qt++] = (int32_t)src, dist[src] = 0, seen[src] = 1;
            while (qh < qt) {
                int64_t v = queue[qh++];
                for (int64_t j = 0; j < m; j++)
                    if (in[j] && j != v && E[v + j * w] != 0 && dist[j] < 0)
                        dist[j] = dist[v] + 1, seen[j] = 1, queue[qt++] = (int32_t)j;
            }
            size = qt;
            if (size <= SPRING_ALL) break;
            int64_t far = -1;
            for (int64_t q = 0; q < size; q++) {
                int64_t v = queue[q];
                if (k == 0 || dist[v] < dmin[v]) dmin[v] = dist[v];
                if (far < 0 || dmin[v] > dmin[far]) far = v;
            }
            if (k < 2) site[k + 1] = far;
        }
        /* a component mostly coupled to the rest gains nothing (its DOFs
           join S2 either way, and the springs cost S2's conditioning): it
           keeps the unit rows of E */
        int64_t inner = 0;
        for (int64_t q = 0; q < size && size > SPRING_ALL; q++) {
            int64_t v = queue[q], out = 0;
            for (int64_t j = 0; j < w && !out; j++) out = (j >= m || !in[j]) && E[v + j * w] != 0;
            inner += !out;
        }
        if (size <= SPRING_ALL || 2 * inner < size) {
            for (int64_t q = 0; q < size; q++)
                for (int64_t r = 0; r < size; r++) {
                    int64_t i = queue[r], j = queue[q];
                    ue[i + j * w] = E[i + j * w];
                }
            for (int64_t q = 0; q < size; q++) in[queue[q]] = 0;
            continue;
        }
        nkept += size;
        for (int k = 0; k < 3; k++) {
            int64_t v = site[k];
            /* v and the DOFs of E(P, P) with v's pattern (its node's other components) */
            for (int64_t q = 0; q < size; q++) {
                int64_t j = queue[q], same = 1;
                for (int64_t r = 0; r < m && same; r++)
                    if (in[r]) same = (E[r + v * w] != 0) == (E[r + j * w] != 0);
                if (same) ue[j + j * w] = -(E[j + j * w] + 1.0);
            }
        }
    }
    if (nkept == 0) return u;
    *tmp = *u;
    tmp->E = ue;
    tmp->keep = in;
    return tmp;
}

/* One step: K_t and f_t (AMPS eq. 3.1), the background factor swapped in when
   it is ready, the step composed into the update relative to the base, then
   every requested method in order, the --check reference, and the next
   background job. */
int aug_solver_step(aug_solver *s, const aug_update *u, const int32_t *out, int64_t nout,
                    int flags, aug_err *e)
{
    s->step = u->step;
    s->nstep++;
    if (aug_cutmat_apply(&s->cut, u, e)) return e->code;
    if (buffers(s, s->cut.cum.n)) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    aug_cutmat_rhs(&s->cut, s->f);
    int swapped, rc;
    if ((rc = join_background(s, &swapped, e))) return rc;
    if ((s->au_swapped = swapped && s->use[AUG_M_AUTO])) aug_auto_rebased(&s->au);
    aug_update kt;
    const aug_update *ub = keep_blocks(s, u, &kt);
    if (!ub) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    if (aug_cum_apply(&s->cum, ub, e)) return e->code;
    if (s->bg && aug_bg_running(s->bg) && aug_bg_push(s->bg, ub, e)) return e->code;
    if (s->o.dynamic) return dynamic_step(s, u, swapped, e);
    /* a step that detaches a piece without Dirichlet support is singular */
    int detached = (flags & AUG_STEP_DETACHED) && !(flags & (AUG_STEP_PINNED | AUG_STEP_DROPPED));
    step_req q = {u, out, nout, !out || s->o.refine_iter > 0};
    int unsolved = 0;
    for (int oi = 0; oi < s->o.nmeth; oi++) {
        if ((rc = run_method(s, s->o.order[oi], &q, detached, swapped, e))) return rc;
        unsolved |= !s->converged[s->o.order[oi]];
    }
    if (s->o.check && (rc = check_direct(s, out, nout, e))) return rc;
    /* auto starts a job only when its cost model asks for one */
    if (s->bg && !aug_bg_running(s->bg) && (!s->use[AUG_M_AUTO] || s->au.want_bg))
        return start_background(s, unsolved, e);
    return 0;
}
