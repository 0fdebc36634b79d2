/* Command-line side shared by the tools: messages, exit codes, stream set-up.
   Unlike lib/, this code prints to stderr and exits: 2 = usage (the command
   line alone is wrong), 1 = data (the input is bad, or an option disagrees
   with it, e.g. a group or set the input does not have). */
#ifndef AUG_TOOL_H
#define AUG_TOOL_H

#include "../aug_stream.h"

typedef struct aug_tool {
    const char *prog;
    const char *inname;   /* input file name as shown in messages ("-" = stdin) */
    FILE *in;
    aug_reader *r;
    aug_writer *w;
    int argc;
    char **argv;
    int usage_errors;
    int cmdline_errors;   /* usage_errors when the command line's own checks ended */
    int cmdline_ended;
} aug_tool;

void aug_tool_init(aug_tool *t, const char *prog, int argc, char **argv);
/* Report one error of the command line, or after aug_tool_cmdline_end of an
   option checked against the input (counted); all are reported before exiting. */
void aug_tool_usage(aug_tool *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The command line's own checks are over: errors reported from now on are
   options checked against the input (data errors). A tool that checks its
   options only on the command line need not call it. */
void aug_tool_cmdline_end(aug_tool *t);
/* If errors were reported: with any of the command line itself, the synopsis
   and exit 2; with only options that disagree with the input, exit 1. */
void aug_tool_usage_done(aug_tool *t, const char *synopsis);
/* Open the input stream (path NULL or "-": stdin); dies on error. */
void aug_tool_open_in(aug_tool *t, const char *path);
/* Open the output stream on stdout with a provenance record; dies on error. */
void aug_tool_open_out(aug_tool *t);
/* Next record: 1, or 0 at the end of a whole stream; dies on any error. */
int aug_tool_read(aug_tool *t, aug_rec *rec);
void aug_tool_pass(aug_tool *t, const aug_rec *rec);   /* write rec byte for byte */
void aug_tool_check(aug_tool *t, int rc, const aug_err *e); /* dies if rc != 0 */
/* Write TAIL and close; only a stream closed this way is whole. */
void aug_tool_close(aug_tool *t);
/* "prog: file: record N (TYPE): message", exit 1. Output side uses "<stdout>". */
void aug_tool_fail(aug_tool *t, const aug_err *e) __attribute__((noreturn));
void aug_tool_die(aug_tool *t, const char *fmt, ...) __attribute__((noreturn, format(printf, 2, 3)));

/* Option values: "a,b,c" into exactly n doubles; an integer; 0 on success. */
int aug_parse_doubles(const char *s, double *v, int n);
int aug_parse_long(const char *s, long *v);
int aug_parse_double(const char *s, double *v);

/* Progress of a per-step loop, called once per step done (i of n; n <= 0:
   unknown): when stderr is a terminal and the run is past about 2 s since the
   first call, one line "prog: step i/n, R Hz" on stderr, rewritten in place
   (\r) at most 4 times a second and cleared when i reaches n, at exit or by
   i < 0 (before a message); silent when stderr is not a terminal. */
void aug_progress(const aug_tool *t, long i, long n);

/* Threads of CHOLMOD/OpenBLAS (nthreads <= 0: 1). Call right after option
   parsing, before any input is read: when OMP_THREAD_LIMIT is not set, the
   tool re-executes itself once with OMP_THREAD_LIMIT=1 (libgomp reads it only
   at start-up, and CHOLMOD's fixed-size OpenMP teams otherwise oversubscribe
   the cores beside OpenBLAS's threads) and OPENBLAS_NUM_THREADS=nthreads
   unless set; an OMP_THREAD_LIMIT set by the user is kept, and under valgrind
   there is no re-execution (valgrind would lose the child).
   Then aug_set_threads(nthreads). Every tool taking --threads calls it. */
void aug_tool_threads(aug_tool *t, int nthreads);

#endif
