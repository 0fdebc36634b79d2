/* Background re-factorization (paper 000 sec. 3.6): a thread factors the cut
   matrix of a past step while steps go on; its factor becomes the new base.
   Once the factor is ready the thread also catches AMPS up with the steps
   taken meanwhile (their composed update, the V columns and H'K^-1H for the
   new base), batch after batch (one update at a time with a --bg-lag
   schedule, so that the rounding does not depend on timing); when it has
   caught up it says it is done and
   keeps up with new steps until the join, which lets it drain the queue: the
   swap step adds only its own update. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include "aug_solve.h"
#include "aug_par.h"

struct aug_bg {
    pthread_t th;
    int running;
    atomic_int done;
    cholmod_common cm;
    cholmod_sparse *K;
    double *f;
    int *perm;           /* ordering to reuse, or NULL */
    int32_t step;
    aug_base *base;
    aug_err err;
    int nthreads;
    int stepwise;        /* catch up one update at a time (aug_bg_new) */
    double lnz_ref;      /* nnz(L) of the ordering last chosen (0: none yet; the
                            first job's given ordering sets it) */
    /* updates of the steps taken while the job runs (main thread appends) */
    pthread_mutex_t mu;
    pthread_cond_t cv;   /* signalled on push and on stop */
    int stop;            /* the join has begun: drain the queue and return */
    aug_update *q;
    int nq, qcap;
    int applied;         /* queued updates composed into cum by the thread */
    int amps;            /* prepare AMPS: 0 no, 1 path reach, 2 cholmod reach */
    int have_cum, have_amps;
    aug_cum cum;
    aug_amps am;
};

aug_bg *aug_bg_new(int nthreads, int stepwise)
{
    aug_bg *bg = aug_calloc(1, sizeof *bg);
    if (!bg) return NULL;
    bg->nthreads = nthreads, bg->stepwise = stepwise;
    atomic_init(&bg->done, 0);
    if (pthread_mutex_init(&bg->mu, NULL)) {
        free(bg);
        return NULL;
    }
    if (pthread_cond_init(&bg->cv, NULL)) {
        pthread_mutex_destroy(&bg->mu);
        free(bg);
        return NULL;
    }
    cholmod_start(&bg->cm);
    bg->cm.error_handler = NULL;
    bg->cm.print = 0;
    return bg;
}

/* the queue and whatever the thread prepared (no job running) */
static void drop(aug_bg *bg)
{
    for (int i = 0; i < bg->nq; i++) aug_update_free(&bg->q[i]);
    bg->nq = 0;
    bg->applied = 0;
    if (bg->have_cum) aug_cum_free(&bg->cum);
    if (bg->have_amps) aug_amps_free(&bg->am);
    bg->have_cum = bg->have_amps = 0;
}

void aug_bg_free(aug_bg *bg)
{
    if (!bg) return;
    if (bg->running) {
        aug_err e;
        aug_base *b = aug_bg_join(bg, &e);
        if (b) aug_base_release(b, &bg->cm);
    }
    drop(bg);
    free(bg->q);
    pthread_cond_destroy(&bg->cv);
    pthread_mutex_destroy(&bg->mu);
    cholmod_finish(&bg->cm);
    free(bg);
}

/* compose the queued updates (paper 001 eq. 3.1) relative to the new base and grow
   its memo for them (eqs. 3.23-3.27), until none is left; any failure just leaves
   the work to the swap step */
static void catch_up(aug_bg *bg)
{
    aug_err e;
    if (aug_cum_init(&bg->cum, bg->base->n, &e)) return;
    bg->have_cum = 1;
    aug_amps_init(&bg->am);
    bg->am.memo.use_cholmod = bg->amps == 2;
    bg->have_amps = 1;
    aug_update *batch = NULL;
    for (;;) {
        pthread_mutex_lock(&bg->mu);
        while (bg->applied == bg->nq && !bg->stop) {
            atomic_store(&bg->done, 1); /* caught up: the main thread may join */
            pthread_cond_wait(&bg->cv, &bg->mu);
        }
        int lo = bg->applied, hi = bg->stepwise && bg->nq > lo ? lo + 1 : bg->nq;
        aug_update *nbat = hi > lo ? aug_realloc(batch, (size_t)(hi - lo) * sizeof *batch) : batch;
        /* shallow copies: the arrays they point to live until the join */
        if (nbat) memcpy(nbat, bg->q + lo, (size_t)(hi - lo) * sizeof *nbat);
        pthread_mutex_unlock(&bg->mu);
        if (hi == lo || !nbat) break;
        batch = nbat;
        for (int i = 0; i < hi - lo; i++) {
            if (aug_cum_apply(&bg->cum, &batch[i], &e)) goto fail;
            bg->applied++;
        }
        if (aug_memo_reach(&bg->am.memo, bg->base, &bg->cum, NULL, &bg->cm, &e) ||
            aug_memo_grow(&bg->am.memo, bg->base, NULL, &e))
            goto fail;
    }
    free(batch);
    return;
fail:
    free(batch);
    aug_cum_free(&bg->cum);
    aug_amps_free(&bg->am);
    bg->have_cum = bg->have_amps = 0;
    bg->applied = 0;
}

/* P K P' = L D L' analysed with the ordering perm as given (CHOLMOD_GIVEN,
   postordered); NULL on failure */
static cholmod_factor *analyze_given(aug_bg *bg)
{
    int nm = bg->cm.nmethods, ord = bg->cm.method[0].ordering;
    bg->cm.nmethods = 1, bg->cm.method[0].ordering = CHOLMOD_GIVEN;
    cholmod_factor *L = cholmod_analyze_p(bg->K, bg->perm, NULL, 0, &bg->cm);
    bg->cm.nmethods = nm, bg->cm.method[0].ordering = ord;
    return L;
}

/* the ordering of the job: the base's, extended by the DOFs added since (no
   ordering cost), while its fill nnz(L) stays within REORDER_FILL of lnz_ref;
   beyond it K is ordered anew, AMD or METIS by the cost of an AMPS step
   (aug_analyze_steps), and its fill becomes lnz_ref. The extended ordering puts every new DOF
   last, on top of the elimination tree, so its fill grows with the steps (the
   1 x 1 x 2 brick in 8 x 20 x 48 cells, one node a step: +50% in 1,000 steps,
   and both bases in memory with it: hence tighter than the 1.2 of the
   refactor baseline, AUG_REFACTOR_FILL, which holds one factor). */
#define REORDER_FILL 1.1
static cholmod_factor *analyze(aug_bg *bg)
{
    if (!bg->perm) return cholmod_analyze(bg->K, &bg->cm);
    cholmod_factor *L = analyze_given(bg);
    if (!L) return NULL;
    if (bg->lnz_ref == 0) bg->lnz_ref = bg->cm.lnz;
    if (!(bg->cm.lnz > REORDER_FILL * bg->lnz_ref)) return L;
    cholmod_free_factor(&L, &bg->cm);
    aug_err e;
    L = aug_analyze_steps(bg->K, AUG_ORDER_AUTO, &bg->cm, &e);
    if (L) bg->lnz_ref = bg->cm.lnz;
    return L;
}

/* the job (paper 000 sec. 3.6): P K P' = L D L' by CHOLMOD (ordering: analyze),
   made an aug_base (simplicial LDL' for the sparse solves), a_b = K^-1 f; then
   catch_up when AMPS is prepared */
static void *work(void *arg)
{
    aug_bg *bg = arg;
    cholmod_factor *L = analyze(bg);
    if (L && cholmod_factorize(bg->K, L, &bg->cm) && L->minor == L->n) {
        bg->base = aug_base_new(L, bg->K, bg->f, bg->step, &bg->cm, &bg->err);
        if (bg->base && bg->nthreads >= 2) aug_base_split(bg->base); /* the caller's pool solves on it */
    } else {
        if (L) cholmod_free_factor(&L, &bg->cm);
        aug_err_set(&bg->err, AUG_ESINGULAR, -1, "UPDT",
                    "background factorization of step %d failed: not positive definite", (int)bg->step);
    }
    cholmod_free_sparse(&bg->K, &bg->cm);
    free(bg->f);
    free(bg->perm);
    bg->f = NULL;
    bg->perm = NULL;
    if (bg->base && bg->amps) catch_up(bg);
    atomic_store(&bg->done, 1);
    return NULL;
}

/* start the job on K (taken) and a copy of f: the factor of step's matrix in a
   thread (paper 000 sec. 3.6), perm reused as given ordering when set; amps > 0
   also prepares AMPS for the steps pushed meanwhile (catch_up) */
int aug_bg_start(aug_bg *bg, cholmod_sparse *K, const double *f, const int32_t *perm,
                 int32_t step, int amps, aug_err *e)
{
    if (bg->running) return aug_err_set(e, AUG_EUSAGE, -1, "", "a background job is running");
    drop(bg);
    int64_t n = (int64_t)K->nrow;
    bg->f = aug_malloc((size_t)(n + 1) * sizeof *bg->f);
    bg->perm = perm ? aug_malloc((size_t)(n + 1) * sizeof *bg->perm) : NULL;
    if (!bg->f || (perm && !bg->perm)) {
        free(bg->f), free(bg->perm);
        bg->f = NULL, bg->perm = NULL;
        return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    }
    memcpy(bg->f, f, (size_t)n * sizeof *f);
    for (int64_t i = 0; perm && i < n; i++) bg->perm[i] = perm[i];
    bg->K = K;
    bg->step = step;
    bg->amps = amps;
    bg->base = NULL;
    bg->stop = 0;
    aug_err_clear(&bg->err);
    atomic_store(&bg->done, 0);
    if (pthread_create(&bg->th, NULL, work, bg)) {
        free(bg->f);
        free(bg->perm);
        bg->f = NULL;
        bg->perm = NULL;
        bg->K = NULL;
        return aug_err_set(e, AUG_ENOMEM, -1, "", "cannot start the background thread");
    }
    bg->running = 1;
    return 0;
}

int aug_bg_push(aug_bg *bg, const aug_update *u, aug_err *e)
{
    int64_t s = (int64_t)u->m + u->k;
    aug_update d;
    aug_update_init(&d);
    d.step = u->step, d.m = u->m, d.k = u->k;
    d.H = aug_malloc((size_t)(u->m + 1) * sizeof *d.H);
    d.E = aug_malloc((size_t)(s * s + 1) * sizeof *d.E);
    d.df = aug_malloc((size_t)(s + 1) * sizeof *d.df);
    if (!d.H || !d.E || !d.df) goto nomem;
    memcpy(d.H, u->H, (size_t)u->m * sizeof *d.H);
    memcpy(d.E, u->E, (size_t)(s * s) * sizeof *d.E);
    memcpy(d.df, u->df, (size_t)s * sizeof *d.df);
    if (u->keep) {
        if (!(d.keep = aug_malloc((size_t)u->m + 1))) goto nomem;
        memcpy(d.keep, u->keep, (size_t)u->m);
    }
    pthread_mutex_lock(&bg->mu);
    if (bg->nq == bg->qcap) {
        int c = bg->qcap ? 2 * bg->qcap : 16;
        aug_update *q = aug_realloc(bg->q, (size_t)c * sizeof *q);
        if (!q) {
            pthread_mutex_unlock(&bg->mu);
            goto nomem;
        }
        bg->q = q, bg->qcap = c;
    }
    bg->q[bg->nq++] = d;
    pthread_cond_signal(&bg->cv);
    pthread_mutex_unlock(&bg->mu);
    return 0;
nomem:
    aug_update_free(&d);
    return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
}

int aug_bg_running(const aug_bg *bg) { return bg->running; }
int32_t aug_bg_step(const aug_bg *bg) { return bg->step; }

int aug_bg_done(aug_bg *bg) { return bg->running && atomic_load(&bg->done); }

/* stop the job once it has drained the queue, wait, and hand over the new base
   (NULL with the thread's error, e.g. K not positive definite; the queue dropped) */
aug_base *aug_bg_join(aug_bg *bg, aug_err *e)
{
    if (!bg->running) {
        aug_err_set(e, AUG_EUSAGE, -1, "", "no background job");
        return NULL;
    }
    pthread_mutex_lock(&bg->mu);
    bg->stop = 1;
    pthread_cond_signal(&bg->cv);
    pthread_mutex_unlock(&bg->mu);
    pthread_join(bg->th, NULL);
    bg->running = 0;
    if (!bg->base) {
        *e = bg->err;
        drop(bg);
    }
    aug_base *b = bg->base;
    bg->base = NULL;
    return b;
}

/* c = the composition (paper 001 eq. 3.1) of the updates queued since the
   snapshot, relative to the new base (the thread's, plus those it had not
   applied); a = the AMPS state the thread prepared, or a fresh one */
int aug_bg_take(aug_bg *bg, int64_t nb, aug_cum *c, aug_amps *a, aug_err *e)
{
    int rc = 0;
    if (bg->have_cum) {
        *c = bg->cum;
    } else if (aug_cum_init(c, nb, e)) {
        rc = -1;
    }
    if (bg->have_amps) {
        *a = bg->am;
    } else {
        aug_amps_init(a);
        a->memo.use_cholmod = bg->amps == 2;
    }
    int from = bg->have_cum ? bg->applied : 0;
    bg->have_cum = bg->have_amps = 0;
    for (int i = from; i < bg->nq && !rc; i++)
        if (aug_cum_apply(c, &bg->q[i], e)) rc = -1;
    drop(bg);
#ifdef __GLIBC__
    /* the swap has freed a whole base and AMPS state, in two threads' arenas,
       which the tools' malloc keeps (lib/cli/tool.c): give it back, once a
       swap, so that it does not stay resident beside the next job's factor */
    malloc_trim(0);
#endif
    return rc ? e->code : 0;
}
