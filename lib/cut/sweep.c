/* The surface a moving blade sweeps: blade files, the blade's position over
   the motion time, the swept triangles of a time interval. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

void aug_blade_free(aug_blade *b)
{
    free(b->key);
    free(b->nctrl);
    free(b->ctrl);
    memset(b, 0, sizeof *b);
}

/* "blade" or "curve" and six finite numbers: 1 blade, 2 curve, 0 blank or
   comment, -1 not a line of the syntax */
static int parse_line(char *s, double v[6])
{
    char *c = strchr(s, '#');
    if (c) *c = 0;
    while (isspace((unsigned char)*s)) s++;
    if (!*s) return 0;
    int kind = !strncmp(s, "blade", 5) ? 1 : !strncmp(s, "curve", 5) ? 2 : -1;
    if (kind < 0 || !isspace((unsigned char)s[5])) return -1;
    s += 5;
    for (int k = 0; k < 6; k++) {
        char *end;
        v[k] = strtod(s, &end);
        if (end == s || !isfinite(v[k])) return -1;
        s = end;
    }
    while (isspace((unsigned char)*s)) s++;
    return *s ? -1 : kind;
}

/* keys and the control positions between them (man/cut.1, BLADE FILE) */
int aug_blade_parse(FILE *f, const char *name, aug_blade *b, aug_err *e)
{
    aug_err_clear(e);
    memset(b, 0, sizeof *b);
    char line[1024];
    int ln = 0, cap = 0, pend = 0, lastkind = 0;
    double pc[AUG_BLADE_MAXCTRL * 6];
    while (fgets(line, sizeof line, f)) {
        ln++;
        double v[6];
        int kind = parse_line(line, v);
        if (kind == 0) continue;
        if (kind < 0) {
            aug_blade_free(b);
            return aug_err_set(e, AUG_EUSAGE, -1, "", "%s:%d: not 'blade ax ay az bx by bz' "
                               "or 'curve ax ay az bx by bz'", name, ln);
        }
        lastkind = kind;
        if (kind == 2) {
            if (b->nkey == 0 || pend == AUG_BLADE_MAXCTRL) {
                aug_blade_free(b);
                return aug_err_set(e, AUG_EUSAGE, -1, "", "%s:%d: %s", name, ln,
                                   b->nkey ? "more than 8 curve lines between two keys"
                                           : "a curve line before the first blade key");
            }
            memcpy(pc + 6 * pend++, v, sizeof v);
            continue;
        }
        if (b->nkey == cap) {
            cap = cap ? 2 * cap : 16;
            double *k = realloc(b->key, (size_t)cap * 6 * sizeof *k);
            int *n = k ? realloc(b->nctrl, (size_t)cap * sizeof *n) : NULL;
            if (k) b->key = k;
            if (n) b->nctrl = n;
            double *c = n ? realloc(b->ctrl, (size_t)cap * AUG_BLADE_MAXCTRL * 6 * sizeof *c) : NULL;
            if (!c) {
                aug_blade_free(b);
                return aug_err_set(e, AUG_ENOMEM, -1, "", "%s: out of memory", name);
            }
            b->ctrl = c;
        }
        if (b->nkey > 0) {
            b->nctrl[b->nkey - 1] = pend;
            memcpy(b->ctrl + (size_t)(b->nkey - 1) * AUG_BLADE_MAXCTRL * 6, pc, (size_t)pend * 6 * sizeof *pc);
        }
        pend = 0;
        memcpy(b->key + 6 * b->nkey++, v, sizeof v);
    }
    if (ferror(f)) {
        aug_blade_free(b);
        return aug_err_set(e, AUG_EIO, -1, "", "%s: read error", name);
    }
    if (b->nkey < 2 || lastkind != 1) {
        int n = b->nkey;
        aug_blade_free(b);
        return aug_err_set(e, AUG_EUSAGE, -1, "", "%s: %s", name,
                           n < 2 ? "a blade needs two or more 'blade' key lines"
                                 : "the last line is a curve line, not a blade key");
    }
    return 0;
}

/* Key interval i = floor(tau (nkey - 1)) at local time u; its control polygon
   key i, curve lines, key i+1 evaluated in Bernstein form by de Casteljau
   (thesis 003 eq. 3.4). */
void aug_blade_at(const aug_blade *b, double tau, double p[6])
{
    int ni = b->nkey - 1;
    double s = tau * ni;
    int i = (int)floor(s);
    if (i < 0) i = 0;
    if (i > ni - 1) i = ni - 1;
    double u = s - i;
    int nc = b->nctrl[i], deg = nc + 1;
    double q[AUG_BLADE_MAXCTRL + 2][6];
    memcpy(q[0], b->key + 6 * i, sizeof q[0]);
    memcpy(q[1], b->ctrl + (size_t)i * AUG_BLADE_MAXCTRL * 6, (size_t)nc * sizeof q[0]);
    memcpy(q[deg], b->key + 6 * (i + 1), sizeof q[0]);
    for (int r = 1; r <= deg; r++)
        for (int j = 0; j <= deg - r; j++)
            for (int k = 0; k < 6; k++) q[j][k] = (1 - u) * q[j][k] + u * q[j + 1][k];
    memcpy(p, q[0], sizeof q[0]);
}

void aug_soup_free(aug_soup *s)
{
    free(s->t);
    memset(s, 0, sizeof *s);
}

static double dist2(const double *a, const double *b)
{
    double s = 0;
    for (int k = 0; k < 3; k++) s += (a[k] - b[k]) * (a[k] - b[k]);
    return s;
}

int aug_soup_point_ok(const double *p)
{
    for (int k = 0; k < 3; k++)
        if (!(fabs(p[k]) <= AUG_COORD_MAX)) return 0;
    return 1;
}

int aug_soup_add(aug_soup *s, const double *p, const double *q, const double *r)
{
    double u[3], v[3], n[3];
    for (int k = 0; k < 3; k++) u[k] = q[k] - p[k], v[k] = r[k] - p[k];
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double a2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    double l2 = fmax(dist2(p, q), fmax(dist2(q, r), dist2(r, p)));
    if (!(a2 > 1e-24 * l2 * l2)) return 0;
    if (s->n == s->cap) {
        int64_t nc = s->cap ? 2 * s->cap : 256;
        double *t = aug_realloc(s->t, (size_t)nc * 9 * sizeof *t);
        if (!t) return -1;
        s->t = t;
        s->cap = nc;
    }
    double *t = s->t + 9 * s->n++;
    memcpy(t, p, 3 * sizeof *t);
    memcpy(t + 3, q, 3 * sizeof *t);
    memcpy(t + 6, r, 3 * sizeof *t);
    return 1;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* the sample times in [t0, t1]: the ends, the key times, on curved intervals
   j / AUG_BLADE_SUB of the interval; the quads between consecutive ones */
int aug_blade_sweep(const aug_blade *b, double t0, double t1, aug_soup *s)
{
    int ni = b->nkey - 1;
    int64_t cap = 2 + (int64_t)ni * (AUG_BLADE_SUB + 1), n = 0;
    double *tau = aug_malloc((size_t)cap * sizeof *tau);
    if (!tau) return -1;
    tau[n++] = t0;
    tau[n++] = t1;
    for (int i = 0; i < ni; i++) {
        int sub = b->nctrl[i] ? AUG_BLADE_SUB : 1;
        for (int j = 0; j <= sub; j++) {
            /* the same double for the same sample in every call */
            double t = ((double)i + (double)j / sub) / ni;
            if (t > t0 && t < t1) tau[n++] = t;
        }
    }
    qsort(tau, (size_t)n, sizeof *tau, cmp_double);
    double p[6], q[6];
    aug_blade_at(b, tau[0], p);
    for (int64_t i = 1; i < n; i++) {
        if (!(tau[i] > tau[i - 1])) continue;
        aug_blade_at(b, tau[i], q);
        if (aug_soup_add(s, p, p + 3, q + 3) < 0 || aug_soup_add(s, p, q + 3, q) < 0) {
            free(tau);
            return -1;
        }
        memcpy(p, q, sizeof p);
    }
    free(tau);
    return 0;
}

typedef struct keyed_tri {
    double key;
    int64_t i;
} keyed_tri;

static int cmp_keyed_tri(const void *a, const void *b)
{
    const keyed_tri *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return (x->i > y->i) - (x->i < y->i);
}

/* key = (c.dir - min) / (max - min) over the centroids c (every key 1 when
   they all have one c.dir) */
int aug_soup_order(aug_soup *s, const double *dir, double *key, aug_err *e)
{
    aug_err_clear(e);
    keyed_tri *kt = aug_malloc((size_t)s->n * sizeof *kt + 1);
    double *t = aug_malloc((size_t)s->n * 9 * sizeof *t + 1);
    if (!kt || !t) {
        free(kt);
        free(t);
        return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    }
    double d[3] = {0, 0, 0}, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < s->n; i++)
        for (int k = 0; k < 3; k++) {
            double c = (s->t[9 * i + k] + s->t[9 * i + 3 + k] + s->t[9 * i + 6 + k]) / 3;
            lo[k] = fmin(lo[k], c);
            hi[k] = fmax(hi[k], c);
        }
    if (dir) {
        double l = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        for (int k = 0; k < 3; k++) d[k] = dir[k] / l;
    } else {
        int ax = 0;
        for (int k = 1; k < 3; k++)
            if (hi[k] - lo[k] > hi[ax] - lo[ax]) ax = k;
        d[ax] = 1;
    }
    double mn = INFINITY, mx = -INFINITY;
    for (int64_t i = 0; i < s->n; i++) {
        double c = 0;
        for (int k = 0; k < 3; k++) c += d[k] * (s->t[9 * i + k] + s->t[9 * i + 3 + k] + s->t[9 * i + 6 + k]) / 3;
        kt[i].key = c;
        kt[i].i = i;
        mn = fmin(mn, c);
        mx = fmax(mx, c);
    }
    qsort(kt, (size_t)s->n, sizeof *kt, cmp_keyed_tri);
    for (int64_t i = 0; i < s->n; i++) {
        memcpy(t + 9 * i, s->t + 9 * kt[i].i, 9 * sizeof *t);
        key[i] = mx > mn ? (kt[i].key - mn) / (mx - mn) : 1.0;
    }
    free(s->t);
    s->t = t;
    s->cap = s->n;
    free(kt);
    return 0;
}
