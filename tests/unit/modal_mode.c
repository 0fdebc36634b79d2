/* The MODE record codec (formats/stream.md 7.5): write and read back bit for
   bit through a stream (both kinds, -0, subnormal and huge values), the
   writer refusing what the reader would, and the reader's checks on crafted
   payloads (exact and overflow-safe length, fields, node order, finite
   values, sigma order per kind) and allocation failures. */
#include <stdio.h>
#include <string.h>
#include "augcut.h"
#include "t.h"

static aug_moderec sample(int kind, int64_t count, int dim, int r)
{
    aug_moderec m = {3, 7, dim, kind, count, r, malloc(count * sizeof(int32_t)),
                     malloc(r * sizeof(double)), malloc(r * count * dim * sizeof(double))};
    for (int64_t k = 0; k < count; k++) m.nodes[k] = (int32_t)(2 * k + 1);
    for (int j = 0; j < r; j++) m.sigma[j] = kind == 0 ? 4.0 / (j + 1) : -1.0 + j * j;
    if (kind == 0 && r > 1) m.sigma[r - 1] = 0;   /* zero singular values are allowed */
    for (int64_t i = 0; i < r * count * dim; i++) m.phi[i] = sin(0.3 * (double)i + 1);
    m.phi[0] = -0.0, m.phi[1] = 4.9e-324, m.phi[2] = 1.7e308;
    return m;
}

/* the records of a stream held in memory: the i-th of type MODE into rec */
static char *write_stream(const aug_moderec *a, int n, int32_t step, size_t *len)
{
    char *p = NULL;
    FILE *f = open_memstream(&p, len);
    aug_err e;
    aug_writer *w = aug_writer_open(f, "modal_mode", &e);
    for (int i = 0; w && i < n; i++)
        if (aug_write_mode(w, step, a + i, &e)) {
            printf("write: %s\n", e.msg);
            break;
        }
    if (w) aug_writer_close(w, &e), aug_writer_free(w);
    fclose(f);
    return p;
}

static int same(const aug_moderec *a, const aug_moderec *b)
{
    size_t np = (size_t)a->r * a->count * a->dim;
    return a->domain == b->domain && a->frame == b->frame && a->dim == b->dim && a->kind == b->kind &&
           a->count == b->count && a->r == b->r &&
           !memcmp(a->nodes, b->nodes, a->count * sizeof *a->nodes) &&
           !memcmp(a->sigma, b->sigma, a->r * sizeof *a->sigma) && !memcmp(a->phi, b->phi, np * sizeof *a->phi);
}

static void round_trip(void)
{
    aug_moderec a[3] = {sample(0, 40, 3, 5), sample(1, 9, 2, 18), sample(0, 1, 3, 1)};
    size_t len;
    char *s = write_stream(a, 3, 4, &len);
    FILE *f = fmemopen(s, len, "rb");
    aug_err e;
    aug_reader *r = aug_reader_open(f, "mem", &e);
    T_CHECK(r != NULL, "reader: %s", e.msg);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    int n = 0, rc;
    while (r && (rc = aug_read(r, &rec, &e)) == 1) {
        if (memcmp(rec.type, "MODE", 4)) continue;
        T_CHECK(rec.step == 4, "step %d", rec.step);
        T_CHECK(aug_check_payload(&rec, &e) == 0, "check: %s", e.msg);
        aug_moderec b;
        T_CHECK(aug_read_mode(&rec, &b, &e) == 0, "read: %s", e.msg);
        T_CHECK(n < 3 && same(&a[n], &b), "record %d differs", n);
        T_CHECK(rec.len == 32 + 4 * (uint64_t)b.count + 8 * (uint64_t)b.r * (1 + b.count * b.dim),
                "length %llu", (unsigned long long)rec.len);
        aug_moderec_free(&b);
        n++;
    }
    T_CHECK(n == 3, "%d MODE records read back", n);
    aug_rec_free(&rec);
    if (r) aug_reader_free(r);
    fclose(f);
    free(s);
    for (int i = 0; i < 3; i++) aug_moderec_free(&a[i]);
}

/* a payload in memory as a record */
static aug_rec as_rec(unsigned char *p, uint64_t len)
{
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    memcpy(rec.type, "MODE", 5);
    rec.index = 5, rec.step = 1, rec.data = p, rec.len = len;
    return rec;
}

static unsigned char *payload(const aug_moderec *m, uint64_t *len)
{
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, m->domain), aug_buf_i32(&b, m->frame), aug_buf_i32(&b, m->dim);
    aug_buf_i32(&b, m->kind), aug_buf_i64(&b, m->count), aug_buf_i32(&b, m->r), aug_buf_i32(&b, 0);
    aug_buf_i32v(&b, m->nodes, m->count);
    aug_buf_f64v(&b, m->sigma, m->r);
    aug_buf_f64v(&b, m->phi, (size_t)m->r * m->count * m->dim);
    unsigned char *p = malloc(b.len + 16);
    memcpy(p, b.p, b.len);
    *len = b.len;
    aug_buf_free(&b);
    return p;
}

/* one damaged field: the reader refuses with code and a message holding what;
   the writer refuses the same struct (when it can be one) */
static void refuse(aug_moderec *m, uint64_t dlen, int code, const char *what, int writer)
{
    uint64_t len;
    unsigned char *p = payload(m, &len);
    aug_rec rec = as_rec(p, len + dlen);
    aug_moderec out;
    aug_err e;
    int rc = aug_read_mode(&rec, &out, &e);
    T_CHECK(rc == code && strstr(e.msg, what) && e.record == 5 && !strcmp(e.type, "MODE"),
            "%s: code %d, message '%s'", what, rc, e.msg);
    T_CHECK(out.nodes == NULL && out.sigma == NULL && out.phi == NULL && out.r == 0, "%s: filled", what);
    T_CHECK(aug_codec_mode.check(&rec, &e) == code, "%s: the table's check passes it", what);
    if (writer) {
        char *s = NULL;
        size_t n;
        FILE *f = open_memstream(&s, &n);
        aug_writer *w = aug_writer_open(f, "t", &e);
        T_CHECK(aug_write_mode(w, 1, m, &e) == AUG_EDATA && strstr(e.msg, what), "writer took %s", what);
        aug_writer_free(w);
        fclose(f);
        free(s);
    }
    free(p);
}

/* the header field at byte off (dim 8, r 24) = val in m's valid payload: the
   reader refuses it; the writer refuses m with that field */
static void refuse_at(const aug_moderec *m, int off, int32_t val, const char *what)
{
    uint64_t n;
    unsigned char *q = payload(m, &n);
    memcpy(q + off, &val, 4);
    aug_rec rq = as_rec(q, n);
    aug_moderec o, bad = *m;
    aug_err e;
    T_CHECK(aug_read_mode(&rq, &o, &e) == AUG_EDATA && strstr(e.msg, what), "%s: %s", what, e.msg);
    free(q);
    if (off == 8) bad.dim = val;
    else bad.r = val;
    char *s = NULL;
    size_t sn;
    FILE *f = open_memstream(&s, &sn);
    aug_writer *w = aug_writer_open(f, "t", &e);
    T_CHECK(aug_write_mode(w, 1, &bad, &e) == AUG_EDATA && strstr(e.msg, what), "writer took %s", what);
    aug_writer_free(w);
    fclose(f);
    free(s);
}

static void checks(void)
{
    aug_moderec m = sample(0, 6, 3, 4);
    refuse(&m, 8, AUG_EPAYLOAD, "bytes for 6 nodes in 3-D and 4 modes", 0);
    refuse(&m, (uint64_t)-8, AUG_EPAYLOAD, "bytes for 6 nodes", 0);
    /* dim 4 and r 19 patched into a valid payload (the writer checks them before its arrays) */
    refuse_at(&m, 8, 4, "dim 4");
    refuse_at(&m, 24, 19, "rank 19 for 18 DOFs");
    m.kind = 2, refuse(&m, 0, AUG_EDATA, "kind 2", 1), m.kind = 0;
    m.domain = -1, refuse(&m, 0, AUG_EDATA, "domain -1", 1), m.domain = 3;
    m.frame = -2, refuse(&m, 0, AUG_EDATA, "frame -2", 1), m.frame = 7;
    m.r = 0, refuse(&m, 0, AUG_EDATA, "rank 0 for 18 DOFs", 1);
    m.r = 4;
    m.nodes[3] = m.nodes[2], refuse(&m, 0, AUG_EDATA, "node 3 (5) not increasing", 1);
    m.nodes[3] = 7, m.nodes[0] = -1, refuse(&m, 0, AUG_EDATA, "node 0 (-1)", 1), m.nodes[0] = 1;
    m.phi[40] = NAN, refuse(&m, 0, AUG_EDATA, "mode 2, node 1: value not finite", 1), m.phi[40] = 0;
    m.phi[71] = INFINITY, refuse(&m, 0, AUG_EDATA, "mode 3, node 5: value not finite", 1), m.phi[71] = 0;
    m.sigma[1] = NAN, refuse(&m, 0, AUG_EDATA, "sigma 1 not finite", 1);
    m.sigma[1] = 5, refuse(&m, 0, AUG_EDATA, "sigma 1 not descending", 1);
    m.sigma[1] = 2, m.sigma[3] = -1e-300, refuse(&m, 0, AUG_EDATA, "sigma 3 negative", 1), m.sigma[3] = 0;
    m.kind = 1, refuse(&m, 0, AUG_EDATA, "sigma 1 not ascending", 1);
    /* LMA eigenvalues may be negative and repeated */
    m.sigma[0] = -3, m.sigma[1] = -3, m.sigma[2] = 0, m.sigma[3] = 1e300;
    uint64_t len;
    unsigned char *p = payload(&m, &len);
    aug_rec rec = as_rec(p, len);
    aug_moderec out;
    aug_err e;
    T_CHECK(aug_read_mode(&rec, &out, &e) == 0, "LMA sigma -3 -3 0 1e300: %s", e.msg);
    aug_moderec_free(&out);
    /* failing allocations: each of the three, nothing leaked (ASan build) */
    for (int k = 0; k < 3; k++) {
        aug_fail_after(k);
        int rc = aug_read_mode(&rec, &out, &e);
        aug_fail_after(-1);
        T_CHECK(rc == AUG_ENOMEM && out.nodes == NULL, "allocation %d: %d", k, rc);
    }
    /* header only, shorter than it, and counts whose sizes overflow 64 bits */
    T_CHECK(aug_read_mode(&(aug_rec){.type = "MODE", .data = p, .len = 31}, &out, &e) == AUG_EPAYLOAD,
            "31 bytes taken");
    memcpy(p + 16, &(int64_t){INT32_MAX}, 8);
    memcpy(p + 24, &(int32_t){INT32_MAX}, 4);
    memcpy(p + 8, &(int32_t){3}, 4);
    rec = as_rec(p, len);
    T_CHECK(aug_read_mode(&rec, &out, &e) == AUG_EPAYLOAD, "count 2^31-1, r 2^31-1: %s", e.msg);
    memcpy(p + 16, &(int64_t){(int64_t)1 << 62}, 8);
    T_CHECK(aug_read_mode(&rec, &out, &e) == AUG_EDATA && strstr(e.msg, "count"), "count 2^62: %s", e.msg);
    free(p);
    aug_moderec_free(&m);
}

int main(void)
{
    T_RUN(round_trip);
    T_RUN(checks);
    T_EXIT();
}
