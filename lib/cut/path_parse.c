/* The path file (man/cut.1, PATH FILE): lines, polylines, Bezier and rational
   Bezier curves of any degree, arcs, circles; strokes; arc-length parametrisation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

void aug_path_free(aug_path *p)
{
    for (int i = 0; i < p->n; i++)
        if (p->c[i].kind == AUG_CURVE_BEZIER) free(p->c[i].h);
    free(p->c);
    free(p->s0);
    free(p->tab);
    memset(p, 0, sizeof *p);
}

static int add_curve(aug_path *p, int *cap, const aug_curve *c)
{
    if (p->n == *cap) {
        int nc = *cap ? 2 * *cap : 16;
        aug_curve *q = aug_realloc(p->c, (size_t)nc * sizeof *q);
        if (!q) return -1;
        p->c = q;
        *cap = nc;
    }
    p->c[p->n++] = *c;
    return 0;
}

/* up to max numbers from s; their count, -1 on a malformed or non-finite one */
static int numbers(char *s, double *v, int max)
{
    int n = 0;
    char *tok, *save = NULL;
    for (tok = strtok_r(s, " \t\r\n,", &save); tok; tok = strtok_r(NULL, " \t\r\n,", &save)) {
        if (tok[0] == '#') break;
        char *end;
        double x = strtod(tok, &end);
        if (*end || !isfinite(x) || n == max) return -1;
        v[n++] = x;
    }
    return n;
}

/* the end point of curve c */
static void last_point(const aug_curve *c, double q[2])
{
    if (c->kind == AUG_CURVE_BEZIER) {
        const double *h = c->h + 3 * c->deg;
        q[0] = h[0] / h[2];
        q[1] = h[1] / h[2];
        return;
    }
    const double *e = c->kind == AUG_CURVE_LINE ? c->p[1] : (c->kind == AUG_CURVE_CUBIC ? c->p[3] : c->p[2]);
    q[0] = e[0];
    q[1] = e[1];
}

static int degenerate(const aug_curve *c)
{
    if (c->kind == AUG_CURVE_BEZIER) {
        const double *h = c->h;
        for (int i = 1; i <= c->deg; i++)
            if (h[3 * i] / h[3 * i + 2] != h[0] / h[2] || h[3 * i + 1] / h[3 * i + 2] != h[1] / h[2]) return 0;
        return 1;
    }
    int np = c->kind == AUG_CURVE_LINE ? 2 : (c->kind == AUG_CURVE_CUBIC ? 4 : 3);
    for (int i = 1; i < np; i++)
        if (c->p[i][0] != c->p[0][0] || c->p[i][1] != c->p[0][1]) return 0;
    return 1;
}

/* a general Bezier curve of degree n from n+1 points (stride 2, weights 1) or
   n+1 (x, y, w) triples (stride 3): homogeneous points (w x, w y, w) */
static int general(aug_curve *c, const double *v, int n, int stride)
{
    c->kind = AUG_CURVE_BEZIER;
    c->deg = n;
    c->h = aug_malloc((size_t)(n + 1) * 3 * sizeof *c->h);
    if (!c->h) return -1;
    for (int i = 0; i <= n; i++) {
        double w = stride == 3 ? v[3 * i + 2] : 1;
        c->h[3 * i] = w * v[stride * i];
        c->h[3 * i + 1] = w * v[stride * i + 1];
        c->h[3 * i + 2] = w;
    }
    return 0;
}

#define MAXNUM 4096

int aug_path_parse(FILE *f, const char *name, aug_path *p, aug_err *e)
{
    aug_err_clear(e);
    memset(p, 0, sizeof *p);
    char line[65536];
    double *v = aug_malloc(MAXNUM * sizeof *v);
    int cap = 0, lineno = 0;
    if (!v) goto nomem;
#define FAIL(...)                                                                           \
    do {                                                                                    \
        char msg_[200];                                                                     \
        snprintf(msg_, sizeof msg_, __VA_ARGS__);                                           \
        aug_err_set(e, AUG_EDATA, -1, "", "%s:%d: %s", name, lineno, msg_);                 \
        goto fail;                                                                          \
    } while (0)
    while (fgets(line, sizeof line, f)) {
        lineno++;
        if (!strchr(line, '\n') && !feof(f)) FAIL("line too long");
        char *s = line;
        while (*s == ' ' || *s == '\t') s++;
        if (*s == '#' || *s == '\n' || *s == '\r' || *s == 0) continue;
        char kw[16];
        int kl = 0;
        while (s[kl] && s[kl] != ' ' && s[kl] != '\t' && s[kl] != '\n' && s[kl] != '\r' && kl < 15) {
            kw[kl] = s[kl];
            kl++;
        }
        kw[kl] = 0;
        int nv = numbers(s + kl, v, MAXNUM);
        if (nv < 0) FAIL("malformed or non-finite number (at most %d numbers)", MAXNUM);
        aug_curve c;
        memset(&c, 0, sizeof c);
        c.line = lineno;
        int start = p->n;
        if (strcmp(kw, "line") == 0) {
            if (nv != 4) FAIL("'line' takes 4 numbers: x0 y0 x1 y1");
            c.kind = AUG_CURVE_LINE;
            memcpy(c.p, v, 4 * sizeof *v);
            if (degenerate(&c)) FAIL("the line has zero length");
            if (add_curve(p, &cap, &c)) goto nomem;
        } else if (strcmp(kw, "polyline") == 0) {
            if (nv < 4 || nv % 2) FAIL("'polyline' takes an even number (>= 4) of coordinates");
            for (int i = 0; i + 3 < nv; i += 2) {
                c.kind = AUG_CURVE_LINE;
                memcpy(c.p, v + i, 4 * sizeof *v);
                if (degenerate(&c)) FAIL("polyline segment %d has zero length", i / 2 + 1);
                if (add_curve(p, &cap, &c)) goto nomem;
            }
        } else if (strcmp(kw, "bezier") == 0 && nv == 8) {
            c.kind = AUG_CURVE_CUBIC;
            memcpy(c.p, v, 8 * sizeof *v);
            if (degenerate(&c)) FAIL("the curve is a point");
            if (add_curve(p, &cap, &c)) goto nomem;
        } else if (strcmp(kw, "bezier") == 0 || strcmp(kw, "rbezier") == 0) {
            int st = kw[0] == 'r' ? 3 : 2, n = nv / st - 1;
            if (nv % st || n < 1 || n > AUG_CURVE_MAXDEG)
                FAIL("'%s' takes %s of n+1 control points, degree 1 <= n <= %d", kw,
                     st == 3 ? "x y w triples" : "x y pairs", AUG_CURVE_MAXDEG);
            double wlo = INFINITY, whi = 0;
            for (int i = 0; st == 3 && i <= n; i++) {
                if (!(v[3 * i + 2] > 0)) FAIL("weight %d of the rbezier is not positive", i);
                wlo = fmin(wlo, v[3 * i + 2]), whi = fmax(whi, v[3 * i + 2]);
            }
            if (st == 3 && !(whi <= AUG_PATH_WRATIO * wlo))
                FAIL("the rbezier's weights span %g to %g, more than a factor 1e4: the curve turns "
                     "within a sliver of its parameter, finer than the path is walked (a corner: polyline)", wlo, whi);
            if (general(&c, v, n, st)) goto nomem;
            if (degenerate(&c)) {
                free(c.h);
                FAIL("the curve is a point");
            }
            if (add_curve(p, &cap, &c)) {
                free(c.h);
                goto nomem;
            }
        } else if (strcmp(kw, "arc") == 0) {
            if (nv != 7) FAIL("'arc' takes 7 numbers: x0 y0 x1 y1 x2 y2 w");
            if (!(v[6] > 0)) FAIL("the arc weight must be positive");
            if (!(v[6] >= 1 / AUG_PATH_WRATIO && v[6] <= AUG_PATH_WRATIO))
                FAIL("the arc weight %g is outside 1e-4..1e4: the curve turns within a sliver of its "
                     "parameter, finer than the path is walked (a corner: polyline)", v[6]);
            c.kind = AUG_CURVE_RQUAD;
            memcpy(c.p, v, 6 * sizeof *v);
            c.w = v[6];
            if (degenerate(&c)) FAIL("the arc is a point");
            if (add_curve(p, &cap, &c)) goto nomem;
        } else if (strcmp(kw, "circle") == 0) {
            if (nv != 3) FAIL("'circle' takes 3 numbers: cx cy r");
            if (!(v[2] > 0)) FAIL("the radius must be positive");
            /* four quarter arcs (thesis fig. 3.1), counter-clockwise; the circular weight
               is w = cos(theta/2) with theta = 90 deg the sweep of each */
            double cx = v[0], cy = v[1], r = v[2];
            double pts[9][2] = {{cx + r, cy}, {cx + r, cy + r}, {cx, cy + r}, {cx - r, cy + r},
                                {cx - r, cy}, {cx - r, cy - r}, {cx, cy - r}, {cx + r, cy - r},
                                {cx + r, cy}};
            for (int q = 0; q < 4; q++) {
                c.kind = AUG_CURVE_RQUAD;
                memcpy(c.p, pts + 2 * q, 6 * sizeof(double));
                c.w = sqrt(0.5);
                if (add_curve(p, &cap, &c)) goto nomem;
            }
        } else {
            FAIL("unknown keyword '%s' (line, polyline, bezier, rbezier, arc, circle)", kw);
        }
        /* a curve continues the stroke when it starts where the previous one ends */
        for (int i = start; i < p->n; i++) {
            aug_curve *ci = &p->c[i];
            if (i == 0) {
                ci->newstroke = 1;
                continue;
            }
            double q[2];
            last_point(&p->c[i - 1], q);
            double tol = 1e-9 * fmax(1.0, fmax(fabs(q[0]), fabs(q[1])));
            double f[2] = {ci->p[0][0], ci->p[0][1]};
            if (ci->kind == AUG_CURVE_BEZIER) aug_curve_eval(ci, 0, f);
            ci->newstroke = !(fabs(q[0] - f[0]) <= tol && fabs(q[1] - f[1]) <= tol);
        }
    }
    if (ferror(f)) FAIL("read error");
    if (p->n == 0) {
        lineno = 0;
        FAIL("the path has no curves");
    }
    p->s0 = aug_malloc((size_t)(p->n + 1) * sizeof *p->s0);
    p->tab = aug_malloc((size_t)p->n * (AUG_PATH_NS + 1) * sizeof *p->tab);
    if (!p->s0 || !p->tab) goto nomem;
    double s = 0;
    for (int i = 0; i < p->n; i++) {
        double *tb = p->tab + (size_t)i * (AUG_PATH_NS + 1), a[2], b[2];
        p->s0[i] = s;
        tb[0] = 0;
        aug_curve_eval(&p->c[i], 0, a);
        for (int k = 1; k <= AUG_PATH_NS; k++) {
            aug_curve_eval(&p->c[i], (double)k / AUG_PATH_NS, b);
            tb[k] = tb[k - 1] + hypot(b[0] - a[0], b[1] - a[1]);
            a[0] = b[0];
            a[1] = b[1];
        }
        s += tb[AUG_PATH_NS];
    }
    p->s0[p->n] = s;
    p->total = s;
    free(v);
    return 0;
#undef FAIL
nomem:
    aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory reading %s", name);
fail:
    free(v);
    aug_path_free(p);
    return e->code;
}

/* t(s) on curve i: the inverse of its arc-length table (AUG_PATH_NS + 1 chord
   sums), linear between entries; 0 below, 1 beyond its length */
double aug_path_param(const aug_path *p, int i, double s)
{
    const double *tb = p->tab + (size_t)i * (AUG_PATH_NS + 1);
    if (s <= 0) return 0;
    if (s >= tb[AUG_PATH_NS]) return 1;
    int lo = 0, hi = AUG_PATH_NS;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (tb[mid] <= s) lo = mid;
        else hi = mid;
    }
    double d = tb[hi] - tb[lo];
    return (lo + (d > 0 ? (s - tb[lo]) / d : 0)) / AUG_PATH_NS;
}
