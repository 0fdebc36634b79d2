/* cut: a stream (mesh, possibly factor and earlier steps) -> + per cut step
   MDLT, BDLT, UPDT, pATH (planar cut by node duplication, a 2-D path, a 3-D
   blade sweep or surface, or no cut: deformation-only steps of --constrain
   and --drag). */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "augcut.h"
#include "cli/aug_opt.h"
#include "cli/aug_gmsh.h"

static const char *synopsis =
    "cut [FILE] [--plane nx,ny,nz,d|random [--advance dx,dy,dz] [--polygon PTS] [--per-step K] [--seed S]\n"
    "           | --path PFILE [--mode split|snap] [--snap-tol T] [--chords] [--view U,V]\n"
    "           | --blade BFILE | --surface SFILE [--advance dx,dy,dz] [--mode snap|split] [--snap-tol T]]\n"
    "           --steps N [--pull F] [--detached auto|error|pin|drop|keep]\n"
    "           [--constrain SET|box:LO,HI[=u,v[,w]][@S]]... [--drag SET|box:LO,HI:dx,dy[,dz]]...\n"
    "           [--stats] [--deflate] [-h]";

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
    "  --blade BFILE        3-D: cut along the surface a moving blade segment sweeps: key\n"
    "                       positions 'blade ax ay az bx by bz', Bezier controls 'curve ...'\n"
    "                       between them (see cut(1)); step t of N cuts up to t/N of the motion\n"
    "  --surface SFILE      3-D: cut along a triangle surface (STL, or a gmsh .msh surface\n"
    "                       mesh), realised in the order of --advance (default: widest axis)\n"
    "                       blade and surface: --mode snap (default) or split (tet4)\n"
    "  --snap-tol T         split mode: snap to a node within T of an edge (default 0.05;\n"
    "                       --blade and --surface: 0.2)\n"
    "  --view ux,uy,uz,vx,vy,vz  membrane (mem3) sheet: the path is in screen coordinates\n"
    "                       (u.x, v.x) and is projected onto the sheet along u x v\n"
    "  --chords             split mode: no vertex at the curvature maximum inside an\n"
    "                       element, chords between the crossings only (thesis fig. 3.5)\n"
    "  --steps N            number of cut steps (N >= 1)\n"
    "  --pull F             opposing forces F on each node copy and its original\n"
    "  --detached POLICY    piece without Dirichlet support: auto (default: drop it when\n"
    "                       below 0.1% of the mesh volume, else error), error, pin, drop,\n"
    "                       keep (write the singular step, flagged, for solvers)\n"
    "  --constrain SPEC     fix the nodes of a set or box:x0,y0,z0,x1,y1,z1 (2-D: 4\n"
    "                       numbers) to 0 or =u,v[,w], at step @S (default 1)\n"
    "  --drag SPEC:dx,dy,dz every DOF of the nodes of a set or box (as --constrain) to\n"
    "                       u = (t/N) d at step t of N (2-D: dx,dy)\n"
    "                       --constrain/--drag without --plane or --path: deformation-only\n"
    "                       steps, which change only constraints\n"
    "  --seed S             random generator seed of --plane random (default 1)\n"
    "  --stats              write sTAt and tIMe (tag cut) for every step\n"
    "  --deflate            zlib-deflate payloads of 64 KiB and more\n"
    "  -h                   this help; see cut(1)\n";

typedef struct options {
    const char *file, *pathfile, *bladefile, *surffile;
    int plane, random_plane, have_adv, mode, mode_given, tol_given, policy, stats, deflate, chords;
    aug_cutsurf surf;          /* --blade or --surface */
    int npoly;                 /* --polygon vertices (3-D points) */
    double poly[3 * 64];
    double n[4], adv[3], pull, snap_tol, view[6];
    int have_view;
    long steps, per_step, seed;
    aug_path path;
    aug_constraint *con;
    int ncon;
} options;

/* --plane nx,ny,nz,d | random */
static int plane(aug_tool *t, const char *opt, const char *val, void *dst)
{
    options *o = dst;
    o->plane = 1;
    if (!strcmp(val, "random")) {
        o->random_plane = 1;
        return 0;
    }
    if (aug_parse_doubles(val, o->n, 4)) return -1;
    if (o->n[0] == 0 && o->n[1] == 0 && o->n[2] == 0) aug_tool_usage(t, "%s %s: the normal is zero", opt, val);
    return 0;
}

/* --polygon x,y,z,...: 3 to 64 points */
static int polygon(aug_tool *t, const char *opt, const char *val, void *dst)
{
    options *o = dst;
    int n = aug_parse_reals(val, o->poly, 3 * 64);
    (void)t, (void)opt;
    if (n < 9 || n % 3) return -1;
    o->npoly = n / 3;
    return 0;
}

/* --constrain SPEC and --drag SPEC:d, repeatable, in the order given */
static int constrain(aug_tool *t, const char *opt, const char *val, void *dst)
{
    options *o = dst;
    aug_constraint *q = realloc(o->con, (size_t)(o->ncon + 1) * sizeof *q);
    if (!q) aug_tool_die(t, "out of memory");
    o->con = q;
    if (!strcmp(opt, "--drag") ? aug_drag_parse(val, &q[o->ncon]) : aug_constraint_parse(val, &q[o->ncon]))
        return -1;
    o->ncon++;
    return 0;
}

static const aug_word modes[] = {{"split", AUG_PATH_SPLIT}, {"snap", AUG_PATH_SNAP}, {NULL, 0}};
static const aug_word policies[] = {{"error", AUG_DETACH_ERROR}, {"pin", AUG_DETACH_PIN},
                                    {"drop", AUG_DETACH_DROP},   {"keep", AUG_DETACH_KEEP},
                                    {"auto", AUG_DETACH_AUTO},
                                    {NULL, 0}};

/* --blade BFILE or --surface SFILE (.msh: gmsh's API, else STL) into o->surf */
static void parse_surface(aug_tool *t, options *o)
{
    aug_err e;
    memset(&o->surf, 0, sizeof o->surf);
    if (!o->mode_given) o->mode = AUG_PATH_SNAP;
    if (!o->tol_given) o->snap_tol = 0.2; /* 3-D split: fewer, better tets (cut(1)) */
    if (o->bladefile) {
        FILE *f = fopen(o->bladefile, "r");
        if (!f) aug_tool_usage(t, "--blade %s: cannot open it", o->bladefile);
        else {
            if (aug_blade_parse(f, o->bladefile, &o->surf.b, &e)) aug_tool_usage(t, "%s", e.msg);
            else o->surf.blade = 1;
            fclose(f);
        }
        return;
    }
    size_t l = strlen(o->surffile);
    int rc = l > 4 && !strcmp(o->surffile + l - 4, ".msh") ? aug_surface_gmsh(o->surffile, &o->surf.all, &e)
                                                           : aug_stl_read(o->surffile, &o->surf.all, &e);
    if (!rc) rc = aug_cutsurf_surface(&o->surf, o->have_adv ? o->adv : NULL, &e);
    if (rc) aug_tool_usage(t, "--surface %s", e.msg);
}

static void parse(aug_tool *t, int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    o->mode = AUG_PATH_SPLIT;
    o->policy = AUG_DETACH_AUTO;
    o->snap_tol = 0.05;
    o->seed = 1;
    int nsteps = 0, g_per = 0, g_seed = 0;
    o->adv[0] = o->adv[1] = o->adv[2] = NAN; /* unread (--advance nan: its own error only) */
    const aug_opt opt[] = {
        {AUG_OPT_CALL("--plane", plane, o, "nx,ny,nz,d or random"), .flags = AUG_OPT_ONCE},
        {AUG_OPT_REALS("--advance", o->adv, 3, "dx,dy,dz"), .given = &o->have_adv},
        {AUG_OPT_CALL("--polygon", polygon, o, "3 to 64 points x,y,z,x,y,z,..."), .flags = AUG_OPT_ONCE},
        {AUG_OPT_INT("--steps", &o->steps, 1, 1000000, "a count from 1 to 1000000"), .given = &nsteps},
        {AUG_OPT_INT("--per-step", &o->per_step, 1, LONG_MAX, "a count >= 1"), .given = &g_per},
        {AUG_OPT_INT("--seed", &o->seed, 0, LONG_MAX, "an integer >= 0"), .given = &g_seed},
        {AUG_OPT_REAL("--pull", &o->pull, -1e12, 1e12, "a force of at most 1e12 in magnitude")},
        {AUG_OPT_REAL("--snap-tol", &o->snap_tol, 0, 0.5, "a number in [0, 0.5)"), .flags = AUG_OPT_HI_OPEN,
         .given = &o->tol_given},
        {AUG_OPT_CHOICE("--mode", &o->mode, modes, "split or snap"), .given = &o->mode_given},
        {AUG_OPT_CHOICE("--detached", &o->policy, policies, "auto, error, pin, drop or keep")},
        {AUG_OPT_CALL("--constrain", constrain, o, "SET or box:LO,HI, optionally =u,v[,w] (each at most 1e30 in magnitude) and @STEP")},
        {AUG_OPT_CALL("--drag", constrain, o, "SET:dx,dy,dz or box:LO,HI:dx,dy,dz (each at most 1e30 in magnitude)")},
        {AUG_OPT_STRING("--path", &o->pathfile, "a file"), .flags = AUG_OPT_ONCE},
        {AUG_OPT_STRING("--blade", &o->bladefile, "a file"), .flags = AUG_OPT_ONCE},
        {AUG_OPT_STRING("--surface", &o->surffile, "a file"), .flags = AUG_OPT_ONCE},
        {AUG_OPT_FLAG("--stats", &o->stats)},
        {AUG_OPT_FLAG("--deflate", &o->deflate)},
        {AUG_OPT_FLAG("--chords", &o->chords)},
        {AUG_OPT_REALS("--view", o->view, 6, "ux,uy,uz,vx,vy,vz"), .given = &o->have_view},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &o->file, synopsis, help);
    if (!nsteps) aug_tool_usage(t, "--steps N is required");
    int ncut = !!o->plane + !!o->pathfile + !!o->bladefile + !!o->surffile;
    if (ncut > 1) aug_tool_usage(t, "give exactly one of --plane and --path (3-D: or --blade, --surface)");
    else if (!ncut && !o->ncon)
        aug_tool_usage(t, "give exactly one of --plane and --path (or --constrain/--drag alone: "
                       "deformation-only steps; 3-D: or --blade, --surface)");
    for (int i = 0; i < o->ncon; i++)
        if (o->steps >= 1 && o->con[i].step > o->steps)
            aug_tool_usage(t, "--constrain at step %ld after the last step %ld", o->con[i].step, o->steps);
    if (o->have_adv && !(o->adv[0] != 0 || o->adv[1] != 0 || o->adv[2] != 0))
        aug_tool_usage(t, "--advance: the zero vector has no direction");
    /* an option of another kind of cut is an error, not ignored (the
       synopsis: --plane takes --advance, --polygon, --per-step, --seed;
       --path --mode, --snap-tol, --chords, --view; --blade and --surface
       --mode, --snap-tol, --surface also --advance) */
    const char *kind = o->plane ? "--plane" : o->pathfile ? "--path" : o->bladefile ? "--blade"
                     : o->surffile ? "--surface" : "a deformation-only step (--constrain/--drag alone)";
    int pl = !!o->plane, pa = !!o->pathfile, sf = o->bladefile || o->surffile;
    const struct { const char *name; int given, ok; } fit[] = {
        {"--advance", o->have_adv, pl || o->surffile}, {"--polygon", o->npoly > 0, pl},
        {"--per-step", g_per, pl}, {"--seed", g_seed, pl},
        {"--mode", o->mode_given, pa || sf}, {"--snap-tol", o->tol_given, pa || sf},
        {"--chords", o->chords, pa},
    };
    /* (after the options' own errors: a bad value is its option's one error) */
    for (size_t i = 0; ncut <= 1 && !t->usage_errors && i < sizeof fit / sizeof *fit; i++)
        if (fit[i].given && !fit[i].ok) aug_tool_usage(t, "%s does not apply to %s", fit[i].name, kind);
    aug_err ve;
    if (o->have_view && !o->pathfile) aug_tool_usage(t, "--view needs --path");
    if (o->have_view && o->pull != 0) aug_tool_usage(t, "--view takes no --pull");
    if (o->have_view && aug_view_axes(o->view, &ve)) aug_tool_usage(t, "--view: %s", ve.msg);
    if (o->pathfile) {
        FILE *f = fopen(o->pathfile, "r");
        aug_err e;
        if (!f) aug_tool_usage(t, "--path %s: cannot open it", o->pathfile);
        else {
            if (aug_path_parse(f, o->pathfile, &o->path, &e)) aug_tool_usage(t, "%s", e.msg);
            fclose(f);
        }
    }
    if (o->bladefile || o->surffile) parse_surface(t, o);
    aug_tool_usage_done(t, synopsis);
}

int main(int argc, char **argv)
{
    aug_tool t;
    options o;
    aug_err e;
    aug_rec rec;
    aug_replay rp;
    memset(&rec, 0, sizeof rec);
    aug_tool_init(&t, "cut", argc, argv);
    parse(&t, argc, argv, &o);
    aug_set_threads(1); /* GSL's small eigenproblems call OpenBLAS: no idle spinning threads */
    aug_replay_init(&rp);
    rp.check_sys = 1; /* KMAT, FVEC, FACT pass on unread: checked here */
    aug_tool_open_in(&t, o.file);
    aug_tool_open_out(&t);
    if (o.deflate) aug_writer_deflate(t.w, 65536);
    /* everything upstream passes byte for byte: the factor of K0 stays valid */
    while (aug_tool_read(&t, &rec) == 1) {
        aug_tool_check(&t, aug_replay_add(&rp, &rec, &e), &e);
        if (!memcmp(rec.type, "pLAN", 4)) /* the upstream plan, extended by this cut's steps */
            aug_tool_check(&t, aug_write_plan(t.w, rp.plan_first, rp.plan_last + (int32_t)o.steps, &e), &e);
        else
            aug_tool_pass(&t, &rec);
    }
    aug_tool_check(&t, aug_replay_end(&rp, &e), &e);
    aug_mesh *m = &rp.mesh;
    if (!(m->have & AUG_HAVE_NODE) || !(m->have & AUG_HAVE_ELEM))
        aug_tool_die(&t, "%s: the stream has no mesh (NODE and ELEM records)", t.inname);
    aug_tool_check(&t, aug_replay_start(&rp, &e), &e);
    if (o.pathfile && !o.have_view && (m->dim != 2 || m->etype != AUG_TRI3))
        aug_tool_die(&t, "%s: --path needs a 2-D triangle mesh (or a membrane and --view)", t.inname);
    const char *sopt = o.bladefile ? "--blade" : "--surface", *sfile = o.bladefile ? o.bladefile : o.surffile;
    if (sfile && m->dim != 3) aug_tool_die(&t, "%s: %s needs a 3-D mesh", t.inname, sopt);
    int meets = sfile ? aug_cutsurf_meets(&o.surf, m) : 1;
    if (meets == -1) aug_tool_die(&t, "%s: %s %s: out of memory", t.inname, sopt, sfile);
    if (meets == -2)
        aug_tool_die(&t, "%s: %s %s sweeps no surface (its positions do not move the edge)", t.inname, sopt, sfile);
    if (meets == 0)
        aug_tool_die(&t, "%s: %s %s misses the mesh (no part of it meets the mesh's box)", t.inname, sopt, sfile);
    aug_view vw;
    memset(&vw, 0, sizeof vw);
    if (o.have_view) aug_tool_check(&t, aug_view_init(&vw, m, o.view, o.view + 3, &e), &e);
    aug_cutter c;
    aug_tool_check(&t, aug_cutter_init(&c, m, rp.nn0, rp.map0, rp.nfree0, &e), &e);
    c.policy = o.policy;
    c.dyn = rp.dynamic ? &rp.dyn : NULL;
    c.pull = o.pull;
    aug_plane_cut pc;
    aug_path_cut pp;
    aug_blade_cut bcut;
    memset(&bcut, 0, sizeof bcut);
    if (sfile) aug_tool_check(&t, aug_blade_cut_init(&bcut, m, o.mode, o.snap_tol, &e), &e);
    memset(&pc, 0, sizeof pc);
    memset(&pp, 0, sizeof pp);
    int64_t per = o.per_step;
    if (o.plane) {
        if (o.random_plane) aug_plane_random(m, (unsigned long)o.seed, o.n);
        if (m->dim == 2) o.n[2] = 0;
        aug_tool_check(&t, aug_plane_plan(&pc, m, &c.adj, o.n, o.n[3], o.have_adv ? o.adv : NULL, &e), &e);
        if (o.npoly) aug_tool_check(&t, aug_plane_restrict(&pc, m, o.poly, o.npoly, &e), &e);
        if (per == 0) per = (pc.ncut + 63) / 64;
        c.pull_dir = pc.n; /* pull the cut faces apart along the plane's normal */
    } else if (o.pathfile) {
        aug_path_cut_init(&pp, &o.path, o.mode, o.snap_tol);
        pp.kappa = !o.chords;
    }
    /* the steps this cut brings (pLAN: solve-aug's auto knows where it ends),
       unless the upstream plan was extended above */
    if (!rp.plan_last)
        aug_tool_check(&t, aug_write_plan(t.w, rp.last_step + 1, rp.last_step + (int32_t)o.steps, &e), &e);
    int64_t nseg = 0; /* segments of the path inside the mesh, over every step */
    for (long k = 1; k <= o.steps; k++) {
        int32_t step = rp.last_step + (int32_t)k;
        aug_cut_step st;
        aug_cut_step_init(&st, step);
        double t0 = aug_now();
        if (o.plane) {
            if (pc.next >= pc.ncut)
                aug_tool_die(&t, "%s: step %d: all %lld cut nodes of the plane are cut "
                             "(fewer --steps or a larger --per-step)", t.inname, (int)step,
                             (long long)pc.ncut);
            aug_tool_check(&t, aug_plane_step(&pc, &c.ed, per, &st.seg, &st.nseg, &e), &e);
        } else if (o.pathfile) {
            double s_to = o.path.total * (double)k / (double)o.steps;
            aug_tool_check(&t, o.have_view ? aug_view_path_step(&vw, &pp, &c.ed, step, s_to, &st.seg, &st.nseg, &e)
                                           : aug_path_step(&pp, &c.ed, s_to, &st.seg, &st.nseg, &e), &e);
        } else if (sfile) {
            aug_tool_check(&t, aug_cutsurf_step(&o.surf, k, o.steps, &e), &e);
            aug_tool_check(&t, aug_blade_cut_step(&bcut, &c.ed, &c.fn, o.surf.step.t, o.surf.step.n, &st.seg,
                                                  &st.nseg, &e), &e);
        }
        nseg += st.nseg;
        aug_tool_check(&t, aug_cutter_apply(&c, &st, &e), &e);
        int rc = aug_constrain_step(o.con, o.ncon, m, k, o.steps, &st.bc, &e);
        if (rc == AUG_EUSAGE) aug_tool_die(&t, "%s", e.msg); /* the option does not fit the mesh */
        aug_tool_check(&t, rc, &e);
        aug_tool_check(&t, aug_cutter_update(&c, &st, &e), &e);
        double ms = 1e3 * (aug_now() - t0);
        int64_t n = aug_cut_order(m, rp.nn0, rp.nfree0);
        aug_tool_check(&t, aug_cut_step_write(t.w, m, &st, o.stats, n, ms, &e), &e);
        aug_cut_step_free(&st);
        aug_progress(&t, k, o.steps);
    }
    if (o.pathfile && nseg == 0)
        aug_tool_die(&t, "%s: --path %s cuts nothing: no part of it crosses an element edge (it misses the mesh, "
                     "or stays within one element)", t.inname, o.pathfile);
    if (sfile && bcut.nface == 0) aug_tool_die(&t, "%s: %s %s misses the mesh (it cuts no face)", t.inname, sopt, sfile);
    aug_blade_cut_free(&bcut);
    aug_cutsurf_free(&o.surf);
    aug_tool_close(&t);
    aug_plane_free(&pc);
    aug_path_cut_free(&pp);
    aug_view_free(&vw);
    aug_cutter_free(&c);
    aug_path_free(&o.path);
    free(o.con);
    aug_rec_free(&rec);
    aug_replay_free(&rp);
    return 0;
}
