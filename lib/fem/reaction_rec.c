/* Reaction-family codec: rEAC, the reaction forces of one step (frame) at the
   constrained DOFs and their resultants per named set (formats/stream.md 7.10). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

#define HDR 32u /* dim, frame, time, n, nset */

/* bytes of the payload after the header for n DOFs and nset sets of dimension
   dim, or 0 when that overflows */
static uint64_t body_len(int64_t n, int64_t nset, int dim)
{
    uint64_t per = AUG_NAME + 8u * (uint64_t)dim;
    if (n < 0 || nset < 0 || (uint64_t)n > ((uint64_t)1 << 40) / 12 ||
        (uint64_t)nset > ((uint64_t)1 << 40) / per)
        return 0;
    return 12u * (uint64_t)n + 8u * (uint64_t)dim + per * (uint64_t)nset;
}

/* rEAC: i32 dim, i32 frame, f64 time, i64 n, i64 nset, i32 dof[n], f64 r[n],
   f64 total[dim], nset times (name, f64 resultant[dim]); every value finite */
int aug_write_reaction(aug_writer *w, int32_t step, const aug_reaction *q, aug_err *e)
{
    aug_err_clear(e);
    int d = q->dim, bad = !isfinite(q->time);
    for (int64_t k = 0; k < q->n && !bad; k++) bad = !isfinite(q->r[k]);
    for (int c = 0; c < d && !bad; c++) bad = !isfinite(q->total[c]);
    for (int64_t k = 0; k < q->nset * d && !bad; k++) bad = !isfinite(q->res[k]);
    if (bad)
        return aug_err_set(e, AUG_EDATA, aug_writer_count(w), "rEAC",
                           "step %d: a reaction is not finite (none is written)", (int)step);
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, d);
    aug_buf_i32(&b, q->frame);
    aug_buf_f64(&b, q->time);
    aug_buf_i64(&b, q->n);
    aug_buf_i64(&b, q->nset);
    aug_buf_i32v(&b, q->dof, (size_t)q->n);
    aug_buf_f64v(&b, q->r, (size_t)q->n);
    aug_buf_f64v(&b, q->total, (size_t)d);
    for (int64_t s = 0; s < q->nset; s++) {
        aug_buf_name(&b, q->name[s]);
        aug_buf_f64v(&b, q->res + s * d, (size_t)d);
    }
    return aug_buf_write(w, "rEAC", step, &b, e);
}

static int cmp_name(const void *a, const void *b) { return strncmp(a, b, AUG_NAME); }

/* set names: each NUL-terminated within its field, not empty, all different */
static int names_ok(const aug_reaction *q, int64_t *bad)
{
    for (int64_t s = 0; s < q->nset; s++)
        if (!q->name[s][0] || !memchr(q->name[s], 0, AUG_NAME)) {
            *bad = s;
            return 0;
        }
    if (q->nset < 2) return 1;
    char(*sorted)[AUG_NAME] = aug_malloc((size_t)q->nset * AUG_NAME);
    if (!sorted) return -1;
    memcpy(sorted, q->name, (size_t)q->nset * AUG_NAME);
    qsort(sorted, (size_t)q->nset, AUG_NAME, cmp_name);
    int ok = 1;
    for (int64_t s = 1; s < q->nset && ok; s++) ok = strncmp(sorted[s - 1], sorted[s], AUG_NAME) != 0;
    free(sorted);
    return ok;
}

int aug_read_reaction(const aug_rec *rec, aug_reaction *q, aug_err *e)
{
    aug_err_clear(e);
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t d = aug_cur_i32(&c), frame = aug_cur_i32(&c);
    double time = aug_cur_f64(&c);
    int64_t n = aug_cur_i64(&c), nset = aug_cur_i64(&c);
    uint64_t need = (d == 2 || d == 3) ? body_len(n, nset, d) : 0;
    if (!c.ok || need == 0 || c.len - c.pos != need)
        return aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type,
                           "reaction header (dim %d, %lld DOFs, %lld sets) does not match the payload",
                           (int)d, (long long)n, (long long)nset);
    if (frame < 0 || !isfinite(time))
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "frame %d, time %g: not a frame",
                           (int)frame, time);
    if (aug_reaction_reserve(q, n, nset))
        return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    q->dim = d, q->frame = frame, q->time = time, q->n = n, q->nset = nset;
    aug_cur_i32v(&c, q->dof, (uint64_t)n);
    aug_cur_f64v(&c, q->r, (uint64_t)n);
    aug_cur_f64v(&c, q->total, (uint64_t)d);
    for (int64_t s = 0; s < nset; s++) {
        memcpy(q->name[s], c.p + c.pos, AUG_NAME); /* within the payload: its size is checked */
        c.pos += AUG_NAME;
        aug_cur_f64v(&c, q->res + s * d, (uint64_t)d);
    }
    for (int64_t k = 0; k < n; k++) {
        if (q->dof[k] < 0 || (k > 0 && q->dof[k] <= q->dof[k - 1]))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                               "entry %lld: DOF %d is negative or does not increase", (long long)k,
                               (int)q->dof[k]);
        if (!isfinite(q->r[k]))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                               "entry %lld: the reaction at DOF %d is not finite", (long long)k,
                               (int)q->dof[k]);
    }
    for (int k = 0; k < d; k++)
        if (!isfinite(q->total[k]))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "total not finite");
    for (int64_t k = 0; k < nset * d; k++)
        if (!isfinite(q->res[k]))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                               "set %lld: resultant not finite", (long long)(k / d));
    int64_t bad = -1;
    int ok = names_ok(q, &bad);
    if (ok < 0) return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    if (!ok && bad >= 0)
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "set %lld: empty or unterminated name",
                           (long long)bad);
    if (!ok) return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "a set is named twice");
    return 0;
}

static int reac_check(const aug_rec *rec, aug_err *e)
{
    aug_reaction q;
    memset(&q, 0, sizeof q);
    int rc = aug_read_reaction(rec, &q, e);
    aug_reaction_free(&q);
    return rc;
}

static int reac_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    aug_reaction q;
    memset(&q, 0, sizeof q);
    if (aug_read_reaction(rec, &q, e)) {
        aug_reaction_free(&q);
        return e->code;
    }
    int d = q.dim;
    aug_txt_header(o, rec);
    fprintf(o, "  dim %d\n  frame %d\n  time ", d, (int)q.frame);
    aug_txt_f(o, q.time);
    fprintf(o, "\n  n %lld\n  nset %lld\n", (long long)q.n, (long long)q.nset);
    aug_cur c = aug_cur_mem(q.dof, (uint64_t)q.n * 4);
    aug_txt_i32s(o, "dof", &c, (uint64_t)q.n);
    c = aug_cur_mem(q.r, (uint64_t)q.n * 8);
    aug_txt_f64s(o, "r", &c, (uint64_t)q.n);
    c = aug_cur_mem(q.total, (uint64_t)d * 8);
    aug_txt_f64s(o, "total", &c, (uint64_t)d);
    for (int64_t s = 0; s < q.nset; s++) {
        aug_txt_name(o, "set", q.name[s], AUG_NAME);
        c = aug_cur_mem(q.res + s * d, (uint64_t)d * 8);
        aug_txt_f64s(o, "resultant", &c, (uint64_t)d);
    }
    aug_reaction_free(&q);
    return 0;
}

const aug_codec aug_codec_reac = {"lib/fem/reaction_rec.c", reac_check, reac_dump};
