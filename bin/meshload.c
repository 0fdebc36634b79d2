/* meshload: a gmsh .msh file and scene options -> the mesh records of an augcut stream. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_scene.h"
#include "cli/aug_gmsh.h"
#include "cli/aug_opt.h"

static const char *synopsis =
    "meshload FILE.msh [--fix GROUP|box:x0,y0,z0,x1,y1,z1|plane:nx,ny,nz,d[,tol]]...\n"
    "       [--material GROUP:E=..,nu=..,rho=..,t=..]... [--default-material E=..,nu=..,rho=..,t=..]\n"
    "       [--load GROUP:fx,fy,fz | --load point:x,y,z:fx,fy,fz]... [--output all|surface|GROUP]\n"
    "       [--reorient] [--deflate] [-h]";

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
    "  --output all|surface|GROUP    the nodes whose displacement is wanted (default all)\n"
    "  --reorient            flip inverted elements instead of refusing them\n"
    "  --deflate             zlib-deflate large payloads\n"
    "  -h                    this help; see meshload(1)\n";

enum { NPROP = 4 };
static const char *prop_key[NPROP] = {"E", "nu", "rho", "t"};

typedef struct props {
    int has[NPROP];
    double v[NPROP];
} props;

enum { FIX_GROUP, FIX_BOX, FIX_PLANE };
typedef struct fixopt {
    int kind;
    const char *arg;
    char group[AUG_NAME];
    double v[6];
    int ntol; /* plane: 1 when tol was given */
    int bad;  /* its text was refused */
} fixopt;

typedef struct loadopt {
    int point;
    const char *arg;
    char group[AUG_NAME];
    double p[3], F[3];
    int bad;
} loadopt;

typedef struct matopt {
    const char *arg;
    char group[AUG_NAME];
    props p;
    int bad;
} matopt;

typedef struct options {
    const char *file;
    fixopt *fix;
    int nfix;
    matopt *mat;
    int nmat;
    props def;
    const char *defarg;
    loadopt *load;
    int nload;
    const char *output;
    int reorient, deflate;
} options;

/* "E=..,nu=..": each key at most once, values in range */
static void parse_props(aug_tool *t, const char *opt, const char *s, const char *text, props *p)
{
    char buf[512];
    if (snprintf(buf, sizeof buf, "%s", text) >= (int)sizeof buf) {
        aug_tool_usage(t, "%s %s: too long", opt, s);
        return;
    }
    if (!buf[0]) aug_tool_usage(t, "%s %s: no properties given (E=..,nu=..,rho=..,t=..)", opt, s);
    for (char *save = NULL, *kv = strtok_r(buf, ",", &save); kv; kv = strtok_r(NULL, ",", &save)) {
        char *eq = strchr(kv, '=');
        int k = -1;
        if (eq) {
            *eq = 0;
            for (int i = 0; i < NPROP; i++)
                if (strcmp(kv, prop_key[i]) == 0) k = i;
        }
        double v;
        if (k < 0) {
            aug_tool_usage(t, "%s %s: '%s' is not one of E=, nu=, rho=, t=", opt, s, kv);
        } else if (aug_parse_double(eq + 1, &v)) {
            aug_tool_usage(t, "%s %s: %s=%s is not a number", opt, s, kv, eq + 1);
        } else if ((k == 0 && !(v > 0)) || (k == 1 && !(v > -1 && v < 0.5)) ||
                   (k == 2 && !(v >= 0)) || (k == 3 && !(v > 0))) {
            static const char *range[NPROP] = {"E > 0", "-1 < nu < 0.5", "rho >= 0", "t > 0"};
            aug_tool_usage(t, "%s %s: %s=%s is out of range (%s)", opt, s, kv, eq + 1, range[k]);
        } else if (p->has[k]) {
            aug_tool_usage(t, "%s %s: %s given twice", opt, s, kv);
        } else {
            p->has[k] = 1;
            p->v[k] = v;
        }
    }
}

/* copy a group name (the text before the last ':' or the whole text) */
static int group_name(aug_tool *t, const char *opt, const char *s, size_t len, char *dst)
{
    if (len == 0) {
        aug_tool_usage(t, "%s %s: empty group name", opt, s);
        return -1;
    }
    if (len >= AUG_NAME) {
        aug_tool_usage(t, "%s %s: group name longer than %d bytes", opt, s, AUG_NAME - 1);
        return -1;
    }
    memcpy(dst, s, len);
    dst[len] = 0;
    return 0;
}

/* two or three comma-separated numbers (the third 0 when absent) */
static int vec3(const char *s, double *v)
{
    v[2] = 0;
    return aug_parse_doubles(s, v, 3) && aug_parse_doubles(s, v, 2) ? -1 : 0;
}

static void parse_fix(aug_tool *t, const char *s, fixopt *f)
{
    f->arg = s;
    if (strncmp(s, "box:", 4) == 0) {
        f->kind = FIX_BOX;
        if (aug_parse_doubles(s + 4, f->v, 6))
            aug_tool_usage(t, "--fix %s: want box:x0,y0,z0,x1,y1,z1", s);
        else if (f->v[0] > f->v[3] || f->v[1] > f->v[4] || f->v[2] > f->v[5])
            aug_tool_usage(t, "--fix %s: the box's low corner exceeds its high corner", s);
    } else if (strncmp(s, "plane:", 6) == 0) {
        f->kind = FIX_PLANE;
        f->ntol = aug_parse_doubles(s + 6, f->v, 5) == 0;
        if (!f->ntol && aug_parse_doubles(s + 6, f->v, 4))
            aug_tool_usage(t, "--fix %s: want plane:nx,ny,nz,d[,tol]", s);
        else if (f->v[0] == 0 && f->v[1] == 0 && f->v[2] == 0)
            aug_tool_usage(t, "--fix %s: the normal is zero", s);
        else if (f->ntol && !(f->v[4] >= 0))
            aug_tool_usage(t, "--fix %s: the tolerance is negative", s);
    } else {
        f->kind = FIX_GROUP;
        group_name(t, "--fix", s, strlen(s), f->group);
    }
}

static void parse_load(aug_tool *t, const char *s, loadopt *l)
{
    l->arg = s;
    const char *c = strrchr(s, ':');
    if (!c) {
        aug_tool_usage(t, "--load %s: want GROUP:fx,fy,fz or point:x,y,z:fx,fy,fz", s);
        return;
    }
    if (vec3(c + 1, l->F)) aug_tool_usage(t, "--load %s: the force '%s' is not fx,fy,fz", s, c + 1);
    if (strncmp(s, "point:", 6) == 0 && c > s + 5) {
        l->point = 1;
        char buf[256];
        size_t n = (size_t)(c - (s + 6));
        if (n >= sizeof buf || (memcpy(buf, s + 6, n), buf[n] = 0, vec3(buf, l->p)))
            aug_tool_usage(t, "--load %s: the point is not x,y,z", s);
    } else {
        group_name(t, "--load", s, (size_t)(c - s), l->group);
    }
}

static void parse_material(aug_tool *t, const char *s, matopt *m)
{
    m->arg = s;
    const char *c = strrchr(s, ':');
    if (!c) {
        aug_tool_usage(t, "--material %s: want GROUP:E=..,nu=..,rho=..,t=..", s);
        return;
    }
    group_name(t, "--material", s, (size_t)(c - s), m->group);
    parse_props(t, "--material", s, c + 1, &m->p);
}

/* --fix, --load, --material (repeatable): one more item, marked bad when its
   own text is refused */
static int parse_item(aug_tool *t, const char *opt, const char *s, void *dst)
{
    options *o = dst;
    int n0 = t->usage_errors, *bad;
    if (!strcmp(opt, "--fix")) {
        fixopt *f = &o->fix[o->nfix++];
        parse_fix(t, s, f);
        bad = &f->bad;
    } else if (!strcmp(opt, "--load")) {
        loadopt *l = &o->load[o->nload++];
        parse_load(t, s, l);
        bad = &l->bad;
    } else {
        matopt *m = &o->mat[o->nmat++];
        parse_material(t, s, m);
        bad = &m->bad;
    }
    *bad = t->usage_errors > n0;
    return 0;
}

/* --default-material E=..,nu=..,rho=..,t=.. */
static int parse_default(aug_tool *t, const char *opt, const char *s, void *dst)
{
    options *o = dst;
    o->defarg = s;
    parse_props(t, opt, s, s, &o->def);
    return 0;
}

static void parse(aug_tool *t, int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    o->fix = calloc((size_t)argc, sizeof *o->fix);
    o->mat = calloc((size_t)argc, sizeof *o->mat);
    o->load = calloc((size_t)argc, sizeof *o->load);
    if (!o->fix || !o->mat || !o->load) aug_tool_die(t, "out of memory");
    const aug_opt opt[] = {
        {AUG_OPT_CALL("--fix", parse_item, o, "a value")},
        {AUG_OPT_CALL("--material", parse_item, o, "a value")},
        {AUG_OPT_CALL("--default-material", parse_default, o, "a value"), .flags = AUG_OPT_ONCE},
        {AUG_OPT_CALL("--load", parse_item, o, "a value")},
        {AUG_OPT_STRING("--output", &o->output, "a value"), .bad = "empty set name",
         .flags = AUG_OPT_ONCE | AUG_OPT_NONEMPTY},
        {AUG_OPT_FLAG("--reorient", &o->reorient)},
        {AUG_OPT_FLAG("--deflate", &o->deflate)},
    };
    aug_opt_parse(t, argc, argv, opt, (int)(sizeof opt / sizeof *opt), &o->file, synopsis, help);
    if (!o->file) aug_tool_usage(t, "no mesh file given");
    else if (!strcmp(o->file, "-")) aug_tool_usage(t, "cannot read a mesh from stdin: give a .msh file");
    if (!o->output) o->output = "all";
    /* the rest (groups, selections, 2-D/3-D) is checked against the mesh */
    aug_tool_cmdline_end(t);
}

/* the named set, reported as a usage error when missing or empty */
static const aug_set *need_set(aug_tool *t, const aug_mesh *m, const char *opt, const char *arg,
                               const char *name)
{
    const aug_set *s = aug_mesh_set(m, name);
    if (!s) {
        char known[1024] = "";
        size_t k = 0;
        for (int i = 0; i < m->nset && k < sizeof known; i++)
            k += (size_t)snprintf(known + k, sizeof known - k, "%s%s", i ? ", " : "", m->sets[i].name);
        aug_tool_usage(t, "%s %s: no physical group or set named '%s' (there are: %s)", opt, arg,
                       name, known);
    } else if (s->n == 0) {
        aug_tool_usage(t, "%s %s: set '%s' has no node of the mesh", opt, arg, name);
        return NULL;
    }
    return s;
}

/* material properties: built-in defaults < --default-material < --material */
static void apply_materials(aug_tool *t, const options *o, aug_mesh *m)
{
    if (m->dim == 3 && o->def.has[3])
        aug_tool_usage(t, "--default-material %s: t= (thickness) applies to 2-D meshes only", o->defarg);
    for (int j = 0; j < o->nmat; j++) {
        if (o->mat[j].bad) continue;
        int found = 0;
        for (int i = 0; i < m->nmat; i++) found |= !strcmp(m->mats[i].name, o->mat[j].group);
        if (!found) {
            const aug_set *s = aug_mesh_set(m, o->mat[j].group);
            aug_tool_usage(t, "--material %s: '%s' is %s", o->mat[j].arg, o->mat[j].group,
                           s ? (m->dim == 3 ? "not a physical volume" : "not a physical surface")
                             : "no material of the mesh");
        }
        if (m->dim == 3 && o->mat[j].p.has[3])
            aug_tool_usage(t, "--material %s: t= (thickness) applies to 2-D meshes only", o->mat[j].arg);
    }
    for (int i = 0; i < m->nmat; i++) {
        aug_material *a = &m->mats[i];
        double *v[NPROP] = {&a->E, &a->nu, &a->rho, &a->t};
        for (int k = 0; k < NPROP; k++)
            if (o->def.has[k]) *v[k] = o->def.v[k];
        for (int j = 0; j < o->nmat; j++)
            if (!strcmp(a->name, o->mat[j].group))
                for (int k = 0; k < NPROP; k++)
                    if (o->mat[j].p.has[k]) *v[k] = o->mat[j].p.v[k];
    }
}

static void apply_fix(aug_tool *t, const options *o, aug_mesh *m, unsigned char *mark)
{
    double ext = aug_mesh_extent(m);
    memset(mark, 0, (size_t)m->nn);
    for (int j = 0; j < o->nfix; j++) {
        const fixopt *f = &o->fix[j];
        int64_t n = 0;
        if (f->bad) continue;
        if (f->kind == FIX_GROUP) {
            const aug_set *s = need_set(t, m, "--fix", f->arg, f->group);
            for (int64_t i = 0; s && i < s->n; i++) mark[s->nodes[i]] = 1;
            continue;
        }
        if (f->kind == FIX_BOX) n = aug_nodes_in_box(m, f->v, f->v + 3, mark);
        else n = aug_nodes_on_plane(m, f->v, f->v[3], f->ntol ? f->v[4] : 1e-6 * ext, mark);
        if (n == 0) aug_tool_usage(t, "--fix %s: selects no node", f->arg);
    }
}

static void apply_load(aug_tool *t, const options *o, const aug_mesh *m, double *f)
{
    for (int j = 0; j < o->nload; j++) {
        const loadopt *l = &o->load[j];
        if (l->bad) continue;
        if (m->dim == 2 && l->F[2] != 0)
            aug_tool_usage(t, "--load %s: a 2-D mesh takes no z force", l->arg);
        if (l->point) {
            int32_t i = (int32_t)aug_nearest_node(m, l->p);
            aug_load_spread(m, &i, 1, l->F, f);
        } else {
            const aug_set *s = need_set(t, m, "--load", l->arg, l->group);
            if (s) aug_load_spread(m, s->nodes, s->n, l->F, f);
        }
    }
}

static void apply_output(aug_tool *t, const options *o, aug_mesh *m, unsigned char *mark)
{
    aug_err e;
    const char *name = o->output;
    if (!strcmp(name, "all")) {
        aug_tool_check(t, aug_mesh_set_output(m, AUG_OUT_ALL, "all", NULL, 0, &e), &e);
    } else if (!strcmp(name, "surface")) {
        if (aug_mesh_boundary_nodes(m, mark) < 0) aug_tool_die(t, "out of memory");
        int32_t *v = malloc((size_t)(m->nn ? m->nn : 1) * sizeof *v);
        if (!v) aug_tool_die(t, "out of memory");
        int64_t n = 0;
        for (int64_t i = 0; i < m->nn; i++)
            if (mark[i]) v[n++] = (int32_t)i;
        aug_tool_check(t, aug_mesh_set_output(m, AUG_OUT_SURFACE, "surface", v, n, &e), &e);
        free(v);
    } else {
        const aug_set *s = need_set(t, m, "--output", name, name);
        if (s) aug_tool_check(t, aug_mesh_set_output(m, AUG_OUT_SET, name, s->nodes, s->n, &e), &e);
    }
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
    if (!rc) {
        rc = aug_import(&tg, o.reorient, &m, &e);
        aug_gmsh_free(&tg);
    }
    if (rc) {
        aug_tool_usage_done(&t, synopsis);
        aug_tool_fail(&t, &e);
    }

    unsigned char *fixmark = malloc((size_t)(m.nn ? m.nn : 1)), *outmark = malloc((size_t)(m.nn ? m.nn : 1));
    double *f = calloc((size_t)(m.nn * m.dim), sizeof *f);
    if (!fixmark || !outmark || !f) aug_tool_die(&t, "out of memory");
    apply_materials(&t, &o, &m);
    apply_fix(&t, &o, &m, fixmark);
    apply_load(&t, &o, &m, f);
    apply_output(&t, &o, &m, outmark);
    aug_tool_usage_done(&t, synopsis);
    aug_tool_check(&t, aug_mesh_fix_marked(&m, fixmark, &e), &e);
    aug_tool_check(&t, aug_mesh_set_load(&m, f, &e), &e);

    aug_tool_open_out(&t);
    if (o.deflate) aug_writer_deflate(t.w, 4096);
    aug_tool_check(&t, aug_mesh_write(t.w, &m, &e), &e);
    aug_tool_close(&t);
    free(fixmark);
    free(outmark);
    free(f);
    aug_mesh_free(&m);
    free(o.fix);
    free(o.mat);
    free(o.load);
    return 0;
}
