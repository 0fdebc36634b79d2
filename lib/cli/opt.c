/* Table-driven command-line parsing of the tools (aug_opt.h). */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_opt.h"

/* the row named by the len bytes of a ("--name" or "-c"), or NULL */
static const aug_opt *find(const aug_opt *opt, int nopt, const char *a, size_t len)
{
    for (int k = 0; k < nopt; k++) {
        if (strlen(opt[k].name) == len && !strncmp(opt[k].name, a, len)) return &opt[k];
        if (opt[k].alias && len == 2 && a[0] == '-' && a[1] == opt[k].alias) return &opt[k];
    }
    return NULL;
}

/* x in lo..hi with the row's open or closed ends, or 0 when AUG_OPT_ZERO */
static int in_interval(const aug_opt *r, double x)
{
    if ((r->flags & AUG_OPT_ZERO) && x == 0) return 1;
    int lo = r->flags & AUG_OPT_LO_OPEN ? x > r->lo : x >= r->lo;
    int hi = r->flags & AUG_OPT_HI_OPEN ? x < r->hi : x <= r->hi;
    return lo && hi;
}

/* v into the integer of r->size bytes at r->dst; -1 when it does not fit */
static int store_int(const aug_opt *r, long v)
{
    if (r->size == (int)sizeof(int)) {
        if (v < INT_MIN || v > INT_MAX) return -1;
        int x = (int)v;
        memcpy(r->dst, &x, sizeof x);
    } else if (r->size == (int)sizeof(int64_t)) {
        int64_t x = v;
        memcpy(r->dst, &x, sizeof x);
    } else {
        return -1;
    }
    return 0;
}

/* the value of row r into its destination: 0, or -1 when refused */
static int take(aug_tool *t, const aug_opt *r, const char *val)
{
    long n;
    double x, v[AUG_OPT_MAXREALS];
    switch (r->kind) {
    case AUG_ARG_NONE:
        *(int *)r->dst = !(r->flags & AUG_OPT_CLEAR);
        return 0;
    case AUG_ARG_STRING:
        if ((r->flags & AUG_OPT_NONEMPTY) && !val[0]) return -1;
        *(const char **)r->dst = val;
        return 0;
    case AUG_ARG_INT:
        if (aug_parse_long(val, &n) || (double)n < r->lo || (double)n > r->hi) return -1;
        return store_int(r, n);
    case AUG_ARG_REAL:
        if (aug_parse_double(val, &x) || !in_interval(r, x)) return -1;
        *(double *)r->dst = x;
        return 0;
    case AUG_ARG_REALS:
        if (r->n < 1 || r->n > AUG_OPT_MAXREALS || aug_parse_doubles(val, v, r->n)) return -1;
        memcpy(r->dst, v, (size_t)r->n * sizeof *v);
        return 0;
    case AUG_ARG_CHOICE:
        for (const aug_word *w = r->words; w && w->word; w++)
            if (!strcmp(w->word, val)) {
                *(int *)r->dst = w->value;
                return 0;
            }
        return -1;
    case AUG_ARG_CALL: {
        int n0 = t->usage_errors;
        int rc = r->fn(t, r->name, val, r->dst);
        return rc || t->usage_errors > n0 ? -1 : 0;
    }
    }
    return -1;
}

/* why a number the bounds did not refuse was refused, or NULL: inf, nan
   and values past the doubles ("--pull 1e-400" read "at most 1e12 in
   magnitude", "--max-aspect inf" "a number >= 1.2") */
static const char *not_a_double(const char *val)
{
    char *end;
    errno = 0;
    double x = strtod(val, &end);
    if (end == val || *end) return NULL;
    if (!isfinite(x) && errno != ERANGE) return "not a finite number";
    if (errno == ERANGE) return fabs(x) < 1 ? "below the smallest double (underflow)" : "beyond the largest double";
    return NULL;
}

/* the usage error of a refused value (none when a CALL reported its own) */
static void refused(aug_tool *t, const aug_opt *r, const char *val, int n0)
{
    if (t->usage_errors > n0) return;
    const char *why = r->kind == AUG_ARG_REAL ? not_a_double(val) : NULL;
    if (why) aug_tool_usage(t, "%s %s: %s (%s needs %s)", r->name, val, why, r->name, r->need);
    else if (!r->bad) aug_tool_usage(t, "%s needs %s", r->name, r->need);
    else if (!val[0]) aug_tool_usage(t, "%s: %s", r->name, r->bad);
    else aug_tool_usage(t, "%s %s: %s", r->name, val, r->bad);
}

/* an operand: the input file */
static void operand(aug_tool *t, const char *a, const char **file)
{
    if (!file) aug_tool_usage(t, "unexpected argument %s", a);
    else if (*file) aug_tool_usage(t, "more than one input file (%s, %s)", *file, a);
    else *file = a;
}

void aug_opt_parse(aug_tool *t, int argc, char **argv, const aug_opt *opt, int nopt,
                   const char **file, const char *synopsis, const char *help)
{
    int *seen = calloc((size_t)nopt + 1, sizeof *seen);
    if (!seen) aug_tool_die(t, "out of memory");
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (a[0] != '-' || !a[1]) {
            operand(t, a, file);
            continue;
        }
        const char *eq = a[1] == '-' ? strchr(a, '=') : NULL;
        const char *val = eq ? eq + 1 : NULL;
        size_t len = eq ? (size_t)(eq - a) : strlen(a);
        if ((len == 2 && !strncmp(a, "-h", 2)) || (len == 6 && !strncmp(a, "--help", 6))) {
            if (val) {
                aug_tool_usage(t, "--help takes no value");
                continue;
            }
            printf("usage: %s\n%s", synopsis, help);
            exit(0);
        }
        const aug_opt *r = find(opt, nopt, a, len);
        if (!r) {
            aug_tool_usage(t, "unknown option %.*s", (int)len, a);
            continue;
        }
        if (r->kind == AUG_ARG_NONE) {
            if (val) {
                aug_tool_usage(t, "%s takes no value", r->name);
                continue;
            }
        } else if (!val) {
            if (i + 1 >= argc || !strncmp(argv[i + 1], "--", 2)) {
                aug_tool_usage(t, "%s needs %s", r->name, r->need);
                continue;
            }
            val = argv[++i];
        }
        int once = (r->flags & AUG_OPT_ONCE) ||
                   (r->kind != AUG_ARG_NONE && r->kind != AUG_ARG_CALL && !(r->flags & AUG_OPT_MULTI));
        if (once && seen[r - opt]++) aug_tool_usage(t, "%s given twice", r->name);
        if (r->given) (*r->given)++;
        int n0 = t->usage_errors;
        if (take(t, r, val)) refused(t, r, val, n0);
    }
    free(seen);
}
