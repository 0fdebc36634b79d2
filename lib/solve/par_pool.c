/* A persistent pool of threads that run one job at a time (the two-core
   solves of par_solve.c): the workers live as long as the pool and sleep on
   a condition variable between jobs, so a step pays a wake-up, not a
   pthread_create. */
#include <pthread.h>
#include <stdlib.h>
#include "aug_par.h"
#include "aug_solve.h"

struct aug_par {
    int n;                   /* threads, the caller included */
    pthread_t *tid;
    int nstarted;
    pthread_mutex_t mu;
    pthread_cond_t go, done;
    unsigned long gen;       /* generation of the current job */
    int pending;             /* workers still in the current job */
    int quit;
    aug_par_fn fn;
    void *arg;
    double *buf[AUG_PAR_NBUF];
    size_t bufcap[AUG_PAR_NBUF];
};

typedef struct worker_arg {
    aug_par *p;
    int t;
} worker_arg;

static void *worker(void *v)
{
    worker_arg *wa = v;
    aug_par *p = wa->p;
    int t = wa->t;
    free(wa);
    pthread_mutex_lock(&p->mu);
    unsigned long seen = 0; /* the pool starts at generation 0: a job posted
                               before this thread first waits is not missed */
    for (;;) {
        while (p->gen == seen && !p->quit) pthread_cond_wait(&p->go, &p->mu);
        if (p->quit) break;
        seen = p->gen;
        aug_par_fn fn = p->fn;
        void *arg = p->arg;
        pthread_mutex_unlock(&p->mu);
        fn(arg, t);
        pthread_mutex_lock(&p->mu);
        if (--p->pending == 0) pthread_cond_signal(&p->done);
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

aug_par *aug_par_new(int nthreads)
{
    if (nthreads < 2) return NULL;
    aug_par *p = aug_calloc(1, sizeof *p);
    if (!p) return NULL;
    p->n = nthreads;
    p->tid = aug_calloc((size_t)nthreads, sizeof *p->tid);
    if (!p->tid || pthread_mutex_init(&p->mu, NULL)) {
        free(p->tid), free(p);
        return NULL;
    }
    pthread_cond_init(&p->go, NULL);
    pthread_cond_init(&p->done, NULL);
    for (int t = 1; t < nthreads; t++) {
        worker_arg *wa = aug_malloc(sizeof *wa);
        if (!wa) break;
        wa->p = p, wa->t = t;
        if (pthread_create(&p->tid[t], NULL, worker, wa)) {
            free(wa);
            break;
        }
        p->nstarted++;
    }
    if (p->nstarted != nthreads - 1) {
        aug_par_free(p);
        return NULL;
    }
    return p;
}

void aug_par_free(aug_par *p)
{
    if (!p) return;
    pthread_mutex_lock(&p->mu);
    p->quit = 1;
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    for (int t = 1; t <= p->nstarted; t++) pthread_join(p->tid[t], NULL);
    pthread_cond_destroy(&p->go);
    pthread_cond_destroy(&p->done);
    pthread_mutex_destroy(&p->mu);
    for (int k = 0; k < AUG_PAR_NBUF; k++) free(p->buf[k]);
    free(p->tid);
    free(p);
}

int aug_par_nthreads(const aug_par *p) { return p ? p->n : 1; }

void aug_par_run(aug_par *p, aug_par_fn fn, void *arg)
{
    pthread_mutex_lock(&p->mu);
    p->fn = fn, p->arg = arg;
    p->pending = p->n - 1;
    p->gen++;
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    fn(arg, 0);
    pthread_mutex_lock(&p->mu);
    while (p->pending > 0) pthread_cond_wait(&p->done, &p->mu);
    pthread_mutex_unlock(&p->mu);
}

double *aug_par_buf(aug_par *p, int k, size_t n)
{
    if (k < 0 || k >= AUG_PAR_NBUF) return NULL;
    if (p->bufcap[k] < n) {
        free(p->buf[k]);
        p->buf[k] = aug_malloc((n ? n : 1) * sizeof *p->buf[k]);
        p->bufcap[k] = p->buf[k] ? n : 0;
    }
    return p->buf[k];
}
