/* Shared by the libFuzzer targets: the input as a stream, /dev/null for text. */
#ifndef FUZZ_UTIL_H
#define FUZZ_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include "augcut.h"

/* A reader over data[size] (its FILE in *f, closed by fuzz_close), or NULL. */
aug_reader *fuzz_open(const uint8_t *data, size_t size, FILE **f);
void fuzz_close(aug_reader *r, FILE *f, aug_rec *rec);
/* /dev/null opened for writing once, for dumps and summaries. */
FILE *fuzz_devnull(void);
/* A finding: the message on stderr, then abort() so that libFuzzer keeps the input. */
void fuzz_fail(const char *fmt, ...) __attribute__((noreturn, format(printf, 1, 2)));

#endif
