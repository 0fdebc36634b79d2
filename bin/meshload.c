/* meshload: a gmsh .msh file and scene options -> the mesh records of an augcut stream. */
#include <stdio.h>
#include <string.h>
#include "aug_scene.h"
#include "cli/aug_gmsh.h"
#include "cli/aug_opt.h"

static const char *synopsis =
    "meshload FILE.msh [--fix GROUP|box:x0,y0,z0,x1,y1,z1|plane:nx,ny,nz,d[,tol]]...\n"
    "       [--material GROUP:E=..,nu=..,rho=..,t=..]... [--default-material E=..,nu=..,rho=..,t=..]\n"
    "       [--load GROUP:fx,fy,fz | --load point:x,y,z:fx,fy,fz]... [--gravity gx,gy,gz]\n"
    "       [--output all|surface|GROUP] [--membrane [--foundation K]] [--reorient] [--deflate] [-h]";

static const char *help =
    "  --fix GROUP           fix every component (u = 0) of the nodes of a physical group or set\n"
    "  --fix box:x0,y0,z0,x1,y1,z1   ... of the nodes in the box (z ignored in 2-D)\n"
    "  --fix plane:nx,ny,nz,d[,tol]  ... of the nodes with |n.x - d| <= tol |n|\n"
    "                        (tol defaults to 1e-6 of the mesh's extent)\n"
    "  --material GROUP:E=..,nu=..,rho=..,t=..   properties of a physical volume (2-D: surface)\n"
    "                        or of 'default' (the elements in none); t only in 2-D\n"
    "  --default-material E=..,nu=..,rho=..,t=..  properties of every material (E=1 nu=0.3 rho=1 t=1)\n"
    "  --load GROUP:fx,fy,fz total force on a set, split equally among its nodes\n"
    "  --load point:x,y,z:fx,fy,fz   force on the node nearest to (x,y,z)\n"
    "  --gravity gx,gy,gz    body force rho g on every element (its consistent nodal load,\n"
    "                        added to the --load forces); 2-D: gx,gy\n"
    "  --output all|surface|GROUP    the nodes whose displacement is wanted (default all)\n"
    "  --membrane            a triangle mesh as a thin sheet in 3-D (mem3: plane stress in\n"
    "                        each triangle's plane, 3 DOFs per node; it need not be plane)\n"
    "  --foundation K        with --membrane: a Winkler foundation of modulus K under the\n"
    "                        sheet (force per area and normal displacement; FNDN)\n"
    "  --reorient            flip inverted elements instead of refusing them\n"
    "  --deflate             zlib-deflate large payloads\n"
    "  -h                    this help; see meshload(1)\n";

typedef struct options {
    const char *file;
    aug_scene_spec spec;
    aug_sink sink;             /* the scene options' problems, as usage errors */
    int reorient, deflate, membrane, have_kf;
    double kf;
} options;

static void report(void *t, const char *msg)
{
    aug_tool_usage(t, "%s", msg);
}

/* --fix, --material, --default-material, --load, --gravity: into the scene spec */
static int scene_option(aug_tool *t, const char *opt, const char *val, void *dst)
{
    options *o = dst;
    aug_err e;
    if (aug_scene_spec_add(&o->spec, opt, val, &o->sink, &e)) aug_tool_die(t, "%s", e.msg);
    return 0;
}

static void parse(aug_tool *t, int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    aug_scene_spec_init(&o->spec);
    o->sink.report = report;
    o->sink.ctx = t;
    const aug_opt opt[] = {
        {AUG_OPT_CALL("--fix", scene_option, o, "a value")},
        {AUG_OPT_CALL("--material", scene_option, o, "a value")},
        {AUG_OPT_CALL("--default-material", scene_option, o, "a value"), .flags = AUG_OPT_ONCE},
        {AUG_OPT_CALL("--load", scene_option, o, "a value")},
        {AUG_OPT_CALL("--gravity", scene_option, o, "a value"), .flags = AUG_OPT_ONCE},
        {AUG_OPT_STRING("--output", &o->spec.output, "a value"), .bad = "empty set name",
         .flags = AUG_OPT_ONCE | AUG_OPT_NONEMPTY},
        {AUG_OPT_FLAG("--reorient", &o->reorient)},
        {AUG_OPT_FLAG("--membrane", &o->membrane)},
        {AUG_OPT_REAL("--foundation", &o->kf, 0, 1e300, "a modulus from 0 to 1e300"), .given = &o->have_kf},
        {AUG_OPT_FLAG("--deflate", &o->deflate)},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &o->file, synopsis, help);
    if (o->have_kf && !o->membrane) aug_tool_usage(t, "--foundation needs --membrane");
    if (!o->file) aug_tool_usage(t, "no mesh file given");
    else if (!strcmp(o->file, "-")) aug_tool_usage(t, "cannot read a mesh from stdin: give a .msh file");
    /* the rest (groups, selections, 2-D/3-D) is checked against the mesh */
    aug_tool_cmdline_end(t);
}

int main(int argc, char **argv)
{
    aug_tool t;
    options o;
    aug_err e;
    aug_tagged tg;
    aug_mesh m;
    aug_tool_init(&t, "meshload", argc, argv);
    parse(&t, argc, argv, &o);
    if (!o.file || !strcmp(o.file, "-")) aug_tool_usage_done(&t, synopsis);
    t.inname = o.file;
    /* with usage errors already, the mesh is still read (if it can be) so that
       the options naming its groups are checked too, before exit 2 */
    int rc = aug_gmsh_read(o.file, &tg, &e);
    if (!rc && o.membrane && tg.etype != AUG_TRI3) {
        aug_tool_usage(&t, "--membrane: %s is a %s mesh, not a triangle (surface) mesh", o.file,
                       aug_etype_name(tg.etype));
        aug_gmsh_free(&tg);
        aug_tool_usage_done(&t, synopsis);
    }
    if (!rc) {
        if (o.membrane) tg.etype = AUG_MEM3;
        rc = aug_import(&tg, o.reorient, &m, &e);
        aug_gmsh_free(&tg);
    }
    if (rc) {
        aug_tool_usage_done(&t, synopsis);
        aug_tool_fail(&t, &e);
    }
    aug_tool_check(&t, aug_scene_spec_apply(&o.spec, &m, &o.sink, &e), &e);
    for (int i = 0; o.kf > 0 && i < m.nmat; i++) m.mats[i].kf = o.kf, m.have |= AUG_HAVE_FNDN;
    aug_tool_usage_done(&t, synopsis);

    aug_tool_open_out(&t);
    if (o.deflate) aug_writer_deflate(t.w, 4096);
    aug_tool_check(&t, aug_mesh_write(t.w, &m, &e), &e);
    aug_tool_close(&t);
    aug_mesh_free(&m);
    aug_scene_spec_free(&o.spec);
    return 0;
}
