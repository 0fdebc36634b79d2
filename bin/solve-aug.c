/* solve-aug: factor + update records -> per step the displacement field of the
   output set and per-method sTAt/tIMe (AMPS, augmented GMRES, baselines). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"
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

typedef struct state {
    aug_mesh mesh;
    int dim;
    int64_t ndof, nfree, nn0;
    int32_t *map;
    cholmod_sparse *K0;
    double *f0;
    int64_t nf0;
    cholmod_factor *L0;
    aug_solver *s;
    int out_resolved;
    int32_t step_flags, flags_step;
    double full_ms; /* median full solve with the base factor (ms) */
} state;

static int cmp_i32(const void *a, const void *b)
{
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
}

/* the output set: --output, else the oUTs record, else all; fixed before the
   first mesh delta so that node copies inherit membership */
static void resolve_output(aug_tool *t, state *st, const char *want)
{
    aug_mesh *m = &st->mesh;
    st->out_resolved = 1;
    st->nn0 = m->nn;
    if (!want) return;
    if (!strcmp(want, "all")) {
        m->out_kind = AUG_OUT_ALL;
        m->nout = 0;
        return;
    }
    int32_t *nodes = NULL;
    int64_t n = 0;
    if (!strcmp(want, "surface")) {
        unsigned char *mark = malloc((size_t)m->nn + 1);
        if (!mark || aug_mesh_boundary_nodes(m, mark) < 0) aug_tool_die(t, "out of memory");
        nodes = malloc((size_t)m->nn * sizeof *nodes + 4);
        for (int64_t i = 0; i < m->nn; i++)
            if (mark[i]) nodes[n++] = (int32_t)i;
        free(mark);
        m->out_kind = AUG_OUT_SURFACE;
    } else {
        const aug_set *s = aug_mesh_set(m, want);
        if (!s) aug_tool_die(t, "--output %s: no such node set in the stream", want);
        nodes = malloc((size_t)s->n * sizeof *nodes + 4);
        memcpy(nodes, s->nodes, (size_t)s->n * sizeof *nodes);
        n = s->n;
        m->out_kind = AUG_OUT_SET;
        snprintf(m->out_name, sizeof m->out_name, "%s", want);
    }
    free(m->out_nodes);
    m->out_nodes = nodes;
    m->nout = n;
}

/* matrix index of (node, c) in the cut-matrix numbering (formats 7.2), -1 if fixed */
static int64_t dof_index(const state *st, int64_t node, int c)
{
    if (node < st->nn0) return st->map[node * st->dim + c];
    return st->nfree + (node - st->nn0) * st->dim + c;
}

static double fixed_value(const aug_mesh *m, int64_t dof)
{
    for (int64_t f = 0; f < m->nfix; f++)
        if (m->fix_dof[f] == dof) return m->fix_val[f];
    return 0;
}

static void step(aug_tool *t, state *st, const options *o, const aug_rec *rec)
{
    aug_err e;
    aug_update u;
    if (aug_read_update(rec, &u, &e)) aug_tool_fail(t, &e);
    if (!st->s) {
        if (!st->K0 || !st->f0 || !st->L0 || !st->map)
            aug_tool_die(t, "%s: record %ld (UPDT): DOFM, KMAT (which 0), FVEC and FACT must come first",
                         t->inname, rec->index);
        if (st->nf0 != (int64_t)st->K0->nrow || st->nfree != (int64_t)st->K0->nrow)
            aug_tool_die(t, "%s: record %ld (UPDT): FVEC, DOFM and KMAT orders differ", t->inname, rec->index);
        cholmod_common *cm = malloc(sizeof *cm);
        aug_cholmod_start(cm);
        st->s = aug_solver_new(st->K0, st->f0, st->L0, &o->so, cm, &e);
        st->L0 = NULL;
        if (!st->s) aug_tool_fail(t, &e);
        st->full_ms = aug_solver_full_solve_ms(st->s, 5);
    }
    const aug_mesh *m = &st->mesh;
    /* requested DOFs of the output set */
    int32_t *out = NULL, *nodes = NULL;
    int64_t nout = 0, nnodes = 0;
    int all = m->out_kind == AUG_OUT_ALL || !(m->have & AUG_HAVE_NODE);
    if (!all) {
        nnodes = m->nout;
        nodes = m->out_nodes;
        out = malloc((size_t)(nnodes * st->dim + 1) * sizeof *out);
        for (int64_t i = 0; i < nnodes; i++)
            for (int c = 0; c < st->dim; c++) {
                int64_t id = dof_index(st, nodes[i], c);
                if (id >= 0) out[nout++] = (int32_t)id;
            }
        qsort(out, (size_t)nout, sizeof *out, cmp_i32);
    }
    int flags = st->flags_step == u.step ? st->step_flags : 0;
    if (aug_solver_step(st->s, &u, out, nout, flags, &e)) {
        e.record = rec->index;
        snprintf(e.type, sizeof e.type, "UPDT");
        aug_tool_fail(t, &e);
    }
    aug_tool_pass(t, rec);
    int first = o->so.order[0], nsing = 0;
    char names[128] = "";
    for (int i = 0; i < o->so.nmeth; i++) {
        int mth = o->so.order[i];
        if (aug_solver_singular(st->s, mth)) {
            nsing++;
            strncat(names, names[0] ? "," : "", sizeof names - strlen(names) - 1);
            strncat(names, aug_method_names[mth], sizeof names - strlen(names) - 1);
        } else if (!aug_solver_converged(st->s, mth)) {
            fprintf(stderr, "%s: step %d: %s did not converge (relres %.3g)\n", t->prog, (int)u.step,
                    aug_method_names[mth], aug_kv_get(aug_solver_stat(st->s, mth), "relres", NAN));
        }
    }
    if (nsing && !o->on_singular_report)
        aug_tool_die(t, "%s: record %ld (UPDT): step %d: K_t is singular or not positive definite (%s)",
                     t->inname, rec->index, (int)u.step, names);
    if (nsing)
        fprintf(stderr, "%s: step %d: K_t is singular or not positive definite (%s)\n", t->prog, (int)u.step, names);
    /* fELD of the first method, on the output set */
    if (!aug_solver_singular(st->s, first) && (m->have & AUG_HAVE_NODE)) {
        const double *x = aug_solver_field(st->s, first);
        int64_t cnt = all ? m->nn : nnodes;
        aug_buf b;
        aug_buf_init(&b);
        aug_buf_i32(&b, 0);
        aug_buf_i32(&b, st->dim);
        aug_buf_i64(&b, cnt);
        aug_buf_i32(&b, all ? 0 : 1);
        aug_buf_i32(&b, 0);
        if (!all) aug_buf_i32v(&b, (const int32_t *)nodes, (size_t)cnt);
        for (int64_t i = 0; i < cnt; i++) {
            int64_t node = all ? i : nodes[i];
            for (int c = 0; c < st->dim; c++) {
                int64_t id = dof_index(st, node, c);
                aug_buf_f64(&b, id >= 0 ? x[id] : fixed_value(m, node * st->dim + c));
            }
        }
        if (b.failed) aug_tool_die(t, "out of memory");
        aug_tool_write(t, "fELD", u.step, b.p, b.len);
        aug_buf_free(&b);
    }
    /* the reference a step is compared with, timed next to it (bench) */
    if (o->time_full) st->full_ms = aug_solver_full_solve_ms(st->s, 1);
    for (int i = 0; i < o->so.nmeth; i++) {
        int mth = o->so.order[i];
        aug_tool_check(t, aug_write_kv(t->w, "sTAt", u.step, aug_solver_stat(st->s, mth), &e), &e);
        aug_kv tm = *aug_solver_time(st->s, mth);
        aug_kv_set(&tm, "full_solve_ms", st->full_ms);
        aug_tool_check(t, aug_write_kv(t->w, "tIMe", u.step, &tm, &e), &e);
    }
    free(out);
    aug_update_free(&u);
}

int main(int argc, char **argv)
{
    aug_tool t;
    options o;
    aug_tool_init(&t, "solve-aug", argc, argv);
    parse(&t, argc, argv, &o);
    aug_set_threads(o.so.nthreads);
    aug_tool_open_in(&t, o.file);
    aug_tool_open_out(&t);
    state st;
    memset(&st, 0, sizeof st);
    aug_mesh_init(&st.mesh);
    cholmod_common cm;
    aug_cholmod_start(&cm);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    aug_err e;
    while (aug_tool_read(&t, &rec)) {
        const char *ty = rec.type;
        if (aug_mesh_is_record(ty)) {
            aug_tool_check(&t, aug_mesh_absorb(&st.mesh, &rec, &e), &e);
        } else if (!strcmp(ty, "DOFM")) {
            aug_tool_check(&t, aug_read_dofmap(&rec, &st.dim, &st.ndof, &st.nfree, &st.map, &e), &e);
        } else if (!strcmp(ty, "KMAT")) {
            int which = -1;
            cholmod_sparse *A = aug_read_sparse(&rec, &which, &cm, &e);
            if (!A) aug_tool_fail(&t, &e);
            if (which == 0 && !st.K0) st.K0 = A;
            else cholmod_free_sparse(&A, &cm);
        } else if (!strcmp(ty, "FVEC")) {
            aug_cur c;
            aug_cur_init(&c, &rec);
            int32_t kind = aug_cur_i32(&c);
            aug_cur_i32(&c);
            int64_t n = aug_cur_i64(&c);
            if (!c.ok || n < 0 || !aug_cur_has(&c, (uint64_t)n, 8) || c.len - c.pos != (uint64_t)n * 8) {
                aug_err_set(&e, AUG_EPAYLOAD, rec.index, ty, "payload size does not match n");
                aug_tool_fail(&t, &e);
            }
            if (kind == 0 && !st.f0) {
                st.f0 = malloc((size_t)(n + 1) * sizeof *st.f0);
                aug_cur_f64v(&c, st.f0, (uint64_t)n);
                st.nf0 = n;
            }
        } else if (!strcmp(ty, "FACT")) {
            st.L0 = aug_read_factor(&rec, &cm, &e);
            if (!st.L0) aug_tool_fail(&t, &e);
        } else if (!strcmp(ty, "MDLT") || !strcmp(ty, "UPDT")) {
            if (!st.out_resolved) {
                if (st.mesh.have & AUG_HAVE_NODE) aug_tool_check(&t, aug_mesh_validate(&st.mesh, &e), &e);
                resolve_output(&t, &st, o.output);
            }
            if (!strcmp(ty, "MDLT")) {
                if (!(st.mesh.have & AUG_HAVE_NODE)) aug_tool_die(&t, "%s: record %ld (MDLT): no mesh records before it", t.inname, rec.index);
                aug_mdelta d;
                aug_tool_check(&t, aug_read_mdelta(&rec, st.mesh.dim, st.mesh.nv, &d, &e), &e);
                if (aug_mesh_apply(&st.mesh, &d, &e)) {
                    e.record = rec.index;
                    aug_tool_fail(&t, &e);
                }
                st.step_flags = d.flags, st.flags_step = d.step;
                aug_mdelta_free(&d);
            } else {
                step(&t, &st, &o, &rec);
                aug_progress(&t, rec.step, 0);
                continue; /* passed through before the step's own records */
            }
        }
        aug_tool_pass(&t, &rec);
    }
    aug_tool_close(&t);
    aug_rec_free(&rec);
    aug_solver_free(st.s);
    if (st.L0) cholmod_free_factor(&st.L0, &cm);
    if (st.K0) cholmod_free_sparse(&st.K0, &cm);
    free(st.f0);
    free(st.map);
    aug_mesh_free(&st.mesh);
    cholmod_finish(&cm);
    return 0;
}
