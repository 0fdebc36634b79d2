/* Background re-factorization (paper 000 sec. 3.6): a thread factors the cut
   matrix of a past step while steps go on; its factor becomes the new base. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

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
};

aug_bg *aug_bg_new(int nthreads)
{
    aug_bg *bg = aug_calloc(1, sizeof *bg);
    if (!bg) return NULL;
    bg->nthreads = nthreads;
    atomic_init(&bg->done, 0);
    cholmod_start(&bg->cm);
    bg->cm.error_handler = NULL;
    bg->cm.print = 0;
    return bg;
}

void aug_bg_free(aug_bg *bg)
{
    if (!bg) return;
    if (bg->running) {
        aug_err e;
        aug_base *b = aug_bg_join(bg, &e);
        if (b) aug_base_release(b, &bg->cm);
    }
    cholmod_finish(&bg->cm);
    free(bg);
}

/* P K P' = L D L' (CHOLMOD's ordering and supernodal choice, converted to
   simplicial LDL' for the sparse solves), a_b = K^-1 f */
static void *work(void *arg)
{
    aug_bg *bg = arg;
    cholmod_factor *L;
    if (bg->perm) {
        int nm = bg->cm.nmethods, ord = bg->cm.method[0].ordering;
        bg->cm.nmethods = 1;
        bg->cm.method[0].ordering = CHOLMOD_GIVEN;
        L = cholmod_analyze_p(bg->K, bg->perm, NULL, 0, &bg->cm);
        bg->cm.nmethods = nm, bg->cm.method[0].ordering = ord;
    } else {
        L = cholmod_analyze(bg->K, &bg->cm);
    }
    if (L && cholmod_factorize(bg->K, L, &bg->cm) && L->minor == L->n) {
        bg->base = aug_base_new(L, bg->K, bg->f, bg->step, &bg->cm, &bg->err);
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
    atomic_store(&bg->done, 1);
    return NULL;
}

int aug_bg_start(aug_bg *bg, cholmod_sparse *K, const double *f, const int32_t *perm,
                 int32_t step, aug_err *e)
{
    if (bg->running) return aug_err_set(e, AUG_EUSAGE, -1, "", "a background job is running");
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
    /* the matrix was allocated by the caller's cholmod_common: copy it into ours */
    bg->K = K;
    bg->step = step;
    bg->base = NULL;
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

int aug_bg_running(const aug_bg *bg) { return bg->running; }
int32_t aug_bg_step(const aug_bg *bg) { return bg->step; }

int aug_bg_done(aug_bg *bg) { return bg->running && atomic_load(&bg->done); }

aug_base *aug_bg_join(aug_bg *bg, aug_err *e)
{
    if (!bg->running) {
        aug_err_set(e, AUG_EUSAGE, -1, "", "no background job");
        return NULL;
    }
    pthread_join(bg->th, NULL);
    bg->running = 0;
    if (!bg->base) *e = bg->err;
    aug_base *b = bg->base;
    bg->base = NULL;
    return b;
}
