/* factor: mesh stream -> + DOFM, KMAT, FVEC, FACT, cOND and the step-0 solve
   (fELD, rEAC, sTAt, tIMe) of the intact scene. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"
#include "cli/aug_opt.h"

static const char *synopsis =
    "factor [FILE] [--ordering auto|amd|metis] [--simplicial] [--threads N]\n"
    "       [--mass] [--lumped-mass] [--no-factor] [--no-cond] [--cond-tol T] [--no-reactions]\n"
    "       [--deflate] [-h]";

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
    "  --no-reactions        no reaction forces of the step-0 solve (no rEAC record)\n"
    "  --deflate             zlib-deflate payloads of 64 KiB and more\n"
    "  -h                    this help; see factor(1)\n";

typedef struct options {
    const char *file;
    int ordering, simplicial, threads, mass, lumped, no_factor, no_cond, deflate;
    double cond_tol;
    int no_reactions;
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
        {AUG_OPT_FLAG("--no-reactions", &o->no_reactions)},
        {AUG_OPT_FLAG("--deflate", &o->deflate)},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &o->file, synopsis, help);
    aug_tool_usage_done(t, synopsis);
}

/* Records factor writes itself, or that a wholesale new matrix invalidates
   (formats/stream.md 3.1 rule 3): upstream ones are dropped. */
/* formats 3.1 rule 3: a new K invalidates every unsafe-to-copy record of the
   matrix and step phases, and every unknown unsafe-to-copy one */
static int replaced(const aug_rec *rec)
{
    const aug_rectype *rt = aug_rectype_find(rec->type);
    if (aug_type_safe_to_copy(rec->type)) return 0;
    return !rt || (rt->phase >= 2 && rt->phase <= 3);
}

/* the scene's records, computed once the mesh is complete */
static void run(aug_tool *t, const options *o, const aug_mesh *m, cholmod_common *cm,
                aug_factored *r)
{
    aug_err e;
    aug_factor_opts fo = {o->ordering, o->simplicial, o->threads, o->mass, o->lumped,
                          o->no_factor, o->no_cond, o->cond_tol, o->no_reactions};
    aug_tool_check(t, aug_factored_compute(r, m, &fo, cm, &e), &e);
    aug_tool_check(t, aug_factored_write(t->w, r, m, &fo, cm, &e), &e);
}

int main(int argc, char **argv)
{
    aug_tool t;
    options o;
    aug_err e;
    aug_mesh m;
    aug_rec rec;
    cholmod_common cm;
    aug_factored r;
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
    int done = 0;
    while (aug_tool_read(&t, &rec) == 1) {
        const aug_rectype *rt = aug_rectype_find(rec.type);
        if (!done && rt && rt->phase >= 2) run(&t, &o, &m, &cm, &r), done = 1;
        if (aug_mesh_is_record(rec.type)) aug_tool_check(&t, aug_mesh_absorb(&m, &rec, &e), &e);
        if (!replaced(&rec)) aug_tool_pass(&t, &rec);
    }
    if (!done) run(&t, &o, &m, &cm, &r);
    aug_tool_close(&t);
    aug_rec_free(&rec);
    aug_factored_free(&r, &cm);
    cholmod_finish(&cm);
    aug_mesh_free(&m);
    return 0;
}
