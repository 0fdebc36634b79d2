/* cut's --constrain and --drag specs: a set or a box, to 0 or to given values at
   one step, or pulled along a vector over the steps. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

/* s = "SET" or "box:x0,y0[,z0],x1,y1[,z1]" into c's set or box: 0 or -1 */
static int target(const char *s, aug_constraint *c)
{
    double b[6];
    if (strncmp(s, "box:", 4) != 0) {
        if (!s[0] || strlen(s) >= AUG_NAME) return -1;
        strcpy(c->set, s);
        return 0;
    }
    c->nbox = aug_parse_reals(s + 4, b, 6);
    if (c->nbox != 4 && c->nbox != 6) return -1;
    memcpy(c->lo, b, (size_t)c->nbox / 2 * sizeof *b);
    memcpy(c->hi, b + c->nbox / 2, (size_t)c->nbox / 2 * sizeof *b);
    return 0;
}

/* c = nothing parsed yet, buf = a copy of s: 0, or -1 when s does not fit */
static int start(const char *s, char buf[512], aug_constraint *c)
{
    memset(c, 0, sizeof *c);
    if (strlen(s) >= 512) return -1;
    strcpy(buf, s);
    return 0;
}

/* c's values = the 2 or 3 numbers after sep, which ends the text before,
   each at most 1e30 in magnitude (a displacement is a length, as a
   coordinate, formats/stream.md 5.1, 7.7; --drag 1e200 was taken and every
   solver then called K_t singular, its norms overflowing): 0 or -1 */
static int values(char *sep, aug_constraint *c)
{
    *sep = 0;
    c->nv = aug_parse_reals(sep + 1, c->v, 3);
    for (int i = 0; i < c->nv && i < 3; i++)
        if (!(fabs(c->v[i]) <= 1e30)) return -1;
    return c->nv < 2 ? -1 : 0;
}

/* "SET|box:x0,y0[,z0],x1,y1[,z1]" then "=u,v[,w]" then "@S", the later parts optional */
int aug_constraint_parse(const char *s, aug_constraint *c)
{
    char buf[512];
    if (start(s, buf, c)) return -1;
    c->step = 1;
    char *at = strrchr(buf, '@');
    if (at) {
        char *end;
        *at = 0;
        errno = 0;
        c->step = strtol(at + 1, &end, 10);
        if (end == at + 1 || *end || errno || c->step < 1) return -1;
    }
    char *eq = strchr(buf, '=');
    if (eq && values(eq, c)) return -1;
    return target(buf, c);
}

/* "SET|box:x0,y0[,z0],x1,y1[,z1]:dx,dy[,dz]" (the target is what precedes the last ':') */
int aug_drag_parse(const char *s, aug_constraint *c)
{
    char buf[512];
    if (start(s, buf, c)) return -1;
    c->drag = 1;
    char *colon = strrchr(buf, ':');
    if (!colon || values(colon, c)) return -1;
    return target(buf, c);
}

/* tmp += the constraints of step k of nsteps, in order, after checking each
   against m's dimension: a --constrain of step k with its values, every
   --drag with (k / nsteps) d */
static int collect(const aug_constraint *c, int n, const aug_mesh *m, long k, long nsteps,
                   aug_bdelta *tmp, aug_err *e)
{
    for (int i = 0; i < n; i++) {
        const aug_constraint *q = &c[i];
        const char *opt = q->drag ? "--drag" : "--constrain";
        double d[3];
        const double *v = q->nv ? q->v : NULL;
        int rc;
        if (!q->drag && q->step != k) continue;
        if (q->nv && q->nv != m->dim)
            return aug_err_set(e, AUG_EUSAGE, -1, "", "%s: %d values for a %d-D mesh", opt, q->nv,
                               m->dim);
        if (q->drag) {
            for (int j = 0; j < m->dim; j++) d[j] = ((double)k / (double)nsteps) * q->v[j];
            v = d;
        }
        if (q->set[0]) {
            rc = aug_cut_constrain_set(m, q->set, v, tmp, e);
        } else if (q->nbox != 2 * m->dim) {
            rc = aug_err_set(e, AUG_EUSAGE, -1, "", "%s: a box of %d numbers for a %d-D mesh", opt,
                             q->nbox, m->dim);
        } else {
            rc = aug_cut_constrain_box(m, q->lo, q->hi, v, tmp, e);
        }
        if (rc == AUG_EDATA) { /* the set or box does not fit the mesh: name the option */
            char msg[sizeof e->msg];
            snprintf(msg, sizeof msg, "%s", e->msg);
            return aug_err_set(e, rc, -1, "", "%s: %s", opt, msg);
        }
        if (rc) return rc;
    }
    return 0;
}

/* b += the step's constraints composed (the last one of a DOF wins), less
   those m has already */
int aug_constrain_step(const aug_constraint *c, int n, const aug_mesh *m, long k, long nsteps,
                       aug_bdelta *b, aug_err *e)
{
    aug_err_clear(e);
    aug_bdelta tmp;
    aug_bdelta_init(&tmp);
    int rc = collect(c, n, m, k, nsteps, &tmp, e);
    if (!rc && aug_bdelta_finish(&tmp)) rc = AUG_ENOMEM;
    for (int64_t i = 0; !rc && i < tmp.nfix; i++) {
        double old;
        if (aug_mesh_fixed(m, tmp.fix_dof[i], &old) && old == tmp.fix_val[i]) continue;
        if (aug_bdelta_fix(b, tmp.fix_dof[i], tmp.fix_val[i])) rc = AUG_ENOMEM;
    }
    aug_bdelta_free(&tmp);
    if (rc == AUG_ENOMEM) return aug_err_set(e, rc, -1, "BDLT", "out of memory");
    return rc;
}
