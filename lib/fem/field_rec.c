/* Field-family codecs: fELD, a nodal field of one step, and fRAM, the
   displacement and velocity of one time frame, all nodes or an indexed subset
   (formats/stream.md 7.3, 7.9). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

/* fELD: i32 kind, i32 dim, i64 count, i32 indexed, i32 0, [i32 node[count]],
   f64 u[count*dim]; nodes == NULL writes nodes 0..count-1 (indexed = 0). */
int aug_write_field(aug_writer *w, int32_t step, int32_t kind, int dim, int64_t count,
                    const int32_t *nodes, const double *u, aug_err *e)
{
    aug_err_clear(e);
    for (int64_t i = 0; i < count * dim; i++)
        if (!isfinite(u[i]))
            return aug_err_set(e, AUG_EDATA, aug_writer_count(w), "fELD",
                               "node %lld: value not finite (no field is written)",
                               (long long)(nodes ? nodes[i / dim] : i / dim));
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, kind);
    aug_buf_i32(&b, dim);
    aug_buf_i64(&b, count);
    aug_buf_i32(&b, nodes != NULL);
    aug_buf_i32(&b, 0);
    if (nodes) aug_buf_i32v(&b, nodes, (size_t)count);
    aug_buf_f64v(&b, u, (size_t)(count * dim));
    return aug_buf_write(w, "fELD", step, &b, e);
}

/* the node list (indexed) and nf nodal arrays of count x dim values after a
   header the cursor has passed: sizes, increasing nodes, finite values */
static int read_nodal(aug_cur *c, const aug_rec *rec, int d, int64_t n, int32_t indexed, int nf,
                      int32_t **nodes, double **x, aug_err *e)
{
    if (!c->ok || (d != 2 && d != 3) || (indexed != 0 && indexed != 1) || n < 0 || n > INT32_MAX ||
        c->len - c->pos != (uint64_t)n * (indexed ? 4 : 0) + (uint64_t)nf * n * d * 8)
        return aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type,
                           "field header (dim %d, count %lld, indexed %d) does not match the payload",
                           (int)d, (long long)n, (int)indexed);
    int32_t *nd = indexed ? aug_malloc((size_t)(n ? n : 1) * sizeof *nd) : NULL;
    int ok = !indexed || nd;
    for (int f = 0; f < nf; f++) ok &= (x[f] = aug_malloc((size_t)(n > 0 ? n * d : 1) * sizeof **x)) != NULL;
    if (ok && indexed) aug_cur_i32v(c, nd, (uint64_t)n);
    for (int f = 0; f < nf && ok; f++) aug_cur_f64v(c, x[f], (uint64_t)n * d);
    int64_t bad = -1;
    for (int64_t i = 0; ok && i < n && bad < 0; i++) {
        if (indexed && (nd[i] < 0 || (i > 0 && nd[i] <= nd[i - 1]))) bad = i;
        for (int f = 0; f < nf; f++)
            for (int q = 0; q < d && bad < 0; q++)
                if (!isfinite(x[f][i * d + q])) bad = i;
    }
    if (ok && bad < 0) {
        *nodes = nd;
        return 0;
    }
    free(nd);
    for (int f = 0; f < nf; f++) free(x[f]), x[f] = NULL;
    if (!ok) return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                       "entry %lld: node not increasing or value not finite", (long long)bad);
}

int aug_read_field(const aug_rec *rec, int32_t *kind, int *dim, int64_t *count,
                   int32_t **nodes, double **u, aug_err *e)
{
    aug_err_clear(e);
    *nodes = NULL;
    *u = NULL;
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t k = aug_cur_i32(&c), d = aug_cur_i32(&c);
    int64_t n = aug_cur_i64(&c);
    int32_t indexed = aug_cur_i32(&c);
    aug_cur_i32(&c);
    if (read_nodal(&c, rec, d, n, indexed, 1, nodes, u, e)) return e->code;
    *kind = k;
    *dim = d;
    *count = n;
    return 0;
}

/* fRAM: i32 frame, i32 dim, i64 count, f64 time, i32 indexed, i32 0,
   [i32 node[count]], f64 u[count*dim], f64 v[count*dim] */
int aug_write_frame(aug_writer *w, int32_t step, const aug_frame *f, aug_err *e)
{
    aug_err_clear(e);
    int64_t nv = f->count * f->dim;
    for (int64_t i = 0; i < nv; i++)
        if (!isfinite(f->u[i]) || !isfinite(f->v[i]))
            return aug_err_set(e, AUG_EDATA, aug_writer_count(w), "fRAM",
                               "node %lld: value not finite (no frame is written)",
                               (long long)(f->nodes ? f->nodes[i / f->dim] : i / f->dim));
    if (!isfinite(f->time) || f->frame < 0)
        return aug_err_set(e, AUG_EDATA, aug_writer_count(w), "fRAM", "frame %d at time %g",
                           (int)f->frame, f->time);
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, f->frame);
    aug_buf_i32(&b, f->dim);
    aug_buf_i64(&b, f->count);
    aug_buf_f64(&b, f->time);
    aug_buf_i32(&b, f->nodes != NULL);
    aug_buf_i32(&b, 0);
    if (f->nodes) aug_buf_i32v(&b, f->nodes, (size_t)f->count);
    aug_buf_f64v(&b, f->u, (size_t)nv);
    aug_buf_f64v(&b, f->v, (size_t)nv);
    return aug_buf_write(w, "fRAM", step, &b, e);
}

int aug_read_frame(const aug_rec *rec, aug_frame *f, aug_err *e)
{
    aug_err_clear(e);
    memset(f, 0, sizeof *f);
    aug_cur c;
    aug_cur_init(&c, rec);
    f->frame = aug_cur_i32(&c);
    f->dim = aug_cur_i32(&c);
    f->count = aug_cur_i64(&c);
    f->time = aug_cur_f64(&c);
    int32_t indexed = aug_cur_i32(&c);
    aug_cur_i32(&c);
    if (c.ok && (f->frame < 0 || !isfinite(f->time)))
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "frame %d at time %g", (int)f->frame,
                           f->time);
    double *x[2] = {NULL, NULL};
    if (read_nodal(&c, rec, f->dim, f->count, indexed, 2, &f->nodes, x, e)) return e->code;
    f->u = x[0], f->v = x[1];
    return 0;
}

void aug_frame_free(aug_frame *f)
{
    free(f->nodes);
    free(f->u);
    free(f->v);
    memset(f, 0, sizeof *f);
}

static int feld_check(const aug_rec *rec, aug_err *e)
{
    int32_t kind, *nodes;
    int dim;
    int64_t count;
    double *u;
    int rc = aug_read_field(rec, &kind, &dim, &count, &nodes, &u, e);
    free(nodes);
    free(u);
    return rc;
}

static int feld_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    if (feld_check(rec, e)) return e->code;
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t kind = aug_cur_i32(&c), dim = aug_cur_i32(&c);
    int64_t count = aug_cur_i64(&c);
    int32_t indexed = aug_cur_i32(&c);
    aug_cur_i32(&c);
    aug_txt_header(o, rec);
    fprintf(o, "  kind %d\n  dim %d\n  count %lld\n  indexed %d\n", (int)kind, (int)dim,
            (long long)count, (int)indexed);
    if (indexed) aug_txt_i32s(o, "node", &c, (uint64_t)count);
    aug_txt_rows_f64(o, "u", &c, (uint64_t)count, dim);
    return 0;
}

const aug_codec aug_codec_feld = {"lib/fem/field_rec.c", feld_check, feld_dump};

static int fram_check(const aug_rec *rec, aug_err *e)
{
    aug_frame f;
    int rc = aug_read_frame(rec, &f, e);
    aug_frame_free(&f);
    return rc;
}

static int fram_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    aug_frame f;
    if (aug_read_frame(rec, &f, e)) {
        aug_frame_free(&f);
        return e->code;
    }
    aug_txt_header(o, rec);
    fprintf(o, "  frame %d\n  time ", (int)f.frame);
    aug_txt_f(o, f.time);
    fprintf(o, "\n  dim %d\n  count %lld\n  indexed %d\n", f.dim, (long long)f.count, f.nodes != NULL);
    aug_cur c;
    if (f.nodes) {
        c = aug_cur_mem(f.nodes, (uint64_t)f.count * 4);
        aug_txt_i32s(o, "node", &c, (uint64_t)f.count);
    }
    c = aug_cur_mem(f.u, (uint64_t)(f.count * f.dim) * 8);
    aug_txt_rows_f64(o, "u", &c, (uint64_t)f.count, f.dim);
    c = aug_cur_mem(f.v, (uint64_t)(f.count * f.dim) * 8);
    aug_txt_rows_f64(o, "v", &c, (uint64_t)f.count, f.dim);
    aug_frame_free(&f);
    return 0;
}

const aug_codec aug_codec_fram = {"lib/fem/field_rec.c", fram_check, fram_dump};
