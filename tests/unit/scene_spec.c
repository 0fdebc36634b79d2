/* Unit tests of the scene options (lib/mesh/scene_spec.c, scene_apply.c) and aug_parse_reals. */
#include <math.h>
#include <string.h>
#include "aug_scene.h"
#include "fem_mesh.h"
#include "t.h"

/* a sink that keeps every message */
typedef struct msgs {
    int n;
    char text[16][400];
    size_t len[16];
} msgs;

static void keep(void *ctx, const char *msg)
{
    msgs *q = ctx;
    if (q->n < 16) {
        snprintf(q->text[q->n], sizeof q->text[0], "%s", msg);
        q->len[q->n] = strlen(msg);
    }
    q->n++;
}

static aug_sink sink_of(msgs *q)
{
    memset(q, 0, sizeof *q);
    aug_sink k = {keep, q, 0};
    return k;
}

/* messages equal want[0..n) in order */
static void expect(const msgs *q, const aug_sink *k, const char *const *want, int n, const char *what)
{
    T_CHECK(q->n == n && k->n == n, "%s: %d problems, want %d (first: %s)", what, q->n, n,
            q->n ? q->text[0] : "none");
    for (int i = 0; i < n && i < q->n && i < 16; i++)
        T_CHECK(!strcmp(q->text[i], want[i]), "%s: problem %d '%s', want '%s'", what, i, q->text[i],
                want[i]);
}

/* set name := the nodes with x[axis] == value (none when axis < 0) */
static void add_set(aug_mesh *m, const char *name, int axis, double value)
{
    m->sets = realloc(m->sets, (size_t)(m->nset + 1) * sizeof *m->sets);
    aug_set *s = &m->sets[m->nset++];
    snprintf(s->name, sizeof s->name, "%s", name);
    s->nodes = malloc((size_t)m->nn * sizeof *s->nodes);
    s->n = 0;
    for (int64_t i = 0; i < m->nn; i++)
        if (axis >= 0 && m->x[i * m->dim + axis] == value) s->nodes[s->n++] = (int32_t)i;
}

/* the box 2 x 1 x 1 of 2 x 1 x 1 cubes (12 nodes, node (i,j,k) = i + 3 (j + 2 k)),
   materials soft (id 1) and default (id 0; element 0 only), sets left (x = 0),
   tip (x = 2), empty */
static void scene_box(aug_mesh *m)
{
    tm_box(m, 2, 1, 1, 2, 1, 1, 1, 0.3);
    free(m->mats);
    tm_material(m, 2, AUG_DEFAULT_E, AUG_DEFAULT_NU, AUG_DEFAULT_RHO, AUG_DEFAULT_T);
    strcpy(m->mats[0].name, "soft");
    m->mats[1].id = 0;
    strcpy(m->mats[1].name, "default");
    m->mat[0] = 1;
    add_set(m, "left", 0, 0);
    add_set(m, "tip", 0, 2);
    add_set(m, "empty", -1, 0);
}

/* s += each (opt, text) pair; no problem, no error */
static void add_all(aug_scene_spec *s, const char *const *kv, int n, aug_sink *k)
{
    aug_err e;
    for (int i = 0; i < 2 * n; i += 2)
        T_CHECK(aug_scene_spec_add(s, kv[i], kv[i + 1], k, &e) == 0, "%s %s: %s", kv[i], kv[i + 1], e.msg);
}

/* one application: a mesh, the spec given to it, the problems met */
typedef struct scene_case {
    aug_mesh m;
    aug_scene_spec s;
    msgs q;
    aug_sink k;
    aug_err e;
} scene_case;

/* c->m += the spec of the n (opt, text) pairs kv and output out: 0 or the code */
static int run(scene_case *c, const char *const *kv, int n, const char *out)
{
    c->k = sink_of(&c->q);
    aug_scene_spec_init(&c->s);
    add_all(&c->s, kv, n, &c->k);
    c->s.output = out;
    return aug_scene_spec_apply(&c->s, &c->m, &c->k, &c->e);
}

static void finish(scene_case *c)
{
    aug_scene_spec_free(&c->s);
    aug_mesh_free(&c->m);
}

static void t_parse_reals(void)
{
    double v[4];
    T_CHECK(aug_parse_reals("1,-2.5,3e2", v, 3) == 3 && v[0] == 1 && v[1] == -2.5 && v[2] == 300, "three");
    T_CHECK(aug_parse_reals("1,2", v, 3) == 2, "two of at most three");
    T_CHECK(aug_parse_reals(" 7", v, 1) == 1 && v[0] == 7, "leading blank");
    static const char *bad[] = {"", "1,", ",1", "1,,2", "1 ", "x", "inf", "nan", "1e999", "1,2,3,4"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++)
        T_CHECK(aug_parse_reals(bad[i], v, 3) == -1, "'%s' accepted", bad[i]);
}

static void t_parse(void)
{
    msgs q;
    aug_sink k = sink_of(&q);
    aug_scene_spec s;
    aug_scene_spec_init(&s);
    static const char *const kv[] = {
        "--fix", "fixed", "--fix", "box:0,0,0,1,2,3", "--fix", "plane:0,0,1,2", "--fix", "plane:1,0,0,0,0.5",
        "--load", "tip:1,2", "--load", "point:1,2,3:4,5,6", "--load", "point:1,2:0,1", "--load", "point:7,8,9",
        "--material", "soft:E=10,nu=0.25", "--material", "a:b:rho=0,t=2", "--default-material", "E=5,rho=2"};
    add_all(&s, kv, 11, &k);
    expect(&q, &k, NULL, 0, "good specs");
    T_CHECK(s.nfix == 4 && s.nload == 4 && s.nmat == 2, "counts %d %d %d", s.nfix, s.nload, s.nmat);
    if (s.nfix == 4) {
        T_CHECK(s.fix[0].kind == AUG_FIX_GROUP && !strcmp(s.fix[0].group, "fixed"), "fix group");
        T_CHECK(s.fix[1].kind == AUG_FIX_BOX && s.fix[1].v[4] == 2 && s.fix[1].v[5] == 3, "fix box");
        T_CHECK(s.fix[2].kind == AUG_FIX_PLANE && !s.fix[2].ntol && s.fix[2].v[3] == 2, "fix plane");
        T_CHECK(s.fix[3].ntol && s.fix[3].v[4] == 0.5 && !strcmp(s.fix[3].arg, "plane:1,0,0,0,0.5"),
                "fix plane with tol");
    }
    if (s.nload == 4) {
        const aug_load_spec *l = s.load;
        T_CHECK(!l[0].point && !strcmp(l[0].group, "tip") && l[0].F[1] == 2 && l[0].F[2] == 0, "load set");
        T_CHECK(l[1].point && l[1].p[2] == 3 && l[1].F[0] == 4 && l[1].F[2] == 6, "load point");
        T_CHECK(l[2].point && l[2].p[1] == 2 && l[2].p[2] == 0 && l[2].F[2] == 0, "2-D load point");
        T_CHECK(!l[3].point && !strcmp(l[3].group, "point") && l[3].F[2] == 9, "a set named point");
    }
    if (s.nmat == 2) {
        const aug_mat_spec *m = s.mat;
        T_CHECK(!strcmp(m[0].group, "soft") && m[0].p.has[AUG_PROP_E] && m[0].p.v[AUG_PROP_E] == 10 &&
                    m[0].p.v[AUG_PROP_NU] == 0.25 && !m[0].p.has[AUG_PROP_RHO] && !m[0].p.has[AUG_PROP_T],
                "material soft");
        T_CHECK(!strcmp(m[1].group, "a:b") && m[1].p.has[AUG_PROP_RHO] && m[1].p.v[AUG_PROP_T] == 2,
                "group before the last ':'");
    }
    T_CHECK(s.def.has[AUG_PROP_E] && s.def.v[AUG_PROP_RHO] == 2 && !s.def.has[AUG_PROP_NU] &&
                !strcmp(s.defarg, "E=5,rho=2"),
            "default material");
    aug_scene_spec_free(&s);
}

/* one refused value: its messages, and nothing added */
typedef struct bad_case {
    const char *opt, *text;
    int n;
    const char *want[3];
} bad_case;

static void t_parse_bad(void)
{
    static const bad_case c[] = {
        {"--fix", "box:1,2,3", 1, {"--fix box:1,2,3: want box:x0,y0,z0,x1,y1,z1"}},
        {"--fix", "box:1,1,1,0,0,0", 1, {"--fix box:1,1,1,0,0,0: the box's low corner exceeds its high corner"}},
        {"--fix", "plane:0,0,0,1", 1, {"--fix plane:0,0,0,1: the normal is zero"}},
        {"--fix", "plane:0,0,1,1,-1", 1, {"--fix plane:0,0,1,1,-1: the tolerance is negative"}},
        {"--fix", "plane:0,0,1", 1, {"--fix plane:0,0,1: want plane:nx,ny,nz,d[,tol]"}},
        {"--fix", "", 1, {"--fix : empty group name"}},
        {"--fix", "g234567890123456789012345678901234567890123456789012345678901234", 1,
         {"--fix g234567890123456789012345678901234567890123456789012345678901234: group name longer than 63 bytes"}},
        {"--load", "tip", 1, {"--load tip: want GROUP:fx,fy,fz or point:x,y,z:fx,fy,fz"}},
        {"--load", "a:1,b", 1, {"--load a:1,b: the force '1,b' is not fx,fy,fz"}},
        {"--load", ":1,2,3", 1, {"--load :1,2,3: empty group name"}},
        {"--load", "point:1,x,3:1,0,0", 1, {"--load point:1,x,3:1,0,0: the point is not x,y,z"}},
        {"--load", "point:1:1", 2, {"--load point:1:1: the force '1' is not fx,fy,fz", "--load point:1:1: the point is not x,y,z"}},
        {"--material", "beam", 1, {"--material beam: want GROUP:E=..,nu=..,rho=..,t=.."}},
        {"--material", "beam:", 1, {"--material beam:: no properties given (E=..,nu=..,rho=..,t=..)"}},
        {"--material", "beam:E=1,E=2", 1, {"--material beam:E=1,E=2: E given twice"}},
        {"--material", "beam:E=x", 1, {"--material beam:E=x: E=x is not a number"}},
        {"--material", "x:E=-1,nu=0.7,q=3", 3,
         {"--material x:E=-1,nu=0.7,q=3: E=-1 is out of range (E > 0)",
          "--material x:E=-1,nu=0.7,q=3: nu=0.7 is out of range (-1 < nu < 0.5)",
          "--material x:E=-1,nu=0.7,q=3: 'q' is not one of E=, nu=, rho=, t="}},
        {"--material", ":rho=-1,t=0", 3,
         {"--material :rho=-1,t=0: empty group name", "--material :rho=-1,t=0: rho=-1 is out of range (rho >= 0)",
          "--material :rho=-1,t=0: t=0 is out of range (t > 0)"}},
    };
    for (size_t i = 0; i < sizeof c / sizeof *c; i++) {
        msgs q;
        aug_sink k = sink_of(&q);
        aug_scene_spec s;
        aug_err e;
        aug_scene_spec_init(&s);
        T_CHECK(aug_scene_spec_add(&s, c[i].opt, c[i].text, &k, &e) == 0, "%s %s: %s", c[i].opt, c[i].text, e.msg);
        expect(&q, &k, c[i].want, c[i].n, c[i].text);
        T_CHECK(s.nfix + s.nload + s.nmat == 0, "%s %s was added", c[i].opt, c[i].text);
        aug_scene_spec_free(&s);
    }
    /* --default-material keeps its good keys; another option is an error */
    msgs q;
    aug_sink k = sink_of(&q);
    aug_scene_spec s;
    aug_err e;
    aug_scene_spec_init(&s);
    aug_scene_spec_add(&s, "--default-material", "E=0,rho=3", &k, &e);
    static const char *const want[] = {"--default-material E=0,rho=3: E=0 is out of range (E > 0)"};
    expect(&q, &k, want, 1, "default");
    T_CHECK(!s.def.has[AUG_PROP_E] && s.def.has[AUG_PROP_RHO] && s.def.v[AUG_PROP_RHO] == 3, "default's good keys");
    T_CHECK(aug_scene_spec_add(&s, "--output", "all", &k, &e) == AUG_EUSAGE && k.n == 1, "--output is no spec");
    /* a message longer than the sink's buffer comes whole */
    char name[701];
    memset(name, 'g', 700);
    name[700] = 0;
    k = sink_of(&q);
    aug_scene_spec_add(&s, "--fix", name, &k, &e);
    T_CHECK(q.n == 1 && q.len[0] == strlen("--fix : group name longer than 63 bytes") + 700, "long message");
    /* unsinked problems are counted */
    aug_sink quiet = {NULL, NULL, 0};
    aug_scene_spec_add(&s, "--fix", "box:1", &quiet, &e);
    T_CHECK(quiet.n == 1 && s.nfix == 0, "counted without a report function");
    aug_scene_spec_free(&s);
}

/* precedence of the materials; FIXD u = 0 on the nodes with x = 0 (set and
   box) or x = 1 (plane); loads on the set and the nearest node; the output set */
static void t_apply(void)
{
    scene_case c;
    scene_box(&c.m);
    static const char *const kv[] = {
        "--default-material", "E=5,rho=2", "--material", "soft:E=10,nu=0.25", "--fix", "left",
        "--fix", "plane:1,0,0,1", "--fix", "box:-1,-1,-1,0.5,2,2", "--load", "tip:0,0,-4",
        "--load", "point:2.1,0.9,1.2:1,0,0"};
    T_CHECK(run(&c, kv, 7, "tip") == 0, "apply: %s", c.e.msg);
    expect(&c.q, &c.k, NULL, 0, "apply");
    const aug_mesh *m = &c.m;
    const aug_material *a = &m->mats[0], *d = &m->mats[1];
    T_CHECK(a->E == 10 && a->nu == 0.25 && a->rho == 2 && a->t == AUG_DEFAULT_T, "soft: %g %g %g %g", a->E,
            a->nu, a->rho, a->t);
    T_CHECK(d->E == 5 && d->nu == AUG_DEFAULT_NU && d->rho == 2, "default: %g %g %g", d->E, d->nu, d->rho);
    T_CHECK(m->nfix == 24 && (m->have & AUG_HAVE_FIXD), "%lld constraints", (long long)m->nfix);
    for (int64_t j = 0; j < m->nfix && m->nfix == 24; j++) {
        int32_t node = m->fix_dof[j] / 3;
        T_CHECK(node % 3 != 2 && m->fix_val[j] == 0, "constraint %lld on node %d", (long long)j, node);
        if (j) T_CHECK(m->fix_dof[j] > m->fix_dof[j - 1], "FIXD not increasing");
    }
    /* tip: -1 on each of its 4 nodes in z; node 11 = (2,1,1), the nearest, +1 in x */
    T_CHECK(m->nload == 5, "%lld loads", (long long)m->nload);
    for (int64_t j = 0; j < m->nload; j++) {
        int32_t dof = m->load_dof[j];
        double want = dof == 3 * 11 ? 1.0 : -1.0;
        T_CHECK((dof % 3 == 2 || dof == 33) && (dof / 3) % 3 == 2 && m->load_val[j] == want,
                "load %g on dof %d", m->load_val[j], dof);
    }
    T_CHECK(m->out_kind == AUG_OUT_SET && !strcmp(m->out_name, "tip") && m->nout == 4 &&
                m->out_nodes[3] == 11,
            "output set");
    finish(&c);

    /* output: all (by default) and surface */
    const char *out[2] = {NULL, "surface"};
    for (int i = 0; i < 2; i++) {
        scene_box(&c.m);
        T_CHECK(run(&c, NULL, 0, out[i]) == 0, "apply: %s", c.e.msg);
        T_CHECK(m->out_kind == (i ? AUG_OUT_SURFACE : AUG_OUT_ALL) && m->nout == (i ? 12 : 0) &&
                    !strcmp(m->out_name, i ? "surface" : "all") && m->nfix == 0 && m->nload == 0,
                "output %s", out[i] ? out[i] : "NULL");
        finish(&c);
    }
}

/* options that disagree with the mesh: every problem, in order */
static void t_apply_problems(void)
{
    scene_case c;
    scene_box(&c.m);
    static const char *const kv[] = {
        "--default-material", "t=3", "--material", "nope:E=3", "--material", "left:E=2",
        "--material", "soft:t=2", "--fix", "nosuch", "--fix", "box:50,50,50,60,60,60", "--fix", "tip",
        "--load", "nada:1,1,1", "--load", "empty:1,0,0"};
    T_CHECK(run(&c, kv, 9, "zip") == 0, "apply: %s", c.e.msg);
    static const char *const want[] = {
        "--default-material t=3: t= (thickness) applies to 2-D meshes only",
        "--material nope:E=3: 'nope' is no material of the mesh",
        "--material left:E=2: 'left' is not a physical volume",
        "--material soft:t=2: t= (thickness) applies to 2-D meshes only",
        "--fix nosuch: no physical group or set named 'nosuch' (there are: left, tip, empty)",
        "--fix box:50,50,50,60,60,60: selects no node",
        "--load nada:1,1,1: no physical group or set named 'nada' (there are: left, tip, empty)",
        "--load empty:1,0,0: set 'empty' has no node of the mesh",
        "--output zip: no physical group or set named 'zip' (there are: left, tip, empty)"};
    expect(&c.q, &c.k, want, 9, "problems");
    T_CHECK(c.m.nfix == 12 && c.m.nload == 0 && !(c.m.have & AUG_HAVE_OUTS), "the rest applied: %lld %lld",
            (long long)c.m.nfix, (long long)c.m.nload);
    finish(&c);

    /* 2-D: a z force is a problem (and ignored), a volume is a surface */
    tm_rect(&c.m, 2, 2, 2, 2, 1, 0.3, 1);
    add_set(&c.m, "left", 0, 0);
    static const char *const kv2[] = {"--load", "left:0,3,1", "--material", "left:t=2"};
    T_CHECK(run(&c, kv2, 2, NULL) == 0, "apply: %s", c.e.msg);
    static const char *const want2[] = {"--material left:t=2: 'left' is not a physical surface",
                                        "--load left:0,3,1: a 2-D mesh takes no z force"};
    expect(&c.q, &c.k, want2, 2, "2-D problems");
    T_CHECK(c.m.nload == 3 && c.m.load_dof[0] == 1 && c.m.load_val[0] == 1, "2-D loads");
    finish(&c);
}

/* every allocation failure is AUG_ENOMEM, nothing leaks (the ASan build) */
static void t_nomem(void)
{
    int done = 0;
    for (long n = 0; n < 1000 && !done; n++) {
        aug_mesh m;
        scene_box(&m);
        msgs q;
        aug_sink k = sink_of(&q);
        aug_scene_spec s;
        aug_err e;
        aug_scene_spec_init(&s);
        aug_fail_after(n);
        int rc = aug_scene_spec_add(&s, "--fix", "left", &k, &e);
        if (!rc) rc = aug_scene_spec_add(&s, "--load", "tip:1,0,0", &k, &e);
        if (!rc) rc = aug_scene_spec_add(&s, "--material", "soft:E=2", &k, &e);
        s.output = "surface";
        if (!rc) rc = aug_scene_spec_apply(&s, &m, &k, &e);
        aug_fail_after(-1);
        T_CHECK(rc == 0 || rc == AUG_ENOMEM, "failure after %ld: code %d (%s)", n, rc, e.msg);
        T_CHECK(k.n == 0, "failure after %ld: a problem reported", n);
        done = rc == 0;
        if (done) T_CHECK(m.nfix == 12 && m.nload == 4 && m.nout == 12, "after %ld failures", n);
        aug_scene_spec_free(&s);
        aug_mesh_free(&m);
    }
    T_CHECK(done, "never succeeded");
}

int main(void)
{
    T_RUN(t_parse_reals);
    T_RUN(t_parse);
    T_RUN(t_parse_bad);
    T_RUN(t_apply);
    T_RUN(t_apply_problems);
    T_RUN(t_nomem);
    T_EXIT();
}
