/* refine: a cut stream -> the same stream with every cut step's elements re-meshed
   (conditional Delaunay + bisection, thesis 003 ACDM) and folded into one MDLT,
   BDLT and UPDT per step, plus qUAl and tIMe (tag refine). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "augcut.h"
#include "cli/aug_tool.h"

static const char *synopsis =
    "refine [FILE] [--max-aspect A] [--area-ratio R] [--min-angle DEG] [--no-flip]\n"
    "              [--max-aspect3 A] [--min-dihedral DEG] [--levels3 N] [--max-new N]\n"
    "              [--deflate] [-h]";

static const char *help =
    "  FILE               input stream (default: stdin)\n"
    "  --max-aspect A     2-D bound on longest / shortest edge (default 3)\n"
    "  --area-ratio R     refine only elements larger than R times their original (default 0)\n"
    "  --min-angle DEG    2-D: also refine triangles with a smaller angle (default 0: off)\n"
    "  --no-flip          2-D: plain longest-edge bisection, no Delaunay flips\n"
    "  --max-aspect3 A    3-D bound on R / (3 r), 1 for the regular tet (default 3)\n"
    "  --min-dihedral DEG 3-D: also refine tets with a smaller dihedral angle (default 0)\n"
    "  --levels3 N        3-D: bisection levels per step at most (default 3)\n"
    "  --max-new N        new nodes per step at most (default: 1000 + 100 per element\n"
    "                     of the region the step changed)\n"
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
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        double x;
        long n;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            printf("usage: %s\n%s", synopsis, help);
            exit(0);
        } else if (!strcmp(a, "--max-aspect")) {
            if (!v || aug_parse_double(v, &x) || !(x == 0 || x >= 1.2))
                aug_tool_usage(t, "--max-aspect needs a number >= 1.2 (0: off)");
            else o->opt.max_aspect = x;
            i += v != NULL;
        } else if (!strcmp(a, "--area-ratio")) {
            if (!v || aug_parse_double(v, &x) || !(x >= 0 && x < 1))
                aug_tool_usage(t, "--area-ratio needs a number in [0, 1)");
            else o->opt.area_ratio = x;
            i += v != NULL;
        } else if (!strcmp(a, "--min-angle")) {
            if (!v || aug_parse_double(v, &x) || !(x >= 0 && x <= 30))
                aug_tool_usage(t, "--min-angle needs degrees in [0, 30]");
            else o->opt.min_angle = x;
            i += v != NULL;
        } else if (!strcmp(a, "--max-aspect3")) {
            if (!v || aug_parse_double(v, &x) || !(x == 0 || x >= 1))
                aug_tool_usage(t, "--max-aspect3 needs a number >= 1 (0: off)");
            else o->opt.max_aspect3 = x;
            i += v != NULL;
        } else if (!strcmp(a, "--min-dihedral")) {
            if (!v || aug_parse_double(v, &x) || !(x >= 0 && x < 70))
                aug_tool_usage(t, "--min-dihedral needs degrees in [0, 70)");
            else o->opt.min_dihedral = x;
            i += v != NULL;
        } else if (!strcmp(a, "--levels3")) {
            if (!v || aug_parse_long(v, &n) || n < 0 || n > 20)
                aug_tool_usage(t, "--levels3 needs a count from 0 to 20");
            else o->opt.max_level3 = (int)n;
            i += v != NULL;
        } else if (!strcmp(a, "--max-new")) {
            if (!v || aug_parse_long(v, &n) || n < 1) aug_tool_usage(t, "--max-new needs a count >= 1");
            else o->opt.max_new = n;
            i += v != NULL;
        } else if (!strcmp(a, "--no-flip")) o->opt.flip = 0;
        else if (!strcmp(a, "--deflate")) o->deflate = 1;
        else if (a[0] == '-' && a[1]) aug_tool_usage(t, "unknown option %s", a);
        else if (o->file) aug_tool_usage(t, "more than one input file (%s, %s)", o->file, a);
        else o->file = a;
    }
    aug_tool_usage_done(t, synopsis);
}

typedef struct state {
    aug_replay rp;       /* the original mesh (phase 1) */
    aug_refiner r;
    int started;
    aug_rec *buf;        /* the current step's records, in order */
    int nbuf, capbuf;
    int32_t step;
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

/* the buffered step, refined; the refiner starts from the original mesh at the first step */
static void flush(aug_tool *t, state *s, const options *o)
{
    aug_err e;
    if (!s->nbuf) return;
    if (!s->started) {
        const aug_mesh *m = &s->rp.mesh;
        if (!(m->have & AUG_HAVE_NODE) || !(m->have & AUG_HAVE_ELEM))
            aug_tool_die(t, "%s: the stream has no mesh (NODE and ELEM records)", t->inname);
        aug_tool_check(t, aug_replay_start(&s->rp, &e), &e);
        aug_tool_check(t, aug_refiner_init(&s->r, m, &o->opt, &e), &e);
        s->started = 1;
    }
    aug_tool_check(t, aug_refine_records(&s->r, s->buf, s->nbuf, s->step, t->w, &e), &e);
    for (int i = 0; i < s->nbuf; i++) aug_rec_free(&s->buf[i]);
    s->nbuf = 0;
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
    aug_tool_open_in(&t, o.file);
    aug_tool_open_out(&t);
    if (o.deflate) aug_writer_deflate(t.w, 65536);
    while (aug_tool_read(&t, &rec) == 1) {
        const aug_rectype *rt = aug_rectype_find(rec.type);
        if (rt && rt->perstep && rec.step >= 0) {
            if (s.nbuf && rec.step != s.step) flush(&t, &s, &o);
            s.step = rec.step;
            keep(&t, &s, &rec);
        } else if (s.nbuf) {
            keep(&t, &s, &rec); /* an ancillary record between a step's records keeps its place */
        } else {
            if (!s.started) aug_tool_check(&t, aug_replay_add(&s.rp, &rec, &e), &e);
            aug_tool_pass(&t, &rec);
        }
    }
    flush(&t, &s, &o);
    aug_tool_close(&t);
    aug_rec_free(&rec);
    free(s.buf);
    if (s.started) aug_refiner_free(&s.r);
    aug_replay_free(&s.rp);
    return 0;
}
