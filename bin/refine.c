/* refine: a cut stream -> the same stream with every cut step's elements re-meshed
   (conditional Delaunay + bisection, thesis 003 ACDM) and folded into one MDLT,
   BDLT and UPDT per step, plus qUAl and tIMe (tag refine). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "augcut.h"
#include "cli/aug_opt.h"

static const char *synopsis =
    "refine [FILE] [--max-aspect A] [--area-ratio R] [--min-angle DEG] [--no-flip]\n"
    "              [--max-aspect3 A] [--min-dihedral DEG] [--levels3 N] [--max-new N]\n"
    "              [--deflate] [-h]";

static const char *help =
    "  FILE               input stream (default: stdin)\n"
    "  --max-aspect A     2-D bound on longest / shortest edge (default 3)\n"
    "  --area-ratio R     refine only elements larger than R times their original (default 0)\n"
    "  --min-angle DEG    2-D: also refine triangles with a smaller angle (default 20;\n"
    "                     0: the thesis's aspect bound alone)\n"
    "                     (mem3: only when given; the default is the aspect bound alone)\n"
    "  --no-flip          2-D: plain longest-edge bisection, no Delaunay flips\n"
    "  --max-aspect3 A    3-D bound on R / (3 r), 1 for the regular tet (default 3)\n"
    "  --min-dihedral DEG 3-D: also refine tets with a smaller dihedral angle (default 0)\n"
    "  --levels3 N        3-D: bisection levels per step at most (default 3)\n"
    "  --max-new N        new nodes per step at most (default: 1000 + 100 per element\n"
    "                     of the region the step changed, at most 4096 in 2-D, 2730 in 3-D)\n"
    "  --deflate          zlib-deflate payloads of 64 KiB and more\n"
    "  -h                 this help; see refine(1)\n";

typedef struct options {
    const char *file;
    aug_refine_opt opt;
    int deflate;
} options;

static void parse(aug_tool *t, int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    aug_refine_opt_default(&o->opt);
    aug_refine_opt *r = &o->opt;
    const aug_opt opt[] = {
        {AUG_OPT_REAL("--max-aspect", &r->max_aspect, 1.2, HUGE_VAL, "a number >= 1.2 (0: off)"),
         .flags = AUG_OPT_ZERO},
        {AUG_OPT_REAL("--area-ratio", &r->area_ratio, 0, 1, "a number in [0, 1)"), .flags = AUG_OPT_HI_OPEN},
        {AUG_OPT_REAL("--min-angle", &r->min_angle, 0, 30, "degrees in [0, 30]"), .given = &r->min_angle_given},
        {AUG_OPT_REAL("--max-aspect3", &r->max_aspect3, 1, HUGE_VAL, "a number >= 1 (0: off)"),
         .flags = AUG_OPT_ZERO},
        {AUG_OPT_REAL("--min-dihedral", &r->min_dihedral, 0, 70, "degrees in [0, 70)"),
         .flags = AUG_OPT_HI_OPEN},
        {AUG_OPT_INT("--levels3", &r->max_level3, 0, 20, "a count from 0 to 20")},
        {AUG_OPT_INT("--max-new", &r->max_new, 1, INT64_MAX, "a count >= 1")},
        {AUG_OPT_FLAG("--no-flip", &r->flip), .flags = AUG_OPT_CLEAR},
        {AUG_OPT_FLAG("--deflate", &o->deflate)},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &o->file, synopsis, help);
    aug_tool_usage_done(t, synopsis);
}

typedef struct state {
    aug_replay rp;       /* the original mesh (phase 1) */
    aug_refiner r;
    int started;
    long elem_index;     /* the ELEM record's index (errors about the mesh's elements) */
    aug_rec *buf;        /* the current step's records, in order */
    int nbuf, capbuf;
    int32_t step;
    int ahead;           /* 3-D: the whole stream is read first (aug_refiner_plan) */
    int *run, nrun, caprun; /* ahead: where each step's records start in buf */
} state;

static void keep(aug_tool *t, state *s, const aug_rec *rec)
{
    aug_err e;
    if (s->nbuf == s->capbuf) {
        int cap = s->capbuf ? 2 * s->capbuf : 16;
        aug_rec *b = realloc(s->buf, (size_t)cap * sizeof *b);
        if (!b) aug_tool_die(t, "out of memory");
        s->buf = b;
        s->capbuf = cap;
    }
    aug_tool_check(t, aug_rec_copy(&s->buf[s->nbuf++], rec, &e), &e);
}

/* the refiner, from the original mesh, at the first step */
static void start(aug_tool *t, state *s, const options *o)
{
    aug_err e;
    if (s->started) return;
    const aug_mesh *m = &s->rp.mesh;
    if (!(m->have & AUG_HAVE_NODE) || !(m->have & AUG_HAVE_ELEM))
        aug_tool_die(t, "%s: the stream has no mesh (NODE and ELEM records)", t->inname);
    aug_tool_check(t, aug_replay_start(&s->rp, &e), &e);
    int rc = aug_refiner_init(&s->r, m, &o->opt, &e);
    if (rc && e.record < 0 && !strcmp(e.type, "ELEM")) e.record = s->elem_index; /* name the elements' record */
    aug_tool_check(t, rc, &e);
    s->r.dyn = s->rp.dynamic ? &s->rp.dyn : NULL;
    s->started = 1;
}

/* records buf[i0, i1) of one step, refined */
static void refine_run(aug_tool *t, state *s, int i0, int i1)
{
    aug_err e;
    aug_tool_check(t, aug_refine_records(&s->r, s->buf + i0, i1 - i0, s->buf[i0].step, t->w, &e), &e);
    for (int i = i0; i < i1; i++) aug_rec_free(&s->buf[i]);
}

/* the buffered step, refined (2-D); with look-ahead (3-D) the whole stream at its
   end: every MDLT planned first (aug_refiner_plan), then each step refined */
static void flush(aug_tool *t, state *s, const options *o)
{
    aug_err e;
    if (!s->nbuf) return;
    start(t, s, o);
    if (!s->ahead) {
        aug_tool_check(t, aug_refine_records(&s->r, s->buf, s->nbuf, s->step, t->w, &e), &e);
        for (int i = 0; i < s->nbuf; i++) aug_rec_free(&s->buf[i]);
    } else {
        const aug_mesh *m = &s->r.cut;
        for (int i = 0; i < s->nbuf; i++) {
            if (memcmp(s->buf[i].type, "MDLT", 4)) continue;
            aug_mdelta d;
            aug_mdelta_init(&d);
            aug_tool_check(t, aug_read_mdelta(&s->buf[i], m->dim, m->nv, &d, &e), &e);
            int rc = aug_refiner_plan(&s->r, &d, &e);
            aug_mdelta_free(&d);
            if (rc) {
                e.record = s->buf[i].index;
                memcpy(e.type, "MDLT", 5);
            }
            aug_tool_check(t, rc, &e);
        }
        for (int k = 0; k < s->nrun; k++) refine_run(t, s, s->run[k], k + 1 < s->nrun ? s->run[k + 1] : s->nbuf);
        s->nrun = 0;
    }
    s->nbuf = 0;
}

/* ahead: a step's records start at buf[nbuf] */
static void mark_run(aug_tool *t, state *s)
{
    if (s->nrun == s->caprun) {
        int cap = s->caprun ? 2 * s->caprun : 64;
        int *p = realloc(s->run, (size_t)cap * sizeof *p);
        if (!p) aug_tool_die(t, "out of memory");
        s->run = p;
        s->caprun = cap;
    }
    s->run[s->nrun++] = s->nbuf;
}

int main(int argc, char **argv)
{
    aug_tool t;
    options o;
    aug_err e;
    aug_rec rec;
    state s;
    memset(&rec, 0, sizeof rec);
    memset(&s, 0, sizeof s);
    aug_tool_init(&t, "refine", argc, argv);
    parse(&t, argc, argv, &o);
    aug_replay_init(&s.rp);
    s.rp.check_sys = 1; /* KMAT, FVEC, FACT pass on unread: checked here */
    aug_tool_open_in(&t, o.file);
    aug_tool_open_out(&t);
    if (o.deflate) aug_writer_deflate(t.w, 65536);
    while (aug_tool_read(&t, &rec) == 1) {
        const aug_rectype *rt = aug_rectype_find(rec.type);
        /* a pLAN wherever it comes (after step 0's records, kept in a
           step's place below): its steps against the stream's */
        if (!memcmp(rec.type, "pLAN", 4) && (s.started || s.nbuf))
            aug_tool_check(&t, aug_replay_add(&s.rp, &rec, &e), &e);
        if (rt && rt->perstep && rec.step >= 0) {
            /* the steps' order (formats 7.1), checked as the stream passes */
            aug_tool_check(&t, aug_replay_steps(&s.rp, &rec, &e), &e);
            if (!s.nbuf && !s.nrun) s.ahead = s.rp.mesh.dim == 3;
            if (s.ahead) {
                if (!s.nbuf || rec.step != s.step) mark_run(&t, &s);
            } else if (s.nbuf && rec.step != s.step)
                flush(&t, &s, &o);
            s.step = rec.step;
            aug_progress(&t, s.step, 0);
            keep(&t, &s, &rec);
        } else if (s.nbuf) {
            keep(&t, &s, &rec); /* an ancillary record between a step's records keeps its place */
        } else {
            if (!s.started) aug_tool_check(&t, aug_replay_add(&s.rp, &rec, &e), &e);
            if (!memcmp(rec.type, "ELEM", 4)) s.elem_index = rec.index;
            aug_tool_pass(&t, &rec);
        }
    }
    aug_tool_check(&t, aug_replay_end(&s.rp, &e), &e);
    flush(&t, &s, &o);
    aug_tool_close(&t);
    aug_rec_free(&rec);
    free(s.buf);
    free(s.run);
    if (s.started) aug_refiner_free(&s.r);
    aug_replay_free(&s.rp);
    return 0;
}
