/* Scene options as text: meshload's --fix, --material, --default-material and --load parsed. */
#include <stdarg.h>
#include <stdio.h>
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

void aug_scene_spec_init(aug_scene_spec *s)
{
    memset(s, 0, sizeof *s);
}

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

/* two or three comma-separated numbers (the third 0 when absent): 0 or -1 */
static int vec3(const char *s, double *v)
{
    v[2] = 0;
    int n = aug_parse_reals(s, v, 3);
    return n == 2 || n == 3 ? 0 : -1;
}

/* GROUP | box:x0,y0,z0,x1,y1,z1 (lo <= hi) | plane:nx,ny,nz,d[,tol] (n != 0, tol >= 0) */
static void parse_fix(aug_sink *k, const char *s, aug_fix_spec *f)
{
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

/* GROUP:fx,fy[,fz] | point:x,y[,z]:fx,fy[,fz] (the group or point is what
   precedes the last ':') */
static void parse_load(aug_sink *k, const char *s, aug_load_spec *l)
{
    l->arg = s;
    const char *c = strrchr(s, ':');
    if (!c) {
        aug_sink_report(k, "--load %s: want GROUP:fx,fy,fz or point:x,y,z:fx,fy,fz", s);
        return;
    }
    if (vec3(c + 1, l->F)) aug_sink_report(k, "--load %s: the force '%s' is not fx,fy,fz", s, c + 1);
    if (strncmp(s, "point:", 6) == 0 && c > s + 5) {
        char buf[256];
        size_t n = (size_t)(c - (s + 6));
        l->point = 1;
        if (n >= sizeof buf || (memcpy(buf, s + 6, n), buf[n] = 0, vec3(buf, l->p)))
            aug_sink_report(k, "--load %s: the point is not x,y,z", s);
    } else {
        group_name(k, "--load", s, (size_t)(c - s), l->group);
    }
}

/* GROUP:E=..,nu=..,rho=..,t=.. */
static void parse_material(aug_sink *k, const char *s, aug_mat_spec *m)
{
    m->arg = s;
    const char *c = strrchr(s, ':');
    if (!c) {
        aug_sink_report(k, "--material %s: want GROUP:E=..,nu=..,rho=..,t=..", s);
        return;
    }
    group_name(k, "--material", s, (size_t)(c - s), m->group);
    parse_props(k, "--material", s, c + 1, &m->p);
}

/* v resized to n + 1 items of size bytes, the last zeroed; NULL (v kept) when
   memory runs out */
static void *grow(void *v, int n, size_t size)
{
    char *p = aug_realloc(v, ((size_t)n + 1) * size);
    if (p) memset(p + (size_t)n * size, 0, size);
    return p;
}

int aug_scene_spec_add(aug_scene_spec *s, const char *opt, const char *text, aug_sink *k,
                       aug_err *e)
{
    aug_err_clear(e);
    int n0 = k->n;
    if (!strcmp(opt, "--default-material")) {
        s->defarg = text;
        parse_props(k, opt, text, text, &s->def);
    } else if (!strcmp(opt, "--fix")) {
        aug_fix_spec *f = grow(s->fix, s->nfix, sizeof *f);
        if (!f) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        s->fix = f;
        parse_fix(k, text, &f[s->nfix]);
        s->nfix += k->n == n0;
    } else if (!strcmp(opt, "--load")) {
        aug_load_spec *l = grow(s->load, s->nload, sizeof *l);
        if (!l) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        s->load = l;
        parse_load(k, text, &l[s->nload]);
        s->nload += k->n == n0;
    } else if (!strcmp(opt, "--material")) {
        aug_mat_spec *m = grow(s->mat, s->nmat, sizeof *m);
        if (!m) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        s->mat = m;
        parse_material(k, text, &m[s->nmat]);
        s->nmat += k->n == n0;
    } else {
        return aug_err_set(e, AUG_EUSAGE, -1, "", "%s is not a scene option", opt);
    }
    return 0;
}
