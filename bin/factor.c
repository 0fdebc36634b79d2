/* factor: mesh stream -> + DOFM, KMAT, FVEC, FACT, cOND and the step-0 solve
   (fELD, sTAt, tIMe) of the intact scene. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"
#include "cli/aug_opt.h"

static const char *synopsis =
    "factor [FILE] [--ordering auto|amd|metis] [--simplicial] [--threads N]\n"
    "       [--mass] [--lumped-mass] [--no-factor] [--no-cond] [--cond-tol T] [--deflate] [-h]";

static const char *help =
    "  FILE                  input stream (default: stdin)\n"
    "  --ordering auto|amd|metis   fill-reducing ordering (auto: CHOLMOD's choice)\n"
    "  --simplicial          simplicial LDL' factorization (default: supernodal)\n"
    "  --threads N           threads of CHOLMOD and OpenBLAS (default 1)\n"
    "  --mass                also write the consistent mass matrix (KMAT which 1)\n"
    "  --lumped-mass         also write the lumped mass matrix (KMAT which 2)\n"
    "  --no-factor           do not write the FACT record\n"
    "  --no-cond             do not estimate cond(K) (no cOND record)\n"
    "  --cond-tol T          relative accuracy of the eigenvalue estimates (default 1e-4)\n"
    "  --deflate             zlib-deflate payloads of 64 KiB and more\n"
    "  -h                    this help; see factor(1)\n";

typedef struct options {
    const char *file;
    int ordering, simplicial, threads, mass, lumped, no_factor, no_cond, deflate;
    double cond_tol;
} options;

static const aug_word orderings[] = {
    {"auto", AUG_ORDER_AUTO}, {"amd", AUG_ORDER_AMD}, {"metis", AUG_ORDER_METIS}, {NULL, 0}};

static void parse(aug_tool *t, int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    o->threads = 1;
    o->cond_tol = 1e-4;
    const aug_opt opt[] = {
        {AUG_OPT_CHOICE("--ordering", &o->ordering, orderings, "auto, amd or metis"),
         .bad = "not one of auto, amd, metis"},
        {AUG_OPT_THREADS(&o->threads)},
        {AUG_OPT_REAL("--cond-tol", &o->cond_tol, 0, 1, "a number in (0, 1)"),
         .flags = AUG_OPT_LO_OPEN | AUG_OPT_HI_OPEN},
        {AUG_OPT_FLAG("--simplicial", &o->simplicial)},
        {AUG_OPT_FLAG("--mass", &o->mass)},
        {AUG_OPT_FLAG("--lumped-mass", &o->lumped)},
        {AUG_OPT_FLAG("--no-factor", &o->no_factor)},
        {AUG_OPT_FLAG("--no-cond", &o->no_cond)},
        {AUG_OPT_FLAG("--deflate", &o->deflate)},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &o->file, synopsis, help);
    aug_tool_usage_done(t, synopsis);
}

/* Records factor writes itself, or that a wholesale new matrix invalidates
   (formats/stream.md 3.1 rule 3): upstream ones are dropped. */
static int replaced(const aug_rec *rec)
{
    const aug_rectype *rt = aug_rectype_find(rec->type);
    return rt && rt->phase >= 2 && rt->phase <= 3 && !aug_type_safe_to_copy(rec->type);
}

typedef struct result {
    int32_t *map;
    int64_t nfree;
    cholmod_sparse *K, *M, *ML;
    double *f, *a;
    cholmod_factor *L;
    double relres;
    aug_cond cond;
    double lnz, fl; /* CHOLMOD's analysis: nnz(L) and flop count */
    double t_asm, t_an, t_fac, t_sol, t_cond;
} result;

static void compute(aug_tool *t, const options *o, const aug_mesh *m, cholmod_common *cm,
                    result *r)
{
    aug_err e;
    aug_tool_check(t, aug_mesh_validate(m, &e), &e);
    aug_tool_check(t, aug_check_support(m, &e), &e);
    r->map = malloc((size_t)(m->nn * m->dim) * sizeof *r->map);
    if (!r->map) aug_tool_die(t, "out of memory");
    r->nfree = aug_dofmap(m, r->map);
    if (r->nfree == 0) aug_tool_die(t, "%s: every DOF is constrained: nothing to solve", t->inname);
    double t0 = aug_now();
    r->K = aug_assemble(m, r->map, r->nfree, AUG_MAT_K, cm, &e);
    if (!r->K) aug_tool_fail(t, &e);
    r->f = malloc((size_t)r->nfree * sizeof *r->f);
    r->a = malloc((size_t)r->nfree * sizeof *r->a);
    if (!r->f || !r->a) aug_tool_die(t, "out of memory");
    aug_tool_check(t, aug_load_vector(m, r->map, r->nfree, r->f, &e), &e);
    r->t_asm = aug_now() - t0;
    if (o->mass && !(r->M = aug_assemble(m, r->map, r->nfree, AUG_MAT_M, cm, &e)))
        aug_tool_fail(t, &e);
    if (o->lumped && !(r->ML = aug_assemble(m, r->map, r->nfree, AUG_MAT_ML, cm, &e)))
        aug_tool_fail(t, &e);

    aug_factor_options(cm, o->ordering, o->simplicial);
    t0 = aug_now();
    r->L = aug_analyze(r->K, cm, &e);
    if (!r->L) aug_tool_fail(t, &e);
    r->t_an = aug_now() - t0;
    r->lnz = cm->lnz;
    r->fl = cm->fl;
    t0 = aug_now();
    aug_tool_check(t, aug_factorize(r->K, r->L, m, r->map, cm, &e), &e);
    r->t_fac = aug_now() - t0;
    t0 = aug_now();
    aug_tool_check(t, aug_solve(r->K, r->L, r->f, r->a, &r->relres, cm, &e), &e);
    r->t_sol = aug_now() - t0;
    if (!o->no_cond) {
        t0 = aug_now();
        aug_tool_check(t, aug_cond_estimate(r->K, r->L, o->cond_tol, &r->cond, cm, &e), &e);
        r->t_cond = aug_now() - t0;
    }
}

static void kv(aug_tool *t, aug_kv *k, const char *key, double v)
{
    if (aug_kv_set(k, key, v)) aug_tool_die(t, "too many values in one record");
}

static void emit(aug_tool *t, const options *o, const aug_mesh *m, cholmod_common *cm,
                 result *r)
{
    aug_err e;
    double t0 = aug_now();
    aug_tool_check(t, aug_write_dofmap(t->w, m, r->map, r->nfree, &e), &e);
    aug_tool_check(t, aug_write_sparse(t->w, AUG_MAT_K, r->K, &e), &e);
    if (r->M) aug_tool_check(t, aug_write_sparse(t->w, AUG_MAT_M, r->M, &e), &e);
    if (r->ML) aug_tool_check(t, aug_write_sparse(t->w, AUG_MAT_ML, r->ML, &e), &e);
    aug_tool_check(t, aug_write_vector(t->w, "FVEC", AUG_NOSTEP, 0, r->f, r->nfree, &e), &e);
    if (!o->no_factor) aug_tool_check(t, aug_write_factor(t->w, r->L, cm, &e), &e);
    aug_kv k;
    if (!o->no_cond) {
        aug_kv_init(&k, "arpack-lanczos");
        kv(t, &k, "lambda_max", r->cond.lambda_max);
        kv(t, &k, "lambda_min", r->cond.lambda_min);
        kv(t, &k, "cond", r->cond.cond);
        kv(t, &k, "iters", r->cond.iters_max + r->cond.iters_min);
        kv(t, &k, "iters_max", r->cond.iters_max);
        kv(t, &k, "iters_min", r->cond.iters_min);
        kv(t, &k, "tol", o->cond_tol);
        kv(t, &k, "converged", r->cond.converged);
        aug_tool_check(t, aug_write_kv(t->w, "cOND", AUG_NOSTEP, &k, &e), &e);
    }
    double *u = malloc((size_t)(m->nn * m->dim) * sizeof *u);
    if (!u) aug_tool_die(t, "out of memory");
    aug_expand_field(m, r->map, r->a, u);
    aug_tool_check(t, aug_write_field(t->w, 0, 0, m->dim, m->nn, NULL, u, &e), &e);
    free(u);
    aug_kv_init(&k, "factor");
    kv(t, &k, "n", (double)r->nfree);
    kv(t, &k, "nnz_K", (double)cholmod_nnz(r->K, cm));
    kv(t, &k, "nnz_L", r->lnz);
    kv(t, &k, "flops", r->fl);
    kv(t, &k, "ordering", r->L->ordering);
    kv(t, &k, "is_super", r->L->is_super);
    kv(t, &k, "relres", r->relres);
    kv(t, &k, "m", 0);
    kv(t, &k, "k", 0);
    aug_tool_check(t, aug_write_kv(t->w, "sTAt", 0, &k, &e), &e);
    double t_write = aug_now() - t0;
    aug_kv_init(&k, "factor");
    kv(t, &k, "assemble_ms", 1e3 * r->t_asm);
    kv(t, &k, "analyze_ms", 1e3 * r->t_an);
    kv(t, &k, "factor_ms", 1e3 * r->t_fac);
    kv(t, &k, "solve_ms", 1e3 * r->t_sol);
    kv(t, &k, "cond_ms", 1e3 * r->t_cond);
    kv(t, &k, "write_ms", 1e3 * t_write);
    kv(t, &k, "threads", o->threads);
    aug_tool_check(t, aug_write_kv(t->w, "tIMe", 0, &k, &e), &e);
}

int main(int argc, char **argv)
{
    aug_tool t;
    options o;
    aug_err e;
    aug_mesh m;
    aug_rec rec;
    cholmod_common cm;
    result r;
    memset(&rec, 0, sizeof rec);
    memset(&r, 0, sizeof r);
    aug_tool_init(&t, "factor", argc, argv);
    parse(&t, argc, argv, &o);
    aug_tool_threads(&t, o.threads);
    aug_cholmod_start(&cm);
    aug_mesh_init(&m);
    aug_tool_open_in(&t, o.file);
    aug_tool_open_out(&t);
    if (o.deflate) aug_writer_deflate(t.w, 65536);

    /* phase 1: absorb and pass the mesh; the first record of a later phase (or
       TAIL) triggers the computation, whose records precede it */
    int more, done = 0;
    while ((more = aug_tool_read(&t, &rec)) == 1) {
        const aug_rectype *rt = aug_rectype_find(rec.type);
        if (!done && rt && rt->phase >= 2) {
            compute(&t, &o, &m, &cm, &r);
            emit(&t, &o, &m, &cm, &r);
            done = 1;
        }
        if (aug_mesh_is_record(rec.type)) {
            int rc = aug_mesh_absorb(&m, &rec, &e);
            aug_tool_check(&t, rc, &e);
        }
        if (!replaced(&rec)) aug_tool_pass(&t, &rec);
    }
    if (!done) {
        compute(&t, &o, &m, &cm, &r);
        emit(&t, &o, &m, &cm, &r);
    }
    aug_tool_close(&t);
    aug_rec_free(&rec);
    cholmod_free_sparse(&r.K, &cm);
    cholmod_free_sparse(&r.M, &cm);
    cholmod_free_sparse(&r.ML, &cm);
    cholmod_free_factor(&r.L, &cm);
    cholmod_finish(&cm);
    free(r.map);
    free(r.f);
    free(r.a);
    aug_mesh_free(&m);
    return 0;
}
