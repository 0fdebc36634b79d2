/* Bench helper: the stream library as a filter that changes nothing (read,
   CRC-check and inflate every record, write it again byte for byte).
   stream_pass < in > out          one pass, as a pipeline stage
   stream_pass -n K FILE           K passes in memory (FILE read once, output to
                                   /dev/null); prints "copy_s cold_s warm_s":
                                   median seconds of a memcpy of FILE into a
                                   buffer already touched, of a
                                   stream pass-through whose buffers are fresh
                                   pages (as in a new process: page faults
                                   included), and of one whose buffers reuse
                                   memory already touched (malloc keeps freed
                                   pages) */
#include <malloc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "aug_stream.h"

static int pass(FILE *in, FILE *out, const char *name)
{
    aug_err e;
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    aug_reader *r = aug_reader_open(in, name, &e);
    aug_writer *w = r ? aug_writer_open(out, "stream_pass", &e) : NULL;
    int rc = w ? 1 : -1;
    while (rc == 1 && (rc = aug_read(r, &rec, &e)) == 1)
        if (aug_write_rec(w, &rec, &e)) rc = -1;
    if (rc == 0 && aug_writer_close(w, &e)) rc = -1;
    if (rc < 0) fprintf(stderr, "stream_pass: %s: record %ld (%s): %s\n", name, e.record, e.type, e.msg);
    aug_rec_free(&rec);
    aug_writer_free(w);
    aug_reader_free(r);
    return rc < 0;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    if (argc == 1) return pass(stdin, stdout, "-");
    long k = argc == 4 && !strcmp(argv[1], "-n") ? strtol(argv[2], NULL, 10) : 0;
    FILE *f = k > 0 ? fopen(argv[3], "rb") : NULL;
    if (!f) {
        fprintf(stderr, "usage: stream_pass [-n K FILE]\n");
        return 2;
    }
    fseek(f, 0, SEEK_END);
    size_t n = (size_t)ftell(f);
    rewind(f);
    char *buf = malloc(n), *dst = malloc(n);
    FILE *null = fopen("/dev/null", "wb");
    double *tc = malloc((size_t)k * sizeof *tc), *tp = malloc((size_t)k * sizeof *tp);
    if (!buf || !dst || !null || !tc || !tp || fread(buf, 1, n, f) != n) return 1;
    memset(dst, 1, n);
    fclose(f);
    double *tw = malloc((size_t)k * sizeof *tw);
    if (!tw) return 1;
    for (int warm = 0; warm < 2; warm++) {
        if (warm) { /* keep freed memory in the heap: later passes reuse touched pages */
            mallopt(M_MMAP_THRESHOLD, 1 << 30);
            mallopt(M_TRIM_THRESHOLD, 1 << 30);
        }
        for (long i = 0; i < k; i++) {
            double t0 = now();
            if (!warm) memcpy(dst, buf, n);
            double t1 = now();
            FILE *in = fmemopen(buf, n, "rb");
            if (!in || pass(in, null, argv[3])) return 1;
            fclose(in);
            if (!warm) tc[i] = t1 - t0, tp[i] = now() - t1;
            else tw[i] = now() - t1;
        }
    }
    qsort(tc, (size_t)k, sizeof *tc, cmp);
    qsort(tp, (size_t)k, sizeof *tp, cmp);
    qsort(tw, (size_t)k, sizeof *tw, cmp);
    printf("%.9f %.9f %.9f\n", tc[k / 2], tp[k / 2], tw[k / 2]);
    free(tw);
    if (dst[n / 2] != buf[n / 2]) return 1; /* keeps the copy */
    free(buf), free(dst), free(tc), free(tp), fclose(null);
    return 0;
}
