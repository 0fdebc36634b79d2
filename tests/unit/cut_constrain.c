/* Unit tests of cut's --constrain and --drag specs (lib/cut/constrain_spec.c). */
#include <math.h>
#include <string.h>
#include "aug_cut.h"
#include "fem_mesh.h"
#include "t.h"

static void t_parse(void)
{
    aug_constraint c;
    T_CHECK(aug_constraint_parse("top", &c) == 0 && !strcmp(c.set, "top") && c.nv == 0 && c.step == 1 &&
                c.nbox == 0,
            "set");
    T_CHECK(aug_constraint_parse("a=1,2@7", &c) == 0 && !strcmp(c.set, "a") && c.nv == 2 && c.step == 7,
            "values and step");
    T_CHECK(aug_constraint_parse("s@x@3", &c) == 0 && !strcmp(c.set, "s@x") && c.step == 3, "last '@'");
    T_CHECK(aug_constraint_parse("s=0.5,-1", &c) == 0 && c.nv == 2 && c.v[0] == 0.5 && c.v[1] == -1, "2 values");
    T_CHECK(aug_constraint_parse("box:0,0.1,1,1.1@3", &c) == 0 && !c.set[0] && c.nbox == 4 && c.lo[1] == 0.1 &&
                c.hi[0] == 1 && c.hi[1] == 1.1 && c.step == 3,
            "2-D box");
    T_CHECK(aug_constraint_parse("box:0,0,0,1,2,3=0.1,0,0@2", &c) == 0 && c.nbox == 6 && c.lo[2] == 0 &&
                c.hi[1] == 2 && c.hi[2] == 3 && c.nv == 3 && c.v[0] == 0.1 && c.step == 2,
            "3-D box with values");
    char big[600];
    memset(big, 'x', sizeof big - 1);
    big[sizeof big - 1] = 0;
    const char *bad[] = {"", "@2", "top@", "top@0", "top@-1", "top@2x", "top=", "top=1", "top=1,2,3,4",
                         "top=1,x", "a=b=1,2", "box:1,2,3", "box:1,2,3,4,5", "box:", "box:1,2,3,4=1",
                         "g234567890123456789012345678901234567890123456789012345678901234", big};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++)
        T_CHECK(aug_constraint_parse(bad[i], &c) == -1, "'%.40s' accepted", bad[i]);
}

/* BDLT entries of b: dof -> value, unordered */
static double fixed_value(const aug_bdelta *b, int32_t dof, int *found)
{
    for (int64_t i = 0; i < b->nfix; i++)
        if (b->fix_dof[i] == dof) return *found = 1, b->fix_val[i];
    return *found = 0, 0.0;
}

static void t_step(void)
{
    aug_mesh m;
    tm_rect(&m, 2, 2, 2, 2, 1, 0.3, 1); /* node (i,j) = i + 3 j at (i, j) */
    m.nset = 1;
    m.sets = calloc(1, sizeof *m.sets);
    strcpy(m.sets[0].name, "left");
    m.sets[0].n = 3;
    m.sets[0].nodes = malloc(3 * sizeof(int32_t));
    for (int i = 0; i < 3; i++) m.sets[0].nodes[i] = 3 * i;
    aug_constraint c[3];
    aug_constraint_parse("left=0.1,0.2", &c[0]);
    aug_constraint_parse("box:-1,-1,3,0.5@2", &c[1]);
    aug_constraint_parse("left@2", &c[2]);
    aug_err e;
    aug_bdelta b;
    aug_bdelta_init(&b);
    T_CHECK(aug_constrain_step(c, 3, &m, 1, 3, &b, &e) == 0, "step 1: %s", e.msg);
    T_CHECK(b.nfix == 6, "step 1: %lld constraints", (long long)b.nfix);
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 2; k++) {
            int found;
            double v = fixed_value(&b, 6 * i + k, &found);
            T_CHECK(found && v == (k ? 0.2 : 0.1), "node %d component %d: %g", 3 * i, k, v);
        }
    aug_bdelta_free(&b);
    aug_bdelta_init(&b);
    T_CHECK(aug_constrain_step(c, 3, &m, 2, 3, &b, &e) == 0, "step 2: %s", e.msg);
    aug_bdelta_finish(&b);
    /* the box: y = 0 (nodes 0, 1, 2); left: nodes 0, 3, 6; all to 0 */
    static const int32_t want[] = {0, 1, 2, 3, 4, 5, 6, 7, 12, 13};
    T_CHECK(b.nfix == 10, "step 2: %lld constraints", (long long)b.nfix);
    for (int64_t i = 0; i < b.nfix && b.nfix == 10; i++)
        T_CHECK(b.fix_dof[i] == want[i] && b.fix_val[i] == 0, "step 2: dof %d", b.fix_dof[i]);
    aug_bdelta_free(&b);
    aug_bdelta_init(&b);
    T_CHECK(aug_constrain_step(c, 3, &m, 3, 3, &b, &e) == 0 && b.nfix == 0, "step 3: none");
    aug_bdelta_free(&b);
    aug_mesh_free(&m);
}

static void t_drag_parse(void)
{
    aug_constraint c;
    T_CHECK(aug_drag_parse("tip:0,1e-3,0", &c) == 0 && c.drag && !strcmp(c.set, "tip") && c.nv == 3 &&
                c.v[1] == 1e-3 && c.nbox == 0,
            "set");
    T_CHECK(aug_drag_parse("a:b:1,2", &c) == 0 && !strcmp(c.set, "a:b") && c.nv == 2 && c.v[0] == 1, "last ':'");
    T_CHECK(aug_drag_parse("box:0,0,1,1:0.5,-1", &c) == 0 && !c.set[0] && c.nbox == 4 && c.hi[1] == 1 &&
                c.nv == 2 && c.v[1] == -1,
            "2-D box");
    T_CHECK(aug_drag_parse("box:0,0,0,1,1,2:0,0,0.1", &c) == 0 && c.nbox == 6 && c.hi[2] == 2 && c.v[2] == 0.1,
            "3-D box");
    const char *bad[] = {"", "tip", "tip:", ":1,2", "tip:1", "tip:1,2,3,4", "tip:nan,0", "tip:1,inf",
                         "tip:1,x", "box:1,2,3:1,2", "box:1,2,3,4,5:1,2", "box:0,0,1,1", "box:0,0,0,1,1,1"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++)
        T_CHECK(aug_drag_parse(bad[i], &c) == -1, "'%s' accepted", bad[i]);
}

/* --drag: (k / N) d at every step k, after a --constrain of the same step on the same nodes */
static void t_drag_step(void)
{
    aug_mesh m;
    tm_rect(&m, 2, 2, 2, 2, 1, 0.3, 1); /* node (i,j) = i + 3 j at (i, j) */
    aug_constraint c[2];
    aug_constraint_parse("box:1.5,-1,3,3=7,7@2", &c[0]);
    aug_drag_parse("box:1.5,-1,3,3:0.3,-0.6", &c[1]);
    aug_err e;
    for (long k = 1; k <= 3; k++) {
        aug_bdelta b;
        aug_bdelta_init(&b);
        T_CHECK(aug_constrain_step(c, 2, &m, k, 3, &b, &e) == 0, "step %ld: %s", k, e.msg);
        aug_bdelta_finish(&b);
        T_CHECK(b.nfix == 6, "step %ld: %lld constraints", k, (long long)b.nfix);
        for (int64_t i = 0; i < b.nfix && b.nfix == 6; i++) {
            int node = b.fix_dof[i] / 2, comp = b.fix_dof[i] % 2;
            double want = ((double)k / 3.0) * (comp ? -0.6 : 0.3);
            T_CHECK(node % 3 == 2 && b.fix_val[i] == want, "step %ld: dof %d = %.17g, want %.17g", k,
                    b.fix_dof[i], b.fix_val[i], want);
        }
        aug_bdelta_free(&b);
    }
    aug_mesh_free(&m);
}

/* specs that do not fit the mesh: aug_constrain_step's code and message */
static void t_misfits(void)
{
    static const struct {
        int drag;
        const char *spec;
        int code;
        const char *msg;
    } w[] = {
        {0, "left=1,2,3", AUG_EUSAGE, "--constrain: 3 values for a 2-D mesh"},
        {0, "box:0,0,0,1,1,1", AUG_EUSAGE, "--constrain: a box of 6 numbers for a 2-D mesh"},
        {0, "nosuch", AUG_EDATA, "--constrain: no node set named 'nosuch'"},
        {0, "box:5,5,6,6", AUG_EDATA, "--constrain: the constraint box holds no node"},
        {1, "box:1.5,-1,3,3:1,2,3", AUG_EUSAGE, "--drag: 3 values for a 2-D mesh"},
        {1, "box:0,0,0,1,1,1:1,2", AUG_EUSAGE, "--drag: a box of 6 numbers for a 2-D mesh"},
        {1, "grip:1,2", AUG_EDATA, "--drag: no node set named 'grip'"},
        {1, "box:5,5,6,6:1,2", AUG_EDATA, "--drag: the constraint box holds no node"},
    };
    aug_mesh m;
    tm_rect(&m, 2, 2, 2, 2, 1, 0.3, 1);
    for (size_t i = 0; i < sizeof w / sizeof *w; i++) {
        aug_constraint c;
        aug_err e;
        aug_bdelta b;
        aug_bdelta_init(&b);
        int prc = w[i].drag ? aug_drag_parse(w[i].spec, &c) : aug_constraint_parse(w[i].spec, &c);
        int rc = aug_constrain_step(&c, 1, &m, 1, 3, &b, &e);
        T_CHECK(prc == 0 && rc == w[i].code && !strcmp(e.msg, w[i].msg), "%s: %d (%s)", w[i].spec, rc, e.msg);
        aug_bdelta_free(&b);
    }
    aug_mesh_free(&m);
}

int main(void)
{
    T_RUN(t_parse);
    T_RUN(t_step);
    T_RUN(t_drag_parse);
    T_RUN(t_drag_step);
    T_RUN(t_misfits);
    T_EXIT();
}
