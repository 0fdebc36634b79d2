/* solve-aug: factor + update records -> per step the displacement field of the
   output set and per-method sTAt/tIMe (AMPS, augmented GMRES, baselines). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_solve.h"
#include "cli/aug_tool.h"

static const char *synopsis =
    "solve-aug [FILE] [--method LIST] [--check] [--background] [--bg-lag N]\n"
    "          [--output all|surface|SET] [--refine-iter N] [--refine-tol R]\n"
    "          [--amps-target R] [--fail-tol F] [--tol T] [--maxit N]\n"
    "          [--gmres-prec none|D|spai] [--restart N] [--spare N] [--on-singular error|report]\n"
    "          [--reach path|cholmod] [--threads N] [--time-full] [-h]";

static const char *help =
    "  FILE                 input stream (default: stdin)\n"
    "  --method LIST        comma list of amps,gmres,refactor,rowupdate,pcg (default amps);\n"
    "                       the first one's field is written\n"
    "  --check              err_direct: difference to a fresh CHOLMOD solve of K_t\n"
    "  --background         re-factor in a background thread, swap when done (amps, gmres)\n"
    "  --bg-lag N           swap exactly N steps after each start (deterministic)\n"
    "  --output all|surface|SET  nodes whose displacement is solved and written\n"
    "  --refine-iter N      exactly N iterative refinement steps per solve (default 0:\n"
    "                       adaptive, see --refine-tol)\n"
    "  --refine-tol R       direct methods refine while relres > R, at most 3 steps,\n"
    "                       each halving it (default 1e-8; 0: never)\n"
    "  --amps-target R      amps refines once more when its relres exceeds R (default\n"
    "                       1e-12; 0: off)\n"
    "  --fail-tol F         a direct method whose relres stays above F reports the\n"
    "                       step singular (default 1e-6)\n"
    "  --tol T              relres ||K_t a - f_t||/||f_t|| gmres and pcg stop at (default 1e-8)\n"
    "  --maxit N            iteration cap of gmres and pcg (default 10000)\n"
    "  --gmres-prec P       none, D or spai (default D)\n"
    "  --restart N          GMRES restart length (default 100)\n"
    "  --spare N            rowupdate: spare identity rows for new DOFs (default 3000)\n"
    "  --on-singular error|report  a singular step: exit 1 (default) or report and go on\n"
    "  --reach path|cholmod AMPS V columns: own etree-path solve (default) or cholmod_solve2\n"
    "  --threads N          threads of CHOLMOD and OpenBLAS (default 1)\n"
    "  --time-full          time one full CHOLMOD solve of the base every step\n"
    "                       (full_solve_ms; default: the median of 5 at the start)\n"
    "  -h                   this help; see solve-aug(1)\n";

typedef struct options {
    const char *file, *output;
    aug_solver_opts so;
    int on_singular_report;
    int time_full;
} options;

static void parse(aug_tool *t, int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    aug_solver_opts_default(&o->so);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        long n;
        double d;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            printf("usage: %s\n%s", synopsis, help);
            exit(0);
        } else if (!strcmp(a, "--method")) {
            int k = v ? aug_parse_methods(v, o->so.order) : -1;
            if (k <= 0) aug_tool_usage(t, "--method needs a comma list of amps,gmres,refactor,rowupdate,pcg");
            else o->so.nmeth = k;
            i += v != NULL;
        } else if (!strcmp(a, "--check")) {
            o->so.check = 1;
        } else if (!strcmp(a, "--time-full")) {
            o->time_full = 1;
        } else if (!strcmp(a, "--background")) {
            o->so.background = 1;
        } else if (!strcmp(a, "--bg-lag")) {
            if (!v || aug_parse_long(v, &n) || n < 1 || n > 1000000) aug_tool_usage(t, "--bg-lag needs a count >= 1");
            else o->so.bg_lag = (int)n, o->so.background = 1;
            i += v != NULL;
        } else if (!strcmp(a, "--output")) {
            if (!v || !*v) aug_tool_usage(t, "--output needs all, surface or a set name");
            else o->output = v;
            i += v != NULL;
        } else if (!strcmp(a, "--refine-iter")) {
            if (!v || aug_parse_long(v, &n) || n < 0 || n > 100) aug_tool_usage(t, "--refine-iter needs 0 to 100");
            else o->so.refine_iter = (int)n;
            i += v != NULL;
        } else if (!strcmp(a, "--refine-tol") || !strcmp(a, "--fail-tol") || !strcmp(a, "--amps-target")) {
            if (!v || aug_parse_double(v, &d) || !(d >= 0 && d < 1)) aug_tool_usage(t, "%s needs a number in [0, 1)", a);
            else if (a[2] == 'r') o->so.refine_tol = d, o->so.refine_max = d > 0 ? 3 : 0;
            else if (a[2] == 'a') o->so.amps_target = d;
            else o->so.fail_tol = d;
            i += v != NULL;
        } else if (!strcmp(a, "--tol")) {
            if (!v || aug_parse_double(v, &d) || !(d > 0 && d < 1)) aug_tool_usage(t, "--tol needs a number in (0, 1)");
            else o->so.tol = d;
            i += v != NULL;
        } else if (!strcmp(a, "--maxit")) {
            if (!v || aug_parse_long(v, &n) || n < 1 || n > 100000000) aug_tool_usage(t, "--maxit needs a count >= 1");
            else o->so.maxit = (int)n;
            i += v != NULL;
        } else if (!strcmp(a, "--restart")) {
            if (!v || aug_parse_long(v, &n) || n < 1 || n > 10000) aug_tool_usage(t, "--restart needs 1 to 10000");
            else o->so.restart = (int)n;
            i += v != NULL;
        } else if (!strcmp(a, "--spare")) {
            if (!v || aug_parse_long(v, &n) || n < 1 || n > 100000000) aug_tool_usage(t, "--spare needs a count >= 1");
            else o->so.spare = n;
            i += v != NULL;
        } else if (!strcmp(a, "--gmres-prec")) {
            if (v && !strcmp(v, "none")) o->so.gmres_prec = AUG_PREC_NONE;
            else if (v && !strcmp(v, "D")) o->so.gmres_prec = AUG_PREC_D;
            else if (v && !strcmp(v, "spai")) o->so.gmres_prec = AUG_PREC_SPAI;
            else aug_tool_usage(t, "--gmres-prec needs none, D or spai");
            i += v != NULL;
        } else if (!strcmp(a, "--on-singular")) {
            if (v && !strcmp(v, "error")) o->on_singular_report = 0;
            else if (v && !strcmp(v, "report")) o->on_singular_report = 1;
            else aug_tool_usage(t, "--on-singular needs error or report");
            i += v != NULL;
        } else if (!strcmp(a, "--reach")) {
            if (v && !strcmp(v, "path")) o->so.reach_cholmod = 0;
            else if (v && !strcmp(v, "cholmod")) o->so.reach_cholmod = 1;
            else aug_tool_usage(t, "--reach needs path or cholmod");
            i += v != NULL;
        } else if (!strcmp(a, "--threads")) {
            if (!v || aug_parse_long(v, &n) || n < 1 || n > 1024) aug_tool_usage(t, "--threads needs 1 to 1024");
            else o->so.nthreads = (int)n;
            i += v != NULL;
        } else if (a[0] == '-' && a[1]) {
            aug_tool_usage(t, "unknown option %s", a);
        } else if (o->file) {
            aug_tool_usage(t, "more than one input file");
        } else {
            o->file = a;
        }
    }
    aug_tool_usage_done(t, synopsis);
}

/* report the step's singular and unconverged methods; singular is fatal unless --on-singular report */
static void report(aug_tool *t, const options *o, aug_solver *s, const aug_rec *rec, int32_t step)
{
    int nsing = 0;
    char names[128] = "";
    for (int i = 0; i < o->so.nmeth; i++) {
        int mth = o->so.order[i];
        if (aug_solver_singular(s, mth)) {
            nsing++;
            strncat(names, names[0] ? "," : "", sizeof names - strlen(names) - 1);
            strncat(names, aug_method_names[mth], sizeof names - strlen(names) - 1);
        } else if (!aug_solver_converged(s, mth)) {
            fprintf(stderr, "%s: step %d: %s did not converge (relres %.3g)\n", t->prog, (int)step,
                    aug_method_names[mth], aug_kv_get(aug_solver_stat(s, mth), "relres", NAN));
        }
    }
    if (nsing && !o->on_singular_report)
        aug_tool_die(t, "%s: record %ld (UPDT): step %d: K_t is singular or not positive definite (%s)",
                     t->inname, rec->index, (int)step, names);
    if (nsing)
        fprintf(stderr, "%s: step %d: K_t is singular or not positive definite (%s)\n", t->prog,
                (int)step, names);
}

/* one UPDT: every method solves K_t; the first one's field on the output set,
   then sTAt and tIMe per method */
static void step(aug_tool *t, const options *o, aug_replay *rp, aug_sys0 *sys, double *full_ms,
                 const aug_rec *rec)
{
    aug_err e;
    aug_update u;
    if (aug_read_update(rec, &u, &e)) aug_tool_fail(t, &e);
    if (!sys->solver) {
        aug_tool_check(t, aug_sys0_solver(sys, rp->started ? rp->nfree0 : -1, &o->so, rec, &e), &e);
        *full_ms = aug_solver_full_solve_ms(sys->solver, 5);
    }
    aug_solver *s = sys->solver;
    const int32_t *out;
    int64_t nout;
    aug_tool_check(t, aug_replay_out_dofs(rp, &out, &nout, &e), &e);
    int flags = rp->nmdlt && rp->mdlt_step == u.step ? rp->mdlt_flags : 0;
    if (aug_solver_step(s, &u, aug_replay_all(rp) ? NULL : out, nout, flags, &e)) {
        e.record = rec->index;
        snprintf(e.type, sizeof e.type, "UPDT");
        aug_tool_fail(t, &e);
    }
    aug_tool_pass(t, rec);
    report(t, o, s, rec, u.step);
    int first = o->so.order[0];
    if (!aug_solver_singular(s, first) && (rp->mesh.have & AUG_HAVE_NODE))
        aug_tool_check(t, aug_replay_write_field(t->w, rp, u.step, aug_solver_field(s, first), &e), &e);
    /* the reference a step is compared with, timed next to it (bench) */
    if (o->time_full) *full_ms = aug_solver_full_solve_ms(s, 1);
    for (int i = 0; i < o->so.nmeth; i++) {
        int mth = o->so.order[i];
        aug_tool_check(t, aug_write_kv(t->w, "sTAt", u.step, aug_solver_stat(s, mth), &e), &e);
        aug_kv tm = *aug_solver_time(s, mth);
        aug_kv_set(&tm, "full_solve_ms", *full_ms);
        aug_tool_check(t, aug_write_kv(t->w, "tIMe", u.step, &tm, &e), &e);
    }
    aug_update_free(&u);
}

int main(int argc, char **argv)
{
    aug_tool t;
    options o;
    aug_err e;
    aug_replay rp;
    aug_sys0 sys;
    aug_rec rec;
    double full_ms = 0;
    memset(&rec, 0, sizeof rec);
    aug_tool_init(&t, "solve-aug", argc, argv);
    parse(&t, argc, argv, &o);
    aug_set_threads(o.so.nthreads);
    aug_tool_open_in(&t, o.file);
    aug_tool_open_out(&t);
    aug_replay_init(&rp);
    rp.output = o.output;
    aug_tool_check(&t, aug_sys0_init(&sys, &e), &e);
    while (aug_tool_read(&t, &rec)) {
        aug_tool_check(&t, aug_replay_add(&rp, &rec, &e), &e);
        aug_tool_check(&t, aug_sys0_add(&sys, &rec, &e), &e);
        if (!memcmp(rec.type, "UPDT", 4)) step(&t, &o, &rp, &sys, &full_ms, &rec);
        else aug_tool_pass(&t, &rec);
    }
    aug_tool_close(&t);
    aug_rec_free(&rec);
    aug_sys0_free(&sys);
    aug_replay_free(&rp);
    return 0;
}
