/* The tools' option parser: one table row per option (netpbm's optParseOptions3,
   GMT's common options), every usage error counted before exit 2. */
#ifndef AUG_OPT_H
#define AUG_OPT_H

#include "aug_tool.h"

/* What an option's value is, and where the parser puts it. */
typedef enum aug_argkind {
    AUG_ARG_NONE,    /* a flag: *(int *)dst = 1 (0 with AUG_OPT_CLEAR); "=value" refused */
    AUG_ARG_STRING,  /* *(const char **)dst = the value (argv's own text) */
    AUG_ARG_INT,     /* an integer in [lo, hi] into an integer of size bytes (int, long, int64_t) */
    AUG_ARG_REAL,    /* a finite double in lo..hi, each end closed unless AUG_OPT_*_OPEN */
    AUG_ARG_REALS,   /* exactly n comma-separated finite doubles into (double *)dst */
    AUG_ARG_CHOICE,  /* one of the words: *(int *)dst = that word's value */
    AUG_ARG_CALL     /* fn parses the value (repeatable or structured options) */
} aug_argkind;

enum {
    AUG_OPT_ONCE = 1,       /* given twice is a usage error (the default for every kind but NONE and CALL) */
    AUG_OPT_LO_OPEN = 2,    /* REAL: lo itself refused */
    AUG_OPT_HI_OPEN = 4,    /* REAL: hi itself refused */
    AUG_OPT_ZERO = 8,       /* REAL: 0 accepted too, outside the bounds (0: off) */
    AUG_OPT_NONEMPTY = 16,  /* STRING: the empty string refused */
    AUG_OPT_CLEAR = 32,     /* NONE: the flag stores 0 (a --no-X switch) */
    AUG_OPT_MULTI = 64      /* a value option that may be given again, the last one taken */
};

typedef struct aug_word {
    const char *word;
    int value;
} aug_word;  /* a CHOICE's words, ended by {NULL, 0} */

/* CALL: parse val of option opt into dst. Returns 0 when it took the value;
   otherwise -1, and the parser reports the row's message unless fn reported
   its own errors (aug_tool_usage). */
typedef int (*aug_opt_fn)(aug_tool *t, const char *opt, const char *val, void *dst);

typedef struct aug_opt {
    const char *name;      /* "--threads" */
    char alias;            /* 0, or the short form "-c" */
    aug_argkind kind;
    void *dst;
    /* messages: a missing value "NAME needs NEED"; a refused one "NAME VALUE:
       BAD" ("NAME: BAD" for an empty value) when bad is set, else as missing */
    const char *need, *bad;
    int flags;
    double lo, hi;         /* INT, REAL bounds */
    int size;              /* INT: sizeof *dst */
    int n;                 /* REALS: count (at most AUG_OPT_MAXREALS) */
    const aug_word *words; /* CHOICE */
    aug_opt_fn fn;         /* CALL */
    int *given;            /* NULL, or incremented each time the option is given */
} aug_opt;

enum { AUG_OPT_MAXREALS = 16 };

/* Row shorthands: designators, so that a row may add more, e.g.
   {AUG_OPT_STRING("--path", &o->path, "a file"), .flags = AUG_OPT_ONCE}. */
#define AUG_OPT_FLAG(nm, d) .name = (nm), .kind = AUG_ARG_NONE, .dst = (d)
#define AUG_OPT_STRING(nm, d, nd) .name = (nm), .kind = AUG_ARG_STRING, .dst = (d), .need = (nd)
#define AUG_OPT_INT(nm, d, l, h, nd) \
    .name = (nm), .kind = AUG_ARG_INT, .dst = (d), .size = (int)sizeof *(d), .lo = (l), .hi = (h), .need = (nd)
#define AUG_OPT_REAL(nm, d, l, h, nd) .name = (nm), .kind = AUG_ARG_REAL, .dst = (d), .lo = (l), .hi = (h), .need = (nd)
#define AUG_OPT_REALS(nm, d, count, nd) .name = (nm), .kind = AUG_ARG_REALS, .dst = (d), .n = (count), .need = (nd)
#define AUG_OPT_CHOICE(nm, d, w, nd) .name = (nm), .kind = AUG_ARG_CHOICE, .dst = (d), .words = (w), .need = (nd)
#define AUG_OPT_CALL(nm, f, d, nd) .name = (nm), .kind = AUG_ARG_CALL, .fn = (f), .dst = (d), .need = (nd)
/* The common --threads N of the tools that compute with CHOLMOD/OpenBLAS. */
#define AUG_OPT_THREADS(d) AUG_OPT_INT("--threads", d, 1, 1024, "a count from 1 to 1024")

/* Scan argv[1..argc-1] against the table opt[0..nopt-1]. Options come as
   "--name value" (a value never begins with "--"), "--name=value" or, for a
   row with an alias, "-c value"; -h and --help print "usage: SYNOPSIS" and help
   on stdout and exit 0. Operands are the input file: into *file, one at most
   (file NULL: none taken). Every error is reported through aug_tool_usage and
   counted in t->usage_errors: an unknown option, a missing or refused value,
   "=value" on a flag, a once-only option given twice (every option with a
   value, unless CALL or AUG_OPT_MULTI: `--steps 2 --steps 3` would otherwise
   take the last one without a word; a flag twice is harmless), a second input
   file.
   A refused value leaves its destination unchanged. The caller adds its own
   checks and then calls aug_tool_usage_done. */
void aug_opt_parse(aug_tool *t, int argc, char **argv, const aug_opt *opt, int nopt,
                   const char **file, const char *synopsis, const char *help);

#endif
