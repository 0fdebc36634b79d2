/* augcut stream layer: record framing, validation, pass-through (formats/stream.md). */
#ifndef AUG_STREAM_H
#define AUG_STREAM_H

#include <stdint.h>
#include <stdio.h>
#include <stddef.h>

#define AUG_VERSION_MAJOR 1
#define AUG_VERSION_MINOR 0
#define AUG_VERSION_STRING "1.0.0"

/* The 8-byte signature: high bit, name, CR LF, ^Z, LF (as PNG). */
extern const unsigned char aug_signature[8];

/* Error codes (aug_err.code). 0 is success. */
enum {
    AUG_OK = 0,
    AUG_EIO,        /* read/write failure of the underlying file */
    AUG_ESIG,       /* bad signature */
    AUG_ETRUNC,     /* stream ends inside a record or without a TAIL record */
    AUG_ECRC,       /* CRC mismatch */
    AUG_ELEN,       /* impossible length */
    AUG_ETYPE,      /* malformed or unknown critical type */
    AUG_EORDER,     /* record out of order or repeated */
    AUG_EVERSION,   /* unsupported format version */
    AUG_EPAYLOAD,   /* payload does not match its record's layout */
    AUG_ENOMEM,     /* allocation failed */
    AUG_EZLIB,      /* deflate/inflate failure */
    AUG_EDATA,      /* payload is well formed but its content is invalid */
    AUG_ESINGULAR,  /* a matrix is singular / not positive definite */
    AUG_ENOCONV,    /* an iterative method did not converge */
    AUG_EUSAGE      /* invalid argument to a library function */
};

/* Error report filled by every library function that can fail. */
typedef struct aug_err {
    int code;
    long record;       /* 0-based index of the record in its stream, -1 if none */
    char type[5];      /* its 4-letter type, "" if none */
    char msg[256];
    int output;        /* 1 when the error concerns the output stream */
} aug_err;

void aug_err_clear(aug_err *e);
/* Fill e (code, record, type, printf-style message); returns code. */
int aug_err_set(aug_err *e, int code, long record, const char *type, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));


/* Record flags (u32 in every record body). */
#define AUG_FLAG_DEFLATE 1u   /* payload is zlib-deflated */
#define AUG_NOSTEP (-1)        /* step value of records that are not per-step */

/* One record as read: type, flags, step, the inflated payload, and the exact
   wire bytes (for byte-identical pass-through). */
typedef struct aug_rec {
    char type[5];
    uint32_t flags;
    int32_t step;
    long index;                /* 0-based index in the stream it came from */
    unsigned char *data;       /* inflated payload (points into wire or zbuf) */
    uint64_t len;              /* its length */
    unsigned char *wire;       /* length|type|body|crc exactly as read */
    uint64_t wirelen;
    unsigned char *zbuf;       /* inflation buffer, owned */
    size_t cap_data, cap_wire; /* internal buffer capacities (zbuf, wire) */
} aug_rec;

/* Property bits carried by the letter case of a type. */
int aug_type_critical(const char *type);     /* first letter upper case */
int aug_type_safe_to_copy(const char *type); /* fourth letter lower case */

/* Known record kinds: see aug_record_table in stream.c and formats/stream.md. */
/* Record codecs: one per record type, in the file of its record family
   (formats/stream.md 3.3, column "codec"), bound to the type in the record
   table. check validates a payload on its own, behind the CRC: sizes against
   counts, index ranges and orders, finite values. dump prints it for
   stats --dump, decoding (and so checking) it first: a bad record prints
   nothing; m holds the mesh records seen so far (the mesh codecs absorb into
   it, the step codecs read its dimension and element size). The typed read
   and write functions of each codec are declared in its layer's header. */
struct aug_mesh;
typedef struct aug_codec {
    const char *file;          /* lib/LAYER/FAMILY.c */
    int (*check)(const struct aug_rec *rec, aug_err *e);
    int (*dump)(FILE *out, struct aug_mesh *m, const struct aug_rec *rec, aug_err *e);
} aug_codec;
extern const aug_codec aug_codec_head, aug_codec_prov, aug_codec_tail, aug_codec_plan;
extern const aug_codec aug_codec_mode; /* lib/modal/mode_rec.c */
extern const aug_codec aug_codec_node, aug_codec_matl, aug_codec_elem, aug_codec_nset,
    aug_codec_fixd, aug_codec_load, aug_codec_outs, aug_codec_grav, aug_codec_fndn;
extern const aug_codec aug_codec_dofm, aug_codec_kmat, aug_codec_fvec, aug_codec_fact,
    aug_codec_feld;
extern const aug_codec aug_codec_mdlt, aug_codec_updt, aug_codec_upkm, aug_codec_bdlt, aug_codec_path;
extern const aug_codec aug_codec_dynp, aug_codec_fram;
extern const aug_codec aug_codec_kv;   /* cOND sTAt tIMe qUAl */
extern const aug_codec aug_codec_reac; /* rEAC */

typedef struct aug_rectype {
    const char *type;
    uint64_t minlen, maxlen;   /* inflated payload length bounds */
    int phase;                 /* 0 head, 1 mesh, 2 matrix, 3 steps, 4 tail; -1 anywhere */
    int once;                  /* at most once per stream */
    int perstep;               /* carries a step number >= 0 */
    const aug_codec *codec;
} aug_rectype;
const aug_rectype *aug_rectype_find(const char *type);
/* 1 when rec is a record a cut step's changes come in (MDLT, BDLT, UPKM,
   UPDT: formats/stream.md 7; the first of a step ends the original
   system's records) */
int aug_rec_changes_step(const aug_rec *rec);
/* The i-th row of the record table, NULL past its end. */
const aug_rectype *aug_rectype_at(size_t i);

typedef struct aug_reader aug_reader;
typedef struct aug_writer aug_writer;

/* Open a stream for reading; checks the signature and the HEAD record. name is
   used in messages. Returns NULL and fills e on failure. */
aug_reader *aug_reader_open(FILE *f, const char *name, aug_err *e);
/* Next record after HEAD. Returns 1 with rec filled, 0 at TAIL (the stream is
   whole), or -1 with e filled. Unknown ancillary records are returned (the
   caller passes them through); unknown critical records are an error. */
int aug_read(aug_reader *r, aug_rec *rec, aug_err *e);
/* The upstream HEAD's producer string and minor version. */
const char *aug_reader_producer(const aug_reader *r);
/* The HEAD record as read: minor version, flags, payload length (inflated) and
   wire length (length|type|body|crc). */
void aug_reader_head(const aug_reader *r, uint32_t *minor, uint32_t *flags, uint64_t *len,
                     uint64_t *wirelen);
void aug_reader_free(aug_reader *r);
void aug_rec_free(aug_rec *rec);             /* frees buffers, not rec itself */

/* Open a stream for writing: writes the signature and the HEAD record.
   deflate_min: payloads at least this long are deflated (0: never). */
aug_writer *aug_writer_open(FILE *f, const char *producer, aug_err *e);
void aug_writer_deflate(aug_writer *w, uint64_t deflate_min);
uint64_t aug_writer_deflate_min(const aug_writer *w);
/* Write one record with the given payload. */
int aug_write(aug_writer *w, const char *type, int32_t step, const void *payload,
              uint64_t len, aug_err *e);
/* Write a large record in parts without building its payload in memory:
   begin with the payload length, add parts of n elements of `size` bytes
   (byte-swapped to little-endian where needed), end checks the length and
   writes the CRC. Such records are never deflated. */
int aug_write_begin(aug_writer *w, const char *type, int32_t step, uint64_t len, aug_err *e);
int aug_write_part(aug_writer *w, const void *p, size_t n, size_t size, aug_err *e);
int aug_write_end(aug_writer *w, aug_err *e);
/* Write a record read from another stream byte for byte. */
int aug_write_rec(aug_writer *w, const aug_rec *rec, aug_err *e);
/* pROv (lib/stream/frame_rec.c): "augcut VERSION\nargv[0] argv[1] ..." */
int aug_write_prov(aug_writer *w, int argc, char **argv, aug_err *e);
/* its text as a NUL-terminated copy (free it) */
int aug_read_prov(const aug_rec *rec, char **text, aug_err *e);
/* pLAN (formats/stream.md 4.4): the cut steps first..last that the stream
   brings after it (1 <= first <= last); read checks the range */
int aug_write_plan(aug_writer *w, int32_t first, int32_t last, aug_err *e);
int aug_read_plan(const aug_rec *rec, int32_t *first, int32_t *last, aug_err *e);
/* HEAD as stats --dump prints it (record #0, consumed by aug_reader_open) */
int aug_dump_head(FILE *out, const aug_reader *r, aug_err *e);
/* Payload checks and stats --dump text through the record table: the codec of
   rec's type; records without a codec (unknown ancillary ones) pass check and
   dump as hex. */
int aug_check_payload(const aug_rec *rec, aug_err *e);
int aug_dump_rec(FILE *out, struct aug_mesh *m, const aug_rec *rec, aug_err *e);
/* Deep copy of a record (payload and wire bytes in buffers of its own, freed by
   aug_rec_free), for tools that hold a step's records before writing them. */
int aug_rec_copy(aug_rec *dst, const aug_rec *src, aug_err *e);
/* Write TAIL and flush. Without this call the stream is incomplete, on purpose. */
int aug_writer_close(aug_writer *w, aug_err *e);
void aug_writer_free(aug_writer *w);
long aug_writer_count(const aug_writer *w);

/* Payload building (little-endian on the wire). */
typedef struct aug_buf {
    unsigned char *p;
    size_t len, cap;
    int failed;           /* set when an allocation failed; all later puts are no-ops */
} aug_buf;
void aug_buf_init(aug_buf *b);
void aug_buf_free(aug_buf *b);
/* The record type/step with b's bytes as payload (aug_write), or AUG_ENOMEM
   naming the record when b failed to grow; b is freed either way. */
int aug_buf_write(aug_writer *w, const char *type, int32_t step, aug_buf *b, aug_err *e);
void aug_buf_put(aug_buf *b, const void *src, size_t n);
void aug_buf_i32(aug_buf *b, int32_t v);
void aug_buf_i64(aug_buf *b, int64_t v);
void aug_buf_f64(aug_buf *b, double v);
void aug_buf_i32v(aug_buf *b, const int32_t *v, size_t n);
void aug_buf_i64v(aug_buf *b, const int64_t *v, size_t n);
void aug_buf_f64v(aug_buf *b, const double *v, size_t n);
void aug_buf_name(aug_buf *b, const char *s);  /* fixed 64-byte NUL-padded name */

/* Payload parsing with bounds checks: a get past the end sets ok = 0 and
   returns zero values; check cur.ok once at the end. */
typedef struct aug_cur {
    const unsigned char *p;
    uint64_t len, pos;
    int ok;
} aug_cur;
void aug_cur_init(aug_cur *c, const aug_rec *rec);
int32_t aug_cur_i32(aug_cur *c);
int64_t aug_cur_i64(aug_cur *c);
double aug_cur_f64(aug_cur *c);
/* Copy n elements into dst (dst may be NULL to skip). */
void aug_cur_i32v(aug_cur *c, int32_t *dst, uint64_t n);
void aug_cur_i64v(aug_cur *c, int64_t *dst, uint64_t n);
void aug_cur_f64v(aug_cur *c, double *dst, uint64_t n);
void aug_cur_name(aug_cur *c, char dst[64]);
/* Remaining bytes >= n*size, without overflow. */
int aug_cur_has(const aug_cur *c, uint64_t n, uint64_t size);

/* stats --dump text helpers (lib/stream/dumptext.c), used by every codec:
   "#N TYPE step=S flags=F len=L"; escaped names; %.17g floats; arrays
   "  label[n]" with 10 integers or 4 floats a line; row tables "label[r x c]". */
void aug_txt_header(FILE *o, const aug_rec *rec);
void aug_txt_esc(FILE *o, const char *s, size_t n, int quote);
void aug_txt_name(FILE *o, const char *label, const char *s, size_t cap);
void aug_txt_f(FILE *o, double v);
void aug_txt_i32s(FILE *o, const char *label, aug_cur *c, uint64_t n);
void aug_txt_i64s(FILE *o, const char *label, aug_cur *c, uint64_t n);
void aug_txt_f64s(FILE *o, const char *label, aug_cur *c, uint64_t n);
void aug_txt_rows_i32(FILE *o, const char *label, aug_cur *c, uint64_t rows, int cols);
void aug_txt_rows_f64(FILE *o, const char *label, aug_cur *c, uint64_t rows, int cols);
void aug_txt_hex(FILE *o, const aug_rec *rec);
aug_cur aug_cur_mem(const void *p, uint64_t bytes);
/* dst = src with control bytes written \xNN (names from records in text for people) */
const char *aug_txt_clean(char *dst, size_t cap, const char *src);

/* Named-value records (cOND sTAt tIMe qUAl): a tag (method or tool name) and
   up to AUG_KV_MAX (key, float64) pairs, in insertion order. */
#define AUG_KV_MAX 64
typedef struct aug_kv {
    char tag[16];
    int n;
    char key[AUG_KV_MAX][16];
    double val[AUG_KV_MAX];
} aug_kv;
void aug_kv_init(aug_kv *kv, const char *tag);
/* Set key (replacing an existing one); returns 0, or -1 when full. */
int aug_kv_set(aug_kv *kv, const char *key, double v);
/* Value of key, or def when absent. */
double aug_kv_get(const aug_kv *kv, const char *key, double def);
int aug_write_kv(aug_writer *w, const char *type, int32_t step, const aug_kv *kv, aug_err *e);
int aug_read_kv(const aug_rec *rec, aug_kv *kv, aug_err *e);

/* Monotonic wall clock in seconds (lib/stream/clock.c). */
double aug_now(void);

/* The n finite numbers of "x1,...,xn" into v[0..n), 1 <= n <= max: n, else -1
   (lib/stream/parse_reals.c; the specs of the scene and cut options). */
int aug_parse_reals(const char *s, double *v, int max);

/* Failure injection for tests: the n-th allocation through aug_malloc fails
   (n < 0: never). */
void aug_fail_after(long n);
void *aug_malloc(size_t n);
void *aug_calloc(size_t n, size_t size);
void *aug_realloc(void *p, size_t n);
/* Resize a buffer holding `used` bytes to at least n; large buffers are
   2 MiB-aligned and advised for transparent huge pages (fewer page faults). */
void *aug_regrow(void *p, size_t used, size_t n);

#endif
