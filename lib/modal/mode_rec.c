/* MODE codec (formats/stream.md 7.5): one sub-domain's modal basis, snapshot
   singular vectors (kind 0) or LMA modes (kind 1). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_modal.h"

#define MODE_HDR 32u

/* the payload length for count nodes, dim and rank r, or 0 when it cannot be
   one (overflow-safe: r < 2^31 and count*dim + 1 < 2^33, so their product
   fits; it is compared in units of 8 bytes) */
static int mode_len_ok(uint64_t len, int64_t count, int dim, int32_t r)
{
    uint64_t nodes = (uint64_t)count * 4;
    if (len < MODE_HDR + nodes || (len - MODE_HDR - nodes) % 8) return 0;
    uint64_t reals = (uint64_t)r * ((uint64_t)count * (uint64_t)dim + 1);
    return (len - MODE_HDR - nodes) / 8 == reals;
}

/* header and arrays after the cursor's pass: the layout of 7.5 */
static int mode_check_fields(const aug_rec *rec, const aug_moderec *m, aug_err *e)
{
    const char *t = rec->type;
    long ix = rec->index;
    if (m->domain < 0 || m->frame < 0)
        return aug_err_set(e, AUG_EDATA, ix, t, "domain %d, frame %d", (int)m->domain, (int)m->frame);
    if (m->dim != 2 && m->dim != 3) return aug_err_set(e, AUG_EDATA, ix, t, "dim %d", (int)m->dim);
    if (m->kind != 0 && m->kind != 1) return aug_err_set(e, AUG_EDATA, ix, t, "kind %d", (int)m->kind);
    if (m->count < 1 || m->count > INT32_MAX)
        return aug_err_set(e, AUG_EDATA, ix, t, "count %lld nodes", (long long)m->count);
    if (m->r < 1 || (int64_t)m->r > m->count * m->dim)
        return aug_err_set(e, AUG_EDATA, ix, t, "rank %d for %lld DOFs", (int)m->r,
                           (long long)(m->count * m->dim));
    return 0;
}

static int mode_check_values(const aug_rec *rec, const aug_moderec *m, aug_err *e)
{
    const char *t = rec->type;
    long ix = rec->index;
    for (int64_t i = 0; i < m->count; i++)
        if (m->nodes[i] < 0 || (i > 0 && m->nodes[i] <= m->nodes[i - 1]))
            return aug_err_set(e, AUG_EDATA, ix, t, "node %lld (%d) not increasing", (long long)i,
                               (int)m->nodes[i]);
    for (int j = 0; j < m->r; j++) {
        double s = m->sigma[j];
        if (!isfinite(s)) return aug_err_set(e, AUG_EDATA, ix, t, "sigma %d not finite", j);
        if (m->kind == 0 && s < 0) return aug_err_set(e, AUG_EDATA, ix, t, "sigma %d negative", j);
        if (j > 0 && (m->kind == 0 ? s > m->sigma[j - 1] : s < m->sigma[j - 1]))
            return aug_err_set(e, AUG_EDATA, ix, t, "sigma %d not %s", j,
                               m->kind == 0 ? "descending" : "ascending");
    }
    uint64_t np = (uint64_t)m->r * (uint64_t)(m->count * m->dim);
    for (uint64_t i = 0; i < np; i++)
        if (!isfinite(m->phi[i]))
            return aug_err_set(e, AUG_EDATA, ix, t, "mode %llu, node %llu: value not finite",
                               (unsigned long long)(i / (uint64_t)(m->count * m->dim)),
                               (unsigned long long)(i % (uint64_t)(m->count * m->dim) / m->dim));
    return 0;
}

int aug_write_mode(aug_writer *w, int32_t step, const aug_moderec *m, aug_err *e)
{
    aug_err_clear(e);
    aug_rec rec = {0};
    rec.index = aug_writer_count(w);
    memcpy(rec.type, "MODE", 5);
    if (mode_check_fields(&rec, m, e) || mode_check_values(&rec, m, e)) return e->code;
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, m->domain);
    aug_buf_i32(&b, m->frame);
    aug_buf_i32(&b, m->dim);
    aug_buf_i32(&b, m->kind);
    aug_buf_i64(&b, m->count);
    aug_buf_i32(&b, m->r);
    aug_buf_i32(&b, 0);
    aug_buf_i32v(&b, m->nodes, (size_t)m->count);
    aug_buf_f64v(&b, m->sigma, (size_t)m->r);
    aug_buf_f64v(&b, m->phi, (size_t)m->r * (size_t)(m->count * m->dim));
    return aug_buf_write(w, "MODE", step, &b, e);
}

int aug_read_mode(const aug_rec *rec, aug_moderec *m, aug_err *e)
{
    aug_err_clear(e);
    memset(m, 0, sizeof *m);
    aug_cur c;
    aug_cur_init(&c, rec);
    aug_moderec h = {0};
    h.domain = aug_cur_i32(&c), h.frame = aug_cur_i32(&c);
    h.dim = aug_cur_i32(&c), h.kind = aug_cur_i32(&c);
    h.count = aug_cur_i64(&c);
    h.r = aug_cur_i32(&c);
    aug_cur_i32(&c);
    if (!c.ok) return aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type, "shorter than %u bytes", MODE_HDR);
    if (mode_check_fields(rec, &h, e)) return e->code;
    if (!mode_len_ok(rec->len, h.count, h.dim, h.r))
        return aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type,
                           "%llu bytes for %lld nodes in %d-D and %d modes", (unsigned long long)rec->len,
                           (long long)h.count, (int)h.dim, (int)h.r);
    size_t np = (size_t)h.r * (size_t)(h.count * h.dim);
    h.nodes = aug_malloc((size_t)h.count * sizeof *h.nodes);
    h.sigma = aug_malloc((size_t)h.r * sizeof *h.sigma);
    h.phi = aug_malloc(np * sizeof *h.phi);
    if (!h.nodes || !h.sigma || !h.phi) {
        aug_moderec_free(&h);
        return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    }
    aug_cur_i32v(&c, h.nodes, (uint64_t)h.count);
    aug_cur_f64v(&c, h.sigma, (uint64_t)h.r);
    aug_cur_f64v(&c, h.phi, np);
    if (mode_check_values(rec, &h, e)) {
        aug_moderec_free(&h);
        return e->code;
    }
    *m = h;
    return 0;
}

void aug_moderec_free(aug_moderec *m)
{
    free(m->nodes);
    free(m->sigma);
    free(m->phi);
    memset(m, 0, sizeof *m);
}

static int mode_check(const aug_rec *rec, aug_err *e)
{
    aug_moderec m;
    int rc = aug_read_mode(rec, &m, e);
    aug_moderec_free(&m);
    return rc;
}

/* header, nodes, sigma, then per mode its 2-norm and all its values, one node a row */
static int mode_dump(FILE *o, aug_mesh *mesh, const aug_rec *rec, aug_err *e)
{
    (void)mesh;
    aug_moderec m;
    if (aug_read_mode(rec, &m, e)) return e->code;
    aug_txt_header(o, rec);
    fprintf(o, "  domain %d\n  frame %d\n  dim %d\n  kind %d (%s)\n  count %lld\n  r %d\n",
            (int)m.domain, (int)m.frame, (int)m.dim, (int)m.kind,
            m.kind == 0 ? "snapshot basis" : "LMA modes", (long long)m.count, (int)m.r);
    aug_cur c = aug_cur_mem(m.nodes, (uint64_t)m.count * 4);
    aug_txt_i32s(o, "node", &c, (uint64_t)m.count);
    c = aug_cur_mem(m.sigma, (uint64_t)m.r * 8);
    aug_txt_f64s(o, "sigma", &c, (uint64_t)m.r);
    size_t nd = (size_t)(m.count * m.dim);
    for (int j = 0; j < m.r; j++) {
        const double *p = m.phi + (size_t)j * nd;
        double s = 0;
        for (size_t i = 0; i < nd; i++) s += p[i] * p[i];
        char label[32];
        snprintf(label, sizeof label, "phi_%d", j);
        fprintf(o, "  %s norm ", label);
        aug_txt_f(o, sqrt(s));
        fputc('\n', o);
        c = aug_cur_mem(p, (uint64_t)nd * 8);
        aug_txt_rows_f64(o, label, &c, (uint64_t)m.count, m.dim);
    }
    aug_moderec_free(&m);
    return 0;
}

const aug_codec aug_codec_mode = {"lib/modal/mode_rec.c", mode_check, mode_dump};
