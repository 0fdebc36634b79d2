/* Framing-family codecs (formats/stream.md 4): HEAD, pROv, pLAN, TAIL. The writer
   and reader frame HEAD and TAIL themselves; these are their checks and text. */
#include <stdlib.h>
#include <string.h>
#include "aug_stream.h"

static uint32_t u32_at(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* HEAD: u32 major, u32 minor, producer bytes */
static void head_text(FILE *o, uint32_t flags, uint64_t len, uint32_t minor, const char *p,
                      size_t n)
{
    fprintf(o, "#0 HEAD step=-1 flags=%u len=%llu\n", (unsigned)flags, (unsigned long long)len);
    fprintf(o, "  major %d\n  minor %u\n", AUG_VERSION_MAJOR, (unsigned)minor);
    fprintf(o, "  producer ");
    aug_txt_esc(o, p, n, 1);
    fputc('\n', o);
}

int aug_dump_head(FILE *out, const aug_reader *r, aug_err *e)
{
    aug_err_clear(e);
    uint32_t minor, flags;
    uint64_t len, wl;
    aug_reader_head(r, &minor, &flags, &len, &wl);
    const char *p = aug_reader_producer(r);
    head_text(out, flags, len, minor, p, strlen(p));
    if (ferror(out)) return aug_err_set(e, AUG_EIO, 0, "HEAD", "write failed");
    return 0;
}

static int head_check(const aug_rec *rec, aug_err *e)
{
    if (rec->len < 8) return aug_err_set(e, AUG_EPAYLOAD, rec->index, "HEAD", "shorter than 8 bytes");
    if (u32_at(rec->data) != AUG_VERSION_MAJOR)
        return aug_err_set(e, AUG_EVERSION, rec->index, "HEAD", "format version %u not supported",
                           (unsigned)u32_at(rec->data));
    return 0;
}

static int head_dump(FILE *o, struct aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    if (head_check(rec, e)) return e->code;
    size_t n = strnlen((const char *)rec->data + 8, (size_t)rec->len - 8);
    head_text(o, rec->flags, rec->len, u32_at(rec->data + 4), (const char *)rec->data + 8, n);
    return 0;
}

int aug_write_prov(aug_writer *w, int argc, char **argv, aug_err *e)
{
    aug_buf b;
    aug_buf_init(&b);
    const char *ver = "augcut " AUG_VERSION_STRING;
    aug_buf_put(&b, ver, strlen(ver));
    for (int i = 0; i < argc; i++) {
        aug_buf_put(&b, i == 0 ? "\n" : " ", 1);
        aug_buf_put(&b, argv[i], strlen(argv[i]));
    }
    return aug_buf_write(w, "pROv", AUG_NOSTEP, &b, e);
}

int aug_read_prov(const aug_rec *rec, char **text, aug_err *e)
{
    aug_err_clear(e);
    *text = aug_malloc((size_t)rec->len + 1);
    if (!*text) return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    memcpy(*text, rec->data, (size_t)rec->len);
    (*text)[rec->len] = 0;
    return 0;
}

/* pROv: any bytes; printed one escaped line per text line */
static int prov_dump(FILE *o, struct aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m, (void)e;
    aug_txt_header(o, rec);
    const char *s = (const char *)rec->data;
    uint64_t n = rec->len, a = 0;
    fprintf(o, "  text[%llu]\n", (unsigned long long)n);
    while (a < n) {
        uint64_t b = a;
        while (b < n && s[b] != '\n') b++;
        fputs("    ", o);
        aug_txt_esc(o, s + a, (size_t)(b - a), 1);
        fputc('\n', o);
        a = b + 1;
    }
    if (n && s[n - 1] == '\n') fputs("    \"\"\n", o);
    return 0;
}

/* pLAN: i32 first, i32 last, the cut steps the stream brings after it */
int aug_write_plan(aug_writer *w, int32_t first, int32_t last, aug_err *e)
{
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, first);
    aug_buf_i32(&b, last);
    return aug_buf_write(w, "pLAN", AUG_NOSTEP, &b, e);
}

int aug_read_plan(const aug_rec *rec, int32_t *first, int32_t *last, aug_err *e)
{
    aug_err_clear(e);
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t a = aug_cur_i32(&c), b = aug_cur_i32(&c);
    if (!c.ok || c.pos != c.len) return aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type, "payload is not 8 bytes");
    if (!(a >= 1 && a <= b))
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "steps %d to %d: not 1 <= first <= last", (int)a,
                           (int)b);
    *first = a, *last = b;
    return 0;
}

static int plan_check(const aug_rec *rec, aug_err *e)
{
    int32_t a, b;
    return aug_read_plan(rec, &a, &b, e);
}

static int plan_dump(FILE *o, struct aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    int32_t a, b;
    if (aug_read_plan(rec, &a, &b, e)) return e->code;
    aug_txt_header(o, rec);
    fprintf(o, "  first %d\n  last %d\n", (int)a, (int)b);
    return 0;
}

/* TAIL: u64 count of the records before it (the reader compares it) */
static int tail_check(const aug_rec *rec, aug_err *e)
{
    if (rec->len != 8) return aug_err_set(e, AUG_EPAYLOAD, rec->index, "TAIL", "not 8 bytes");
    return 0;
}

static int tail_dump(FILE *o, struct aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    if (tail_check(rec, e)) return e->code;
    aug_cur c;
    aug_cur_init(&c, rec);
    aug_txt_header(o, rec);
    fprintf(o, "  count %llu\n", (unsigned long long)aug_cur_i64(&c));
    return 0;
}

const aug_codec aug_codec_head = {"lib/stream/frame_rec.c", head_check, head_dump};
const aug_codec aug_codec_prov = {"lib/stream/frame_rec.c", NULL, prov_dump};
const aug_codec aug_codec_tail = {"lib/stream/frame_rec.c", tail_check, tail_dump};
const aug_codec aug_codec_plan = {"lib/stream/frame_rec.c", plan_check, plan_dump};
