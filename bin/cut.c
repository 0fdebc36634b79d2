/* cut: a stream (mesh, possibly factor and earlier steps) -> + per cut step
   MDLT, BDLT, UPDT, pATH (planar cut by node duplication, or a 2-D path). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_rng.h>
#include "augcut.h"
#include "cli/aug_tool.h"

static const char *synopsis =
    "cut [FILE] (--plane nx,ny,nz,d|random [--advance dx,dy,dz] [--polygon PTS] [--per-step K] [--seed S]\n"
    "           | --path PFILE [--mode split|snap] [--snap-tol T])\n"
    "           --steps N [--pull F] [--detached error|pin|drop|keep]\n"
    "           [--constrain SET|box:LO,HI[=u,v[,w]][@S]]... [--stats] [--deflate] [-h]";

static const char *help =
    "  FILE                 input stream (default: stdin)\n"
    "  --plane nx,ny,nz,d   advancing planar cut along n.x = d (2-D: nz ignored)\n"
    "  --plane random       a random plane through the middle of the mesh (--seed)\n"
    "  --advance dx,dy,dz   direction the cut advances (default: away from the fixed set)\n"
    "  --polygon x,y,z,...  3-D: cut only inside this polygon (3 to 64 points, projected\n"
    "                       onto the plane): a bounded, partial cut\n"
    "  --per-step K         cut nodes duplicated per step (default: ceil(cut nodes / 64))\n"
    "  --path PFILE         2-D cut path: line, polyline, bezier, arc, circle (see cut(1))\n"
    "  --mode split|snap    split: new nodes where the path crosses edges (default);\n"
    "                       snap: separate along the mesh edges nearest the path\n"
    "  --snap-tol T         split mode: snap to a node within T of an edge (default 0.05)\n"
    "  --steps N            number of cut steps (N >= 1)\n"
    "  --pull F             opposing forces F on each node copy and its original\n"
    "  --detached POLICY    piece without Dirichlet support: error (default), pin, drop,\n"
    "                       keep (write the singular step, flagged, for solvers)\n"
    "  --constrain SPEC     fix the nodes of a set or box:x0,y0,z0,x1,y1,z1 (2-D: 4\n"
    "                       numbers) to 0 or =u,v[,w], at step @S (default 1)\n"
    "  --seed S             random generator seed of --plane random (default 1)\n"
    "  --stats              write sTAt and tIMe (tag cut) for every step\n"
    "  --deflate            zlib-deflate payloads of 64 KiB and more\n"
    "  -h                   this help; see cut(1)\n";

typedef struct constraint {
    const char *set;     /* set name, or NULL for a box */
    double lo[3], hi[3];
    int nbox;            /* numbers given for the box */
    double v[3];
    int nv;              /* values given (0: all zero) */
    long step;
} constraint;

typedef struct options {
    const char *file, *pathfile;
    int plane, random_plane, have_adv, mode, policy, stats, deflate;
    int npoly;                 /* --polygon vertices (3-D points) */
    double poly[3 * 64];
    double n[4], adv[3], pull, snap_tol;
    long steps, per_step, seed;
    aug_path path;
    constraint *con;
    int ncon;
} options;

static int parse_constraint(const char *s, constraint *c)
{
    char buf[512];
    memset(c, 0, sizeof *c);
    c->step = 1;
    if (strlen(s) >= sizeof buf) return -1;
    strcpy(buf, s);
    char *at = strrchr(buf, '@');
    if (at) {
        *at = 0;
        if (aug_parse_long(at + 1, &c->step) || c->step < 1) return -1;
    }
    char *eq = strchr(buf, '=');
    if (eq) {
        *eq = 0;
        for (c->nv = 3; c->nv >= 2; c->nv--)
            if (!aug_parse_doubles(eq + 1, c->v, c->nv)) break;
        if (c->nv < 2) return -1;
    }
    if (!strncmp(buf, "box:", 4)) {
        double b[6];
        if (!aug_parse_doubles(buf + 4, b, 6)) {
            c->nbox = 6;
            memcpy(c->lo, b, 3 * sizeof *b);
            memcpy(c->hi, b + 3, 3 * sizeof *b);
        } else if (!aug_parse_doubles(buf + 4, b, 4)) {
            c->nbox = 4;
            memcpy(c->lo, b, 2 * sizeof *b);
            memcpy(c->hi, b + 2, 2 * sizeof *b);
        } else
            return -1;
        return 0;
    }
    if (!buf[0] || strlen(buf) >= AUG_NAME) return -1;
    c->set = strdup(s);
    if (!c->set) return -1;
    ((char *)c->set)[strlen(buf)] = 0;
    return 0;
}

static void parse(aug_tool *t, int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    o->mode = AUG_PATH_SPLIT;
    o->snap_tol = 0.05;
    o->seed = 1;
    int have_steps = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            printf("usage: %s\n%s", synopsis, help);
            exit(0);
        } else if (!strcmp(a, "--plane")) {
            if (v && !strcmp(v, "random")) o->random_plane = o->plane = 1;
            else if (!v || aug_parse_doubles(v, o->n, 4))
                aug_tool_usage(t, "--plane needs nx,ny,nz,d or random");
            else if (o->n[0] == 0 && o->n[1] == 0 && o->n[2] == 0)
                aug_tool_usage(t, "--plane %s: the normal is zero", v);
            if (v) o->plane = 1;
            i += v != NULL;
        } else if (!strcmp(a, "--advance")) {
            if (!v || aug_parse_doubles(v, o->adv, 3)) aug_tool_usage(t, "--advance needs dx,dy,dz");
            else o->have_adv = 1;
            i += v != NULL;
        } else if (!strcmp(a, "--polygon")) {
            int nc = 0;
            for (const char *c = v; c && *c; c++) nc += *c == ',';
            if (!v || (nc + 1) % 3 != 0 || (nc + 1) / 3 < 3 || (nc + 1) / 3 > 64 ||
                aug_parse_doubles(v, o->poly, nc + 1))
                aug_tool_usage(t, "--polygon needs 3 to 64 points x,y,z,x,y,z,...");
            else o->npoly = (nc + 1) / 3;
            i += v != NULL;
        } else if (!strcmp(a, "--steps")) {
            if (!v || aug_parse_long(v, &o->steps) || o->steps < 1 || o->steps > 1000000)
                aug_tool_usage(t, "--steps needs a count from 1 to 1000000");
            else have_steps = 1;
            i += v != NULL;
        } else if (!strcmp(a, "--per-step")) {
            if (!v || aug_parse_long(v, &o->per_step) || o->per_step < 1)
                aug_tool_usage(t, "--per-step needs a count >= 1");
            i += v != NULL;
        } else if (!strcmp(a, "--seed")) {
            if (!v || aug_parse_long(v, &o->seed) || o->seed < 0)
                aug_tool_usage(t, "--seed needs an integer >= 0");
            i += v != NULL;
        } else if (!strcmp(a, "--pull")) {
            if (!v || aug_parse_double(v, &o->pull)) aug_tool_usage(t, "--pull needs a force");
            i += v != NULL;
        } else if (!strcmp(a, "--snap-tol")) {
            if (!v || aug_parse_double(v, &o->snap_tol) || !(o->snap_tol >= 0 && o->snap_tol < 0.5))
                aug_tool_usage(t, "--snap-tol needs a number in [0, 0.5)");
            i += v != NULL;
        } else if (!strcmp(a, "--mode")) {
            if (v && !strcmp(v, "split")) o->mode = AUG_PATH_SPLIT;
            else if (v && !strcmp(v, "snap")) o->mode = AUG_PATH_SNAP;
            else aug_tool_usage(t, "--mode needs split or snap");
            i += v != NULL;
        } else if (!strcmp(a, "--detached")) {
            if (v && !strcmp(v, "error")) o->policy = AUG_DETACH_ERROR;
            else if (v && !strcmp(v, "pin")) o->policy = AUG_DETACH_PIN;
            else if (v && !strcmp(v, "drop")) o->policy = AUG_DETACH_DROP;
            else if (v && !strcmp(v, "keep")) o->policy = AUG_DETACH_KEEP;
            else aug_tool_usage(t, "--detached needs error, pin, drop or keep");
            i += v != NULL;
        } else if (!strcmp(a, "--constrain")) {
            constraint c;
            if (!v || parse_constraint(v, &c))
                aug_tool_usage(t, "--constrain needs SET or box:LO,HI, optionally =u,v[,w] and @STEP");
            else {
                constraint *q = realloc(o->con, (size_t)(o->ncon + 1) * sizeof *q);
                if (!q) aug_tool_die(t, "out of memory");
                o->con = q;
                o->con[o->ncon++] = c;
            }
            i += v != NULL;
        } else if (!strcmp(a, "--path")) {
            if (!v) aug_tool_usage(t, "--path needs a file");
            else if (o->pathfile) aug_tool_usage(t, "more than one --path");
            else o->pathfile = v;
            i += v != NULL;
        } else if (!strcmp(a, "--stats")) o->stats = 1;
        else if (!strcmp(a, "--deflate")) o->deflate = 1;
        else if (a[0] == '-' && a[1]) aug_tool_usage(t, "unknown option %s", a);
        else if (o->file) aug_tool_usage(t, "more than one input file (%s, %s)", o->file, a);
        else o->file = a;
    }
    if (!have_steps) aug_tool_usage(t, "--steps N is required");
    if (o->plane == (o->pathfile != NULL)) aug_tool_usage(t, "give exactly one of --plane and --path");
    for (int i = 0; i < o->ncon; i++)
        if (have_steps && o->con[i].step > o->steps)
            aug_tool_usage(t, "--constrain at step %ld after the last step %ld", o->con[i].step, o->steps);
    if (o->pathfile) {
        FILE *f = fopen(o->pathfile, "r");
        aug_err e;
        if (!f) aug_tool_usage(t, "--path %s: cannot open it", o->pathfile);
        else {
            if (aug_path_parse(f, o->pathfile, &o->path, &e)) aug_tool_usage(t, "%s", e.msg);
            fclose(f);
        }
    }
    aug_tool_usage_done(t, synopsis);
}

static void kv(aug_tool *t, aug_kv *k, const char *key, double v)
{
    if (aug_kv_set(k, key, v)) aug_tool_die(t, "too many values in one record");
}

static void write_path(aug_tool *t, int32_t step, int dim, const double *seg, int64_t nseg)
{
    aug_buf b;
    aug_err e;
    aug_buf_init(&b);
    aug_buf_i32(&b, dim);
    aug_buf_i32(&b, 0);
    aug_buf_i64(&b, nseg);
    aug_buf_f64v(&b, seg, (size_t)(nseg * 2 * dim));
    if (b.failed) aug_tool_die(t, "out of memory");
    aug_tool_check(t, aug_write(t->w, "pATH", step, b.p, b.len, &e), &e);
    aug_buf_free(&b);
}

/* a random plane: normal uniform on the sphere (circle in 2-D), through a point
   in the middle half of the bounding box */
static void random_plane(const aug_mesh *m, long seed, double *n)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, (unsigned long)seed);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, s = 0;
    for (int64_t i = 0; i < m->nn; i++)
        for (int k = 0; k < m->dim; k++) {
            lo[k] = fmin(lo[k], m->x[i * m->dim + k]);
            hi[k] = fmax(hi[k], m->x[i * m->dim + k]);
        }
    do {
        s = 0;
        for (int k = 0; k < 3; k++) {
            n[k] = k < m->dim ? 2 * gsl_rng_uniform(r) - 1 : 0;
            s += n[k] * n[k];
        }
    } while (s > 1 || s < 1e-4);
    n[3] = 0;
    for (int k = 0; k < m->dim; k++) {
        n[k] /= sqrt(s);
        n[3] += n[k] * (lo[k] + (0.25 + 0.5 * gsl_rng_uniform(r)) * (hi[k] - lo[k]));
    }
    gsl_rng_free(r);
}

typedef struct state {
    aug_mesh m;
    int started;
    int64_t nn0, nfree0;
    int32_t *map0;
    int32_t last_step;
    int have_dofm;
} state;

/* the original mesh is complete: fix the cut-matrix numbering */
static void start(aug_tool *t, state *s)
{
    aug_err e;
    if (s->started) return;
    if (!(s->m.have & AUG_HAVE_NODE) || !(s->m.have & AUG_HAVE_ELEM))
        aug_tool_die(t, "%s: the stream has no mesh (NODE and ELEM records)", t->inname);
    aug_tool_check(t, aug_mesh_validate(&s->m, &e), &e);
    s->nn0 = s->m.nn;
    s->map0 = malloc((size_t)(s->m.nn * s->m.dim) * sizeof *s->map0 + 1);
    if (!s->map0) aug_tool_die(t, "out of memory");
    s->nfree0 = aug_dofmap(&s->m, s->map0);
    s->started = 1;
}

static void absorb(aug_tool *t, state *s, const aug_rec *rec)
{
    aug_err e;
    const aug_rectype *rt = aug_rectype_find(rec->type);
    if (aug_mesh_is_record(rec->type)) {
        aug_tool_check(t, aug_mesh_absorb(&s->m, rec, &e), &e);
        return;
    }
    if (rt && rt->phase >= 2 && rt->phase <= 3) start(t, s);
    if (rt && rt->perstep && rec->step > s->last_step) s->last_step = rec->step;
    if (!memcmp(rec->type, "DOFM", 4)) {
        int dim;
        int64_t ndof, nfree;
        int32_t *map;
        aug_tool_check(t, aug_read_dofmap(rec, &dim, &ndof, &nfree, &map, &e), &e);
        if (ndof != s->nn0 * s->m.dim || nfree != s->nfree0 ||
            memcmp(map, s->map0, (size_t)ndof * sizeof *map)) {
            aug_err_set(&e, AUG_EDATA, rec->index, rec->type,
                        "DOF numbering does not match the mesh's constraints");
            aug_tool_fail(t, &e);
        }
        free(map);
    } else if (!memcmp(rec->type, "MDLT", 4)) {
        aug_mdelta d;
        aug_tool_check(t, aug_read_mdelta(rec, s->m.dim, s->m.nv, &d, &e), &e);
        if (aug_mesh_apply(&s->m, &d, &e)) {
            e.record = rec->index;
            aug_tool_fail(t, &e);
        }
        aug_mdelta_free(&d);
    } else if (!memcmp(rec->type, "BDLT", 4)) {
        aug_bdelta b;
        aug_tool_check(t, aug_read_bdelta(rec, &b, &e), &e);
        if (aug_mesh_apply_bc(&s->m, &b, &e)) {
            e.record = rec->index;
            aug_tool_fail(t, &e);
        }
        aug_bdelta_free(&b);
    }
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
    aug_tool_init(&t, "cut", argc, argv);
    parse(&t, argc, argv, &o);
    aug_set_threads(1); /* GSL's small eigenproblems call OpenBLAS: no idle spinning threads */
    aug_mesh_init(&s.m);
    aug_tool_open_in(&t, o.file);
    aug_tool_open_out(&t);
    if (o.deflate) aug_writer_deflate(t.w, 65536);
    /* everything upstream passes byte for byte: the factor of K0 stays valid */
    while (aug_tool_read(&t, &rec) == 1) {
        absorb(&t, &s, &rec);
        aug_tool_pass(&t, &rec);
    }
    start(&t, &s);
    aug_mesh *m = &s.m;
    if (o.pathfile && (m->dim != 2 || m->etype != AUG_TRI3))
        aug_tool_die(&t, "%s: --path needs a 2-D triangle mesh", t.inname);
    aug_cutter c;
    aug_tool_check(&t, aug_cutter_init(&c, m, s.nn0, s.map0, s.nfree0, &e), &e);
    c.policy = o.policy;
    c.pull = o.pull;
    aug_plane_cut pc;
    aug_path_cut pp;
    memset(&pc, 0, sizeof pc);
    memset(&pp, 0, sizeof pp);
    int64_t per = o.per_step;
    if (o.plane) {
        if (o.random_plane) random_plane(m, o.seed, o.n);
        if (m->dim == 2) o.n[2] = 0;
        aug_tool_check(&t, aug_plane_plan(&pc, m, &c.adj, o.n, o.n[3], o.have_adv ? o.adv : NULL, &e), &e);
        if (o.npoly) aug_tool_check(&t, aug_plane_restrict(&pc, m, o.poly, o.npoly, &e), &e);
        if (per == 0) per = (pc.ncut + 63) / 64;
        c.pull_dir = pc.n; /* pull the cut faces apart along the plane's normal */
    } else {
        aug_path_cut_init(&pp, &o.path, o.mode, o.snap_tol);
    }
    for (long k = 1; k <= o.steps; k++) {
        int32_t step = s.last_step + (int32_t)k;
        aug_cut_step st;
        aug_cut_step_init(&st, step);
        double t0 = aug_now();
        if (o.plane) {
            if (pc.next >= pc.ncut)
                aug_tool_die(&t, "%s: step %d: all %lld cut nodes of the plane are cut "
                             "(fewer --steps or a larger --per-step)", t.inname, (int)step,
                             (long long)pc.ncut);
            aug_tool_check(&t, aug_plane_step(&pc, &c.ed, per, &st.seg, &st.nseg, &e), &e);
        } else {
            double s_to = o.path.total * (double)k / (double)o.steps;
            aug_tool_check(&t, aug_path_step(&pp, &c.ed, s_to, &st.seg, &st.nseg, &e), &e);
        }
        aug_tool_check(&t, aug_cutter_apply(&c, &st, &e), &e);
        for (int i = 0; i < o.ncon; i++) {
            constraint *q = &o.con[i];
            if (q->step != k) continue;
            if (q->nv && q->nv != m->dim)
                aug_tool_die(&t, "--constrain: %d values for a %d-D mesh", q->nv, m->dim);
            if (q->set)
                aug_tool_check(&t, aug_cut_constrain_set(m, q->set, q->nv ? q->v : NULL, &st.bc, &e), &e);
            else {
                if (q->nbox != 2 * m->dim)
                    aug_tool_die(&t, "--constrain: a box of %d numbers for a %d-D mesh", q->nbox, m->dim);
                aug_tool_check(&t, aug_cut_constrain_box(m, q->lo, q->hi, q->nv ? q->v : NULL, &st.bc, &e), &e);
            }
        }
        aug_tool_check(&t, aug_cutter_update(&c, &st, &e), &e);
        double ms = 1e3 * (aug_now() - t0);
        aug_tool_check(&t, aug_write_mdelta(t.w, m->dim, m->nv, &st.d, &e), &e);
        if (!aug_bdelta_empty(&st.bc)) aug_tool_check(&t, aug_write_bdelta(t.w, &st.bc, &e), &e);
        aug_tool_check(&t, aug_write_update(t.w, &st.u, &e), &e);
        write_path(&t, step, m->dim, st.seg, st.nseg);
        if (o.stats) {
            aug_kv q;
            aug_kv_init(&q, "cut");
            kv(&t, &q, "m", st.u.m);
            kv(&t, &q, "k", st.u.k);
            kv(&t, &q, "n", (double)aug_cut_order(m, s.nn0, s.nfree0));
            kv(&t, &q, "nnew", (double)st.d.nnew);
            kv(&t, &q, "nmod", (double)st.d.nmod);
            kv(&t, &q, "nadd", (double)st.d.nadd);
            kv(&t, &q, "nfix", (double)st.bc.nfix);
            kv(&t, &q, "nload", (double)st.bc.nload);
            kv(&t, &q, "pieces", (double)st.npieces);
            kv(&t, &q, "flags", st.d.flags);
            aug_tool_check(&t, aug_write_kv(t.w, "sTAt", step, &q, &e), &e);
            aug_kv_init(&q, "cut");
            kv(&t, &q, "time_ms", ms);
            aug_tool_check(&t, aug_write_kv(t.w, "tIMe", step, &q, &e), &e);
        }
        aug_cut_step_free(&st);
        aug_progress(&t, k, o.steps);
    }
    aug_tool_close(&t);
    aug_plane_free(&pc);
    aug_path_cut_free(&pp);
    aug_cutter_free(&c);
    aug_path_free(&o.path);
    for (int i = 0; i < o.ncon; i++) free((char *)o.con[i].set);
    free(o.con);
    free(s.map0);
    aug_rec_free(&rec);
    aug_mesh_free(m);
    return 0;
}
