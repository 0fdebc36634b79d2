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
    aug_mesh m;          /* the original mesh (phase 1) */
    aug_refiner r;
    int started;
    aug_rec *buf;        /* the current step's records, in order */
    int nbuf, capbuf;
    int32_t step;
} state;

static void start(aug_tool *t, state *s, const options *o)
{
    aug_err e;
    if (s->started) return;
    if (!(s->m.have & AUG_HAVE_NODE) || !(s->m.have & AUG_HAVE_ELEM))
        aug_tool_die(t, "%s: the stream has no mesh (NODE and ELEM records)", t->inname);
    aug_tool_check(t, aug_mesh_validate(&s->m, &e), &e);
    aug_tool_check(t, aug_refiner_init(&s->r, &s->m, &o->opt, &e), &e);
    s->started = 1;
}

static void keep(aug_tool *t, state *s, const aug_rec *rec)
{
    if (s->nbuf == s->capbuf) {
        int cap = s->capbuf ? 2 * s->capbuf : 16;
        aug_rec *b = realloc(s->buf, (size_t)cap * sizeof *b);
        if (!b) aug_tool_die(t, "out of memory");
        s->buf = b;
        s->capbuf = cap;
    }
    /* a deep copy: the payload in its own buffer (zbuf, freed by aug_rec_free) */
    aug_rec *c = &s->buf[s->nbuf++];
    *c = *rec;
    c->zbuf = malloc(rec->len + 1);
    c->wire = malloc(rec->wirelen + 1);
    if (!c->zbuf || !c->wire) aug_tool_die(t, "out of memory");
    memcpy(c->zbuf, rec->data, rec->len);
    memcpy(c->wire, rec->wire, rec->wirelen);
    c->data = c->zbuf;
    c->cap_data = rec->len + 1;
    c->cap_wire = rec->wirelen + 1;
}

static void fail_at(aug_tool *t, aug_err *e, const aug_rec *rec)
{
    if (e->record < 0) {
        e->record = rec->index;
        memcpy(e->type, rec->type, 5);
    }
    aug_tool_fail(t, e);
}

static double *read_path(aug_tool *t, const aug_rec *rec, int dim, int64_t *nseg)
{
    aug_cur c;
    aug_err e;
    aug_cur_init(&c, rec);
    int32_t d = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t n = aug_cur_i64(&c);
    if (!c.ok || d != dim || n < 0 || !aug_cur_has(&c, (uint64_t)n, 16 * (uint64_t)dim) ||
        c.len - c.pos != (uint64_t)n * 16 * dim) {
        aug_err_set(&e, AUG_EPAYLOAD, rec->index, rec->type, "dimension %d or %lld segments do not "
                    "match the payload", (int)d, (long long)n);
        aug_tool_fail(t, &e);
    }
    double *p = malloc((size_t)(n * 2 * dim + 1) * sizeof *p);
    if (!p) aug_tool_die(t, "out of memory");
    aug_cur_f64v(&c, p, (uint64_t)n * 2 * dim);
    *nseg = n;
    return p;
}

/* rewrite the buffered step: folded MDLT, translated BDLT, rebuilt UPDT, qUAl, tIMe */
static void flush(aug_tool *t, state *s, const options *o)
{
    aug_err e;
    if (!s->nbuf) return;
    start(t, s, o);
    aug_refiner *r = &s->r;
    int dim = r->cut.dim, nv = r->cut.nv;
    int imd = -1, ibc = -1, iup = -1;
    double *seg = NULL;
    int64_t nseg = 0;
    for (int i = 0; i < s->nbuf; i++) {
        const aug_rec *rec = &s->buf[i];
        int *slot = !memcmp(rec->type, "MDLT", 4) ? &imd : !memcmp(rec->type, "BDLT", 4) ? &ibc
                  : !memcmp(rec->type, "UPDT", 4) ? &iup : NULL;
        if (slot) {
            if (*slot >= 0) {
                aug_err_set(&e, AUG_EDATA, rec->index, rec->type, "a second %s in step %d",
                            rec->type, (int)rec->step);
                aug_tool_fail(t, &e);
            }
            *slot = i;
        } else if (!memcmp(rec->type, "pATH", 4)) {
            int64_t n;
            double *p = read_path(t, rec, dim, &n);
            seg = realloc(seg, (size_t)((nseg + n) * 2 * dim + 1) * sizeof *seg);
            if (!seg) aug_tool_die(t, "out of memory");
            memcpy(seg + nseg * 2 * dim, p, (size_t)(n * 2 * dim) * sizeof *p);
            nseg += n;
            free(p);
        } else if (!memcmp(rec->type, "qUAl", 4)) {
            aug_kv kv;
            aug_tool_check(t, aug_read_kv(rec, &kv, &e), &e);
            if (!strcmp(kv.tag, "refine")) {
                aug_err_set(&e, AUG_EDATA, rec->index, rec->type,
                            "step %d was refined already (refine the cut's own output)", (int)rec->step);
                aug_tool_fail(t, &e);
            }
        }
    }
    aug_mdelta d, out;
    aug_bdelta bc, outbc;
    aug_update u;
    aug_refine_q q;
    aug_mdelta_init(&out);
    aug_bdelta_init(&bc);
    aug_bdelta_init(&outbc);
    aug_update_init(&u);
    int have_q = 0;
    if (ibc >= 0) aug_tool_check(t, aug_read_bdelta(&s->buf[ibc], &bc, &e), &e);
    if (imd >= 0) {
        const aug_rec *rec = &s->buf[imd];
        aug_tool_check(t, aug_read_mdelta(rec, dim, nv, &d, &e), &e);
        if (aug_refine_step(r, &d, ibc >= 0 ? &bc : NULL, seg, nseg, &out, &outbc,
                            iup >= 0 ? &u : NULL, &q, &e))
            fail_at(t, &e, rec);
        aug_mdelta_free(&d);
        have_q = 1;
    } else if (ibc >= 0) {
        if (aug_refine_bc_only(r, s->buf[ibc].step, &bc, &outbc, iup >= 0 ? &u : NULL, &e))
            fail_at(t, &e, &s->buf[ibc]);
    } else if (iup >= 0 && (r->cut.nn != r->base.nn || r->cut.ne != r->base.ne)) {
        aug_err_set(&e, AUG_EDATA, s->buf[iup].index, "UPDT",
                    "step %d: an update without MDLT or BDLT cannot be renumbered after refinement",
                    (int)s->buf[iup].step);
        aug_tool_fail(t, &e);
    }
    for (int i = 0; i < s->nbuf; i++) {
        const aug_rec *rec = &s->buf[i];
        if (i == imd) aug_tool_check(t, aug_write_mdelta(t->w, dim, nv, &out, &e), &e);
        else if (i == ibc) {
            outbc.step = rec->step;
            aug_tool_check(t, aug_write_bdelta(t->w, &outbc, &e), &e);
        } else if (i == iup && (imd >= 0 || ibc >= 0)) {
            u.step = rec->step;
            aug_tool_check(t, aug_write_update(t->w, &u, &e), &e);
        } else if (!memcmp(rec->type, "fELD", 4) && imd >= 0)
            continue; /* a field of the unrefined mesh */
        else aug_tool_pass(t, rec);
    }
    if (have_q) {
        aug_kv qual, tim;
        aug_refine_q_kv(&q, dim, &qual, &tim);
        aug_tool_check(t, aug_write_kv(t->w, "qUAl", s->step, &qual, &e), &e);
        aug_tool_check(t, aug_write_kv(t->w, "tIMe", s->step, &tim, &e), &e);
    }
    for (int i = 0; i < s->nbuf; i++) aug_rec_free(&s->buf[i]);
    s->nbuf = 0;
    free(seg);
    aug_mdelta_free(&out);
    aug_bdelta_free(&bc);
    aug_bdelta_free(&outbc);
    aug_update_free(&u);
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
    aug_mesh_init(&s.m);
    aug_tool_open_in(&t, o.file);
    aug_tool_open_out(&t);
    if (o.deflate) aug_writer_deflate(t.w, 65536);
    while (aug_tool_read(&t, &rec) == 1) {
        const aug_rectype *rt = aug_rectype_find(rec.type);
        if (aug_mesh_is_record(rec.type)) {
            aug_tool_check(&t, aug_mesh_absorb(&s.m, &rec, &e), &e);
            aug_tool_pass(&t, &rec);
        } else if (rt && rt->perstep && rec.step >= 0) {
            if (s.nbuf && rec.step != s.step) flush(&t, &s, &o);
            s.step = rec.step;
            aug_progress(&t, s.step, 0);
            keep(&t, &s, &rec);
        } else if (s.nbuf) {
            keep(&t, &s, &rec); /* an ancillary record between a step's records keeps its place */
        } else {
            aug_tool_pass(&t, &rec);
        }
    }
    flush(&t, &s, &o);
    aug_tool_close(&t);
    aug_rec_free(&rec);
    free(s.buf);
    if (s.started) aug_refiner_free(&s.r);
    aug_mesh_free(&s.m);
    return 0;
}
