/* Shared by the libFuzzer targets: the input as a stream, /dev/null for text. */
#ifndef FUZZ_UTIL_H
#define FUZZ_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include "augcut.h"

/* A stream in memory being read: its FILE, the reader, the current record. */
typedef struct fuzz_in {
    FILE *f;
    aug_reader *r;
    aug_rec rec;
} fuzz_in;
/* Open a reader over data[size]: 0, or -1 when it does not open (e filled). */
int fuzz_open(fuzz_in *in, const void *data, size_t size, aug_err *e);
void fuzz_close(fuzz_in *in);
/* /dev/null opened for writing once, for dumps and summaries. */
FILE *fuzz_devnull(void);
/* A finding: the message on stderr, then abort() so that libFuzzer keeps the input. */
void fuzz_fail(const char *fmt, ...) __attribute__((noreturn, format(printf, 1, 2)));

#endif
