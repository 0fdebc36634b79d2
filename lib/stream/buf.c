/* Payload building and bounds-checked parsing (little-endian), and the
   allocation hook used for failure-injection tests. */
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include "aug_stream.h"

static long fail_countdown = -1;

/* the n-th allocation from now fails (n >= 0); n < 0 disables */
void aug_fail_after(long n) { fail_countdown = n; }

static int fail_now(void)
{
    if (fail_countdown < 0) return 0;
    if (fail_countdown == 0) return 1;
    fail_countdown--;
    return 0;
}

void *aug_malloc(size_t n) { return fail_now() ? NULL : malloc(n ? n : 1); }
void *aug_calloc(size_t n, size_t size) { return fail_now() ? NULL : calloc(n ? n : 1, size ? size : 1); }
void *aug_realloc(void *p, size_t n) { return fail_now() ? NULL : realloc(p, n ? n : 1); }

#define BIG ((size_t)4 << 20)
#define HUGE_PAGE ((size_t)2 << 20)

void *aug_regrow(void *p, size_t used, size_t n)
{
    if (n < BIG) return aug_realloc(p, n);
    if (fail_now()) return NULL;
    void *q = NULL;
    size_t nc = (n + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
    if (posix_memalign(&q, HUGE_PAGE, nc) != 0) return NULL;
#ifdef MADV_HUGEPAGE
    madvise(q, nc, MADV_HUGEPAGE);
#endif
    if (used) memcpy(q, p, used);
    free(p);
    return q;
}

void aug_buf_init(aug_buf *b) { memset(b, 0, sizeof *b); }
void aug_buf_free(aug_buf *b)
{
    free(b->p);
    memset(b, 0, sizeof *b);
}

void aug_buf_put(aug_buf *b, const void *src, size_t n)
{
    if (b->failed || n == 0) return;
    if (b->len + n > b->cap) {
        size_t nc = b->cap ? b->cap : 256;
        while (nc < b->len + n) nc *= 2;
        unsigned char *q = aug_regrow(b->p, b->len, nc);
        if (!q) {
            b->failed = 1;
            return;
        }
        b->p = q;
        b->cap = nc;
    }
    memcpy(b->p + b->len, src, n);
    b->len += n;
}

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#define AUG_BIG 1
#else
#define AUG_BIG 0
#endif

static void swap_n(void *p, size_t n, size_t size)
{
    unsigned char *c = p;
    for (size_t i = 0; i < n; i++, c += size)
        for (size_t a = 0, z = size - 1; a < z; a++, z--) {
            unsigned char t = c[a];
            c[a] = c[z];
            c[z] = t;
        }
}

static void put_le(aug_buf *b, const void *v, size_t n, size_t size)
{
    size_t start = b->len;
    aug_buf_put(b, v, n * size);
    if (AUG_BIG && !b->failed) swap_n(b->p + start, n, size);
}

void aug_buf_i32(aug_buf *b, int32_t v) { put_le(b, &v, 1, 4); }
void aug_buf_i64(aug_buf *b, int64_t v) { put_le(b, &v, 1, 8); }
void aug_buf_f64(aug_buf *b, double v) { put_le(b, &v, 1, 8); }
void aug_buf_i32v(aug_buf *b, const int32_t *v, size_t n) { put_le(b, v, n, 4); }
void aug_buf_i64v(aug_buf *b, const int64_t *v, size_t n) { put_le(b, v, n, 8); }
void aug_buf_f64v(aug_buf *b, const double *v, size_t n) { put_le(b, v, n, 8); }

void aug_buf_name(aug_buf *b, const char *s)
{
    char n[64];
    memset(n, 0, sizeof n);
    if (s) strncpy(n, s, sizeof n - 1);
    aug_buf_put(b, n, sizeof n);
}

void aug_cur_init(aug_cur *c, const aug_rec *rec)
{
    c->p = rec->data;
    c->len = rec->len;
    c->pos = 0;
    c->ok = 1;
}

int aug_cur_has(const aug_cur *c, uint64_t n, uint64_t size)
{
    uint64_t left = c->len - c->pos;
    return c->ok && size > 0 && n <= left / size;
}

static int get_le(aug_cur *c, void *dst, uint64_t n, size_t size)
{
    if (!aug_cur_has(c, n, size)) {
        c->ok = 0;
        if (dst && n < ((uint64_t)1 << 40) / size) memset(dst, 0, (size_t)(n * size));
        return 0;
    }
    if (dst) {
        memcpy(dst, c->p + c->pos, (size_t)(n * size));
        if (AUG_BIG) swap_n(dst, (size_t)n, size);
    }
    c->pos += n * size;
    return 1;
}

int32_t aug_cur_i32(aug_cur *c)
{
    int32_t v = 0;
    get_le(c, &v, 1, 4);
    return v;
}
int64_t aug_cur_i64(aug_cur *c)
{
    int64_t v = 0;
    get_le(c, &v, 1, 8);
    return v;
}
double aug_cur_f64(aug_cur *c)
{
    double v = 0;
    get_le(c, &v, 1, 8);
    return v;
}
void aug_cur_i32v(aug_cur *c, int32_t *dst, uint64_t n) { get_le(c, dst, n, 4); }
void aug_cur_i64v(aug_cur *c, int64_t *dst, uint64_t n) { get_le(c, dst, n, 8); }
void aug_cur_f64v(aug_cur *c, double *dst, uint64_t n) { get_le(c, dst, n, 8); }

void aug_cur_name(aug_cur *c, char dst[64])
{
    if (get_le(c, dst, 64, 1)) dst[63] = 0;
    else dst[0] = 0;
}

int aug_buf_write(aug_writer *w, const char *type, int32_t step, aug_buf *b, aug_err *e)
{
    int rc = b->failed ? aug_err_set(e, AUG_ENOMEM, aug_writer_count(w), type, "out of memory")
                       : aug_write(w, type, step, b->p, b->len, e);
    aug_buf_free(b);
    return rc;
}
