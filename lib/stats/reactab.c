/* Reaction resultants per step from rEAC records: the rows of the per-step
   CSV and the summary's table (last step, largest magnitude over steps). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_stats.h"

void aug_reactab_init(aug_reactab *t) { memset(t, 0, sizeof *t); }

void aug_reactab_free(aug_reactab *t)
{
    for (size_t i = 0; i < t->nrow; i++) free(t->row[i].val);
    free(t->row);
    free(t->name);
    free(t->max);
    free(t->max_step);
    free(t->max_frame);
    aug_reaction_free(&t->q);
    aug_reactab_init(t);
}

/* the column of set name (0: the total), appended when new; -1 (memory) */
static int column(aug_reactab *t, const char *name)
{
    for (int k = 1; k < t->ncol; k++)
        if (!strncmp(t->name[k], name, AUG_NAME)) return k;
    if (t->ncol == t->colcap) {
        int cap = t->colcap ? 2 * t->colcap : 8;
        char(*nm)[AUG_NAME] = aug_realloc(t->name, (size_t)cap * AUG_NAME);
        if (nm) t->name = nm;
        double *mx = nm ? aug_realloc(t->max, (size_t)cap * sizeof *mx) : NULL;
        if (mx) t->max = mx;
        int32_t *ms = mx ? aug_realloc(t->max_step, (size_t)cap * sizeof *ms) : NULL;
        if (ms) t->max_step = ms;
        int32_t *mf = ms ? aug_realloc(t->max_frame, (size_t)cap * sizeof *mf) : NULL;
        if (!mf) return -1;
        t->max_frame = mf;
        t->colcap = cap;
    }
    int k = t->ncol++;
    memset(t->name[k], 0, AUG_NAME);
    memcpy(t->name[k], name, strnlen(name, AUG_NAME - 1));
    t->max[k] = -1;
    t->max_step[k] = t->max_frame[k] = -1;
    return k;
}

/* the row of step (the last one when it has that step, else a new one) */
static aug_reacrow *row_of(aug_reactab *t, int32_t step)
{
    if (t->nrow && t->row[t->nrow - 1].step == step) return &t->row[t->nrow - 1];
    if (t->nrow == t->rowcap) {
        size_t cap = t->rowcap ? 2 * t->rowcap : 16;
        aug_reacrow *r = aug_realloc(t->row, cap * sizeof *r);
        if (!r) return NULL;
        t->row = r;
        t->rowcap = cap;
    }
    aug_reacrow *r = &t->row[t->nrow++];
    memset(r, 0, sizeof *r);
    r->step = step;
    return r;
}

static double norm(const double *v, int d)
{
    double s = 0;
    for (int c = 0; c < d; c++) s += v[c] * v[c];
    return sqrt(s);
}

/* the resultant of column k: largest magnitude so far, and where */
static void note_max(aug_reactab *t, int k, const double *v, int32_t step, int32_t frame)
{
    double n = norm(v, t->dim);
    if (n > t->max[k]) t->max[k] = n, t->max_step[k] = step, t->max_frame[k] = frame;
}

int aug_reactab_add(aug_reactab *t, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    aug_reaction *q = &t->q;
    if (aug_read_reaction(rec, q, e)) return e->code;
    if (t->nrec && q->dim != t->dim)
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                           "reactions of dimension %d after reactions of dimension %d", q->dim, t->dim);
    t->dim = q->dim;
    int d = q->dim;
    if (t->ncol == 0 && column(t, "") < 0) goto nomem;
    int *col = aug_malloc((size_t)(q->nset + 1) * sizeof *col);
    if (!col) goto nomem;
    for (int64_t s = 0; s < q->nset; s++)
        if ((col[s] = column(t, q->name[s])) < 0) {
            free(col);
            goto nomem;
        }
    aug_reacrow *r = row_of(t, rec->step);
    double *val = r ? aug_realloc(r->val, (size_t)t->ncol * d * sizeof *val) : NULL;
    if (!val) {
        free(col);
        goto nomem;
    }
    r->val = val;
    r->ncol = t->ncol;
    r->frame = q->frame, r->time = q->time, r->ndof = q->n;
    for (int64_t k = 0; k < (int64_t)t->ncol * d; k++) val[k] = NAN;
    memcpy(val, q->total, (size_t)d * sizeof *val);
    note_max(t, 0, q->total, rec->step, q->frame);
    for (int64_t s = 0; s < q->nset; s++) {
        memcpy(val + (int64_t)col[s] * d, q->res + s * d, (size_t)d * sizeof *val);
        note_max(t, col[s], q->res + s * d, rec->step, q->frame);
    }
    free(col);
    t->nrec++;
    return 0;
nomem:
    return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
}

int aug_reactab_ncsv(const aug_reactab *t) { return t->nrec ? t->ncol * t->dim : 0; }

/* column k of the CSV: reaction_x .. (the total), then SET_x .. per set */
void aug_reactab_csv_name(const aug_reactab *t, int k, char *buf, size_t cap)
{
    static const char ax[] = "xyz";
    int j = k / t->dim;
    snprintf(buf, cap, "%s_%c", j ? t->name[j] : "reaction", ax[k % t->dim]);
}

double aug_reactab_csv_value(const aug_reactab *t, int32_t step, int k, int *found)
{
    size_t lo = 0, hi = t->nrow;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (t->row[mid].step < step) lo = mid + 1;
        else hi = mid;
    }
    double v = NAN;
    if (lo < t->nrow && t->row[lo].step == step && k < t->row[lo].ncol * t->dim) v = t->row[lo].val[k];
    *found = !isnan(v);
    return v;
}

void aug_reactab_print(FILE *o, const aug_reactab *t)
{
    if (!t->nrec) return;
    const aug_reacrow *last = &t->row[t->nrow - 1];
    int d = t->dim;
    fprintf(o, "reactions (rEAC)   %ld records; last: step %d, frame %d, %lld constrained DOFs\n",
            t->nrec, (int)last->step, (int)last->frame, (long long)last->ndof);
    fprintf(o, "  %-24s %-44s %12s  %s\n", "resultant", "last", "max |R|", "at step (frame)");
    for (int k = 0; k < t->ncol; k++) {
        char nm[4 * AUG_NAME + 1], v[128] = "-";
        const double *x = k < last->ncol ? last->val + (int64_t)k * d : NULL;
        if (x && !isnan(x[0])) {
            size_t n = 0;
            for (int c = 0; c < d; c++) n += (size_t)snprintf(v + n, sizeof v - n, "%s%.6g", c ? " " : "", x[c]);
        }
        fprintf(o, "  %-24s %-44s %12.6g  %d (%d)\n",
                k ? aug_txt_clean(nm, sizeof nm, t->name[k]) : "(every constrained DOF)", v, t->max[k],
                (int)t->max_step[k], (int)t->max_frame[k]);
    }
}
