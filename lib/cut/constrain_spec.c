/* cut's --constrain specs: a set or a box, to 0 or to given values, at one step. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

/* "SET|box:x0,y0[,z0],x1,y1[,z1]" then "=u,v[,w]" then "@S", the later parts optional */
int aug_constraint_parse(const char *s, aug_constraint *c)
{
    char buf[512];
    double b[6];
    memset(c, 0, sizeof *c);
    c->step = 1;
    if (strlen(s) >= sizeof buf) return -1;
    strcpy(buf, s);
    char *at = strrchr(buf, '@');
    if (at) {
        char *end;
        *at = 0;
        errno = 0;
        c->step = strtol(at + 1, &end, 10);
        if (end == at + 1 || *end || errno || c->step < 1) return -1;
    }
    char *eq = strchr(buf, '=');
    if (eq) {
        *eq = 0;
        c->nv = aug_parse_reals(eq + 1, c->v, 3);
        if (c->nv < 2) return -1;
    }
    if (strncmp(buf, "box:", 4) != 0) {
        if (!buf[0] || strlen(buf) >= AUG_NAME) return -1;
        strcpy(c->set, buf);
        return 0;
    }
    c->nbox = aug_parse_reals(buf + 4, b, 6);
    if (c->nbox != 4 && c->nbox != 6) return -1;
    memcpy(c->lo, b, (size_t)c->nbox / 2 * sizeof *b);
    memcpy(c->hi, b + c->nbox / 2, (size_t)c->nbox / 2 * sizeof *b);
    return 0;
}

/* the constraints of step k into b, after checking each against m's dimension */
int aug_constrain_step(const aug_constraint *c, int n, const aug_mesh *m, long k,
                       aug_bdelta *b, aug_err *e)
{
    aug_err_clear(e);
    for (int i = 0; i < n; i++) {
        const aug_constraint *q = &c[i];
        const double *v = q->nv ? q->v : NULL;
        int rc;
        if (q->step != k) continue;
        if (q->nv && q->nv != m->dim)
            return aug_err_set(e, AUG_EUSAGE, -1, "", "--constrain: %d values for a %d-D mesh",
                               q->nv, m->dim);
        if (q->set[0]) {
            rc = aug_cut_constrain_set(m, q->set, v, b, e);
        } else if (q->nbox != 2 * m->dim) {
            rc = aug_err_set(e, AUG_EUSAGE, -1, "", "--constrain: a box of %d numbers for a %d-D mesh",
                             q->nbox, m->dim);
        } else {
            rc = aug_cut_constrain_box(m, q->lo, q->hi, v, b, e);
        }
        if (rc) return rc;
    }
    return 0;
}
