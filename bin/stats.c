/* stats: any augcut stream -> a summary, a text dump, a CSV of per-step figures or a .vtu file. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "augcut.h"
#include "cli/aug_opt.h"

static const char *synopsis =
    "stats [--dump [--no-times] | --csv | --vtk FILE.vtu [--step S]] [FILE]";

static const char *help =
    "  (no option)       human-readable summary of the stream\n"
    "  --dump            every record in stream order, decoded, floats exact (%.17g)\n"
    "  --no-times        with --dump: leave out the tIMe records (the only ones that vary)\n"
    "  --csv             one row per (step, method) from sTAt and tIMe records\n"
    "  --vtk FILE.vtu    the mesh of the last step (and its displacement) for ParaView\n"
    "  --step S          with --vtk: the mesh and field of step S instead\n"
    "  FILE              the stream to read (default: stdin)\n"
    "  -h                this help; see stats(1)\n";

typedef struct options {
    int dump, no_times, csv;
    const char *vtk;
    long step;            /* -1: the last step */
    const char *file;
} options;

static void parse(aug_tool *t, int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    o->step = -1;
    int nstep = 0;
    const aug_opt opt[] = {
        {AUG_OPT_FLAG("--dump", &o->dump)},
        {AUG_OPT_FLAG("--no-times", &o->no_times)},
        {AUG_OPT_FLAG("--csv", &o->csv)},
        {AUG_OPT_STRING("--vtk", &o->vtk, "a value"), .bad = "empty file name",
         .flags = AUG_OPT_ONCE | AUG_OPT_NONEMPTY},
        {AUG_OPT_INT("--step", &o->step, 0, INT32_MAX, "a value"), .bad = "not a step number (0, 1, ...)",
         .given = &nstep},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &o->file, synopsis, help);
    if (o->dump + o->csv + (o->vtk != NULL) > 1)
        aug_tool_usage(t, "--dump, --csv and --vtk exclude each other");
    if (o->no_times && !o->dump) aug_tool_usage(t, "--no-times goes with --dump");
    if (nstep && !o->vtk) aug_tool_usage(t, "--step goes with --vtk");
    aug_tool_usage_done(t, synopsis);
}

/* the dump streams: every record is printed as it is read */
static void run_dump(aug_tool *t, const options *o)
{
    aug_dump d;
    aug_rec rec;
    aug_err e;
    memset(&rec, 0, sizeof rec);
    aug_dump_init(&d, o->no_times);
    aug_tool_check(t, aug_dump_head(stdout, t->r, &e), &e);
    for (;;) {
        int rc = aug_read(t->r, &rec, &e);
        if (rc < 0) {
            fflush(stdout);
            aug_tool_fail(t, &e);
        }
        if (aug_dump_record(stdout, &d, &rec, &e)) {
            fflush(stdout);
            aug_tool_fail(t, &e);
        }
        if (rc == 0) break;
    }
    aug_rec_free(&rec);
    aug_dump_free(&d);
}

static void write_vtk(aug_tool *t, const options *o, const aug_summary *s)
{
    aug_err e;
    int32_t last = aug_summary_last_step(s);
    if (o->step > last && last < 0)
        aug_tool_die(t, "%s: --step %ld: the stream has no per-step records", t->inname, o->step);
    if (o->step > last)
        aug_tool_die(t, "%s: --step %ld: the stream's last step is %d", t->inname, o->step, (int)last);
    const aug_mesh *m = aug_summary_mesh(s);
    if (!m) aug_tool_die(t, "%s: no mesh in the stream (NODE, MATL and ELEM needed)", t->inname);
    int32_t fstep;
    double *u;
    unsigned char *mask;
    aug_tool_check(t, aug_summary_field(s, &fstep, &u, &mask, &e), &e);
    int32_t want = o->step >= 0 ? (int32_t)o->step : last;
    if (u && fstep != want) { /* a field of an earlier step does not belong to this mesh */
        free(u);
        free(mask);
        u = NULL;
        mask = NULL;
    }
    FILE *f = fopen(o->vtk, "w");
    if (!f) aug_tool_die(t, "%s: %s", o->vtk, strerror(errno));
    int rc = aug_vtk_write(f, m, u, mask, &e);
    if (fclose(f) != 0 && !rc) rc = aug_err_set(&e, AUG_EIO, -1, "", "write failed");
    free(u);
    free(mask);
    if (rc) {
        remove(o->vtk);
        aug_tool_die(t, "%s: %s", o->vtk, e.msg);
    }
}

/* summary, CSV and VTK read the whole stream first */
static void run_collect(aug_tool *t, const options *o)
{
    aug_err e, bad;
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    aug_summary *s = aug_summary_new(t->r, o->vtk && o->step >= 0 ? (int32_t)o->step : INT32_MAX, &e);
    if (!s) aug_tool_fail(t, &e);
    int rc, failed = 0;
    while ((rc = aug_read(t->r, &rec, &e)) > 0)
        if (aug_summary_add(s, &rec, &e)) {
            failed = 1;
            break;
        }
    if (rc < 0) failed = 1;
    aug_summary_end(s, !failed ? &rec : NULL);
    bad = e;
    if (o->csv) {
        if (failed) aug_tool_fail(t, &bad);
        aug_tool_check(t, aug_steptab_csv(stdout, aug_summary_steps(s), &e), &e);
    } else if (o->vtk) {
        if (failed) aug_tool_fail(t, &bad);
        write_vtk(t, o, s);
    } else {
        /* a broken stream still gets the summary of what was read, then the error */
        aug_tool_check(t, aug_summary_print(stdout, s, t->inname, &e), &e);
        fflush(stdout);
        if (failed) aug_tool_fail(t, &bad);
    }
    aug_rec_free(&rec);
    aug_summary_free(s);
}

int main(int argc, char **argv)
{
    aug_tool t;
    options o;
    aug_tool_init(&t, "stats", argc, argv);
    parse(&t, argc, argv, &o);
    aug_tool_open_in(&t, o.file);
    if (o.dump) run_dump(&t, &o);
    else run_collect(&t, &o);
    if (fflush(stdout) != 0) aug_tool_die(&t, "<stdout>: write failed");
    aug_tool_close(&t);
    return 0;
}
