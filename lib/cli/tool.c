/* Messages, exit codes and stream set-up shared by every tool. */
#include <errno.h>
#include <malloc.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "aug_tool.h"

void aug_tool_init(aug_tool *t, const char *prog, int argc, char **argv)
{
    /* filters allocate and free large work arrays per record or step: keep
       freed memory mapped (no mmap below 64 MiB, no trimming below 256 MiB),
       so that a step does not pay first-touch page faults again */
    mallopt(M_MMAP_THRESHOLD, 1 << 26);
    mallopt(M_TRIM_THRESHOLD, 1 << 28);
    memset(t, 0, sizeof *t);
    t->prog = prog;
    t->argc = argc;
    t->argv = argv;
    t->inname = "-";
}

void aug_tool_usage(aug_tool *t, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "%s: ", t->prog);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    t->usage_errors++;
}

void aug_tool_cmdline_end(aug_tool *t)
{
    t->cmdline_errors = t->usage_errors;
    t->cmdline_ended = 1;
}

void aug_tool_usage_done(aug_tool *t, const char *synopsis)
{
    if (!t->usage_errors) return;
    if (t->cmdline_ended && !t->cmdline_errors) exit(1);
    fprintf(stderr, "usage: %s\n", synopsis);
    exit(2);
}

void aug_tool_fail(aug_tool *t, const aug_err *e)
{
    aug_progress(t, -1, 0);
    const char *where = t->inname;
    if (e->output) where = "<stdout>";
    if (e->record >= 0)
        fprintf(stderr, "%s: %s: record %ld (%s): %s\n", t->prog, where, e->record,
                e->type[0] ? e->type : "?", e->msg);
    else if (e->type[0])
        fprintf(stderr, "%s: %s: %s: %s\n", t->prog, where, e->type, e->msg);
    else
        fprintf(stderr, "%s: %s: %s\n", t->prog, where, e->msg);
    exit(1);
}

void aug_tool_die(aug_tool *t, const char *fmt, ...)
{
    va_list ap;
    aug_progress(t, -1, 0);
    fprintf(stderr, "%s: ", t->prog);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    exit(1);
}

void aug_tool_check(aug_tool *t, int rc, const aug_err *e)
{
    if (rc) aug_tool_fail(t, e);
}

void aug_tool_open_in(aug_tool *t, const char *path)
{
    aug_err e;
    if (path && strcmp(path, "-") != 0) {
        t->in = fopen(path, "rb");
        if (!t->in) aug_tool_die(t, "%s: %s", path, strerror(errno));
        struct stat st; /* a directory opens, then reads as nothing: say what it is */
        if (fstat(fileno(t->in), &st) == 0 && S_ISDIR(st.st_mode)) aug_tool_die(t, "%s: is a directory", path);
        t->inname = path;
    } else {
        if (isatty(0)) aug_tool_die(t, "-: refusing to read a stream from a terminal");
        t->in = stdin;
        t->inname = "-";
    }
    t->r = aug_reader_open(t->in, t->inname, &e);
    if (!t->r) aug_tool_fail(t, &e);
}

void aug_tool_open_out(aug_tool *t)
{
    aug_err e;
    if (isatty(1)) aug_tool_die(t, "refusing to write a binary stream to a terminal (pipe it to stats)");
    t->w = aug_writer_open(stdout, t->prog, &e);
    if (!t->w) aug_tool_fail(t, &e);
    aug_tool_check(t, aug_write_prov(t->w, t->argc, t->argv, &e), &e);
}

int aug_tool_read(aug_tool *t, aug_rec *rec)
{
    aug_err e;
    int rc = aug_read(t->r, rec, &e);
    if (rc < 0) aug_tool_fail(t, &e);
    return rc;
}

void aug_tool_pass(aug_tool *t, const aug_rec *rec)
{
    aug_err e;
    aug_tool_check(t, aug_write_rec(t->w, rec, &e), &e);
}

void aug_tool_close(aug_tool *t)
{
    aug_err e;
    if (t->w) {
        aug_tool_check(t, aug_writer_close(t->w, &e), &e);
        aug_writer_free(t->w);
        t->w = NULL;
    }
    if (t->r) {
        aug_reader_free(t->r);
        t->r = NULL;
    }
    if (t->in && t->in != stdin) fclose(t->in);
    t->in = NULL;
}

int aug_parse_doubles(const char *s, double *v, int n)
{
    return aug_parse_reals(s, v, n) == n ? 0 : -1;
}

int aug_parse_long(const char *s, long *v)
{
    char *end;
    errno = 0;
    *v = strtol(s, &end, 10);
    return (end == s || *end || errno) ? -1 : 0;
}

int aug_parse_double(const char *s, double *v)
{
    return aug_parse_doubles(s, v, 1);
}
