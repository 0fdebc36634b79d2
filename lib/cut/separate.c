/* Node separation by duplication: the star of a node splits along cut faces. */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

static int32_t root(int32_t *up, int32_t i)
{
    while (up[i] != i) i = up[i] = up[up[i]];
    return i;
}

/* the nodes of the facet elements a and b share (sorted into f), 0 if none */
static int common(int etype, const int32_t *ca, const int32_t *cb, int32_t *f)
{
    int n = aug_shared_facet(etype, ca, cb, f);
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && f[j - 1] > f[j]; j--) {
            int32_t t = f[j];
            f[j] = f[j - 1];
            f[j - 1] = t;
        }
    return n;
}

/* Star(p) = elements containing p; a ~ b when they share a facet (p among
   its nodes: aug_shared_facet) that cut() does not report. Each class but the one holding
   the least-ranked element is re-wired to a new copy of p (AMPS sec. 4.3.2:
   "a copy of each node along the cut path was added to the mesh"). */
int aug_separate_node(aug_edit *ed, int32_t p, aug_cutface_fn cut, aug_rank_fn rank, void *ctx,
                      int *ncopies, aug_err *e)
{
    aug_err_clear(e);
    *ncopies = 0;
    int nv = ed->m->nv;
    int32_t s = ed->adj->cnt[p];
    if (s < 2) return 0;
    int32_t *star = aug_malloc((size_t)s * 3 * sizeof *star);
    if (!star) return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
    int32_t *up = star + s, *order = star + 2 * s;
    memcpy(star, ed->adj->list[p], (size_t)s * sizeof *star);
    /* increasing element order makes the result independent of list order */
    for (int32_t i = 1; i < s; i++)
        for (int32_t j = i; j > 0 && star[j - 1] > star[j]; j--) {
            int32_t t = star[j];
            star[j] = star[j - 1];
            star[j - 1] = t;
        }
    for (int32_t i = 0; i < s; i++) up[i] = i;
    for (int32_t i = 0; i < s; i++)
        for (int32_t j = i + 1; j < s; j++) {
            int32_t f[4];
            int nf = common(ed->m->etype, aug_edit_conn(ed, star[i]), aug_edit_conn(ed, star[j]), f);
            if (!nf) continue;
            if (cut && cut(ctx, ed, star[i], star[j], f, nf)) continue;
            int32_t a = root(up, i), b = root(up, j);
            if (a != b) up[a < b ? b : a] = a < b ? a : b;
        }
    /* keeper: the class of the least-ranked element */
    int32_t keep = 0;
    int64_t best = 0;
    for (int32_t i = 0; i < s; i++) {
        int64_t r = rank ? rank(ctx, star[i]) : star[i];
        if (i == 0 || r < best) {
            best = r;
            keep = root(up, i);
        }
    }
    /* classes in order of their least element (roots are least indices) */
    int32_t nclass = 0;
    for (int32_t i = 0; i < s; i++)
        if (root(up, i) == i && i != keep) order[nclass++] = i;
    double x[3];
    memcpy(x, aug_edit_x(ed, p), (size_t)ed->m->dim * sizeof *x);
    for (int32_t c = 0; c < nclass; c++) {
        int32_t q = aug_edit_node(ed, x, p);
        if (q < 0) goto nomem;
        for (int32_t i = 0; i < s; i++) {
            if (root(up, i) != order[c]) continue;
            int32_t conn[AUG_MAX_NV];
            memcpy(conn, aug_edit_conn(ed, star[i]), (size_t)nv * sizeof *conn);
            for (int k = 0; k < nv; k++)
                if (conn[k] == p) conn[k] = q;
            if (aug_edit_set(ed, star[i], conn)) goto nomem;
        }
        (*ncopies)++;
    }
    free(star);
    return 0;
nomem:
    free(star);
    return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
}
