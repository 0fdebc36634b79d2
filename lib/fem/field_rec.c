/* Field-family codec: fELD, a nodal field of one step, all nodes or an indexed subset
   (formats/stream.md 7.3). */
#include <math.h>
#include <stdlib.h>
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
    int rc = b.failed ? aug_err_set(e, AUG_ENOMEM, aug_writer_count(w), "fELD", "out of memory")
                      : aug_write(w, "fELD", step, b.p, b.len, e);
    aug_buf_free(&b);
    return rc;
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
    if (!c.ok || (d != 2 && d != 3) || (indexed != 0 && indexed != 1) || n < 0 ||
        n > INT32_MAX || c.len - c.pos != (uint64_t)n * (indexed ? 4 : 0) + (uint64_t)n * d * 8)
        return aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type,
                           "field header (dim %d, count %lld, indexed %d) does not match the payload",
                           (int)d, (long long)n, (int)indexed);
    int32_t *nd = indexed ? aug_malloc((size_t)(n ? n : 1) * sizeof *nd) : NULL;
    double *x = aug_malloc((size_t)(n > 0 ? n * d : 1) * sizeof *x);
    if (!x || (indexed && !nd)) {
        free(nd);
        free(x);
        return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    }
    if (indexed) aug_cur_i32v(&c, nd, (uint64_t)n);
    aug_cur_f64v(&c, x, (uint64_t)n * d);
    for (int64_t i = 0; i < n; i++) {
        int bad = indexed && (nd[i] < 0 || (i > 0 && nd[i] <= nd[i - 1]));
        for (int q = 0; q < d && !bad; q++) bad = !isfinite(x[i * d + q]);
        if (bad) {
            free(nd);
            free(x);
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                               "entry %lld: node not increasing or value not finite", (long long)i);
        }
    }
    *kind = k;
    *dim = d;
    *count = n;
    *nodes = nd;
    *u = x;
    return 0;
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
