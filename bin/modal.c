/* modal: a dynamic stream with cut steps -> its frames simulated per
   sub-domain, each in full FE or in its own snapshot subspace, coupled at the
   interfaces (paper 004); fRAM, sTAt/tIMe (tag modal) per frame, MODE when a
   basis changes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_msim.h"
#include "aug_solve.h"
#include "cli/aug_opt.h"

static const char *synopsis =
    "modal [FILE] [--domains material|one|GROUPS] [--split K] [--reduce all|none|LIST]\n"
    "      [--rank R] [--svd-tol T] [--tau-svd T] [--err-tol E] [--acc-tol A] [--min-snap N]\n"
    "      [--sync N] [--probes K] [--gate exact|estimate] [--coupling direct|schur|ppcg] [--tol T]\n"
    "      [--maxit N] [--basis svd|identity] [--lead N] [--frames N] [--settle N] [--check]\n"
    "      [--ordering auto|amd|metis] [--after-cut all|neighbours|touched] [--warp] [--lma K]\n"
    "      [--fe-solver amps|cholmod] [--monitor]\n"
    "      [--output all|surface|SET|node:ID,...] [--seed S] [--threads N] [-h]";

static const char *help =
    "  FILE                 input stream of factor --dynamic [| cut ...] (default: stdin)\n"
    "  --domains SPEC       sub-domains: material (default, one per material), one, or\n"
    "                       groups of material names or ids, e.g. bone,muscle/fat\n"
    "  --split K            split every group into K slabs along its longest side (default 1)\n"
    "  --reduce LIST        domains that may switch to their subspace: all (default), none,\n"
    "                       or a comma list of domain numbers\n"
    "  --rank R             rank cap of each domain's basis (default 32)\n"
    "  --svd-tol T          drop singular values <= T s_1 (default 1e-8)\n"
    "  --tau-svd T          switch test, eq. 12: singular-value sum ratio > T (default 0.95)\n"
    "  --err-tol E          switch when the relative projection error < E (default 0.01)\n"
    "  --acc-tol A          error budget of a domain over the run: reduced at projection\n"
    "                       error err, it returns to FE when err plus the accumulated\n"
    "                       residual estimate of its reduced frames passes A, and then\n"
    "                       stays FE (default 0.01)\n"
    "  --min-snap N         snapshots a domain takes before it may switch (default 4)\n"
    "  --sync N             a domain ready to switch waits up to N frames for the other FE\n"
    "                       domains to be ready too (default 10; 0: at once)\n"
    "  --probes K           random probes of the eq. 14 estimate (default 4; 0: none)\n"
    "  --gate exact|estimate  the error the switch tests (default exact)\n"
    "  --coupling C         direct (slave elimination, default), schur (dual Schur\n"
    "                       complement) or ppcg (projected PCG, constraint preconditioner)\n"
    "  --tol T              ppcg relative residual (default 1e-10)\n"
    "  --maxit N            ppcg iteration cap (default 20000)\n"
    "  --basis svd|identity snapshot bases (default) or W = I from the start (a check)\n"
    "  --lead N             frames on the intact mesh before the first cut step (default 0)\n"
    "  --frames N           frames per cut step (default 1)\n"
    "  --settle N           frames after the last step (default 0)\n"
    "  --warp               write the warped displacement (eqs. 16-17)\n"
    "  --lma K              the K lowest modes of every domain (MODE kind 1, sTAt lma)\n"
    "  --check              full FE on the same frames too: l2_err per frame, fe_ms\n"
    "  --output all|surface|SET|node:ID,...  nodes written in fRAM (default: the stream's oUTs)\n"
    "  --after-cut W        which reduced domains a cut step returns to FE: all (default),\n"
    "                       neighbours (those sharing an interface with a domain it\n"
    "                       touches) or touched (only those it re-wires: paper 004)\n"
    "  --monitor            one line per frame on stderr: the domains' states and error budgets\n"
    "  --fe-solver S        every domain FE: amps (default: the stream's factor and its cut\n"
    "                       updates, as solve-aug) or cholmod (the shared-node system factored)\n"
    "  --ordering auto|amd|metis  fill-reducing ordering of the FE factors (default metis)\n"
    "  --seed S             seed of the estimate's probes (default 1)\n"
    "  --threads N          threads of OpenBLAS under CHOLMOD (default 1)\n"
    "  -h                   this help; see modal(1)\n";

typedef struct options {
    const char *file, *output;
    aug_msim_opts mo;
    int frames, settle, lead, check, seed, threads, ordering, lma, fe_cholmod, monitor;
    int32_t red[256];
} options;

static const aug_word gates[] = {{"exact", 0}, {"estimate", 1}, {NULL, 0}};
static const aug_word couplings[] = {
    {"direct", AUG_COUPLE_DIRECT}, {"schur", AUG_COUPLE_SCHUR}, {"ppcg", AUG_COUPLE_PPCG}, {NULL, 0}};
static const aug_word aftercut[] = {
    {"all", AUG_AFTER_CUT_ALL}, {"neighbours", AUG_AFTER_CUT_NEIGHBOURS}, {"touched", AUG_AFTER_CUT_TOUCHED}, {NULL, 0}};
static const aug_word fesolvers[] = {{"amps", 0}, {"cholmod", 1}, {NULL, 0}};
static const aug_word orderings[] = {
    {"auto", AUG_ORDER_AUTO}, {"amd", AUG_ORDER_AMD}, {"metis", AUG_ORDER_METIS}, {NULL, 0}};
static const aug_word bases[] = {{"svd", AUG_BASIS_SVD}, {"identity", AUG_BASIS_IDENTITY}, {NULL, 0}};

/* --reduce all|none|LIST */
static int reduce_list(aug_tool *t, const char *opt, const char *val, void *dst)
{
    options *o = dst;
    o->mo.reduce_all = o->mo.reduce_none = 0, o->mo.nreduce = 0;
    if (!strcmp(val, "all")) return o->mo.reduce_all = 1, 0;
    if (!strcmp(val, "none")) return o->mo.reduce_none = 1, 0;
    const char *s = val;
    while (*s) {
        char *end;
        long v = strtol(s, &end, 10);
        if (end == s || v < 0 || v > 1000000 || o->mo.nreduce == 256 || (*end && *end != ',')) return -1;
        for (int i = 0; i < o->mo.nreduce; i++)
            if (o->red[i] == v) return aug_tool_usage(t, "%s %s: domain %ld given twice", opt, val, v), -1;
        o->red[o->mo.nreduce++] = (int32_t)v;
        if (*end && !end[1]) return -1; /* "0,": an empty last number */
        s = *end ? end + 1 : end;
    }
    o->mo.reduce = o->red;
    return o->mo.nreduce ? 0 : -1;
}

static void parse(aug_tool *t, int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    aug_msim_opts_default(&o->mo);
    o->frames = 1, o->seed = 1, o->ordering = AUG_ORDER_METIS;
    aug_msim_opts *m = &o->mo;
    const aug_opt opt[] = {
        {AUG_OPT_STRING("--domains", &m->domains, "material, one or groups like a,b/c"), .flags = AUG_OPT_NONEMPTY},
        {AUG_OPT_INT("--split", &m->split, 1, 1000, "1 to 1000")},
        {AUG_OPT_CALL("--reduce", reduce_list, o, "all, none or a comma list of domain numbers"), .flags = AUG_OPT_ONCE},
        {AUG_OPT_INT("--rank", &m->rank, 1, 10000, "1 to 10000")},
        {AUG_OPT_REAL("--svd-tol", &m->svd_tol, 0, 1, "a number in [0, 1)"), .flags = AUG_OPT_HI_OPEN},
        {AUG_OPT_REAL("--tau-svd", &m->tau_svd, 0, 1, "a number in (0, 1)"),
         .flags = AUG_OPT_LO_OPEN | AUG_OPT_HI_OPEN},
        {AUG_OPT_REAL("--err-tol", &m->err_tol, 0, 1, "a number in (0, 1)"),
         .flags = AUG_OPT_LO_OPEN | AUG_OPT_HI_OPEN},
        {AUG_OPT_REAL("--acc-tol", &m->acc_tol, 0, 1e6, "a number in (0, 1e6]"), .flags = AUG_OPT_LO_OPEN},
        {AUG_OPT_INT("--min-snap", &m->min_snap, 1, 100000000, "a count >= 1")},
        {AUG_OPT_INT("--sync", &m->sync, 0, 100000000, "a count >= 0")},
        {AUG_OPT_INT("--probes", &m->probes, 0, 64, "0 to 64")},
        {AUG_OPT_CHOICE("--gate", &m->gate_estimate, gates, "exact or estimate")},
        {AUG_OPT_CHOICE("--coupling", &m->coupling, couplings, "direct, schur or ppcg")},
        {AUG_OPT_REAL("--tol", &m->tol, 0, 1, "a number in (0, 1)"), .flags = AUG_OPT_LO_OPEN | AUG_OPT_HI_OPEN},
        {AUG_OPT_INT("--maxit", &m->maxit, 1, 100000000, "a count >= 1")},
        {AUG_OPT_CHOICE("--basis", &m->basis, bases, "svd or identity")},
        {AUG_OPT_INT("--lead", &o->lead, 0, 100000000, "a count >= 0")},
        {AUG_OPT_CHOICE("--ordering", &o->ordering, orderings, "auto, amd or metis")},
        {AUG_OPT_CHOICE("--fe-solver", &o->fe_cholmod, fesolvers, "amps or cholmod")},
        {AUG_OPT_INT("--frames", &o->frames, 1, 100000000, "a count >= 1")},
        {AUG_OPT_INT("--settle", &o->settle, 0, 100000000, "a count >= 0")},
        {AUG_OPT_FLAG("--check", &o->check)},
        {AUG_OPT_CHOICE("--after-cut", &m->after_cut, aftercut, "all, neighbours or touched")},
        {AUG_OPT_FLAG("--warp", &m->warp)},
        {AUG_OPT_FLAG("--monitor", &o->monitor)},
        {AUG_OPT_INT("--lma", &o->lma, 1, AUG_MODES_MAX, "a count from 1 to 24")},
        {AUG_OPT_STRING("--output", &o->output, "all, surface, a set name or node:ID,..."), .flags = AUG_OPT_NONEMPTY},
        {AUG_OPT_INT("--seed", &o->seed, 1, 2000000000, "a positive integer")},
        {AUG_OPT_THREADS(&o->threads)},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &o->file, synopsis, help);
    m->seed = (uint64_t)o->seed;
    /* the estimate of the gate comes from the probes (none: a NaN gate that
       never lets a domain switch, every frame FE without a word) */
    if (m->gate_estimate && m->probes == 0) aug_tool_usage(t, "--gate estimate needs --probes K >= 1");
    aug_tool_usage_done(t, synopsis);
}

/* a library error at record rec (named by it when the library named none) */
static void fail_at(aug_tool *t, aug_err *e, const aug_rec *rec)
{
    /* an option that does not fit the stream (--domains, --reduce) names
       the option, not the record being read when it was found (TAIL) */
    if (e->code == AUG_EUSAGE && !strncmp(e->msg, "--", 2)) {
        e->record = -1, e->type[0] = 0;
        aug_tool_fail(t, e);
    }
    e->record = rec->index;
    if (!e->type[0] || !strcmp(e->type, "MODE")) memcpy(e->type, rec->type, 5);
    aug_tool_fail(t, e);
}

/* the session: the hybrid simulation, the FE reference (--check), the
   stream's own system and its AMPS solver for the frames with every domain FE */
typedef struct session {
    aug_msim sim, ref;
    int started, have_init;
    aug_frame init;
    cholmod_common cm;
    int32_t step;
    aug_sys0 sys;
    aug_replay *rp;
    aug_update km;
    long km_index;
    aug_mext ext;
    int32_t xframe;
} session;

/* the external FE solver (aug_mext) over the stream's A_t */
static int64_t ext_n(void *ctx)
{
    session *ss = ctx;
    return aug_solver_n(ss->sys.solver);
}

static int64_t ext_index(void *ctx, int64_t node, int c)
{
    session *ss = ctx;
    return aug_replay_index(ss->rp, node, c);
}

static int ext_solve(void *ctx, const double *b, double *x, aug_err *e)
{
    session *ss = ctx;
    aug_solver *s = ss->sys.solver;
    if (aug_solver_frame(s, b, ++ss->xframe, e)) return e->code;
    if (aug_solver_frame_singular(s, AUG_M_AMPS))
        return aug_err_set(e, AUG_ESINGULAR, -1, "UPDT", "AMPS did not solve A_t (relres %.3g)",
                           aug_kv_get(aug_solver_stat(s, AUG_M_AMPS), "relres", NAN));
    memcpy(x, aug_solver_field(s, AUG_M_AMPS), (size_t)aug_solver_n(s) * sizeof *x);
    return 0;
}

static void frames(aug_tool *t, const options *o, aug_replay *rp, session *ss, long n, const aug_rec *rec);
static void lma(aug_tool *t, const options *o, session *ss, int all, const aug_rec *rec);

/* the simulation (and its FE reference) on the original mesh, then the
   --lead frames */
static void start(aug_tool *t, const options *o, aug_replay *rp, session *ss, const aug_rec *rec)
{
    aug_err e;
    if (ss->started) return;
    if (!rp->dynamic)
        aug_tool_die(t, "%s: record %ld (%s): a static stream: modal needs the integrator of factor --dynamic "
                     "(DYNP)", t->inname, rec->index, rec->type);
    if (!(rp->mesh.have & AUG_HAVE_NODE) || !(rp->mesh.have & AUG_HAVE_ELEM))
        aug_tool_die(t, "%s: record %ld (%s): modal needs the mesh", t->inname, rec->index, rec->type);
    const aug_mesh *m = &rp->mesh;
    if (ss->have_init && (ss->init.count != m->nn || ss->init.dim != m->dim))
        aug_tool_die(t, "%s: fRAM frame 0 holds %lld nodes, the mesh %lld", t->inname, (long long)ss->init.count,
                     (long long)m->nn);
    const double *u0 = ss->have_init ? ss->init.u : NULL, *v0 = ss->have_init ? ss->init.v : NULL;
    if (aug_msim_init(&ss->sim, &o->mo, &rp->dyn, m, u0, v0, &ss->cm, &e)) fail_at(t, &e, rec);
    if (!o->fe_cholmod) {
        aug_solver_opts so;
        aug_solver_opts_default(&so);
        so.nmeth = 1, so.order[0] = AUG_M_AMPS, so.nthreads = o->threads;
        if (aug_sys0_solver(&ss->sys, rp->have_dofm ? rp->nfree0 : -1, &so, rec, &e)) fail_at(t, &e, rec);
        ss->rp = rp;
        ss->ext = (aug_mext){ss, ext_n, ext_index, ext_solve};
        ss->sim.ext = &ss->ext;
    }
    if (o->check) {
        aug_msim_opts r = o->mo;
        r.reduce_all = 0, r.reduce_none = 1, r.nreduce = 0, r.coupling = AUG_COUPLE_DIRECT, r.basis = AUG_BASIS_SVD;
        if (aug_msim_init(&ss->ref, &r, &rp->dyn, m, u0, v0, &ss->cm, &e)) fail_at(t, &e, rec);
        if (!o->fe_cholmod) ss->ref.ext = &ss->ext;
    }
    rp->track = 1;
    rp->nchg = 0;
    ss->started = 1;
    lma(t, o, ss, 1, rec);
    if (o->lead > 0) frames(t, o, rp, ss, o->lead, rec);
}

/* --lma: the lowest modes of every domain rebuilt (all at the start) */
static void lma(aug_tool *t, const options *o, session *ss, int all, const aug_rec *rec)
{
    aug_err e;
    aug_msim *s = &ss->sim;
    for (int d = 0; d < s->nd && o->lma; d++) {
        if (!all && !s->d[d].rebuilt) continue;
        aug_moderec mr;
        if (aug_msim_lma(s, d, o->lma, &mr, &e)) fail_at(t, &e, rec);
        if (mr.r == 0) continue;
        aug_tool_check(t, aug_write_mode(t->w, ss->step, &mr, &e), &e);
        aug_kv k;
        aug_kv_init(&k, "lma");
        aug_kv_set(&k, "frame", s->frame);
        aug_kv_set(&k, "domain", d);
        for (int j = 0; j < mr.r; j++) {
            char key[32];
            snprintf(key, sizeof key, "lambda%d", j);
            aug_kv_set(&k, key, mr.sigma[j]);
        }
        aug_moderec_free(&mr);
        aug_tool_check(t, aug_write_kv(t->w, "sTAt", ss->step, &k, &e), &e);
    }
}

/* a MODE for every domain that switched to its subspace this frame; with
   --lma how well that basis spans the domain's modes (paper 004 fig. 3) */
static void modes(aug_tool *t, const options *o, session *ss, const aug_rec *rec)
{
    aug_err e;
    aug_msim *s = &ss->sim;
    for (int d = 0; d < s->nd; d++) {
        if (s->d[d].switched != 1) continue;
        aug_moderec mr;
        if (aug_msim_mode(s, d, &mr, &e)) fail_at(t, &e, rec);
        aug_tool_check(t, aug_write_mode(t->w, ss->step, &mr, &e), &e);
        aug_moderec_free(&mr);
        double rel[AUG_MODES_MAX];
        int n = o->lma ? aug_msim_lma_fit(s, d, rel) : 0;
        if (n < 0) aug_tool_die(t, "out of memory");
        if (n == 0) continue;
        aug_kv k;
        aug_kv_init(&k, "lma");
        aug_kv_set(&k, "frame", s->frame);
        aug_kv_set(&k, "domain", d);
        aug_kv_set(&k, "rank", s->d[d].r);
        for (int j = 0; j < n; j++) {
            char key[32];
            snprintf(key, sizeof key, "fit%d", j);
            aug_kv_set(&k, key, rel[j]);
        }
        aug_tool_check(t, aug_write_kv(t->w, "sTAt", ss->step, &k, &e), &e);
    }
}

/* --monitor: the frame on one stderr line, for watching a run (the same
   figures as its sTAt, which the stream keeps): per domain F (FE) or R
   (reduced) and its error (FE: projection error of the last snapshot;
   reduced: the error at the switch plus the budget used), l2_err with
   --check (NaN: none) */
static void monitor(const aug_tool *t, const session *ss, double l2)
{
    const aug_msim *s = &ss->sim;
    int nred = 0;
    for (int di = 0; di < s->nd; di++) nred += s->d[di].mode == AUG_MD_RED;
    fprintf(stderr, "%s: step %d frame %d: reduced %d of %d, events %d, redo %d", t->prog, (int)ss->step,
            (int)s->frame, nred, s->nd, s->events, s->redo);
    if (!isnan(l2)) fprintf(stderr, ", l2_err %.3g", l2);
    for (int di = 0; di < s->nd && di < 16; di++) {
        const aug_mdomain *d = &s->d[di];
        double err = d->mode == AUG_MD_RED ? d->err_switch + d->acc : d->last_err;
        fprintf(stderr, "; d%d %c %.3g", di, d->mode == AUG_MD_RED ? 'R' : 'F', err);
    }
    fprintf(stderr, s->nd > 16 ? "; ...\n" : "\n");
}

/* relative L2 distance of the hybrid's nodal displacement to the FE one */
static double l2_err(const aug_msim *a, const aug_msim *b)
{
    double d2 = 0, n2 = 0;
    for (int64_t k = 0; k < a->nn * a->dim; k++) {
        double d = a->u[k] - b->u[k];
        d2 += d * d, n2 += b->u[k] * b->u[k];
    }
    return n2 > 0 ? sqrt(d2 / n2) : sqrt(d2);
}

static void frames(aug_tool *t, const options *o, aug_replay *rp, session *ss, long n, const aug_rec *rec)
{
    aug_err e;
    for (long f = 0; f < n; f++) {
        if (aug_msim_frame(&ss->sim, &e)) fail_at(t, &e, rec);
        aug_kv st, tm;
        aug_msim_stats(&ss->sim, &st, &tm);
        double l2 = NAN;
        if (o->check) {
            double t0 = aug_now();
            if (aug_msim_frame(&ss->ref, &e)) fail_at(t, &e, rec);
            aug_kv_set(&tm, "fe_ms", 1e3 * (aug_now() - t0));
            aug_kv_set(&st, "l2_err", l2 = l2_err(&ss->sim, &ss->ref));
        }
        if (o->monitor) monitor(t, ss, l2);
        aug_msim *s = &ss->sim;
        if (s->o.coupling == AUG_COUPLE_PPCG && !s->converged)
            fprintf(stderr, "%s: step %d, frame %d: ppcg did not converge (relres %.3g after %d iterations)\n",
                    t->prog, (int)ss->step, (int)s->frame, s->relres, s->iters);
        const double *out = aug_msim_output(s, &rp->mesh, &e);
        if (!out) fail_at(t, &e, rec);
        aug_tool_check(t, aug_replay_write_frame(t->w, rp, ss->step, s->frame, s->time, out, s->v, &e), &e);
        modes(t, o, ss, rec);
        aug_tool_check(t, aug_write_kv(t->w, "sTAt", ss->step, &st, &e), &e);
        aug_tool_check(t, aug_write_kv(t->w, "tIMe", ss->step, &tm, &e), &e);
    }
}

/* one cut step (its UPDT): the domains it touched re-wired, then its frames */
static void step(aug_tool *t, const options *o, aug_replay *rp, session *ss, const aug_rec *rec)
{
    aug_err e;
    start(t, o, rp, ss, rec);
    ss->step = rec->step;
    const aug_mesh *m = &rp->mesh;
    int64_t nn_old = ss->sim.nn;
    const int32_t *parent = rp->mdlt_step == rec->step ? rp->mdlt_parent : NULL;
    if (m->nn != nn_old && !parent)
        aug_tool_die(t, "%s: record %ld (UPDT): step %d: the mesh grew without its MDLT", t->inname, rec->index,
                     (int)rec->step);
    if (ss->sys.solver) { /* the stream's update of A_t for AMPS */
        aug_update u;
        if (aug_read_update(rec, &u, &e)) aug_tool_fail(t, &e);
        if (!ss->km.EK)
            aug_tool_die(t, "%s: record %ld (UPDT): step %d of a dynamic stream has no UPKM", t->inname, rec->index,
                         (int)u.step);
        aug_tool_check(t, aug_update_attach_km(&u, &ss->km, ss->km_index, rec, ss->sys.dyn.cM, ss->sys.dyn.cK, &e), &e);
        aug_update_free(&ss->km);
        int flags = rp->nmdlt && rp->mdlt_step == u.step ? rp->mdlt_flags : 0;
        if (aug_solver_step(ss->sys.solver, &u, NULL, 0, flags, &e)) fail_at(t, &e, rec);
        aug_update_free(&u);
    }
    aug_msim *sims[2] = {&ss->sim, &ss->ref};
    for (int i = 0; i < 1 + o->check; i++)
        if (aug_msim_step(sims[i], m, nn_old, parent, rp->chg, rp->nchg, &e)) fail_at(t, &e, rec);
    rp->nchg = 0;
    lma(t, o, ss, 0, rec);
    frames(t, o, rp, ss, o->frames, rec);
}

int main(int argc, char **argv)
{
    aug_tool t;
    options o;
    aug_err e;
    aug_replay rp;
    aug_rec rec;
    session ss;
    memset(&rec, 0, sizeof rec);
    memset(&ss, 0, sizeof ss);
    aug_tool_init(&t, "modal", argc, argv);
    parse(&t, argc, argv, &o);
    aug_tool_threads(&t, o.threads);
    aug_tool_open_in(&t, o.file);
    aug_tool_open_out(&t);
    aug_cholmod_start(&ss.cm);
    aug_tool_check(&t, aug_sys0_init(&ss.sys, &e), &e);
    aug_factor_options(&ss.cm, o.ordering, 0);
    aug_replay_init(&rp);
    rp.output = o.output;
    while (aug_tool_read(&t, &rec)) {
        /* the simulation starts on the original mesh, before the first step's
           records, and before a pLAN: the step-0 records of --lead and --lma
           after it would lie outside the steps it plans (formats/stream.md 4.4) */
        if (!ss.started && (aug_rec_changes_step(&rec) || !memcmp(rec.type, "pLAN", 4)))
            start(&t, &o, &rp, &ss, &rec);
        aug_tool_check(&t, aug_replay_add(&rp, &rec, &e), &e);
        if (!o.fe_cholmod) aug_tool_check(&t, aug_sys0_add(&ss.sys, &rec, &e), &e);
        if (!memcmp(rec.type, "UPKM", 4) && !o.fe_cholmod) {
            aug_update_free(&ss.km);
            aug_tool_check(&t, aug_read_updkm(&rec, &ss.km, &e), &e);
            ss.km_index = rec.index;
        }
        if (!memcmp(rec.type, "fRAM", 4) && !ss.started && !ss.have_init) {
            aug_frame_free(&ss.init);
            aug_tool_check(&t, aug_read_frame(&rec, &ss.init, &e), &e);
            ss.have_init = rec.step == 0 && !ss.init.nodes && ss.init.frame == 0;
        }
        aug_tool_pass(&t, &rec);
        if (!memcmp(rec.type, "UPDT", 4)) {
            step(&t, &o, &rp, &ss, &rec);
            aug_progress(&t, rec.step, 0);
        }
    }
    aug_tool_check(&t, aug_replay_end(&rp, &e), &e);
    /* nothing to simulate: no frame would be written (modal(1): a stream
       without cut steps needs --lead or --settle) */
    if (!ss.started && o.lead == 0 && o.settle == 0 && o.lma == 0)
        aug_tool_die(&t, "%s: the stream has no cut step: give --lead N or --settle N (frames on the intact mesh)",
                     t.inname);
    if (!ss.started) start(&t, &o, &rp, &ss, &rec);
    if (o.settle > 0) frames(&t, &o, &rp, &ss, o.settle, &rec);
    aug_tool_close(&t);
    aug_msim_free(&ss.sim);
    aug_msim_free(&ss.ref);
    aug_frame_free(&ss.init);
    aug_update_free(&ss.km);
    aug_sys0_free(&ss.sys);
    cholmod_finish(&ss.cm);
    aug_rec_free(&rec);
    aug_replay_free(&rp);
    return 0;
}
