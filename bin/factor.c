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
    "       [--mass consistent|lumped] [--lumped-mass] [--no-factor] [--no-cond] [--cond-tol T]\n"
    "       [--dynamic DT [--rayleigh ALPHA,BETA] [--integrator euler|newmark]] [--modes N]\n"
    "       [--no-reactions]\n"
    "       [--deflate] [-h]";

static const char *help =
    "  FILE                  input stream (default: stdin)\n"
    "  --ordering auto|amd|metis   fill-reducing ordering (auto: CHOLMOD's choice)\n"
    "  --simplicial          simplicial LDL' factorization (default: supernodal)\n"
    "  --threads N           threads of OpenBLAS under CHOLMOD (default 1)\n"
    "  --mass consistent|lumped  also write that mass matrix (KMAT which 1 or 2);\n"
    "                        with --dynamic: the M of the integrator (default consistent)\n"
    "  --lumped-mass         also write the lumped mass matrix (KMAT which 2)\n"
    "  --dynamic DT          implicit time stepping with step DT: factor the integrator's\n"
    "                        A = M + a h D + b h^2 K instead of K (DYNP, KMAT which 3)\n"
    "  --rayleigh ALPHA,BETA Rayleigh damping D = ALPHA M + BETA K (default 0,0)\n"
    "  --integrator euler|newmark  backward Euler (default) or Newmark average\n"
    "                        acceleration (trapezoidal)\n"
    "  --modes N             the N lowest eigenvalues of K x = lambda M x and their\n"
    "                        periods (cOND tag modes; ARPACK shift-invert on the factor)\n"
    "  --no-factor           do not write the FACT record\n"
    "  --no-cond             do not estimate cond(K) (no cOND record)\n"
    "  --cond-tol T          relative accuracy of the eigenvalue estimates (default 1e-4)\n"
    "  --no-reactions        no reaction forces of the step-0 solve (no rEAC record)\n"
    "  --deflate             zlib-deflate payloads of 64 KiB and more\n"
    "  -h                    this help; see factor(1)\n";

typedef struct options {
    const char *file;
    int ordering, simplicial, threads, mass, lumped, no_factor, no_cond, deflate;
    int nmass, ndyn, nray, nint, integrator, modes;
    double cond_tol, dt, rayleigh[2];
    aug_dynp dyn;
    int no_reactions;
} options;

static const aug_word masses[] = {{"consistent", AUG_MAT_M}, {"lumped", AUG_MAT_ML}, {NULL, 0}};
static const aug_word integrators[] = {
    {"euler", AUG_INT_EULER}, {"newmark", AUG_INT_NEWMARK}, {NULL, 0}};

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
        {AUG_OPT_CHOICE("--mass", &o->mass, masses, "consistent or lumped"), .given = &o->nmass},
        {AUG_OPT_REAL("--dynamic", &o->dt, 0, 1e6, "a time step in (0, 1e6]"),
         .flags = AUG_OPT_LO_OPEN, .given = &o->ndyn},
        {AUG_OPT_REALS("--rayleigh", o->rayleigh, 2, "ALPHA,BETA"), .given = &o->nray},
        {AUG_OPT_CHOICE("--integrator", &o->integrator, integrators, "euler or newmark"),
         .given = &o->nint},
        {AUG_OPT_FLAG("--lumped-mass", &o->lumped)},
        {AUG_OPT_FLAG("--no-factor", &o->no_factor)},
        {AUG_OPT_INT("--modes", &o->modes, 1, AUG_MODES_MAX, "a count from 1 to 24")},
        {AUG_OPT_FLAG("--no-cond", &o->no_cond)},
        {AUG_OPT_FLAG("--no-reactions", &o->no_reactions)},
        {AUG_OPT_FLAG("--deflate", &o->deflate)},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &o->file, synopsis, help);
    if ((o->nray || o->nint) && !o->ndyn) aug_tool_usage(t, "--rayleigh and --integrator need --dynamic");
    if (o->nray && !(o->rayleigh[0] >= 0 && o->rayleigh[1] >= 0 && isfinite(o->rayleigh[0]) &&
                     isfinite(o->rayleigh[1])))
        aug_tool_usage(t, "--rayleigh %g,%g: damping factors must be finite and >= 0", o->rayleigh[0],
                       o->rayleigh[1]);
    else if (o->ndyn && o->dt > 0 &&
             aug_dynp_set(&o->dyn, o->integrator, o->nmass ? o->mass : AUG_MAT_M, o->dt, o->rayleigh[0],
                          o->rayleigh[1]))
        aug_tool_usage(t, "--dynamic %g with --rayleigh %g,%g: A = M + a h D + b h^2 K is not finite",
                       o->dt, o->rayleigh[0], o->rayleigh[1]);
    if (o->modes && !o->ndyn && !o->nmass && !o->lumped)
        aug_tool_usage(t, "--modes needs a mass matrix (--mass or --dynamic)");
    if (o->nmass && o->mass == AUG_MAT_ML) o->lumped = 1, o->mass = 0;
    else if (o->nmass) o->mass = 1;
    aug_tool_usage_done(t, synopsis);
}

/* Records factor writes itself, or that a wholesale new matrix invalidates
   (formats/stream.md 3.1 rule 3): upstream ones are dropped: every
   unsafe-to-copy record of the matrix and step phases, every unknown
   unsafe-to-copy one, and pLAN (4.4), whose steps are among those dropped
   (kept, it promised steps that never come: solve-aug and cut refused the
   stream of a second factor). */
static int replaced(const aug_rec *rec)
{
    const aug_rectype *rt = aug_rectype_find(rec->type);
    if (!memcmp(rec->type, "pLAN", 4)) return 1;
    if (aug_type_safe_to_copy(rec->type)) return 0;
    return !rt || (rt->phase >= 2 && rt->phase <= 3);
}

/* the scene's records, computed once the mesh is complete */
static void run(aug_tool *t, const options *o, const aug_mesh *m, cholmod_common *cm,
                aug_factored *r)
{
    aug_err e;
    aug_factor_opts fo = {o->ordering, o->simplicial, o->threads, o->mass, o->lumped,
                          o->no_factor, o->no_cond, o->cond_tol, o->ndyn ? &o->dyn : NULL,
                          o->modes, o->no_reactions};
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
