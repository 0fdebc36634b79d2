/* Shared by the libFuzzer targets: the input as a stream, /dev/null for text. */
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include "fuzz_util.h"

aug_reader *fuzz_open(const uint8_t *data, size_t size, FILE **f)
{
    aug_err e;
    *f = size ? fmemopen((void *)data, size, "rb") : NULL;
    if (!*f) return NULL;
    aug_reader *r = aug_reader_open(*f, "fuzz", &e);
    if (!r) fclose(*f);
    return r;
}

void fuzz_close(aug_reader *r, FILE *f, aug_rec *rec)
{
    aug_rec_free(rec);
    aug_reader_free(r);
    fclose(f);
}

FILE *fuzz_devnull(void)
{
    static FILE *null;
    if (!null && !(null = fopen("/dev/null", "w"))) abort();
    return null;
}

void fuzz_fail(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    abort();
}
