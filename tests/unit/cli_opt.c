/* Unit tests of the tools' option parser (lib/cli/opt.c) and of the exit-code
   policy: --opt=value equals --opt value for every kind of row, several usage
   errors reported at once, flags refusing =value, bounds, -h, exit 2 / 1. */
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include "cli/aug_opt.h"
#include "t.h"

typedef struct fx {
    int flag, clr, count, wide, pick, ncall, nname;
    long big;
    int64_t w;
    double closed, open, zero, vec[3];
    const char *name, *nonempty, *file;
    char calls[4][16];
} fx;

static const aug_word picks[] = {{"a", 7}, {"b", 9}, {NULL, 0}};
static const char *syn = "tprog [FILE] [--flag] ...";
static const char *hlp = "  --flag   a flag\n";

/* --call: "bad" refused silently, "worse" refused with two messages of its own */
static int call(aug_tool *t, const char *opt, const char *val, void *dst)
{
    fx *x = dst;
    if (!strcmp(val, "bad")) return -1;
    if (!strcmp(val, "worse")) {
        aug_tool_usage(t, "%s %s: first", opt, val);
        aug_tool_usage(t, "%s %s: second", opt, val);
        return 0;
    }
    if (x->ncall < 4) snprintf(x->calls[x->ncall++], sizeof x->calls[0], "%s", val);
    return 0;
}

static void table_parse(aug_tool *t, int argc, char **argv, fx *x)
{
    const aug_opt opt[] = {
        {AUG_OPT_FLAG("--flag", &x->flag), .alias = 'f'},
        {AUG_OPT_FLAG("--no-clr", &x->clr), .flags = AUG_OPT_CLEAR},
        {AUG_OPT_STRING("--name", &x->name, "a name"), .alias = 'n', .flags = AUG_OPT_ONCE,
         .given = &x->nname},
        {AUG_OPT_STRING("--nonempty", &x->nonempty, "a name"), .bad = "empty name",
         .flags = AUG_OPT_NONEMPTY},
        {AUG_OPT_INT("--count", &x->count, 1, 10, "a count from 1 to 10")},
        {AUG_OPT_INT("--wide", &x->wide, 0, 1e12, "a count")},
        {AUG_OPT_INT("--big", &x->big, 0, LONG_MAX, "an integer >= 0")},
        {AUG_OPT_INT("--w", &x->w, -5, 5, "-5 to 5")},
        {AUG_OPT_REAL("--closed", &x->closed, 0, 1, "a number in [0, 1]")},
        {AUG_OPT_REAL("--open", &x->open, 0, 1, "a number in (0, 1)"),
         .flags = AUG_OPT_LO_OPEN | AUG_OPT_HI_OPEN},
        {AUG_OPT_REAL("--zero", &x->zero, 1.2, HUGE_VAL, "a number >= 1.2 (0: off)"), .flags = AUG_OPT_ZERO},
        {AUG_OPT_REALS("--vec", x->vec, 3, "x,y,z")},
        {AUG_OPT_CHOICE("--pick", &x->pick, picks, "a or b"), .bad = "not one of a, b"},
        {AUG_OPT_CALL("--call", call, x, "a value")},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &x->file, syn, hlp);
}

static char err[8192];

static void fx_init(fx *x)
{
    memset(x, 0, sizeof *x);
    x->clr = 1;
    x->count = -1;
    x->closed = -1;
}

/* parse argv (NULL-ended) into x; stderr in err; the usage error count */
static int run(fx *x, char **argv)
{
    int argc = 0;
    while (argv[argc]) argc++;
    fx_init(x);
    fflush(stderr);
    int saved = dup(2);
    FILE *tf = tmpfile();
    if (saved < 0 || !tf) return -1;
    dup2(fileno(tf), 2);
    aug_tool t;
    aug_tool_init(&t, "tprog", argc, argv);
    table_parse(&t, argc, argv, x);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    rewind(tf);
    size_t n = fread(err, 1, sizeof err - 1, tf);
    err[n] = 0;
    fclose(tf);
    return t.usage_errors;
}

#define ARGV(...) ((char *[]){"tprog", __VA_ARGS__, NULL})

/* lines of err, each "tprog: ..." (else -1) */
static int err_lines(void)
{
    int n = 0;
    for (const char *p = err; *p; n++) {
        if (strncmp(p, "tprog: ", 7)) return -1;
        const char *nl = strchr(p, '\n');
        if (!nl) return -1;
        p = nl + 1;
    }
    return n;
}

static int same(const fx *a, const fx *b)
{
    return a->flag == b->flag && a->clr == b->clr && a->count == b->count && a->wide == b->wide &&
           a->pick == b->pick && a->big == b->big && a->w == b->w && a->closed == b->closed &&
           a->open == b->open && a->zero == b->zero && !memcmp(a->vec, b->vec, sizeof a->vec) &&
           a->ncall == b->ncall && !memcmp(a->calls, b->calls, sizeof a->calls) &&
           (a->name == b->name || (a->name && b->name && !strcmp(a->name, b->name))) &&
           (a->nonempty == b->nonempty || (a->nonempty && b->nonempty && !strcmp(a->nonempty, b->nonempty)));
}

static void equals_forms(void)
{
    static const char *pairs[][2] = {
        {"--name", "abc"},  {"--nonempty", "q"}, {"--count", "7"},  {"--wide", "123456"},
        {"--big", "9000000000"}, {"--w", "-3"},  {"--closed", "0.25"}, {"--open", "1e-3"},
        {"--zero", "2.5"},  {"--vec", "1,-2,3.5"}, {"--pick", "b"},   {"--call", "x=1"},
    };
    for (size_t k = 0; k < sizeof pairs / sizeof *pairs; k++) {
        fx a, b;
        char joined[64];
        snprintf(joined, sizeof joined, "%s=%s", pairs[k][0], pairs[k][1]);
        int ea = run(&a, ARGV((char *)pairs[k][0], (char *)pairs[k][1]));
        int eb = run(&b, ARGV(joined));
        T_CHECK(ea == 0 && eb == 0, "%s: %d, %d errors: %.200s", joined, ea, eb, err);
        T_CHECK(same(&a, &b), "%s: the two forms differ", joined);
        fx d;
        run(&d, ARGV("-"));
        T_CHECK(!same(&a, &d), "%s: took no effect", joined);
    }
    fx a;
    T_CHECK(run(&a, ARGV("--w", "-3", "--vec", "1,-2,3.5", "--call=a", "--call", "b")) == 0, "%.200s", err);
    T_CHECK(a.w == -3 && a.vec[1] == -2 && a.ncall == 2 && !strcmp(a.calls[1], "b"), "values");
    T_CHECK(run(&a, ARGV("--pick", "a", "--big", "9000000000", "--name=")) == 0, "%.200s", err);
    T_CHECK(a.pick == 7 && a.big == 9000000000L && a.name && !a.name[0], "choice, long, empty string");
}

static void flags_and_aliases(void)
{
    fx a;
    T_CHECK(run(&a, ARGV("-f", "--no-clr", "-n", "nm", "in.aug")) == 0, "%.200s", err);
    T_CHECK(a.flag == 1 && a.clr == 0 && !strcmp(a.name, "nm") && !strcmp(a.file, "in.aug"), "aliases, clear");
    T_CHECK(run(&a, ARGV("--flag=1")) == 1 && a.flag == 0, "a flag took =value");
    T_CHECK(strstr(err, "tprog: --flag takes no value\n") != NULL, "message: %.200s", err);
    T_CHECK(run(&a, ARGV("--no-clr=", "--help=x")) == 2 && a.clr == 1 && err_lines() == 2, "%.200s", err);
    T_CHECK(run(&a, ARGV("-")) == 0 && !strcmp(a.file, "-"), "- is the standard input operand");
}

static void several_errors(void)
{
    fx a;
    int n = run(&a, ARGV("--bogus=3", "--count", "0", "--flag=x", "--pick", "c", "--nonempty=",
                         "--name", "a", "--name", "b", "x.aug", "y.aug", "--vec", "1,2",
                         "--open", "1", "--call", "bad", "--call", "worse", "-z", "--closed"));
    T_CHECK(n == 14, "%d errors, want 14: %.200s", n, err);
    T_CHECK(err_lines() == n, "%d lines for %d errors: %.200s", err_lines(), n, err);
    static const char *want[] = {
        "tprog: unknown option --bogus\n",
        "tprog: --count needs a count from 1 to 10\n",
        "tprog: --flag takes no value\n",
        "tprog: --pick c: not one of a, b\n",
        "tprog: --nonempty: empty name\n",
        "tprog: --name given twice\n",
        "tprog: more than one input file (x.aug, y.aug)\n",
        "tprog: --vec needs x,y,z\n",
        "tprog: --open needs a number in (0, 1)\n",
        "tprog: --call needs a value\n",
        "tprog: --call worse: first\ntprog: --call worse: second\n",
        "tprog: unknown option -z\n",
        "tprog: --closed needs a number in [0, 1]\n",
    };
    for (size_t k = 0; k < sizeof want / sizeof *want; k++)
        T_CHECK(strstr(err, want[k]) != NULL, "missing '%s' in: %.200s", want[k], err);
    T_CHECK(a.count == -1 && a.pick == 0 && !a.nonempty && a.vec[0] == 0 && a.open == 0, "refused values stored");
    T_CHECK(a.nname == 2 && !strcmp(a.name, "b"), "given count %d", a.nname);
    T_CHECK(!strcmp(a.file, "x.aug"), "first operand kept");
    /* a value never begins with "--": the next option is parsed, not swallowed */
    n = run(&a, ARGV("--count", "--flag", "--name"));
    T_CHECK(n == 2 && a.flag == 1 && strstr(err, "tprog: --count needs") && strstr(err, "tprog: --name needs a name"),
            "%d: %.200s", n, err);
}

static void bounds(void)
{
    fx a;
    struct { const char *opt, *val; int ok; } c[] = {
        {"--count", "1", 1},   {"--count", "10", 1},  {"--count", "11", 0}, {"--count", "0", 0},
        {"--count", "2.5", 0}, {"--count", "", 0},    {"--count", "3x", 0},
        {"--wide", "2147483647", 1}, {"--wide", "2147483648", 0},  /* beyond int */
        {"--big", "-1", 0},    {"--w", "-5", 1},      {"--w", "-6", 0},
        {"--closed", "0", 1},  {"--closed", "1", 1},  {"--closed", "1.0001", 0}, {"--closed", "-0.1", 0},
        {"--open", "0", 0},    {"--open", "1", 0},    {"--open", "0.999", 1},
        {"--open", "nan", 0},  {"--open", "inf", 0},
        {"--zero", "0", 1},    {"--zero", "1.2", 1},  {"--zero", "1.19", 0}, {"--zero", "1e300", 1},
        {"--vec", "1,2,3", 1}, {"--vec", "1,2,3,4", 0}, {"--vec", "1,,3", 0}, {"--vec", "1,2,inf", 0},
        {"--pick", "A", 0},
    };
    for (size_t k = 0; k < sizeof c / sizeof *c; k++) {
        int n = run(&a, ARGV((char *)c[k].opt, (char *)c[k].val));
        T_CHECK((n == 0) == c[k].ok, "%s %s: %d errors (%.200s)", c[k].opt, c[k].val, n, err);
    }
    run(&a, ARGV("--wide", "2147483647", "--closed", "1", "--zero", "1e300"));
    T_CHECK(a.wide == INT_MAX && a.closed == 1 && a.zero == 1e300, "stored values");
}

/* the exit status and stdout of f run in a child */
static int child(void (*f)(void), char *out, size_t cap)
{
    fflush(NULL);
    FILE *tf = tmpfile();
    pid_t p = fork();
    if (p == 0) {
        dup2(fileno(tf), 1);
        int dn = open("/dev/null", O_WRONLY);
        if (dn >= 0) dup2(dn, 2);
        f();
        fflush(NULL);
        _exit(99);
    }
    int st = -1;
    waitpid(p, &st, 0);
    rewind(tf);
    size_t n = fread(out, 1, cap - 1, tf);
    out[n] = 0;
    fclose(tf);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static void do_help(void)
{
    fx x;
    fx_init(&x);
    char **argv = ARGV("--bogus", "-h", "--flag");
    aug_tool t;
    aug_tool_init(&t, "tprog", 4, argv);
    table_parse(&t, 4, argv, &x);
}
/* errors: usage ones before the end of the command line, data ones after */
static int n_usage, n_data;
static void do_errors(void)
{
    aug_tool t;
    aug_tool_init(&t, "tprog", 1, ARGV("x"));
    for (int k = 0; k < n_usage; k++) aug_tool_usage(&t, "bad option");
    aug_tool_cmdline_end(&t);
    for (int k = 0; k < n_data; k++) aug_tool_usage(&t, "group not in the input");
    aug_tool_usage_done(&t, syn);
    exit(0);
}
static int exit_code(int usage, int data, char *out, size_t cap)
{
    n_usage = usage;
    n_data = data;
    return child(do_errors, out, cap);
}

static void help_and_exit_codes(void)
{
    char out[1024], want[1024];
    snprintf(want, sizeof want, "usage: %s\n%s", syn, hlp);
    int rc = child(do_help, out, sizeof out);
    T_CHECK(rc == 0 && !strcmp(out, want), "-h: exit %d, printed '%.200s'", rc, out);
    T_CHECK((rc = exit_code(1, 1, out, sizeof out)) == 2, "usage and data errors: exit %d, want 2", rc);
    T_CHECK((rc = exit_code(2, 0, out, sizeof out)) == 2, "usage errors: exit %d, want 2", rc);
    T_CHECK((rc = exit_code(0, 2, out, sizeof out)) == 1, "data errors only: exit %d, want 1", rc);
    T_CHECK((rc = exit_code(0, 0, out, sizeof out)) == 0, "no error: exit %d", rc);
}

int main(void)
{
    T_RUN(equals_forms);
    T_RUN(flags_and_aliases);
    T_RUN(several_errors);
    T_RUN(bounds);
    T_RUN(help_and_exit_codes);
    T_EXIT();
}
