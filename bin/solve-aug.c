/* solve-aug: factor + update records -> per step the displacement field of the
   output set, the reaction forces and per-method sTAt/tIMe (AMPS, augmented
   GMRES, baselines). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_solve.h"
#include "cli/aug_opt.h"

static const char *synopsis =
    "solve-aug [FILE] [--method LIST] [--check] [--background] [--bg-lag N] [--horizon N]\n"
    "          [--output all|surface|SET|node:ID,..] [--refine-iter N] [--refine-tol R]\n"
    "          [--amps-target R] [--amps-correct N] [--amps-pivot s2|alt|auto]\n"
    "          [--amps-field solve|memo] [--fail-tol F] [--tol T] [--maxit N]\n"
    "          [--gmres-prec none|D|spai] [--restart N] [--spare N] [--on-singular error|report]\n"
    "          [--reach path|cholmod] [--threads N] [--time-full] [--frames N] [--settle N]\n"
    "          [--no-reactions] [--prefault MIB] [--pcg-prec none|jacobi|ic|ic-amd] [--cgm-eps E] [--cgm-p P]\n"
    "          [--cgm-max-n N] [--ns-tol T] [--ns-maxit N] [-h]";

static const char *help =
    "  FILE                 input stream (default: stdin)\n"
    "  --method LIST        comma list of auto,amps,gmres,refactor,rowupdate,pcg, cgm-cov,\n"
    "                       cgm-es,cgm-log,cgm-as (default auto: AMPS or a re-factorization\n"
    "                       per step by measured cost; not with amps or gmres); the first\n"
    "                       one's field is written\n"
    "  --check              err_direct: difference to a fresh CHOLMOD solve of K_t\n"
    "  --background         re-factor in a background thread, swap when done (amps, gmres;\n"
    "                       auto: lets it choose one)\n"
    "  --bg-lag N           swap exactly N steps after each start (deterministic)\n"
    "  --horizon N          auto: the stream brings N steps (a pre-defined cut, e.g. cut\n"
    "                       --steps N); no re-factorization the steps left cannot pay back\n"
    "                       (default: the stream's pLAN; 0: unknown, the online rule)\n"
    "  --output all|surface|SET  nodes whose displacement is solved and written\n"
    "  --output node:ID[,ID...]  only these nodes (0-based, as in the stream), e.g. a\n"
    "                       haptic tool contact\n"
    "  --refine-iter N      exactly N iterative refinement steps per solve (default 0:\n"
    "                       adaptive, see --refine-tol)\n"
    "  --refine-tol R       direct methods refine while relres > R, at most 3 steps,\n"
    "                       each halving it (default 1e-8; 0: never)\n"
    "  --amps-target R      amps refines once more when its relres exceeds R (default\n"
    "                       1e-12; 0: off)\n"
    "  --amps-correct N     amps corrects on the rows of H at most N times per step,\n"
    "                       residuals from back-substitutions over their closure\n"
    "                       (default 2; 0: never)\n"
    "  --amps-pivot P       amps's Schur pivot: s2 (eq. 3.8, default), alt (eqs.\n"
    "                       3.16-3.17: the forces solved for directly) or auto\n"
    "  --amps-field F       amps's K^-1 H w: solve (a forward solve over the closure\n"
    "                       of H, default) or memo (the memo's V columns, paper 001)\n"
    "  --fail-tol F         a direct method whose relres stays above F reports the\n"
    "                       step singular (default 1e-6, or 100 x the base's relres)\n"
    "  --tol T              relres ||K_t a - f_t||/||f_t|| gmres and pcg stop at (default 1e-8)\n"
    "  --maxit N            iteration cap of gmres and pcg (default 10000)\n"
    "  --gmres-prec P       none, D or spai (default D)\n"
    "  --restart N          GMRES restart length (default 100)\n"
    "  --spare N            rowupdate: spare identity rows for new DOFs (default 3000)\n"
    "  --on-singular error|report  a singular step: exit 1 (default) or report and go on\n"
    "  --reach path|cholmod AMPS V columns: own etree-path solve (default) or cholmod_solve2\n"
    "  --threads N          threads of OpenBLAS under CHOLMOD (default 1); 2 or more: AMPS's\n"
    "                       full-field back-substitution on two cores (solve-aug(1))\n"
    "  --frames N           dynamic stream: time frames per cut step (default 1)\n"
    "  --settle N           dynamic stream: frames after the last step (default 0)\n"
    "  --time-full          time one full CHOLMOD solve of the base every step\n"
    "                       (full_solve_ms; default: the median of 5 at the start)\n"
    "  --no-reactions       no reaction forces (rEAC) per step\n"
    "  --prefault MIB       touch MIB MiB of heap before the first step, for the arrays\n"
    "                       that grow with the steps (default 0; solve-aug(1))\n"
    "  --pcg-prec P         pcg preconditioner: none, jacobi (default), ic (IC(0)) or\n"
    "                       ic-amd (IC(0) on the AMD ordering)\n"
    "  --cgm-eps E          cgm-*: D' = D + E I, AS: COV + E I (default 1e-6)\n"
    "  --cgm-p P            cgm-es: exponent of D' (default 0.5)\n"
    "  --cgm-max-n N        cgm-*: refuse K_t of order above N (dense; default 8400)\n"
    "  --ns-tol T           cgm-as: Newton-Schulz stops at ||I - Q_k P_k||_F <= T (default 1e-10)\n"
    "  --ns-maxit N         cgm-as: Newton-Schulz iteration cap (default 100)\n"
    "  -h                   this help; see solve-aug(1)\n";

typedef struct options {
    const char *file, *output;
    aug_solver_opts so;
    int on_singular_report;
    int time_full;
    int frames, settle, nframes, nsettle;
    int no_reactions;
    int prefault;     /* MiB */
    double pf_ms;     /* its time, reported once (< 0: reported or none) */
} options;

static const aug_word precs[] = {
    {"none", AUG_PREC_NONE}, {"D", AUG_PREC_D}, {"spai", AUG_PREC_SPAI}, {NULL, 0}};
static const aug_word singular[] = {{"error", 0}, {"report", 1}, {NULL, 0}};
static const aug_word reaches[] = {{"path", 0}, {"cholmod", 1}, {NULL, 0}};
static const aug_word pivots[] = {
    {"s2", AUG_PIVOT_S2}, {"alt", AUG_PIVOT_ALT}, {"auto", AUG_PIVOT_AUTO}, {NULL, 0}};
static const aug_word fields[] = {{"solve", 0}, {"memo", 1}, {NULL, 0}};
static const aug_word pcg_precs[] = {
    {"none", AUG_PCG_NONE}, {"jacobi", AUG_PCG_JACOBI}, {"ic", AUG_PCG_IC}, {"ic-amd", AUG_PCG_IC_AMD}, {NULL, 0}};

/* --method LIST: the methods in order */
static int methods(aug_tool *t, const char *opt, const char *val, void *dst)
{
    aug_solver_opts *so = dst;
    char why[64];
    int k = aug_methods_parse(val, so->order, why);
    if (k <= 0) return aug_tool_usage(t, "%s %s: %s", opt, val, why), -1;
    so->nmeth = k;
    return 0;
}

static void parse(aug_tool *t, int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    aug_solver_opts_default(&o->so);
    o->frames = 1;
    aug_solver_opts *so = &o->so;
    int nlag = 0, nrtol = 0, max_n = (int)so->cgm.max_n, horizon = -1;
    const aug_opt opt[] = {
        {AUG_OPT_CALL("--method", methods, so,
                      "a comma list of auto,amps,gmres,refactor,rowupdate,pcg,cgm-cov,cgm-es,cgm-log,cgm-as"), .flags = AUG_OPT_ONCE},
        {AUG_OPT_FLAG("--check", &so->check)},
        {AUG_OPT_FLAG("--time-full", &o->time_full)},
        {AUG_OPT_FLAG("--no-reactions", &o->no_reactions)},
        {AUG_OPT_FLAG("--background", &so->background)},
        {AUG_OPT_INT("--bg-lag", &so->bg_lag, 1, 1000000, "a count >= 1"), .given = &nlag},
        {AUG_OPT_INT("--horizon", &horizon, 0, 1000000000, "a count >= 0")},
        {AUG_OPT_STRING("--output", &o->output, "all, surface, a set name or node:ID[,ID...]"), .flags = AUG_OPT_NONEMPTY},
        {AUG_OPT_INT("--refine-iter", &so->refine_iter, 0, 100, "0 to 100")},
        {AUG_OPT_REAL("--refine-tol", &so->refine_tol, 0, 1, "a number in [0, 1)"),
         .flags = AUG_OPT_HI_OPEN, .given = &nrtol},
        {AUG_OPT_REAL("--fail-tol", &so->fail_tol, 0, 1, "a number in (0, 1)"), .flags = AUG_OPT_LO_OPEN | AUG_OPT_HI_OPEN,
         .given = &so->fail_tol_fixed},
        {AUG_OPT_REAL("--amps-target", &so->amps_target, 0, 1, "a number in [0, 1)"),
         .flags = AUG_OPT_HI_OPEN},
        {AUG_OPT_INT("--amps-correct", &so->amps_correct, 0, 10, "0 to 10")},
        {AUG_OPT_CHOICE("--amps-pivot", &so->amps_pivot, pivots, "s2, alt or auto")},
        {AUG_OPT_CHOICE("--amps-field", &so->amps_field_memo, fields, "solve or memo")},
        {AUG_OPT_REAL("--tol", &so->tol, 0, 1, "a number in (0, 1)"),
         .flags = AUG_OPT_LO_OPEN | AUG_OPT_HI_OPEN},
        {AUG_OPT_INT("--maxit", &so->maxit, 1, 100000000, "a count >= 1")},
        {AUG_OPT_INT("--restart", &so->restart, 1, 10000, "1 to 10000")},
        {AUG_OPT_INT("--spare", &so->spare, 1, 100000000, "a count >= 1")},
        {AUG_OPT_CHOICE("--gmres-prec", &so->gmres_prec, precs, "none, D or spai")},
        {AUG_OPT_CHOICE("--on-singular", &o->on_singular_report, singular, "error or report")},
        {AUG_OPT_CHOICE("--reach", &so->reach_cholmod, reaches, "path or cholmod")},
        {AUG_OPT_THREADS(&so->nthreads)},
        {AUG_OPT_INT("--frames", &o->frames, 1, 100000000, "a count >= 1"), .given = &o->nframes},
        {AUG_OPT_INT("--settle", &o->settle, 0, 100000000, "a count >= 0"), .given = &o->nsettle},
        {AUG_OPT_CHOICE("--pcg-prec", &so->pcg_prec, pcg_precs, "none, jacobi, ic or ic-amd")},
        {AUG_OPT_REAL("--cgm-eps", &so->cgm.eps, 0, 1e300, "a number in (0, 1e300]"), .flags = AUG_OPT_LO_OPEN},
        {AUG_OPT_REAL("--cgm-p", &so->cgm.p, 0, 1e300, "a number in (0, 1e300]"), .flags = AUG_OPT_LO_OPEN},
        {AUG_OPT_INT("--cgm-max-n", &max_n, 1, 46340, "1 to 46340")},
        {AUG_OPT_INT("--prefault", &o->prefault, 0, 1900, "0 to 1900 (MiB)")},
        {AUG_OPT_REAL("--ns-tol", &so->cgm.ns_tol, 0, 1, "a number in (0, 1)"),
         .flags = AUG_OPT_LO_OPEN | AUG_OPT_HI_OPEN},
        {AUG_OPT_INT("--ns-maxit", &so->cgm.ns_maxit, 1, 100000, "1 to 100000")},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &o->file, synopsis, help);
    if (nlag) so->background = 1;
    so->cgm.max_n = max_n;
    so->horizon = horizon;
    if (nrtol) so->refine_max = so->refine_tol > 0 ? 3 : 0;
    if (aug_solver_opts_conflict(so)) aug_tool_usage(t, "%s", aug_solver_opts_conflict(so)); /* before any input */
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

/* a dynamic stream's session: the integrator's state, the step's UPKM until
   its UPDT, the initial frame factor wrote */
typedef struct dyn {
    aug_dynsim sim;
    int started;
    aug_update km;
    long km_index;
    aug_frame init;
    int have_init;
    double *b;
    int64_t bcap;
} dyn;

/* the solver (and, dynamic, the state) at the first update or settle frame */
static void start(aug_tool *t, options *o, aug_replay *rp, aug_sys0 *sys, dyn *dy,
                  double *full_ms, const aug_rec *rec)
{
    aug_err e;
    if (!sys->solver) {
        aug_tool_check(t, aug_sys0_solver(sys, rp->have_dofm ? rp->nfree0 : -1, &o->so, rec, &e), &e);
        *full_ms = aug_solver_full_solve_ms(sys->solver, 5);
        /* after the base's own arrays, before the first step's */
        if (o->prefault && (o->pf_ms = aug_prefault((size_t)o->prefault << 20)) < 0)
            aug_tool_die(t, "%s: record %ld (%s): out of memory (--prefault %d)", t->inname, rec->index,
                         rec->type, o->prefault);
    }
    if (!sys->dynamic || dy->started) return;
    if (!(rp->mesh.have & AUG_HAVE_NODE))
        aug_tool_die(t, "%s: record %ld (%s): a dynamic stream needs its mesh", t->inname, rec->index,
                     rec->type);
    aug_tool_check(t, aug_dynsim_init(&dy->sim, &sys->dyn, sys->K0, sys->Mk[sys->dyn.mass - 1],
                                      sys->f0, sys->cm, &e), &e);
    aug_tool_check(t, aug_dynsim_start(&dy->sim, rp, dy->have_init ? &dy->init : NULL, &e), &e);
    dy->started = 1;
}

/* the first tIMe after the prefault carries its time (prefault_ms) */
static void pf_once(options *o, aug_kv *tm)
{
    if (o->pf_ms >= 0 && o->prefault) aug_kv_set(tm, "prefault_ms", o->pf_ms);
    o->pf_ms = -1;
}

/* n frames of the current step: the right-hand side from the state, every
   method's solve, the state advanced by the first method's solution, then
   fRAM, sTAt and tIMe per method and sTAt (tag dynamics) per frame */
static void frames(aug_tool *t, options *o, aug_replay *rp, aug_sys0 *sys, dyn *dy,
                   int32_t step, long n, double full_ms, const aug_rec *rec, aug_react *rs)
{
    aug_err e;
    aug_solver *s = sys->solver;
    aug_dynsim *d = &dy->sim;
    int first = o->so.order[0];
    for (long f = 0; f < n; f++) {
        if (d->n > dy->bcap) {
            free(dy->b);
            dy->bcap = 2 * d->n;
            if (!(dy->b = malloc((size_t)dy->bcap * sizeof *dy->b))) aug_tool_die(t, "out of memory");
        }
        double t0 = aug_now();
        aug_tool_check(t, aug_dynsim_rhs(d, rp, dy->b, &e), &e);
        double t_rhs = aug_now() - t0;
        if (aug_solver_frame(s, dy->b, d->frame + 1, &e)) {
            e.record = rec->index;
            aug_tool_fail(t, &e);
        }
        if (o->so.check && !aug_replay_all(rp)) { /* err_out on the output set (and reaction DOFs) */
            const int32_t *out;
            int64_t nout;
            aug_tool_check(t, aug_replay_out_dofs(rp, &out, &nout, &e), &e);
            if (rs) aug_tool_check(t, aug_react_out_dofs(rs, &out, &nout, &e), &e);
            aug_solver_frame_err_out(s, out, nout);
        }
        for (int i = 0; i < o->so.nmeth; i++) {
            int mth = o->so.order[i];
            if (aug_solver_frame_singular(s, mth) && (mth == first || !o->on_singular_report))
                aug_tool_die(t, "%s: record %ld (%s): step %d, frame %d: %s did not solve A_t "
                             "(relres %.3g)", t->inname, rec->index, rec->type, (int)step,
                             (int)d->frame + 1, aug_method_names[mth],
                             aug_kv_get(aug_solver_stat(s, mth), "relres", NAN));
            /* the first method's frame is the state the next one starts
               from: one it did not solve (pcg or gmres not converged) ends
               the run as a singular one does, no fRAM or rEAC written as
               if it were solved (formats/stream.md 7.3) */
            if (!aug_solver_converged(s, mth) && mth == first && (mth == AUG_M_PCG || mth == AUG_M_GMRES))
                aug_tool_die(t, "%s: record %ld (%s): step %d, frame %d: %s did not converge (relres %.3g): the "
                             "frames go on from its field", t->inname, rec->index, rec->type, (int)step,
                             (int)d->frame + 1, aug_method_names[mth], aug_kv_get(aug_solver_stat(s, mth), "relres", NAN));
            if (!aug_solver_converged(s, mth))
                fprintf(stderr, "%s: step %d, frame %d: %s did not converge (relres %.3g)\n",
                        t->prog, (int)step, (int)d->frame + 1, aug_method_names[mth],
                        aug_kv_get(aug_solver_stat(s, mth), "relres", NAN));
        }
        t0 = aug_now();
        aug_tool_check(t, aug_dynsim_advance(d, rp, aug_solver_field(s, first), &e), &e);
        double t_adv = aug_now() - t0;
        if (rp->mesh.have & AUG_HAVE_NODE)
            aug_tool_check(t, aug_replay_write_frame(t->w, rp, step, d->frame, d->time, d->u, d->v, &e), &e);
        if (rs && (rp->mesh.have & AUG_HAVE_NODE)) {
            aug_react_frame fr = {d->frame, d->time, d->v, d->acc, d->p.alpha, d->p.beta, d->p.mass == 2};
            aug_tool_check(t, aug_react_write(t->w, rs, step, d->u, &fr, &e), &e);
        }
        for (int i = 0; i < o->so.nmeth; i++) {
            int mth = o->so.order[i];
            aug_kv st = *aug_solver_stat(s, mth), tm = *aug_solver_time(s, mth);
            aug_kv_set(&st, "time", d->time);
            aug_tool_check(t, aug_write_kv(t->w, "sTAt", step, &st, &e), &e);
            aug_kv_set(&tm, "frame", d->frame);
            aug_kv_set(&tm, "full_solve_ms", full_ms);
            pf_once(o, &tm); /* (a settle-only run has no step's tIMe) */
            aug_tool_check(t, aug_write_kv(t->w, "tIMe", step, &tm, &e), &e);
        }
        aug_kv k;
        aug_kv_init(&k, "dynamics");
        aug_kv_set(&k, "frame", d->frame);
        aug_kv_set(&k, "time", d->time);
        aug_kv_set(&k, "kinetic", d->kinetic);
        aug_kv_set(&k, "potential", d->potential);
        aug_kv_set(&k, "work", d->work);
        aug_kv_set(&k, "energy", d->kinetic + d->potential - d->work);
        aug_tool_check(t, aug_write_kv(t->w, "sTAt", step, &k, &e), &e);
        aug_kv_init(&k, "dynamics");
        aug_kv_set(&k, "frame", d->frame);
        aug_kv_set(&k, "rhs_ms", 1e3 * t_rhs);
        aug_kv_set(&k, "advance_ms", 1e3 * t_adv);
        aug_tool_check(t, aug_write_kv(t->w, "tIMe", step, &k, &e), &e);
    }
}

/* one UPDT: every method solves K_t; the first one's field on the output set
   and the reaction forces (rs, NULL: none), then sTAt and tIMe per method;
   dynamic: the step's frames */
static void step(aug_tool *t, options *o, aug_replay *rp, aug_sys0 *sys, dyn *dy,
                 double *full_ms, const aug_rec *rec, aug_react *rs)
{
    aug_err e;
    aug_update u;
    if (aug_read_update(rec, &u, &e)) aug_tool_fail(t, &e);
    if (sys->dynamic) {
        if (!dy->km.EK)
            aug_tool_die(t, "%s: record %ld (UPDT): step %d of a dynamic stream has no UPKM", t->inname,
                         rec->index, (int)u.step);
        aug_tool_check(t, aug_update_attach_km(&u, &dy->km, dy->km_index, rec, sys->dyn.cM, sys->dyn.cK, &e), &e);
        aug_update_free(&dy->km);
    }
    start(t, o, rp, sys, dy, full_ms, rec);
    aug_solver *s = sys->solver;
    const int32_t *out;
    int64_t nout;
    aug_tool_check(t, aug_replay_out_dofs(rp, &out, &nout, &e), &e);
    if (rs) aug_tool_check(t, aug_react_out_dofs(rs, &out, &nout, &e), &e);
    int flags = rp->nmdlt && rp->mdlt_step == u.step ? rp->mdlt_flags : 0;
    aug_solver_plan(s, rp->plan_last);
    if (aug_solver_step(s, &u, aug_replay_all(rp) ? NULL : out, nout, flags, &e)) {
        e.record = rec->index;
        snprintf(e.type, sizeof e.type, "UPDT");
        aug_tool_fail(t, &e);
    }
    aug_tool_pass(t, rec);
    report(t, o, s, rec, u.step);
    if (sys->dynamic) {
        aug_tool_check(t, aug_dynsim_step(&dy->sim, &u, rp, rp->mdlt_step == u.step ? rp->mdlt_parent : NULL,
                                          rp->mdlt_step == u.step ? rp->mdlt_nnew : 0, &e), &e);
        for (int i = 0; i < o->so.nmeth; i++) {
            int mth = o->so.order[i];
            aug_tool_check(t, aug_write_kv(t->w, "sTAt", u.step, aug_solver_stat(s, mth), &e), &e);
            aug_kv tm = *aug_solver_time(s, mth);
            pf_once(o, &tm);
            aug_tool_check(t, aug_write_kv(t->w, "tIMe", u.step, &tm, &e), &e);
        }
        /* the reference of the step's frames (A_t's), timed next to them */
        if (o->time_full) *full_ms = aug_solver_full_solve_ms(s, 1);
        frames(t, o, rp, sys, dy, u.step, o->frames, *full_ms, rec, rs);
        aug_update_free(&u);
        return;
    }
    int first = o->so.order[0];
    /* formats/stream.md 7.3: a step the first method did not solve (singular,
       or pcg or gmres not converged) writes no field; cgm-* write the x of
       their own system whatever its iteration did (their sTAt says how far) */
    int iter = first == AUG_M_PCG || first == AUG_M_GMRES;
    int solved = !aug_solver_singular(s, first) && (!iter || aug_solver_converged(s, first));
    if (solved && (rp->mesh.have & AUG_HAVE_NODE))
        aug_tool_check(t, aug_replay_write_field(t->w, rp, u.step, aug_solver_field(s, first), &e), &e);
    if (rs && solved && (rp->mesh.have & AUG_HAVE_NODE))
        aug_tool_check(t, aug_react_write(t->w, rs, u.step, aug_solver_field(s, first), NULL, &e), &e);
    /* the reference a step is compared with, timed next to it (bench) */
    if (o->time_full) *full_ms = aug_solver_full_solve_ms(s, 1);
    for (int i = 0; i < o->so.nmeth; i++) {
        int mth = o->so.order[i];
        aug_tool_check(t, aug_write_kv(t->w, "sTAt", u.step, aug_solver_stat(s, mth), &e), &e);
        aug_kv tm = *aug_solver_time(s, mth);
        aug_kv_set(&tm, "full_solve_ms", *full_ms);
        pf_once(o, &tm);
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
    aug_react rs;
    aug_sys0 sys;
    aug_rec rec;
    double full_ms = 0;
    memset(&rec, 0, sizeof rec);
    aug_tool_init(&t, "solve-aug", argc, argv);
    parse(&t, argc, argv, &o);
    aug_tool_threads(&t, o.so.nthreads);
    aug_tool_open_in(&t, o.file);
    aug_tool_open_out(&t);
    aug_replay_init(&rp);
    rp.output = o.output;
    aug_react_init(&rs, o.no_reactions ? NULL : &rp);
    aug_tool_check(&t, aug_sys0_init(&sys, &e), &e);
    dyn dy;
    memset(&dy, 0, sizeof dy);
    while (aug_tool_read(&t, &rec)) {
        int perstep = aug_rec_changes_step(&rec);
        /* a static stream is known by its first step (DYNP comes before):
           refused there, not after solving every step */
        if (perstep && !sys.dynamic && (o.nsettle || o.nframes))
            aug_tool_die(&t, "%s: record %ld (%s): --frames and --settle need a dynamic stream (factor --dynamic)",
                         t.inname, rec.index, rec.type);
        /* the state starts on the original mesh, before the first step's records */
        if (sys.dynamic && !dy.started && perstep)
            start(&t, &o, &rp, &sys, &dy, &full_ms, &rec);
        aug_tool_check(&t, aug_replay_add(&rp, &rec, &e), &e);
        aug_tool_check(&t, aug_sys0_add(&sys, &rec, &e), &e);
        if (!memcmp(rec.type, "UPDT", 4)) {
            step(&t, &o, &rp, &sys, &dy, &full_ms, &rec, o.no_reactions ? NULL : &rs);
            aug_progress(&t, rec.step, 0);
            continue;
        }
        if (!memcmp(rec.type, "UPKM", 4)) {
            if (!sys.dynamic)
                aug_tool_die(&t, "%s: record %ld (UPKM): an update of K and M without DYNP", t.inname,
                             rec.index);
            aug_update_free(&dy.km);
            aug_tool_check(&t, aug_read_updkm(&rec, &dy.km, &e), &e);
            dy.km_index = rec.index;
        } else if (!memcmp(rec.type, "fRAM", 4) && !dy.started && !dy.have_init) {
            aug_frame_free(&dy.init);
            aug_tool_check(&t, aug_read_frame(&rec, &dy.init, &e), &e);
            dy.have_init = rec.step == 0 && !dy.init.nodes;
        }
        aug_tool_pass(&t, &rec);
    }
    aug_tool_check(&t, aug_replay_end(&rp, &e), &e);
    /* a stream without the original system solves nothing: not a success */
    if (!sys.K0 && !sys.A0)
        aug_tool_die(&t, "%s: no KMAT record: solve-aug needs a factored stream (meshload | factor | ...)",
                     t.inname);
    if (sys.dynamic && o.settle > 0) {
        start(&t, &o, &rp, &sys, &dy, &full_ms, &rec);
        frames(&t, &o, &rp, &sys, &dy, rp.last_step, o.settle, full_ms, &rec, o.no_reactions ? NULL : &rs);
    } else if (!sys.dynamic && (o.nsettle || o.nframes)) {
        aug_tool_die(&t, "%s: --frames and --settle need a dynamic stream (factor --dynamic)", t.inname);
    }
    aug_tool_close(&t);
    aug_dynsim_free(&dy.sim);
    aug_update_free(&dy.km);
    aug_frame_free(&dy.init);
    free(dy.b);
    aug_rec_free(&rec);
    aug_sys0_free(&sys);
    aug_react_free(&rs);
    aug_replay_free(&rp);
    return 0;
}
