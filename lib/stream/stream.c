/* Stream framing: signature, length|type|body|CRC-32 records, validation, pass-through. */
#include <stdlib.h>
#include <string.h>
#include <zlib.h>
#include "aug_stream.h"

const unsigned char aug_signature[8] = {0x89, 'A', 'U', 'G', '\r', '\n', 0x1a, '\n'};

/* Largest body accepted on the wire and largest inflated payload (1 TiB: beyond
   any mesh this tool chain handles, small enough to catch garbage lengths). */
#define AUG_MAX_BODY ((uint64_t)1 << 40)
#define BODY_HDR 16u /* flags u32, step i32, rawlen u64 */
#define READ_CHUNK ((uint64_t)1 << 24)
/* zlib cannot expand by more than about 1032:1 */
#define MAX_INFLATE_RATIO 1040u

/* The fuzz build (make fuzz) compiles this file with -DAUG_FUZZ_NO_CRC: the CRC
   is not compared, so that mutated payloads reach the codecs behind it. No
   other build defines it (-DFUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION goes with it). */
#if defined(AUG_FUZZ_NO_CRC) && !defined(FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION)
#error "AUG_FUZZ_NO_CRC is for the fuzz build only"
#endif
#ifdef AUG_FUZZ_NO_CRC
#define CRC_COMPARED 0
#else
#define CRC_COMPARED 1
#endif

/* One row per record type: inflated payload bounds, phase, multiplicity and
   its codec. formats/stream.md section "Record table" is the normative copy. */
static const aug_rectype table[] = {
    {"HEAD", 8, 4096, 0, 1, 0, &aug_codec_head},
    {"pROv", 0, 1 << 20, -1, 0, 0, &aug_codec_prov},
    {"pLAN", 8, 8, -1, 0, 0, &aug_codec_plan},
    {"NODE", 16, AUG_MAX_BODY, 1, 1, 0, &aug_codec_node},
    {"ELEM", 16, AUG_MAX_BODY, 1, 1, 0, &aug_codec_elem},
    {"MATL", 4, 1 << 24, 1, 1, 0, &aug_codec_matl},
    {"nSEt", 72, AUG_MAX_BODY, 1, 0, 0, &aug_codec_nset},
    {"FIXD", 8, AUG_MAX_BODY, 1, 1, 0, &aug_codec_fixd},
    {"LOAD", 8, AUG_MAX_BODY, 1, 1, 0, &aug_codec_load},
    {"oUTs", 80, AUG_MAX_BODY, 1, 1, 0, &aug_codec_outs},
    {"GRAV", 24, 24, 1, 1, 0, &aug_codec_grav},
    {"FNDN", 8, 1 << 24, 1, 1, 0, &aug_codec_fndn},
    {"DOFM", 24, AUG_MAX_BODY, 2, 1, 0, &aug_codec_dofm},
    {"KMAT", 24, AUG_MAX_BODY, 2, 0, 0, &aug_codec_kmat},
    {"FVEC", 16, AUG_MAX_BODY, 2, 0, 0, &aug_codec_fvec},
    {"FACT", 24, AUG_MAX_BODY, 2, 1, 0, &aug_codec_fact},
    {"cOND", 24, 1 << 20, 2, 0, 0, &aug_codec_kv},
    {"DYNP", 48, 48, 2, 1, 0, &aug_codec_dynp},
    {"MDLT", 32, AUG_MAX_BODY, 3, 0, 1, &aug_codec_mdlt},
    {"BDLT", 16, AUG_MAX_BODY, 3, 0, 1, &aug_codec_bdlt},
    {"UPKM", 8, AUG_MAX_BODY, 3, 0, 1, &aug_codec_upkm},
    {"UPDT", 8, AUG_MAX_BODY, 3, 0, 1, &aug_codec_updt},
    {"pATH", 16, AUG_MAX_BODY, 3, 0, 1, &aug_codec_path},
    {"fELD", 24, AUG_MAX_BODY, 3, 0, 1, &aug_codec_feld},
    {"fRAM", 32, AUG_MAX_BODY, 3, 0, 1, &aug_codec_fram},
    {"rEAC", 48, AUG_MAX_BODY, 3, 0, 1, &aug_codec_reac},
    {"sTAt", 24, 1 << 20, 3, 0, 1, &aug_codec_kv},
    {"tIMe", 24, 1 << 20, 3, 0, 1, &aug_codec_kv},
    {"qUAl", 24, 1 << 20, 3, 0, 1, &aug_codec_kv},
    {"MODE", 32, AUG_MAX_BODY, 3, 0, 1, &aug_codec_mode},
    {"TAIL", 8, 8, 4, 1, 0, &aug_codec_tail},
};

int aug_rec_changes_step(const aug_rec *rec)
{
    return !memcmp(rec->type, "MDLT", 4) || !memcmp(rec->type, "BDLT", 4) || !memcmp(rec->type, "UPKM", 4) ||
           !memcmp(rec->type, "UPDT", 4);
}

const aug_rectype *aug_rectype_find(const char *type)
{
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++)
        if (memcmp(table[i].type, type, 4) == 0) return &table[i];
    return NULL;
}

const aug_rectype *aug_rectype_at(size_t i)
{
    return i < sizeof table / sizeof table[0] ? &table[i] : NULL;
}

int aug_type_critical(const char *type) { return type[0] >= 'A' && type[0] <= 'Z'; }
int aug_type_safe_to_copy(const char *type) { return type[3] >= 'a' && type[3] <= 'z'; }

static int type_wellformed(const char *t)
{
    for (int i = 0; i < 4; i++) {
        unsigned char c = (unsigned char)t[i];
        if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'))) return 0;
    }
    return 1;
}

static void put_u32(unsigned char *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) p[i] = (unsigned char)(v >> (8 * i));
}
static void put_u64(unsigned char *p, uint64_t v)
{
    for (int i = 0; i < 8; i++) p[i] = (unsigned char)(v >> (8 * i));
}
static uint32_t get_u32(const unsigned char *p)
{
    uint32_t v = 0;
    for (int i = 3; i >= 0; i--) v = (v << 8) | p[i];
    return v;
}
static uint64_t get_u64(const unsigned char *p)
{
    uint64_t v = 0;
    for (int i = 7; i >= 0; i--) v = (v << 8) | p[i];
    return v;
}

/* crc32 over n bytes, in chunks that fit zlib's uInt */
static uint32_t crc_update(uint32_t crc, const unsigned char *p, uint64_t n)
{
    while (n > 0) {
        uInt c = n > (1u << 30) ? (1u << 30) : (uInt)n;
        crc = (uint32_t)crc32(crc, p, c);
        p += c;
        n -= c;
    }
    return crc;
}

/* capacity >= need, keeping the first `used` bytes */
static int grow(unsigned char **p, size_t *cap, uint64_t used, uint64_t need)
{
    if (need <= *cap) return 1;
    if (need > SIZE_MAX / 2) return 0;
    size_t nc = *cap ? *cap : 256;
    while (nc < need) nc *= 2;
    unsigned char *q = aug_regrow(*p, used, nc);
    if (!q) return 0;
    *p = q;
    *cap = nc;
    return 1;
}

struct aug_reader {
    FILE *f;
    char name[256];
    long count;          /* records read including HEAD */
    int phase;
    int32_t last_step;
    unsigned seen_once[sizeof table / sizeof table[0]];
    char producer[256];
    uint32_t minor;
    uint32_t head_flags;   /* HEAD as read, for stats */
    uint64_t head_len, head_wirelen;
    int done;
};

/* read exactly n bytes; 0 on short read */
static int read_full(FILE *f, void *p, size_t n)
{
    return fread(p, 1, n, f) == n;
}

static int inflate_payload(aug_rec *rec, const unsigned char *src, uint64_t srclen,
                           uint64_t rawlen, aug_err *e)
{
    if (!grow(&rec->zbuf, &rec->cap_data, 0, rawlen ? rawlen : 1))
        return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory (%llu bytes)",
                           (unsigned long long)rawlen);
    rec->data = rec->zbuf;
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit(&z) != Z_OK)
        return aug_err_set(e, AUG_EZLIB, rec->index, rec->type, "inflateInit failed");
    uint64_t in_left = srclen, out_left = rawlen;
    const unsigned char *ip = src;
    unsigned char *op = rec->data;
    int rc = Z_OK, extra_used = 0;
    while (rc == Z_OK) {
        if (z.avail_in == 0 && in_left > 0) {
            z.next_in = (Bytef *)ip;
            z.avail_in = in_left > (1u << 30) ? (1u << 30) : (uInt)in_left;
            ip += z.avail_in;
            in_left -= z.avail_in;
        }
        if (z.avail_out == 0) {
            if (out_left == 0) {
                unsigned char extra;
                z.next_out = &extra;
                z.avail_out = 1;
                extra_used = 1;
                rc = inflate(&z, Z_NO_FLUSH);
                if (z.avail_out == 0) rc = Z_DATA_ERROR; /* more output than rawlen */
                break;
            }
            z.next_out = op;
            z.avail_out = out_left > (1u << 30) ? (1u << 30) : (uInt)out_left;
            op += z.avail_out;
            out_left -= z.avail_out;
        }
        rc = inflate(&z, Z_NO_FLUSH);
        if (rc == Z_BUF_ERROR && z.avail_in == 0 && in_left == 0) break;
    }
    /* the probe byte past rawlen counts only when inflate wrote it */
    uint64_t produced = extra_used ? rawlen + (1u - z.avail_out)
                                   : (uint64_t)(op - rec->data) - z.avail_out;
    /* bytes after the end of the deflated data (taken, and passed on as
       they were by tools that copy a record) */
    uint64_t left = z.avail_in + in_left;
    inflateEnd(&z);
    if (rc == Z_STREAM_END && left > 0)
        return aug_err_set(e, AUG_EZLIB, rec->index, rec->type, "%llu bytes after the end of the deflated payload",
                           (unsigned long long)left);
    if (rc != Z_STREAM_END || produced != rawlen)
        return aug_err_set(e, AUG_EZLIB, rec->index, rec->type,
                           "deflated payload does not inflate to its stated %llu bytes",
                           (unsigned long long)rawlen);
    rec->len = rawlen;
    return 0;
}

/* a payload of len bytes against its type's bounds (table): 0 or AUG_ELEN */
static int check_len(const aug_rectype *t, uint64_t len, int64_t index, const char *type, aug_err *e)
{
    if (len >= t->minlen && len <= t->maxlen) return 0;
    return aug_err_set(e, AUG_ELEN, index, type, "payload of %llu bytes outside [%llu, %llu]",
                       (unsigned long long)len, (unsigned long long)t->minlen, (unsigned long long)t->maxlen);
}

/* Read one raw record into rec (framing, CRC, body header, inflate). */
static int read_record(aug_reader *r, aug_rec *rec, aug_err *e)
{
    unsigned char hdr[12];
    rec->index = r->count;
    rec->type[0] = 0;
    size_t got = fread(hdr, 1, 12, r->f);
    if (got == 0 && feof(r->f))
        return aug_err_set(e, AUG_ETRUNC, r->count, "",
                           "stream ends without a TAIL record (upstream tool failed?)");
    if (got < 12)
        return aug_err_set(e, ferror(r->f) ? AUG_EIO : AUG_ETRUNC, r->count, "",
                           "stream ends inside a record header");
    uint64_t blen = get_u64(hdr);
    memcpy(rec->type, hdr + 8, 4);
    rec->type[4] = 0;
    if (!type_wellformed(rec->type)) {
        rec->type[0] = 0;
        return aug_err_set(e, AUG_ETYPE, r->count, "", "record type is not four ASCII letters");
    }
    if (blen < BODY_HDR || blen > AUG_MAX_BODY)
        return aug_err_set(e, AUG_ELEN, r->count, rec->type, "impossible record length %llu",
                           (unsigned long long)blen);
    uint64_t wl = 12 + blen + 4;
    /* grow with the data actually read, so a damaged length fails at EOF
       instead of allocating what it claims */
    uint64_t have = 12;
    if (!grow(&rec->wire, &rec->cap_wire, 0, 12))
        return aug_err_set(e, AUG_ENOMEM, r->count, rec->type, "out of memory");
    memcpy(rec->wire, hdr, 12);
    while (have < wl) {
        /* read what fits the buffer, then double it: a damaged length
           costs at most twice what the stream really holds */
        uint64_t room = rec->cap_wire > have ? rec->cap_wire - have : 0;
        if (room == 0) room = have < READ_CHUNK ? READ_CHUNK : have;
        uint64_t chunk = wl - have < room ? wl - have : room;
        if (!grow(&rec->wire, &rec->cap_wire, have, have + chunk))
            return aug_err_set(e, AUG_ENOMEM, r->count, rec->type, "out of memory (%llu bytes)",
                               (unsigned long long)wl);
        if (!read_full(r->f, rec->wire + have, (size_t)chunk))
            return aug_err_set(e, ferror(r->f) ? AUG_EIO : AUG_ETRUNC, r->count, rec->type,
                               "stream ends inside the record (%llu bytes announced)",
                               (unsigned long long)blen);
        have += chunk;
    }
    rec->wirelen = wl;
    uint32_t crc = crc_update((uint32_t)crc32(0, Z_NULL, 0), rec->wire + 8, 4 + blen);
    if (CRC_COMPARED && crc != get_u32(rec->wire + 12 + blen))
        return aug_err_set(e, AUG_ECRC, r->count, rec->type, "CRC mismatch (damaged stream)");
    const unsigned char *body = rec->wire + 12;
    rec->flags = get_u32(body);
    rec->step = (int32_t)get_u32(body + 4);
    uint64_t rawlen = get_u64(body + 8);
    if (rec->flags & ~AUG_FLAG_DEFLATE)
        return aug_err_set(e, AUG_EPAYLOAD, r->count, rec->type, "unknown flags 0x%x",
                           (unsigned)rec->flags);
    if (rec->flags & AUG_FLAG_DEFLATE) {
        if (rawlen > AUG_MAX_BODY || rawlen / MAX_INFLATE_RATIO > blen)
            return aug_err_set(e, AUG_ELEN, r->count, rec->type,
                               "impossible inflated length %llu", (unsigned long long)rawlen);
        /* the stated length against the type's bounds before inflating (as
           check_known does after): a 2 MB pROv stating 2 GiB took 8.9 s and
           2.1 GB to inflate before being refused */
        const aug_rectype *t = aug_rectype_find(rec->type);
        if (t && check_len(t, rawlen, r->count, rec->type, e)) return e->code;
        if (inflate_payload(rec, body + BODY_HDR, blen - BODY_HDR, rawlen, e)) return e->code;
    } else {
        if (rawlen != blen - BODY_HDR)
            return aug_err_set(e, AUG_ELEN, r->count, rec->type,
                               "payload length %llu disagrees with record length %llu",
                               (unsigned long long)rawlen, (unsigned long long)blen);
        rec->data = rec->wire + 12 + BODY_HDR;
        rec->len = rawlen;
    }
    r->count++;
    return 0;
}

/* Check a known record against the table: bounds, phase, multiplicity, step. */
static int check_known(aug_reader *r, const aug_rec *rec, aug_err *e)
{
    const aug_rectype *t = aug_rectype_find(rec->type);
    if (!t) {
        if (aug_type_critical(rec->type))
            return aug_err_set(e, AUG_ETYPE, rec->index, rec->type,
                               "unknown critical record type");
        return 0;
    }
    if (check_len(t, rec->len, rec->index, rec->type, e)) return e->code;
    size_t ti = (size_t)(t - table);
    if (t->once && r->seen_once[ti])
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "record repeated");
    r->seen_once[ti] = 1;
    if (t->phase == 0)
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "HEAD after the first record");
    if (t->phase > 0) {
        if (t->phase < r->phase && aug_type_critical(rec->type))
            return aug_err_set(e, AUG_EORDER, rec->index, rec->type,
                               "record belongs before the records already read");
        if (t->phase > r->phase) r->phase = t->phase;
    }
    if (t->perstep) {
        if (rec->step < 0)
            return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "per-step record without a step");
        if (rec->step < r->last_step)
            return aug_err_set(e, AUG_EORDER, rec->index, rec->type,
                               "step %d after step %d", (int)rec->step, (int)r->last_step);
        r->last_step = rec->step;
    } else if (rec->step != AUG_NOSTEP) {
        return aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type,
                           "step %d on a record that is not per-step", (int)rec->step);
    }
    return 0;
}

aug_reader *aug_reader_open(FILE *f, const char *name, aug_err *e)
{
    aug_err_clear(e);
    aug_reader *r = aug_calloc(1, sizeof *r);
    if (!r) {
        aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        return NULL;
    }
    r->f = f;
    snprintf(r->name, sizeof r->name, "%s", name ? name : "-");
    r->last_step = -1;
    unsigned char sig[8];
    size_t got = fread(sig, 1, 8, f);
    if (got == 0) {
        aug_err_set(e, AUG_ETRUNC, -1, "", "empty stream (upstream tool failed?)");
        free(r);
        return NULL;
    }
    if (got < 8 || memcmp(sig, aug_signature, 8) != 0) {
        int text = got == 8 && memcmp(sig + 1, "AUG", 3) == 0;
        aug_err_set(e, AUG_ESIG, -1, "",
                    text ? "signature damaged (text-mode transfer?)"
                         : "not an augcut stream (bad signature)");
        free(r);
        return NULL;
    }
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    if (read_record(r, &rec, e)) goto fail;
    if (memcmp(rec.type, "HEAD", 4) != 0) {
        aug_err_set(e, AUG_EORDER, 0, rec.type, "first record is not HEAD");
        goto fail;
    }
    if (rec.len < 8) {
        aug_err_set(e, AUG_ELEN, 0, "HEAD", "HEAD payload too short");
        goto fail;
    }
    uint32_t major = get_u32(rec.data), minor = get_u32(rec.data + 4);
    if (major != AUG_VERSION_MAJOR) {
        aug_err_set(e, AUG_EVERSION, 0, "HEAD",
                    "format version %u.%u not supported (this is %d.%d)", major, minor,
                    AUG_VERSION_MAJOR, AUG_VERSION_MINOR);
        goto fail;
    }
    /* its bounds and step as any record's (a HEAD of 5 KB or of step 7 was
       taken: the first record skipped check_known) */
    if (check_len(&table[0], rec.len, 0, "HEAD", e)) goto fail;
    if (rec.step != AUG_NOSTEP) {
        aug_err_set(e, AUG_EPAYLOAD, 0, "HEAD", "step %d on a record that is not per-step", (int)rec.step);
        goto fail;
    }
    r->minor = minor;
    r->head_flags = rec.flags;
    r->head_len = rec.len;
    r->head_wirelen = rec.wirelen;
    size_t pl = rec.len - 8 < sizeof r->producer - 1 ? rec.len - 8 : sizeof r->producer - 1;
    memcpy(r->producer, rec.data + 8, pl);
    r->producer[pl] = 0;
    r->seen_once[0] = 1;
    aug_rec_free(&rec);
    return r;
fail:
    aug_rec_free(&rec);
    free(r);
    return NULL;
}

int aug_read(aug_reader *r, aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    if (r->done) return 0;
    if (read_record(r, rec, e)) return -1;
    if (check_known(r, rec, e)) return -1;
    if (memcmp(rec->type, "TAIL", 4) == 0) {
        uint64_t n = get_u64(rec->data);
        if (n != (uint64_t)rec->index) {
            aug_err_set(e, AUG_EDATA, rec->index, "TAIL",
                        "TAIL counts %llu records before it, stream had %ld",
                        (unsigned long long)n, rec->index);
            return -1;
        }
        r->done = 1;
        /* the stream ends with its TAIL: a byte after it (a second stream
           appended, trailing garbage) is an error */
        int c = fgetc(r->f);
        if (c != EOF)
            return aug_err_set(e, AUG_EDATA, rec->index, "TAIL", "bytes after the TAIL record"), -1;
        return 0;
    }
    return 1;
}

const char *aug_reader_producer(const aug_reader *r) { return r->producer; }
void aug_reader_head(const aug_reader *r, uint32_t *minor, uint32_t *flags, uint64_t *len,
                     uint64_t *wirelen)
{
    *minor = r->minor;
    *flags = r->head_flags;
    *len = r->head_len;
    *wirelen = r->head_wirelen;
}
void aug_reader_free(aug_reader *r) { free(r); }

void aug_rec_free(aug_rec *rec)
{
    if (!rec) return;
    free(rec->zbuf);
    free(rec->wire);
    memset(rec, 0, sizeof *rec);
}

struct aug_writer {
    FILE *f;
    long count;
    uint64_t deflate_min;
    int failed;
    int open_rec;           /* inside aug_write_begin .. aug_write_end */
    char rec_type[5];
    uint64_t rec_left;      /* payload bytes still owed */
    uint32_t rec_crc;
};

static int write_bytes(aug_writer *w, const void *p, size_t n, aug_err *e)
{
    if (n && fwrite(p, 1, n, w->f) != n) {
        w->failed = 1;
        aug_err_set(e, AUG_EIO, w->count, "", "write failed");
        e->output = 1;
        return AUG_EIO;
    }
    return 0;
}

static int write_body(aug_writer *w, const char *type, uint32_t flags, int32_t step,
                      uint64_t rawlen, const void *payload, uint64_t plen, aug_err *e)
{
    if (w->open_rec)
        return aug_err_set(e, AUG_EUSAGE, w->count, type, "record %s still open", w->rec_type);
    unsigned char hdr[12 + BODY_HDR];
    uint64_t blen = BODY_HDR + plen;
    put_u64(hdr, blen);
    memcpy(hdr + 8, type, 4);
    put_u32(hdr + 12, flags);
    put_u32(hdr + 16, (uint32_t)step);
    put_u64(hdr + 20, rawlen);
    uint32_t crc = crc_update((uint32_t)crc32(0, Z_NULL, 0), hdr + 8, 4 + BODY_HDR);
    crc = crc_update(crc, payload, plen);
    unsigned char tail[4];
    put_u32(tail, crc);
    if (write_bytes(w, hdr, sizeof hdr, e) || write_bytes(w, payload, plen, e) ||
        write_bytes(w, tail, 4, e))
        return e->code;
    w->count++;
    return 0;
}

int aug_write_begin(aug_writer *w, const char *type, int32_t step, uint64_t len, aug_err *e)
{
    aug_err_clear(e);
    if (!type_wellformed(type) || len > AUG_MAX_BODY - BODY_HDR || w->open_rec)
        return aug_err_set(e, AUG_EUSAGE, w->count, "", "bad record type, length or nesting");
    unsigned char hdr[12 + BODY_HDR];
    put_u64(hdr, BODY_HDR + len);
    memcpy(hdr + 8, type, 4);
    put_u32(hdr + 12, 0);
    put_u32(hdr + 16, (uint32_t)step);
    put_u64(hdr + 20, len);
    if (write_bytes(w, hdr, sizeof hdr, e)) return e->code;
    w->rec_crc = crc_update((uint32_t)crc32(0, Z_NULL, 0), hdr + 8, 4 + BODY_HDR);
    w->rec_left = len;
    w->open_rec = 1;
    memcpy(w->rec_type, type, 5);
    return 0;
}

int aug_write_part(aug_writer *w, const void *p, size_t n, size_t size, aug_err *e)
{
    uint64_t bytes = (uint64_t)n * size;
    if (!w->open_rec || bytes > w->rec_left)
        return aug_err_set(e, AUG_EUSAGE, w->count, w->rec_type, "record part exceeds its length");
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    unsigned char tmp[4096];
    const unsigned char *c = p;
    for (size_t done = 0; done < bytes;) {
        size_t k = bytes - done < sizeof tmp ? bytes - done : sizeof tmp / size * size;
        memcpy(tmp, c + done, k);
        for (size_t i = 0; i < k; i += size)
            for (size_t a = 0, z = size - 1; a < z; a++, z--) {
                unsigned char t = tmp[i + a];
                tmp[i + a] = tmp[i + z];
                tmp[i + z] = t;
            }
        w->rec_crc = crc_update(w->rec_crc, tmp, k);
        if (write_bytes(w, tmp, k, e)) return e->code;
        done += k;
    }
#else
    w->rec_crc = crc_update(w->rec_crc, p, bytes);
    if (write_bytes(w, p, (size_t)bytes, e)) return e->code;
#endif
    w->rec_left -= bytes;
    return 0;
}

int aug_write_end(aug_writer *w, aug_err *e)
{
    if (!w->open_rec || w->rec_left != 0)
        return aug_err_set(e, AUG_EUSAGE, w->count, w->rec_type,
                           "record ended %llu bytes short of its length",
                           (unsigned long long)w->rec_left);
    unsigned char tail[4];
    put_u32(tail, w->rec_crc);
    w->open_rec = 0;
    if (write_bytes(w, tail, 4, e)) return e->code;
    w->count++;
    return 0;
}

aug_writer *aug_writer_open(FILE *f, const char *producer, aug_err *e)
{
    aug_err_clear(e);
    aug_writer *w = aug_calloc(1, sizeof *w);
    if (!w) {
        aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        return NULL;
    }
    w->f = f;
    unsigned char head[8 + 256];
    size_t pl = producer ? strlen(producer) : 0;
    if (pl > 255) pl = 255;
    put_u32(head, AUG_VERSION_MAJOR);
    put_u32(head + 4, AUG_VERSION_MINOR);
    if (pl) memcpy(head + 8, producer, pl);
    if (write_bytes(w, aug_signature, 8, e) ||
        write_body(w, "HEAD", 0, AUG_NOSTEP, 8 + pl, head, 8 + pl, e)) {
        free(w);
        return NULL;
    }
    return w;
}

void aug_writer_deflate(aug_writer *w, uint64_t deflate_min) { w->deflate_min = deflate_min; }
long aug_writer_count(const aug_writer *w) { return w->count; }
uint64_t aug_writer_deflate_min(const aug_writer *w) { return w->deflate_min; }

int aug_write(aug_writer *w, const char *type, int32_t step, const void *payload,
              uint64_t len, aug_err *e)
{
    aug_err_clear(e);
    if (!type_wellformed(type) || len > AUG_MAX_BODY - BODY_HDR)
        return aug_err_set(e, AUG_EUSAGE, w->count, "", "bad record type or length");
    if (w->failed) {
        aug_err_set(e, AUG_EIO, w->count, type, "earlier write failed");
        e->output = 1;
        return AUG_EIO;
    }
    if (w->deflate_min && len >= w->deflate_min && len < ((uint64_t)1 << 31)) {
        uLongf zl = compressBound((uLong)len);
        unsigned char *z = aug_malloc(zl ? zl : 1);
        if (!z) return aug_err_set(e, AUG_ENOMEM, w->count, type, "out of memory");
        if (compress2(z, &zl, payload, (uLong)len, Z_DEFAULT_COMPRESSION) != Z_OK) {
            free(z);
            return aug_err_set(e, AUG_EZLIB, w->count, type, "deflate failed");
        }
        int rc = 0;
        if (zl < len)
            rc = write_body(w, type, AUG_FLAG_DEFLATE, step, len, z, zl, e);
        else
            rc = write_body(w, type, 0, step, len, payload, len, e);
        free(z);
        return rc;
    }
    return write_body(w, type, 0, step, len, payload, len, e);
}

int aug_write_rec(aug_writer *w, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    if (w->open_rec)
        return aug_err_set(e, AUG_EUSAGE, w->count, rec->type, "record %s still open", w->rec_type);
    if (w->failed) {
        aug_err_set(e, AUG_EIO, w->count, rec->type, "earlier write failed");
        e->output = 1;
        return AUG_EIO;
    }
    if (write_bytes(w, rec->wire, rec->wirelen, e)) return e->code;
    w->count++;
    return 0;
}

int aug_writer_close(aug_writer *w, aug_err *e)
{
    if (w->open_rec)
        return aug_err_set(e, AUG_EUSAGE, w->count, "TAIL", "record %s still open", w->rec_type);
    unsigned char n[8];
    put_u64(n, (uint64_t)w->count);
    if (write_body(w, "TAIL", 0, AUG_NOSTEP, 8, n, 8, e)) return e->code;
    if (fflush(w->f) != 0) {
        w->failed = 1;
        aug_err_set(e, AUG_EIO, w->count, "TAIL", "flush failed");
        e->output = 1;
        return AUG_EIO;
    }
    return 0;
}

void aug_writer_free(aug_writer *w) { free(w); }

int aug_check_payload(const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    const aug_rectype *t = aug_rectype_find(rec->type);
    return t && t->codec->check ? t->codec->check(rec, e) : 0;
}

int aug_dump_rec(FILE *out, struct aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    const aug_rectype *t = aug_rectype_find(rec->type);
    if (t && t->codec->dump) return t->codec->dump(out, m, rec, e);
    aug_txt_header(out, rec);
    aug_txt_hex(out, rec);
    return 0;
}

int aug_rec_copy(aug_rec *dst, const aug_rec *src, aug_err *e)
{
    *dst = *src;
    dst->zbuf = aug_malloc((size_t)src->len + 1);
    dst->wire = aug_malloc((size_t)src->wirelen + 1);
    if (!dst->zbuf || !dst->wire) {
        free(dst->zbuf);
        free(dst->wire);
        memset(dst, 0, sizeof *dst);
        return aug_err_set(e, AUG_ENOMEM, src->index, src->type, "out of memory");
    }
    memcpy(dst->zbuf, src->data, (size_t)src->len);
    memcpy(dst->wire, src->wire, (size_t)src->wirelen);
    dst->data = dst->zbuf;
    dst->cap_data = (size_t)src->len + 1;
    dst->cap_wire = (size_t)src->wirelen + 1;
    return 0;
}
