/* Per-step table: sTAt and tIMe records matched by (step, method), with the
   reaction resultants of their step (rEAC), and its CSV. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_stats.h"

void aug_steptab_init(aug_steptab *t)
{
    memset(t, 0, sizeof *t);
    aug_reactab_init(&t->react);
}
void aug_steptab_free(aug_steptab *t)
{
    free(t->row);
    aug_reactab_free(&t->react);
    aug_steptab_init(t);
}

/* The row a record of (step, tag) belongs to: the earliest row of the same
   step and method that lacks this kind of record, else a new row. Steps never
   decrease along a stream, so only the rows of the current step are searched. */
static aug_steprow *row_for(aug_steptab *t, int32_t step, const char *tag, int is_time)
{
    size_t b = t->n;
    while (b > 0 && t->row[b - 1].step == step) b--;
    for (size_t i = b; i < t->n; i++) {
        aug_steprow *r = &t->row[i];
        if (strncmp(r->method, tag, 16) == 0 && !(is_time ? r->has_time : r->has_stat)) return r;
    }
    if (t->n == t->cap) {
        size_t nc = t->cap ? 2 * t->cap : 16;
        aug_steprow *q = aug_realloc(t->row, nc * sizeof *q);
        if (!q) return NULL;
        t->row = q;
        t->cap = nc;
    }
    aug_steprow *r = &t->row[t->n++];
    memset(r, 0, sizeof *r);
    r->step = step;
    memcpy(r->method, tag, 16);
    r->method[15] = 0;
    return r;
}

int aug_steptab_add(aug_steptab *t, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    if (!memcmp(rec->type, "rEAC", 4)) return aug_reactab_add(&t->react, rec, e);
    int is_time = memcmp(rec->type, "tIMe", 4) == 0;
    if (!is_time && memcmp(rec->type, "sTAt", 4) != 0) return 0;
    aug_kv kv;
    if (aug_read_kv(rec, &kv, e)) return e->code;
    aug_steprow *r = row_for(t, rec->step, kv.tag, is_time);
    if (!r) return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    if (is_time) r->time = kv, r->has_time = 1;
    else r->stat = kv, r->has_stat = 1;
    return 0;
}

static int kv_find(const aug_kv *kv, const char *key, double *v)
{
    for (int i = 0; i < kv->n; i++)
        if (strncmp(kv->key[i], key, 16) == 0) {
            *v = kv->val[i];
            return 1;
        }
    return 0;
}

double aug_steprow_get(const aug_steprow *r, const char *key, int *found)
{
    double v = NAN;
    int f = (r->has_stat && kv_find(&r->stat, key, &v)) || (r->has_time && kv_find(&r->time, key, &v));
    if (found) *found = f;
    return f ? v : NAN;
}

/* median of v[0..n) (v is sorted in place; the mean of the two middle values for
   even n; NAN for n = 0) */
double aug_median(double *v, size_t n)
{
    /* NaN (a singular step's relres: no number) is no value: left out (it
       was sorted in, and the median of 3.6e-14, nan, nan read nan) */
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        if (!isnan(v[i])) v[k++] = v[i];
    n = k;
    if (n == 0) return NAN;
    for (size_t i = 1; i < n; i++) /* insertion sort: tables are small */
        for (size_t j = i; j > 0 && v[j - 1] > v[j]; j--) {
            double x = v[j];
            v[j] = v[j - 1];
            v[j - 1] = x;
        }
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static const char *lead[] = {"time_ms", "relres", "m", "k"};
#define NLEAD 4

static int cmp_key(const void *a, const void *b) { return strncmp(a, b, 16); }

/* sorted union of the keys of all rows, the leading columns left out */
static char (*other_keys(const aug_steptab *t, size_t *nk))[16]
{
    size_t cap = 64, n = 0;
    char(*k)[16] = aug_malloc(cap * 16);
    if (!k) return NULL;
    for (size_t i = 0; i < t->n; i++)
        for (int w = 0; w < 2; w++) {
            const aug_kv *kv = w ? &t->row[i].time : &t->row[i].stat;
            if (!(w ? t->row[i].has_time : t->row[i].has_stat)) continue;
            for (int j = 0; j < kv->n; j++) {
                int skip = 0;
                for (int l = 0; l < NLEAD; l++) skip |= strncmp(kv->key[j], lead[l], 16) == 0;
                for (size_t l = 0; l < n && !skip; l++) skip = strncmp(k[l], kv->key[j], 16) == 0;
                if (skip) continue;
                if (n == cap) {
                    char(*q)[16] = aug_realloc(k, 2 * cap * 16);
                    if (!q) {
                        free(k);
                        return NULL;
                    }
                    k = q;
                    cap *= 2;
                }
                memcpy(k[n], kv->key[j], 16);
                k[n++][15] = 0;
            }
        }
    qsort(k, n, 16, cmp_key);
    *nk = n;
    return k;
}

/* RFC 4180 field: quoted when it holds a comma, quote or line break */
static void csv_str(FILE *o, const char *s)
{
    if (!strpbrk(s, ",\"\r\n")) {
        fputs(s, o);
        return;
    }
    fputc('"', o);
    for (; *s; s++) {
        if (*s == '"') fputc('"', o);
        fputc(*s, o);
    }
    fputc('"', o);
}

static void csv_val(FILE *o, const aug_steprow *r, const char *key)
{
    int f;
    double v = aug_steprow_get(r, key, &f);
    fputc(',', o);
    if (f) fprintf(o, "%.17g", v);
}

int aug_steptab_csv(FILE *out, const aug_steptab *t, aug_err *e)
{
    aug_err_clear(e);
    size_t nk = 0;
    char(*k)[16] = other_keys(t, &nk);
    if (!k) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    fputs("step,method", out);
    for (int l = 0; l < NLEAD; l++) fprintf(out, ",%s", lead[l]);
    for (size_t j = 0; j < nk; j++) {
        fputc(',', out);
        csv_str(out, k[j]);
    }
    int nr = aug_reactab_ncsv(&t->react);
    for (int j = 0; j < nr; j++) {
        char name[AUG_NAME + 16];
        aug_reactab_csv_name(&t->react, j, name, sizeof name);
        fputc(',', out);
        csv_str(out, name);
    }
    fputc('\n', out);
    for (size_t i = 0; i < t->n; i++) {
        const aug_steprow *r = &t->row[i];
        fprintf(out, "%d,", (int)r->step);
        csv_str(out, r->method);
        for (int l = 0; l < NLEAD; l++) csv_val(out, r, lead[l]);
        for (size_t j = 0; j < nk; j++) csv_val(out, r, k[j]);
        for (int j = 0; j < nr; j++) {
            int f;
            double v = aug_reactab_csv_value(&t->react, r->step, j, &f);
            fputc(',', out);
            if (f) fprintf(out, "%.17g", v);
        }
        fputc('\n', out);
    }
    free(k);
    if (ferror(out)) return aug_err_set(e, AUG_EIO, -1, "", "write failed");
    return 0;
}
