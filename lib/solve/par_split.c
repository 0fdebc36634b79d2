/* The split of a supernodal elimination tree into a top part and two bins of
   independent subtrees for the two-core triangular solves (par_solve.c).
   Paper 001 sec. 3.6 leaves steps 5-6 (the solves, the c |L| term of its
   eq. 3.34) serial; here the subtrees below a separator, which share no
   entry of x but their ancestors' (paper 000 thm 3: a column's solve reads
   only its etree path), are the parallel work. */
#include <stdlib.h>
#include "aug_par.h"
#include "aug_solve.h"

enum { TOP = 2, KMAX = 512 };

typedef struct wnode {
    double w;
    int32_t s;
} wnode;

/* heavier first, then the lower supernode: a deterministic order */
static int cmp_wnode(const void *x, const void *y)
{
    const wnode *a = x, *b = y;
    if (a->w != b->w) return a->w > b->w ? -1 : 1;
    return (a->s > b->s) - (a->s < b->s);
}

/* longest-processing-time assignment of the frontier's subtrees (weights
   W) to two bins: heaviest first, each to the lighter bin (ties: bin 0).
   Returns the heavier bin's weight; bin[t] receives the bin of front[t]
   when bin is not NULL. tmp: nf wnodes. */
static double lpt2(const int32_t *front, int64_t nf, const double *W, wnode *tmp,
                   unsigned char *bin_of, double wb[2])
{
    for (int64_t t = 0; t < nf; t++) tmp[t].w = W[front[t]], tmp[t].s = front[t];
    qsort(tmp, (size_t)nf, sizeof *tmp, cmp_wnode);
    wb[0] = wb[1] = 0;
    for (int64_t t = 0; t < nf; t++) {
        int k = wb[1] < wb[0];
        wb[k] += tmp[t].w;
        if (bin_of) bin_of[tmp[t].s] = (unsigned char)k;
    }
    return wb[0] > wb[1] ? wb[0] : wb[1];
}

void aug_par_plan_free(aug_par_plan *pl)
{
    if (!pl) return;
    free(pl->top), free(pl->bin[0]), free(pl->bin[1]);
    free(pl->defer_i0), free(pl->defer_at);
    free(pl->task_p), free(pl->task_s);
    free(pl);
}

/* The cost of a split is wtop + max(wbin) entries read (the solves are
   bound by memory traffic): the top part runs on one thread, then the two
   bins side by side. Starting from the roots, the heaviest subtree of the
   frontier moves to the top part, its children join the frontier; the best
   of the first KMAX such splits is kept, if it beats the serial cost by 5%. */
aug_par_plan *aug_par_plan_new(const cholmod_factor *Ls)
{
    if (!Ls || !Ls->is_super || Ls->nsuper < 2) return NULL;
    int64_t ns = (int64_t)Ls->nsuper, n = (int64_t)Ls->n;
    const int *sup = Ls->super, *pi = Ls->pi, *rows = Ls->s;
    aug_par_plan *pl = aug_calloc(1, sizeof *pl);
    int32_t *sof = aug_malloc((size_t)n * sizeof *sof);
    int32_t *spar = aug_malloc((size_t)ns * sizeof *spar), *head = aug_malloc((size_t)ns * sizeof *head);
    int32_t *next = aug_malloc((size_t)ns * sizeof *next), *front = aug_malloc((size_t)ns * sizeof *front);
    int32_t *expd = aug_malloc(KMAX * sizeof *expd);
    double *w = aug_malloc((size_t)ns * sizeof *w), *W = aug_malloc((size_t)ns * sizeof *W);
    unsigned char *label = aug_malloc((size_t)ns);
    wnode *tmp = aug_malloc((size_t)ns * sizeof *tmp);
    int ok = pl && sof && spar && head && next && front && expd && w && W && label && tmp;
    if (!ok) goto fail;
    pl->nsuper = ns;
    for (int64_t s = 0; s < ns; s++)
        for (int j = sup[s]; j < sup[s + 1]; j++) sof[j] = (int32_t)s;
    double wall = 0;
    for (int64_t s = 0; s < ns; s++) {
        int nscol = sup[s + 1] - sup[s], nsrow = pi[s + 1] - pi[s];
        spar[s] = nsrow > nscol ? sof[rows[pi[s] + nscol]] : -1;
        if (spar[s] >= 0 && spar[s] <= s) goto fail; /* parents follow children */
        if (nsrow - nscol > pl->tmpmax) pl->tmpmax = nsrow - nscol;
        w[s] = (double)nsrow * nscol + (nsrow - nscol);
        W[s] = 0;
        head[s] = -1;
    }
    for (int64_t s = 0; s < ns; s++) {
        W[s] += w[s];
        if (spar[s] >= 0) W[spar[s]] += W[s];
        wall += w[s];
    }
    for (int64_t s = ns - 1; s >= 0; s--)
        if (spar[s] >= 0) next[s] = head[spar[s]], head[spar[s]] = (int32_t)s;
    /* the greedy: front = the subtrees below the first k expansions */
    int64_t nf = 0;
    for (int64_t s = 0; s < ns; s++)
        if (spar[s] < 0) front[nf++] = (int32_t)s;
    double wtop = 0, best = wall, wb[2];
    int bestk = -1;
    for (int k = 0; k < KMAX && nf > 0; k++) {
        double cost = wtop + lpt2(front, nf, W, tmp, NULL, wb);
        if (cost < best) best = cost, bestk = k;
        int64_t h = 0;
        for (int64_t t = 1; t < nf; t++)
            if (W[front[t]] > W[front[h]] || (W[front[t]] == W[front[h]] && front[t] < front[h])) h = t;
        int32_t r = front[h];
        front[h] = front[--nf];
        expd[k] = r;
        wtop += w[r];
        for (int32_t c = head[r]; c >= 0; c = next[c]) front[nf++] = c;
    }
    if (bestk < 0 || best > 0.95 * wall) goto fail;
    /* rebuild the best split: top = the first bestk expansions */
    for (int64_t s = 0; s < ns; s++) label[s] = 0xff;
    for (int k = 0; k < bestk; k++) label[expd[k]] = TOP;
    nf = 0;
    for (int64_t s = 0; s < ns; s++)
        if (label[s] != TOP && (spar[s] < 0 || label[spar[s]] == TOP)) front[nf++] = (int32_t)s;
    lpt2(front, nf, W, tmp, label, wb);
    /* tasks: the frontier's subtrees in tmp's order (heaviest first); head
       becomes the task of each supernode below top */
    for (int64_t s = 0; s < ns; s++) head[s] = -1;
    for (int64_t t = 0; t < nf; t++) head[tmp[t].s] = (int32_t)t;
    for (int64_t s = ns - 1; s >= 0; s--) {
        if (label[s] == 0xff) label[s] = label[spar[s]];
        if (label[s] != TOP && head[s] < 0) head[s] = head[spar[s]];
    }
    pl->ntask = (int32_t)nf;
    pl->task_p = aug_calloc((size_t)nf + 1, sizeof *pl->task_p);
    pl->task_s = aug_malloc((size_t)ns * sizeof *pl->task_s);
    if (!pl->task_p || !pl->task_s) goto fail;
    for (int64_t s = 0; s < ns; s++)
        if (head[s] >= 0) pl->task_p[head[s] + 1]++;
    for (int64_t t = 0; t < nf; t++) pl->task_p[t + 1] += pl->task_p[t];
    for (int64_t t = 0; t < nf; t++) front[t] = (int32_t)pl->task_p[t]; /* fill pointers */
    for (int64_t s = 0; s < ns; s++)
        if (head[s] >= 0) pl->task_s[front[head[s]]++] = (int32_t)s;
    pl->top = aug_malloc((size_t)(bestk + 1) * sizeof *pl->top);
    pl->bin[0] = aug_malloc((size_t)ns * sizeof *pl->bin[0]);
    pl->bin[1] = aug_malloc((size_t)ns * sizeof *pl->bin[1]);
    pl->defer_i0 = aug_malloc((size_t)ns * sizeof *pl->defer_i0);
    pl->defer_at = aug_malloc((size_t)ns * sizeof *pl->defer_at);
    if (!pl->top || !pl->bin[0] || !pl->bin[1] || !pl->defer_i0 || !pl->defer_at) goto fail;
    for (int64_t s = 0; s < ns; s++) {
        int l = label[s], nscol = sup[s + 1] - sup[s];
        pl->defer_i0[s] = -1, pl->defer_at[s] = -1;
        if (l == TOP) {
            pl->top[pl->ntop++] = (int32_t)s;
            pl->wtop += w[s];
            continue;
        }
        pl->bin[l][pl->nbin[l]++] = (int32_t)s;
        pl->wbin[l] += w[s];
        /* the rows in top: a suffix of the rows below the diagonal block */
        int nb = pi[s + 1] - pi[s] - nscol, i0 = nb;
        const int *rs = rows + pi[s] + nscol;
        while (i0 > 0 && label[sof[rs[i0 - 1]]] == TOP) i0--;
        for (int i = 0; i < i0; i++)
            if (label[sof[rs[i]]] != l) goto fail;
        if (i0 < nb) {
            pl->defer_i0[s] = i0;
            pl->defer_at[s] = pl->ndefer;
            pl->ndefer += nb - i0;
        }
    }
    free(sof), free(spar), free(head), free(next), free(front), free(expd);
    free(w), free(W), free(label), free(tmp);
    return pl;
fail:
    free(sof), free(spar), free(head), free(next), free(front), free(expd);
    free(w), free(W), free(label), free(tmp);
    aug_par_plan_free(pl);
    return NULL;
}

void aug_base_split(aug_base *b)
{
    if (b->split_done || !b->Ls) return;
    b->split_done = 1;
    b->par_plan = aug_par_plan_new(b->Ls);
}
