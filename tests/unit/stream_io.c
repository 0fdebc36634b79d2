/* Stream layer: round trips of every record type, damage detection at every
   byte, ordering rules, pass-through, and a malloc-failure loop. */
#include <stdint.h>
#include <string.h>
#include <zlib.h>
#include "augcut.h"
#include "t.h"

/* a regular-ish two-tet mesh with every mesh record */
static void make_mesh(aug_mesh *m)
{
    static double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
    static int32_t conn[] = {0, 1, 2, 3, 1, 2, 3, 4};
    aug_mesh_init(m);
    m->dim = 3, m->etype = AUG_TET4, m->nv = 4, m->nn = 5, m->ne = 2;
    m->x = malloc(sizeof x);
    memcpy(m->x, x, sizeof x);
    m->conn = malloc(sizeof conn);
    memcpy(m->conn, conn, sizeof conn);
    m->mat = calloc(2, sizeof(int32_t));
    m->mat[1] = 1;
    m->nmat = 2;
    m->mats = calloc(2, sizeof *m->mats);
    m->mats[0] = (aug_material){3, "soft", 1e3, 0.45, 1000, 1, 0};
    m->mats[1] = (aug_material){4, "hard", 1e6, 0.3, 2000, 1, 0};
    m->nset = 1;
    m->sets = calloc(1, sizeof *m->sets);
    strcpy(m->sets[0].name, "fixed");
    m->sets[0].n = 3;
    m->sets[0].nodes = malloc(3 * sizeof(int32_t));
    for (int i = 0; i < 3; i++) m->sets[0].nodes[i] = i;
    m->nfix = 3;
    m->fix_dof = malloc(3 * sizeof(int32_t));
    m->fix_val = malloc(3 * sizeof(double));
    for (int i = 0; i < 3; i++) m->fix_dof[i] = i, m->fix_val[i] = 0.25 * i;
    m->nload = 1;
    m->load_dof = malloc(sizeof(int32_t));
    m->load_val = malloc(sizeof(double));
    m->load_dof[0] = 14, m->load_val[0] = -2.5;
    m->out_kind = AUG_OUT_SET;
    strcpy(m->out_name, "fixed");
    m->nout = 2;
    m->out_nodes = malloc(2 * sizeof(int32_t));
    m->out_nodes[0] = 1, m->out_nodes[1] = 4;
    m->have = AUG_HAVE_NODE | AUG_HAVE_ELEM | AUG_HAVE_MATL | AUG_HAVE_FIXD | AUG_HAVE_LOAD |
              AUG_HAVE_OUTS;
}

/* write a stream holding every record type; returns 0 or an error code */
static int write_all(FILE *f, uint64_t deflate_min, aug_err *e)
{
    aug_mesh m;
    make_mesh(&m);
    int rc = AUG_ENOMEM;
    aug_writer *w = aug_writer_open(f, "stream_io", e);
    if (!w) goto out;
    aug_writer_deflate(w, deflate_min);
    char *argv[] = {"stream_io", "--flag", "value"};
    if ((rc = aug_write_prov(w, 3, argv, e))) goto out;
    if ((rc = aug_mesh_write(w, &m, e))) goto out;
    /* phase-2 records as raw payloads of the specified layouts */
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, 3), aug_buf_i32(&b, 0), aug_buf_i64(&b, 15), aug_buf_i64(&b, 12);
    for (int i = 0; i < 15; i++) aug_buf_i32(&b, i < 3 ? -1 : i - 3);
    if ((rc = b.failed ? AUG_ENOMEM : aug_write(w, "DOFM", -1, b.p, b.len, e))) goto outb;
    aug_buf_free(&b);
    double big[4096];
    for (int i = 0; i < 4096; i++) big[i] = (i % 7) * 0.5;
    aug_buf_i32(&b, 0), aug_buf_i32(&b, 1), aug_buf_i64(&b, 3), aug_buf_i64(&b, 4);
    int64_t cp[] = {0, 1, 2, 4};
    int32_t ri[] = {0, 1, 1, 2};
    aug_buf_i64v(&b, cp, 4), aug_buf_i32v(&b, ri, 4), aug_buf_f64v(&b, big, 4);
    if ((rc = b.failed ? AUG_ENOMEM : aug_write(w, "KMAT", -1, b.p, b.len, e))) goto outb;
    aug_buf_free(&b);
    aug_buf_i32(&b, 0), aug_buf_i32(&b, 0), aug_buf_i64(&b, 4096), aug_buf_f64v(&b, big, 4096);
    if ((rc = b.failed ? AUG_ENOMEM : aug_write(w, "FVEC", -1, b.p, b.len, e))) goto outb;
    aug_buf_free(&b);
    aug_buf_i64(&b, 3), aug_buf_i64(&b, 4), aug_buf_i32(&b, 2), aug_buf_i32(&b, 0);
    int32_t perm[] = {2, 0, 1};
    aug_buf_i32v(&b, perm, 3), aug_buf_i64v(&b, cp, 4), aug_buf_i32v(&b, ri, 4);
    aug_buf_f64v(&b, big, 4);
    if ((rc = b.failed ? AUG_ENOMEM : aug_write(w, "FACT", -1, b.p, b.len, e))) goto outb;
    aug_buf_free(&b);
    aug_kv kv;
    aug_kv_init(&kv, "lanczos");
    aug_kv_set(&kv, "lambda_max", 3.5), aug_kv_set(&kv, "lambda_min", 1e-3);
    aug_kv_set(&kv, "cond", 3.5e3);
    if ((rc = aug_write_kv(w, "cOND", -1, &kv, e))) goto out;
    /* step 1: MDLT, UPDT, pATH, fELD, sTAt, tIMe, qUAl, MODE */
    aug_mdelta d;
    aug_mdelta_init(&d);
    int32_t parent[] = {1}, elem[] = {1}, nconn[] = {5, 2, 3, 4};
    double nx[] = {1, 0, 0};
    d.step = 1, d.nnew = 1, d.parent = parent, d.x = nx, d.nmod = 1, d.elem = elem;
    d.conn = nconn;
    if ((rc = aug_write_mdelta(w, 3, 4, &d, e))) goto out;
    aug_update u;
    int32_t H[] = {0, 2};
    double E[25], df[5] = {0, 0, 1, 2, 3};
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 5; j++) E[i + 5 * j] = 1.0 / (1 + i + j);
    aug_update_init(&u);
    u.step = 1, u.m = 2, u.k = 3, u.H = H, u.E = E, u.df = df;
    if ((rc = aug_write_update(w, &u, e))) goto out;
    aug_buf_i32(&b, 3), aug_buf_i32(&b, 0), aug_buf_i64(&b, 1), aug_buf_f64v(&b, big, 6);
    if ((rc = b.failed ? AUG_ENOMEM : aug_write(w, "pATH", 1, b.p, b.len, e))) goto outb;
    aug_buf_free(&b);
    aug_buf_i32(&b, 0), aug_buf_i32(&b, 3), aug_buf_i64(&b, 6), aug_buf_i32(&b, 0);
    aug_buf_i32(&b, 0), aug_buf_f64v(&b, big, 18);
    if ((rc = b.failed ? AUG_ENOMEM : aug_write(w, "fELD", 1, b.p, b.len, e))) goto outb;
    aug_buf_free(&b);
    aug_kv_init(&kv, "amps");
    aug_kv_set(&kv, "relres", 1e-15);
    if ((rc = aug_write_kv(w, "sTAt", 1, &kv, e))) goto out;
    aug_kv_set(&kv, "time_ms", 0.125);
    if ((rc = aug_write_kv(w, "tIMe", 1, &kv, e))) goto out;
    aug_kv_init(&kv, "refine");
    if ((rc = aug_write_kv(w, "qUAl", 1, &kv, e))) goto out;
    /* MODE (formats 7.5): domain 0, frame 0, 3-D, kind 0, 5 nodes, 2 modes */
    aug_buf_i32(&b, 0), aug_buf_i32(&b, 0), aug_buf_i32(&b, 3), aug_buf_i32(&b, 0);
    aug_buf_i64(&b, 5), aug_buf_i32(&b, 2), aug_buf_i32(&b, 0);
    aug_buf_i32v(&b, (int32_t[]){0, 1, 2, 3, 4}, 5);
    aug_buf_f64v(&b, (double[]){2, 1}, 2), aug_buf_f64v(&b, big, 30);
    if ((rc = b.failed ? AUG_ENOMEM : aug_write(w, "MODE", 2, b.p, b.len, e))) goto outb;
    aug_buf_free(&b);
    rc = aug_writer_close(w, e);
    goto out;
outb:
    aug_buf_free(&b);
out:
    if (w) aug_writer_free(w);
    aug_mesh_free(&m);
    return rc ? rc : (e->code ? e->code : 0);
}

static const char *expect_types[] = {"pROv", "NODE", "MATL", "ELEM", "nSEt", "FIXD", "LOAD",
                                     "oUTs", "DOFM", "KMAT", "FVEC", "FACT", "cOND", "MDLT",
                                     "UPDT", "pATH", "fELD", "sTAt", "tIMe", "qUAl", "MODE"};
#define NEXPECT (sizeof expect_types / sizeof expect_types[0])

static unsigned char *make_stream(uint64_t deflate_min, size_t *len)
{
    char *buf = NULL;
    FILE *f = open_memstream(&buf, len);
    aug_err e;
    int rc = write_all(f, deflate_min, &e);
    fclose(f);
    if (rc) {
        free(buf);
        return NULL;
    }
    return (unsigned char *)buf;
}

/* read all records; returns count read, or -(error code) */
static long read_all(const unsigned char *s, size_t len, aug_mesh *m, aug_err *e,
                     char types[][5], unsigned char **payloads, uint64_t *lens)
{
    FILE *f = fmemopen((void *)s, len, "rb");
    aug_reader *r = aug_reader_open(f, "mem", e);
    if (!r) {
        fclose(f);
        return -e->code;
    }
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    long n = 0;
    int rc;
    while ((rc = aug_read(r, &rec, e)) == 1) {
        if (types && n < 64) {
            memcpy(types[n], rec.type, 5);
            payloads[n] = malloc(rec.len ? rec.len : 1);
            memcpy(payloads[n], rec.data, rec.len);
            lens[n] = rec.len;
        }
        if (m && aug_mesh_is_record(rec.type) && aug_mesh_absorb(m, &rec, e)) {
            rc = -1;
            break;
        }
        n++;
    }
    aug_rec_free(&rec);
    aug_reader_free(r);
    fclose(f);
    return rc < 0 ? -e->code : n;
}

static void test_roundtrip_every_type(void)
{
    size_t len0, len1;
    unsigned char *s0 = make_stream(0, &len0), *s1 = make_stream(64, &len1);
    T_CHECK(s0 && s1, "writing failed");
    if (!s0 || !s1) return;
    T_CHECK(len1 < len0, "deflated stream not smaller (%zu vs %zu)", len1, len0);
    char t0[64][5], t1[64][5];
    unsigned char *p0[64], *p1[64];
    uint64_t l0[64], l1[64];
    aug_err e;
    aug_mesh m;
    aug_mesh_init(&m);
    long n0 = read_all(s0, len0, &m, &e, t0, p0, l0);
    aug_mesh ref;
    make_mesh(&ref);
    T_CHECK(n0 == (long)NEXPECT, "read %ld records (%s)", n0, e.msg);
    long n1 = read_all(s1, len1, NULL, &e, t1, p1, l1);
    T_CHECK(n1 == n0, "deflated stream read %ld records (%s)", n1, e.msg);
    for (long i = 0; i < n0 && i < n1 && i < (long)NEXPECT; i++) {
        T_CHECK(strcmp(t0[i], expect_types[i]) == 0, "record %ld is %s, not %s", i, t0[i],
                expect_types[i]);
        T_CHECK(l0[i] == l1[i] && memcmp(p0[i], p1[i], l0[i]) == 0,
                "record %ld (%s) differs after deflate", i, t0[i]);
    }
    for (long i = 0; i < n0 && i < 64; i++) free(p0[i]);
    for (long i = 0; i < n1 && i < 64; i++) free(p1[i]);
    /* mesh fields survive */
    T_CHECK(m.nn == ref.nn && m.ne == ref.ne && m.nmat == 2 && m.nset == 1, "mesh counts");
    T_CHECK(memcmp(m.x, ref.x, 15 * sizeof(double)) == 0, "coordinates");
    T_CHECK(memcmp(m.conn, ref.conn, 8 * sizeof(int32_t)) == 0, "connectivity");
    T_CHECK(m.mats[1].E == 1e6 && m.mats[0].nu == 0.45 && strcmp(m.mats[1].name, "hard") == 0,
            "materials");
    T_CHECK(m.nfix == 3 && m.fix_val[2] == 0.5 && m.load_val[0] == -2.5, "constraints/loads");
    T_CHECK(m.out_kind == AUG_OUT_SET && m.nout == 2 && m.out_nodes[1] == 4, "output set");
    aug_mesh_free(&m);
    aug_mesh_free(&ref);
    free(s0);
    free(s1);
}

static void test_update_records(void)
{
    size_t len;
    unsigned char *s = make_stream(0, &len);
    FILE *f = fmemopen(s, len, "rb");
    aug_err e;
    aug_reader *r = aug_reader_open(f, "mem", &e);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    int seen = 0;
    while (aug_read(r, &rec, &e) == 1) {
        if (!strcmp(rec.type, "UPDT")) {
            aug_update u;
            T_CHECK(aug_read_update(&rec, &u, &e) == 0, "UPDT: %s", e.msg);
            T_CHECK(u.step == 1 && u.m == 2 && u.k == 3 && u.H[1] == 2, "UPDT header");
            T_CHECK(u.E[1 + 5 * 3] == 1.0 / 5 && u.df[4] == 3, "UPDT values");
            aug_update_free(&u);
            seen++;
        } else if (!strcmp(rec.type, "MDLT")) {
            aug_mdelta d;
            T_CHECK(aug_read_mdelta(&rec, 3, 4, &d, &e) == 0, "MDLT: %s", e.msg);
            T_CHECK(d.nnew == 1 && d.parent[0] == 1 && d.nmod == 1 && d.conn[0] == 5, "MDLT");
            aug_mdelta_free(&d);
            seen++;
        } else if (!strcmp(rec.type, "tIMe")) {
            aug_kv kv;
            T_CHECK(aug_read_kv(&rec, &kv, &e) == 0, "tIMe: %s", e.msg);
            T_CHECK(!strcmp(kv.tag, "amps") && aug_kv_get(&kv, "time_ms", 0) == 0.125 &&
                        aug_kv_get(&kv, "relres", 0) == 1e-15 && kv.n == 2,
                    "kv values");
            seen++;
        }
    }
    T_CHECK(seen == 3, "saw %d of 3 decoded records", seen);
    aug_rec_free(&rec);
    aug_reader_free(r);
    fclose(f);
    free(s);
}

/* every truncation is an error, never a whole stream */
static void test_truncation_everywhere(void)
{
    size_t len;
    unsigned char *s = make_stream(64, &len);
    aug_err e;
    for (size_t cut = 0; cut < len; cut++) {
        long n = read_all(s, cut, NULL, &e, NULL, NULL, NULL);
        T_CHECK(n < 0, "stream cut at byte %zu of %zu read as whole", cut, len);
    }
    T_CHECK(read_all(s, len, NULL, &e, NULL, NULL, NULL) == (long)NEXPECT, "whole stream");
    free(s);
}

/* every single-byte change is detected */
static void test_flip_everywhere(void)
{
    size_t len;
    unsigned char *s = make_stream(64, &len);
    aug_err e;
    for (size_t i = 0; i < len; i++) {
        for (int bit = 0; bit < 8; bit += 7) {
            s[i] ^= (unsigned char)(1u << bit);
            long n = read_all(s, len, NULL, &e, NULL, NULL, NULL);
            T_CHECK(n < 0, "flip of bit %d in byte %zu not detected", bit, i);
            s[i] ^= (unsigned char)(1u << bit);
        }
    }
    free(s);
}

/* append a raw record (valid CRC) after the stream's last record (before TAIL) */
static unsigned char *with_record(const char *type, int32_t step, uint32_t major, size_t *len)
{
    char *buf = NULL;
    FILE *f = open_memstream(&buf, len);
    aug_err e;
    aug_writer *w = aug_writer_open(f, "t", &e);
    aug_mesh m;
    make_mesh(&m);
    aug_mesh_write(w, &m, &e);
    unsigned char payload[24] = {1, 2, 3};
    aug_write(w, type, step, payload, sizeof payload, &e);
    aug_writer_close(w, &e);
    aug_writer_free(w);
    fclose(f);
    aug_mesh_free(&m);
    if (major != AUG_VERSION_MAJOR) { /* rewrite HEAD's major and fix its CRC */
        unsigned char *h = (unsigned char *)buf + 8;
        memcpy(h + 12 + 16, &major, 4);
        uint64_t bl;
        memcpy(&bl, h, 8);
        uLong c = crc32(0, h + 8, (uInt)(4 + bl));
        uint32_t c32 = (uint32_t)c;
        memcpy(h + 12 + bl, &c32, 4);
    }
    return (unsigned char *)buf;
}

static void test_rules(void)
{
    size_t len;
    aug_err e;
    unsigned char *s = with_record("xPRi", -1, AUG_VERSION_MAJOR, &len);
    T_CHECK(read_all(s, len, NULL, &e, NULL, NULL, NULL) > 0, "unknown ancillary refused: %s",
            e.msg);
    free(s);
    s = with_record("XPRI", -1, AUG_VERSION_MAJOR, &len);
    T_CHECK(read_all(s, len, NULL, &e, NULL, NULL, NULL) == -AUG_ETYPE && e.record == 8 &&
                !strcmp(e.type, "XPRI"),
            "unknown critical: code %d record %ld (%s)", e.code, e.record, e.msg);
    free(s);
    s = with_record("sTAt", -1, AUG_VERSION_MAJOR, &len);
    T_CHECK(read_all(s, len, NULL, &e, NULL, NULL, NULL) < 0, "per-step record without step");
    free(s);
    s = with_record("NODE", -1, AUG_VERSION_MAJOR, &len);
    T_CHECK(read_all(s, len, NULL, &e, NULL, NULL, NULL) == -AUG_EORDER, "repeated NODE: %s",
            e.msg);
    free(s);
    s = with_record("xPRi", -1, 2, &len);
    T_CHECK(read_all(s, len, NULL, &e, NULL, NULL, NULL) == -AUG_EVERSION, "future version: %s",
            e.msg);
    free(s);
}

/* records out of phase and decreasing steps */
static void test_order(void)
{
    char *buf = NULL;
    size_t len;
    FILE *f = open_memstream(&buf, &len);
    aug_err e;
    aug_writer *w = aug_writer_open(f, "t", &e);
    aug_kv kv;
    aug_kv_init(&kv, "x");
    aug_write_kv(w, "sTAt", 5, &kv, &e);
    aug_write_kv(w, "sTAt", 4, &kv, &e);
    aug_writer_close(w, &e);
    aug_writer_free(w);
    fclose(f);
    long n = read_all((unsigned char *)buf, len, NULL, &e, NULL, NULL, NULL);
    T_CHECK(n == -AUG_EORDER && e.record == 2, "decreasing step: %ld %s", n, e.msg);
    free(buf);
    f = open_memstream(&buf, &len);
    w = aug_writer_open(f, "t", &e);
    aug_kv_init(&kv, "x");
    aug_write_kv(w, "cOND", -1, &kv, &e);
    aug_mesh m;
    make_mesh(&m);
    aug_mesh_write(w, &m, &e);
    aug_writer_close(w, &e);
    aug_writer_free(w);
    fclose(f);
    aug_mesh_free(&m);
    n = read_all((unsigned char *)buf, len, NULL, &e, NULL, NULL, NULL);
    T_CHECK(n == -AUG_EORDER && !strcmp(e.type, "NODE"), "mesh after matrix: %ld %s", n, e.msg);
    free(buf);
}

/* bad mesh content: NaN coordinate, inverted element, node out of range */
static void test_bad_mesh(void)
{
    const char *what[] = {"nan", "inverted", "range"};
    for (int k = 0; k < 3; k++) {
        aug_mesh m;
        make_mesh(&m);
        if (k == 0) m.x[4] = NAN;
        if (k == 1) {
            int32_t t = m.conn[1];
            m.conn[1] = m.conn[2];
            m.conn[2] = t;
        }
        if (k == 2) m.conn[7] = 9;
        char *buf = NULL;
        size_t len;
        FILE *f = open_memstream(&buf, &len);
        aug_err e;
        aug_writer *w = aug_writer_open(f, "t", &e);
        aug_mesh_write(w, &m, &e);
        aug_writer_close(w, &e);
        aug_writer_free(w);
        fclose(f);
        aug_mesh_free(&m);
        aug_mesh_init(&m);
        long n = read_all((unsigned char *)buf, len, &m, &e, NULL, NULL, NULL);
        const char *type = k == 0 ? "NODE" : "ELEM";
        T_CHECK(n == -AUG_EDATA && !strcmp(e.type, type), "%s: %ld %s %s", what[k], n, e.type,
                e.msg);
        if (k == 1) T_CHECK(strstr(e.msg, "element 0") != NULL, "inverted: %s", e.msg);
        aug_mesh_free(&m);
        free(buf);
    }
}

/* allocation failure at every point: clean error or success, never a crash */
static void test_malloc_failure(void)
{
    size_t len;
    unsigned char *s = make_stream(64, &len);
    int ok_seen = 0;
    for (long n = 0; n < 2000 && !ok_seen; n++) {
        aug_err e;
        aug_mesh m;
        aug_mesh_init(&m);
        aug_fail_after(n);
        long r = read_all(s, len, &m, &e, NULL, NULL, NULL);
        aug_fail_after(-1);
        T_CHECK(r == (long)NEXPECT || r == -AUG_ENOMEM, "after %ld allocations: %ld (%s)", n, r,
                e.msg);
        ok_seen = r == (long)NEXPECT;
        aug_mesh_free(&m);
    }
    T_CHECK(ok_seen, "reader never succeeded");
    ok_seen = 0;
    for (long n = 0; n < 2000 && !ok_seen; n++) {
        char *buf = NULL;
        size_t l;
        FILE *f = open_memstream(&buf, &l);
        aug_err e;
        aug_err_clear(&e);
        aug_fail_after(n);
        int rc = write_all(f, 64, &e);
        aug_fail_after(-1);
        fclose(f);
        T_CHECK(rc == 0 || rc == AUG_ENOMEM, "writer after %ld allocations: %d", n, rc);
        if (rc == 0) {
            ok_seen = 1;
            T_CHECK(l == len && memcmp(buf, s, len) == 0, "writer output differs");
        }
        free(buf);
    }
    T_CHECK(ok_seen, "writer never succeeded");
    free(s);
}

/* pass-through is byte-identical, deflated or not */
static void test_passthrough(void)
{
    size_t len;
    unsigned char *s = make_stream(64, &len);
    FILE *f = fmemopen(s, len, "rb");
    char *out = NULL;
    size_t olen;
    FILE *g = open_memstream(&out, &olen);
    aug_err e;
    aug_reader *r = aug_reader_open(f, "mem", &e);
    aug_writer *w = aug_writer_open(g, "stream_io", &e);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    while (aug_read(r, &rec, &e) == 1) aug_write_rec(w, &rec, &e);
    aug_writer_close(w, &e);
    aug_writer_free(w);
    aug_reader_free(r);
    aug_rec_free(&rec);
    fclose(f);
    fclose(g);
    T_CHECK(olen == len && memcmp(out, s, len) == 0, "pass-through changed the stream");
    free(out);
    free(s);
}

/* a record written in parts is byte-identical to one written whole */
static void test_write_parts(void)
{
    double v[1000];
    int32_t iv[333];
    for (int i = 0; i < 1000; i++) v[i] = i * 0.1;
    for (int i = 0; i < 333; i++) iv[i] = -i;
    char *b1 = NULL, *b2 = NULL;
    size_t l1, l2;
    aug_err e;
    FILE *f = open_memstream(&b1, &l1);
    aug_writer *w = aug_writer_open(f, "t", &e);
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_f64v(&b, v, 1000);
    aug_buf_i32v(&b, iv, 333);
    aug_write(w, "FVEC", -1, b.p, b.len, &e);
    aug_buf_free(&b);
    aug_writer_close(w, &e);
    aug_writer_free(w);
    fclose(f);
    f = open_memstream(&b2, &l2);
    w = aug_writer_open(f, "t", &e);
    int rc = aug_write_begin(w, "FVEC", -1, 8000 + 4 * 333, &e);
    rc |= aug_write_part(w, v, 500, 8, &e);
    rc |= aug_write_part(w, v + 500, 500, 8, &e);
    T_CHECK(aug_writer_close(w, &e) == AUG_EUSAGE, "close with an open record accepted");
    rc |= aug_write_part(w, iv, 333, 4, &e);
    T_CHECK(aug_write_part(w, iv, 1, 4, &e) == AUG_EUSAGE, "overlong part accepted");
    rc |= aug_write_end(w, &e);
    rc |= aug_writer_close(w, &e);
    aug_writer_free(w);
    fclose(f);
    T_CHECK(rc == 0, "parts: %s", e.msg);
    T_CHECK(l1 == l2 && memcmp(b1, b2, l1) == 0, "parts differ from the whole record");
    free(b1);
    free(b2);
}

int main(void)
{
    const char *seed = getenv("AUG_WRITE_SEED"); /* fuzz corpus seed (make fuzz) */
    if (seed) {
        size_t len;
        unsigned char *s = make_stream(64, &len);
        FILE *f = fopen(seed, "wb");
        if (!s || !f || fwrite(s, 1, len, f) != len) return 1;
        fclose(f);
        free(s);
        return 0;
    }
    T_RUN(test_roundtrip_every_type);
    T_RUN(test_update_records);
    T_RUN(test_truncation_everywhere);
    T_RUN(test_flip_everywhere);
    T_RUN(test_rules);
    T_RUN(test_order);
    T_RUN(test_bad_mesh);
    T_RUN(test_malloc_failure);
    T_RUN(test_passthrough);
    T_RUN(test_write_parts);
    T_EXIT();
}
