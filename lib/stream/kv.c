/* Key/value family codec (formats/stream.md 6.5, 7.4): cOND sTAt tIMe qUAl, a
   tag, a count and (key[16], f64) pairs. */
#include <string.h>
#include "aug_stream.h"

void aug_kv_init(aug_kv *kv, const char *tag)
{
    memset(kv, 0, sizeof *kv);
    strncpy(kv->tag, tag ? tag : "", sizeof kv->tag - 1);
}

int aug_kv_set(aug_kv *kv, const char *key, double v)
{
    for (int i = 0; i < kv->n; i++)
        if (strncmp(kv->key[i], key, 15) == 0) {
            kv->val[i] = v;
            return 0;
        }
    if (kv->n >= AUG_KV_MAX) return -1;
    memset(kv->key[kv->n], 0, 16);
    strncpy(kv->key[kv->n], key, 15);
    kv->val[kv->n++] = v;
    return 0;
}

double aug_kv_get(const aug_kv *kv, const char *key, double def)
{
    for (int i = 0; i < kv->n; i++)
        if (strncmp(kv->key[i], key, 15) == 0) return kv->val[i];
    return def;
}

int aug_write_kv(aug_writer *w, const char *type, int32_t step, const aug_kv *kv, aug_err *e)
{
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_put(&b, kv->tag, 16);
    aug_buf_i32(&b, kv->n);
    aug_buf_i32(&b, 0);
    for (int i = 0; i < kv->n; i++) {
        aug_buf_put(&b, kv->key[i], 16);
        aug_buf_f64(&b, kv->val[i]);
    }
    return aug_buf_write(w, type, step, &b, e);
}

int aug_read_kv(const aug_rec *rec, aug_kv *kv, aug_err *e)
{
    aug_err_clear(e);
    aug_cur c;
    aug_cur_init(&c, rec);
    memset(kv, 0, sizeof *kv);
    if (aug_cur_has(&c, 16, 1)) memcpy(kv->tag, c.p, 16);
    c.pos += 16;
    kv->tag[15] = 0;
    int32_t n = aug_cur_i32(&c);
    aug_cur_i32(&c);
    if (!c.ok || n < 0 || n > AUG_KV_MAX || c.len - c.pos != (uint64_t)n * 24)
        return aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type, "bad named-value count %d", (int)n);
    for (int i = 0; i < n; i++) {
        memcpy(kv->key[i], c.p + c.pos, 16);
        kv->key[i][15] = 0;
        c.pos += 16;
        kv->val[i] = aug_cur_f64(&c);
    }
    kv->n = n;
    return 0;
}

static int kv_check(const aug_rec *rec, aug_err *e)
{
    aug_kv kv;
    return aug_read_kv(rec, &kv, e);
}

static int kv_dump(FILE *o, struct aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    aug_kv kv;
    if (aug_read_kv(rec, &kv, e)) return e->code;
    aug_txt_header(o, rec);
    aug_txt_name(o, "tag", kv.tag, sizeof kv.tag);
    fprintf(o, "  n %d\n", kv.n);
    for (int i = 0; i < kv.n; i++) { /* indented: a key may be called "n" too */
        fputs("    ", o);
        aug_txt_esc(o, kv.key[i], strnlen(kv.key[i], 16), 0);
        fputc(' ', o);
        aug_txt_f(o, kv.val[i]);
        fputc('\n', o);
    }
    return 0;
}

const aug_codec aug_codec_kv = {"lib/stream/kv.c", kv_check, kv_dump};
