/* Scene options as text: meshload's --fix, --material, --default-material, --load and --gravity parsed. */
#include <stdarg.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_scene.h"

/* k->n += 1; the message, however long, to k->report (truncated to 512
   bytes only when memory runs out) */
void aug_sink_report(aug_sink *k, const char *fmt, ...)
{
    char small[512], *msg = small;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (n >= (int)sizeof small && (msg = aug_malloc((size_t)n + 1)) != NULL) {
        va_start(ap, fmt);
        vsnprintf(msg, (size_t)n + 1, fmt, ap);
        va_end(ap);
    } else {
        msg = small;
    }
    k->n++;
    if (k->report) k->report(k->ctx, msg);
    if (msg != small) free(msg);
}

/* s = no option given */
void aug_scene_spec_init(aug_scene_spec *s)
{
    memset(s, 0, sizeof *s);
}

/* the arrays of s freed; s as after init */
void aug_scene_spec_free(aug_scene_spec *s)
{
    free(s->fix);
    free(s->load);
    free(s->mat);
    aug_scene_spec_init(s);
}

static const char *prop_key[AUG_NPROP] = {"E", "nu", "rho", "t"};

/* "E=..,nu=..": each key at most once, E > 0, -1 < nu < 0.5, rho >= 0, t > 0 */
static void parse_props(aug_sink *k, const char *opt, const char *s, const char *text, aug_props *p)
{
    static const char *range[AUG_NPROP] = {"E > 0", "-1 < nu < 0.5", "rho >= 0", "t > 0"};
    char buf[512];
    if (snprintf(buf, sizeof buf, "%s", text) >= (int)sizeof buf) {
        aug_sink_report(k, "%s %s: too long", opt, s);
        return;
    }
    if (!buf[0]) aug_sink_report(k, "%s %s: no properties given (E=..,nu=..,rho=..,t=..)", opt, s);
    for (char *save = NULL, *kv = strtok_r(buf, ",", &save); kv; kv = strtok_r(NULL, ",", &save)) {
        char *eq = strchr(kv, '=');
        int i = -1;
        double v;
        if (eq) {
            *eq = 0;
            for (int j = 0; j < AUG_NPROP; j++)
                if (strcmp(kv, prop_key[j]) == 0) i = j;
        }
        if (i < 0)
            aug_sink_report(k, "%s %s: '%s' is not one of E=, nu=, rho=, t=", opt, s, kv);
        else if (aug_parse_reals(eq + 1, &v, 1) != 1)
            aug_sink_report(k, "%s %s: %s=%s is not a number", opt, s, kv, eq + 1);
        else if ((i == AUG_PROP_E && !(v > 0)) || (i == AUG_PROP_NU && !(v > -1 && v < 0.5)) ||
                 (i == AUG_PROP_RHO && !(v >= 0)) || (i == AUG_PROP_T && !(v > 0)))
            aug_sink_report(k, "%s %s: %s=%s is out of range (%s)", opt, s, kv, eq + 1, range[i]);
        else if (p->has[i])
            aug_sink_report(k, "%s %s: %s given twice", opt, s, kv);
        else
            p->has[i] = 1, p->v[i] = v;
    }
}

/* dst = the first len bytes of s: a group name (not empty, < AUG_NAME bytes) */
static void group_name(aug_sink *k, const char *opt, const char *s, size_t len, char *dst)
{
    if (len == 0) {
        aug_sink_report(k, "%s %s: empty group name", opt, s);
    } else if (len >= AUG_NAME) {
        aug_sink_report(k, "%s %s: group name longer than %d bytes", opt, s, AUG_NAME - 1);
    } else {
        memcpy(dst, s, len);
        dst[len] = 0;
    }
}

/* two or three comma-separated numbers into v (v[2] = 0 when two): their
   count, or -1 */
static int vec3(const char *s, double *v)
{
    v[2] = 0;
    int n = aug_parse_reals(s, v, 3);
    return n == 2 || n == 3 ? n : -1;
}

/* GROUP | box:x0,y0,z0,x1,y1,z1 (lo <= hi) | plane:nx,ny,nz,d[,tol] (n != 0, tol >= 0) */
static void parse_fix(aug_sink *k, const char *s, aug_fix_spec *f)
{
    memset(f, 0, sizeof *f);
    f->arg = s;
    if (strncmp(s, "box:", 4) == 0) {
        f->kind = AUG_FIX_BOX;
        if (aug_parse_reals(s + 4, f->v, 6) != 6)
            aug_sink_report(k, "--fix %s: want box:x0,y0,z0,x1,y1,z1", s);
        else if (f->v[0] > f->v[3] || f->v[1] > f->v[4] || f->v[2] > f->v[5])
            aug_sink_report(k, "--fix %s: the box's low corner exceeds its high corner", s);
    } else if (strncmp(s, "plane:", 6) == 0) {
        f->kind = AUG_FIX_PLANE;
        int n = aug_parse_reals(s + 6, f->v, 5);
        f->ntol = n == 5;
        if (n != 4 && n != 5)
            aug_sink_report(k, "--fix %s: want plane:nx,ny,nz,d[,tol]", s);
        else if (f->v[0] == 0 && f->v[1] == 0 && f->v[2] == 0)
            aug_sink_report(k, "--fix %s: the normal is zero", s);
        else if (f->ntol && !(f->v[4] >= 0))
            aug_sink_report(k, "--fix %s: the tolerance is negative", s);
    } else {
        f->kind = AUG_FIX_GROUP;
        group_name(k, "--fix", s, strlen(s), f->group);
    }
}

/* the last ':' of s, or NULL with the problem "OPT S: want WANT" */
static const char *last_colon(aug_sink *k, const char *opt, const char *s, const char *want)
{
    const char *c = strrchr(s, ':');
    if (!c) aug_sink_report(k, "%s %s: want %s", opt, s, want);
    return c;
}

/* GROUP:fx,fy[,fz] | point:x,y[,z]:fx,fy[,fz] (the group or point is what
   precedes the last ':') */
static void parse_load(aug_sink *k, const char *s, aug_load_spec *l)
{
    memset(l, 0, sizeof *l);
    l->arg = s;
    const char *c = last_colon(k, "--load", s, "GROUP:fx,fy,fz or point:x,y,z:fx,fy,fz");
    if (!c) return;
    if ((l->nF = vec3(c + 1, l->F)) < 0) aug_sink_report(k, "--load %s: the force '%s' is not fx,fy,fz", s, c + 1);
    if (strncmp(s, "point:", 6) == 0 && c > s + 5) {
        char buf[256];
        size_t n = (size_t)(c - (s + 6));
        l->point = 1;
        if (n >= sizeof buf || (memcpy(buf, s + 6, n), buf[n] = 0, (l->np = vec3(buf, l->p)) < 0))
            aug_sink_report(k, "--load %s: the point is not x,y,z", s);
    } else {
        group_name(k, "--load", s, (size_t)(c - s), l->group);
    }
}

/* GROUP:E=..,nu=..,rho=..,t=.. */
static void parse_material(aug_sink *k, const char *s, aug_mat_spec *m)
{
    memset(m, 0, sizeof *m);
    m->arg = s;
    const char *c = last_colon(k, "--material", s, "GROUP:E=..,nu=..,rho=..,t=..");
    if (!c) return;
    group_name(k, "--material", s, (size_t)(c - s), m->group);
    parse_props(k, "--material", s, c + 1, &m->p);
}

/* room for one more item of each kind: 0, or -1 (memory; s keeps what it had) */
static int reserve(aug_scene_spec *s)
{
    if (s->nfix < s->cap && s->nload < s->cap && s->nmat < s->cap) return 0;
    int cap = 2 * s->cap + 4;
    aug_fix_spec *f = aug_realloc(s->fix, (size_t)cap * sizeof *f);
    if (f) s->fix = f;
    aug_load_spec *l = f ? aug_realloc(s->load, (size_t)cap * sizeof *l) : NULL;
    if (l) s->load = l;
    aug_mat_spec *m = l ? aug_realloc(s->mat, (size_t)cap * sizeof *m) : NULL;
    if (m) s->mat = m, s->cap = cap;
    return m ? 0 : -1;
}

/* s += text of opt, kept only when it met no problem (--default-material:
   its well-formed keys) */
int aug_scene_spec_add(aug_scene_spec *s, const char *opt, const char *text, aug_sink *k,
                       aug_err *e)
{
    aug_err_clear(e);
    int n0 = k->n;
    if (!strcmp(opt, "--default-material")) {
        s->defarg = text;
        parse_props(k, opt, text, text, &s->def);
        return 0;
    }
    if (!strcmp(opt, "--gravity")) {
        s->garg = text;
        int n = vec3(text, s->g);
        if (n < 0) aug_sink_report(k, "--gravity %s: want gx,gy,gz (finite numbers)", text);
        else if (!(fabs(s->g[0]) <= 1e12 && fabs(s->g[1]) <= 1e12 && fabs(s->g[2]) <= 1e12))
            aug_sink_report(k, "--gravity %s: a component above 1e12 (GRAV's bound, formats/stream.md 5.8)", text);
        else s->gravity = n;
        return 0;
    }
    if (strcmp(opt, "--fix") && strcmp(opt, "--load") && strcmp(opt, "--material"))
        return aug_err_set(e, AUG_EUSAGE, -1, "", "%s is not a scene option", opt);
    if (reserve(s)) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    if (!strcmp(opt, "--fix")) {
        parse_fix(k, text, &s->fix[s->nfix]);
        s->nfix += k->n == n0;
    } else if (!strcmp(opt, "--load")) {
        parse_load(k, text, &s->load[s->nload]);
        s->nload += k->n == n0;
    } else {
        parse_material(k, text, &s->mat[s->nmat]);
        s->nmat += k->n == n0;
    }
    return 0;
}
