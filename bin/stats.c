/* stats: any augcut stream -> a summary, a text dump, a CSV of per-step figures, VTK or Matrix Market files. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "augcut.h"
#include "cli/aug_opt.h"

static const char *synopsis =
    "stats [--dump [--no-times] | --csv | --vtk FILE.vtu [--step S] | --vtk DIR/NAME.pvd |\n"
    "       --mtx PREFIX [--step S]] [FILE]";

static const char *help =
    "  (no option)       human-readable summary of the stream\n"
    "  --dump            every record in stream order, decoded, floats exact (%.17g)\n"
    "  --no-times        with --dump: leave out the tIMe records (the only ones that vary)\n"
    "  --csv             one row per (step, method) from sTAt and tIMe records\n"
    "  --vtk FILE.vtu    the mesh of the last step (and its displacement) for ParaView\n"
    "  --vtk D/NAME.pvd  every step as D/NAME_SSSS.vtu and their ParaView collection\n"
    "  --mtx PREFIX      K (and M) of the last step in Matrix Market: PREFIX_K.mtx ...\n"
    "  --step S          with --vtk FILE.vtu or --mtx: step S instead of the last\n"
    "  FILE              the stream to read (default: stdin)\n"
    "  -h                this help; see stats(1)\n";

typedef struct options {
    int dump, no_times, csv;
    const char *vtk, *mtx;
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
        {AUG_OPT_STRING("--mtx", &o->mtx, "a value"), .bad = "empty file name",
         .flags = AUG_OPT_ONCE | AUG_OPT_NONEMPTY},
        {AUG_OPT_INT("--step", &o->step, 0, INT32_MAX, "a value"), .bad = "not a step number (0, 1, ...)",
         .given = &nstep},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &o->file, synopsis, help);
    if (o->dump + o->csv + (o->vtk != NULL) + (o->mtx != NULL) > 1)
        aug_tool_usage(t, "--dump, --csv, --vtk and --mtx exclude each other");
    if (o->no_times && !o->dump) aug_tool_usage(t, "--no-times goes with --dump");
    if (o->vtk && !strcmp(o->vtk, "-")) aug_tool_usage(t, "--vtk -: a file name (FILE.vtu or DIR/NAME.pvd), not standard output");
    if (nstep && !o->mtx && (!o->vtk || aug_path_is_pvd(o->vtk)))
        aug_tool_usage(t, "--step goes with --vtk FILE.vtu or --mtx (a .pvd has every step)");
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

/* the step of --step, or the last one; dies when the stream does not reach it */
static int32_t chosen_step(aug_tool *t, const options *o, const aug_summary *s)
{
    int32_t last = aug_summary_last_step(s);
    if (o->step > last && last < 0)
        aug_tool_die(t, "%s: --step %ld: the stream has no per-step records", t->inname, o->step);
    if (o->step > last)
        aug_tool_die(t, "%s: --step %ld: the stream's last step is %d", t->inname, o->step, (int)last);
    return o->step >= 0 ? (int32_t)o->step : last < 0 ? 0 : last;
}

/* a failed run leaves no .pvd, .vtu or .mtx behind; output errors name their file */
static void fail(aug_tool *t, aug_pvd *pvd, aug_mtx *mx, const aug_err *e)
{
    aug_pvd_free(pvd, 1);
    aug_mtx_free(mx, 1);
    if ((e->code == AUG_EIO || e->code == AUG_EUSAGE) && e->record < 0) aug_tool_die(t, "%s", e->msg);
    aug_tool_fail(t, e);
}

/* summary, CSV, VTK and Matrix Market read the whole stream first (a .pvd
   writes each step as the stream passes it) */
static void run_collect(aug_tool *t, const options *o)
{
    aug_err e, bad;
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    aug_summary *s = aug_summary_new(t->r, o->step >= 0 ? (int32_t)o->step : INT32_MAX, &e);
    aug_pvd *pvd = NULL;
    aug_mtx *mx = NULL;
    aug_out_protect(fileno(t->in)); /* no output replaces the input */
    if (!s || (o->vtk && aug_path_is_pvd(o->vtk) && !(pvd = aug_pvd_new(o->vtk, &e))) ||
        (o->mtx && !(mx = aug_mtx_new(&e))))
        fail(t, pvd, mx, &e);
    int rc, failed = 0;
    while ((rc = aug_read(t->r, &rec, &e)) > 0)
        if ((pvd && aug_pvd_add(pvd, s, &rec, &e)) || (mx && aug_mtx_add(mx, &rec, &e)) ||
            aug_summary_add(s, &rec, &e)) {
            failed = 1;
            break;
        }
    if (rc < 0) failed = 1;
    bad = e;
    if (aug_summary_end(s, !failed ? &rec : NULL, &e)) failed = 1, bad = e;
    if (o->csv) {
        if (failed) aug_tool_fail(t, &bad);
        aug_tool_check(t, aug_steptab_csv(stdout, aug_summary_steps(s), &e), &e);
    } else if (o->vtk || o->mtx) {
        if (failed) fail(t, pvd, mx, &bad);
        if (pvd) rc = aug_pvd_end(pvd, s, &e);
        else if (mx) rc = aug_mtx_write(mx, chosen_step(t, o, s), aug_summary_mesh(s), o->mtx, &e);
        else rc = aug_vtk_step_file(o->vtk, s, chosen_step(t, o, s), &e);
        if (rc) fail(t, pvd, mx, &e);
    } else {
        /* a broken stream still gets the summary of what was read, then the error */
        aug_tool_check(t, aug_summary_print(stdout, s, t->inname, &e), &e);
        fflush(stdout);
        if (failed) aug_tool_fail(t, &bad);
    }
    aug_pvd_free(pvd, 0);
    aug_mtx_free(mx, 0);
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
