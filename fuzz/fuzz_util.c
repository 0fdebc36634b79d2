/* Shared by the libFuzzer targets: the input as a stream, /dev/null for text. */
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include "fuzz_util.h"

int fuzz_open(fuzz_in *in, const void *data, size_t size, aug_err *e)
{
    memset(in, 0, sizeof *in);
    aug_err_clear(e);
    in->f = size ? fmemopen((void *)data, size, "rb") : NULL;
    if (!in->f) return -1;
    in->r = aug_reader_open(in->f, "fuzz", e);
    if (in->r) return 0;
    fclose(in->f);
    return -1;
}

void fuzz_close(fuzz_in *in)
{
    aug_rec_free(&in->rec);
    aug_reader_free(in->r);
    fclose(in->f);
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
