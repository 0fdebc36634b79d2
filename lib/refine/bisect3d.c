/* Conformal edge bisection of tetrahedra below the quality bound: an edge of a bad
   tet (longest first) is split at its midpoint together with every tet around
   it, so no node hangs, when that improves the worst tet around the edge
   (unguarded longest-edge bisection, Rivara & Levin 1992, made cut slivers
   worse in our tests); a bounded number of levels. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_refine.h"

#define X(w, i) ((w)->m.x + 3 * (size_t)(i))
#define C(w, t) ((w)->m.conn + 4 * (size_t)(t))

static double len2(const aug_work *w, int32_t a, int32_t b)
{
    const double *p = X(w, a), *q = X(w, b);
    double s = 0;
    for (int c = 0; c < 3; c++) s += (q[c] - p[c]) * (q[c] - p[c]);
    return s;
}

/* R / (3 r) of the tet (p0, p1, p2, p3) (as aug_elem_quality); +inf if not positive */
static double tet_aspect(const double *p0, const double *p1, const double *p2, const double *p3)
{
    double a[3], b[3], c[3], t[3], num[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) a[k] = p1[k] - p0[k], b[k] = p2[k] - p0[k], c[k] = p3[k] - p0[k];
#define CROSS(u, v, r) (r[0] = u[1] * v[2] - u[2] * v[1], r[1] = u[2] * v[0] - u[0] * v[2], r[2] = u[0] * v[1] - u[1] * v[0])
#define DOT(u, v) (u[0] * v[0] + u[1] * v[1] + u[2] * v[2])
    CROSS(a, b, t);
    double V6 = DOT(t, c);
    if (!(V6 > 0)) return INFINITY;
    for (int k = 0; k < 3; k++) num[k] += DOT(c, c) * t[k];
    CROSS(b, c, t);
    for (int k = 0; k < 3; k++) num[k] += DOT(a, a) * t[k];
    CROSS(c, a, t);
    for (int k = 0; k < 3; k++) num[k] += DOT(b, b) * t[k];
    double R = sqrt(DOT(num, num)) / (2 * V6);
    const double *P[4] = {p0, p1, p2, p3};
    static const int F[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
    double area = 0;
    for (int f = 0; f < 4; f++) {
        double u[3], v[3], n[3];
        for (int k = 0; k < 3; k++) u[k] = P[F[f][1]][k] - P[F[f][0]][k], v[k] = P[F[f][2]][k] - P[F[f][0]][k];
        CROSS(u, v, n);
        area += 0.5 * sqrt(DOT(n, n));
    }
#undef CROSS
#undef DOT
    double r = 3 * (V6 / 6) / area;
    return R / (3 * r);
}

/* bad: R / (3 r) > max_aspect3 or least dihedral < min_dihedral; with area_ratio
   > 0 only when also |V| > area_ratio V_0 */
int aug_bisect3d_bad(const aug_work *w, int64_t t, const aug_refine_opt *o)
{
    aug_quality q;
    aug_elem_quality(&w->m, t, &q);
    int bad = (o->max_aspect3 > 0 && q.aspect > o->max_aspect3) ||
              (o->min_dihedral > 0 && q.min_angle < o->min_dihedral);
    if (bad && o->area_ratio > 0) bad = fabs(q.measure) > o->area_ratio * w->area0[t];
    return bad;
}

static int32_t score(const aug_work *w, const aug_parent_rule *pr, int32_t node)
{
    while (node >= pr->nscore && node >= w->nn_begin) node = w->parent[node - w->nn_begin];
    return node < pr->nscore ? pr->score[node] : 0;
}

typedef struct ctx3 {
    aug_work *w;
    const aug_refine_opt *o;
    const aug_parent_rule *pr;
    aug_bisect_stats *st;
    int64_t *q, nq, capq;     /* queue: element << 20 | version */
    unsigned char *lev;       /* bisection level of each element this call */
    int64_t caplev;
    int32_t *star;
    int64_t capstar;
} ctx3;

static int push(ctx3 *c, int64_t t)
{
    if (c->nq == c->capq) {
        int64_t cap = c->capq ? 2 * c->capq : 256;
        int64_t *p = aug_realloc(c->q, (size_t)cap * sizeof *p);
        if (!p) return AUG_ENOMEM;
        c->q = p, c->capq = cap;
    }
    c->q[c->nq++] = t << 20 | (c->w->ver[t] & 0xfffff);
    return 0;
}

/* the tets around edge {a, b} into c->star; their count */
static int64_t star(ctx3 *c, int32_t a, int32_t b)
{
    aug_work *w = c->w;
    int64_t ns = 0;
    for (int32_t k = 0; k < w->ncnt[a]; k++) {
        int32_t s = w->nel[a][k];
        const int32_t *v = C(w, s);
        if (v[0] != b && v[1] != b && v[2] != b && v[3] != b) continue;
        if (ns == c->capstar) {
            int64_t cap = c->capstar ? 2 * c->capstar : 32;
            int32_t *p = aug_realloc(c->star, (size_t)cap * sizeof *p);
            if (!p) return -1;
            c->star = p, c->capstar = cap;
        }
        c->star[ns++] = s;
    }
    return ns;
}

/* split edge {a, b} at its midpoint m: every tet around it becomes the child
   keeping a and the child keeping b (conforming); m's parent is the end with the
   lower score (the lower index on ties); children are queued one level deeper */
static int split(ctx3 *c, int32_t a, int32_t b)
{
    aug_work *w = c->w;
    int64_t ns = star(c, a, b);
    if (ns < 0) return AUG_ENOMEM;
    int32_t sa = score(w, c->pr, a), sb = score(w, c->pr, b);
    int32_t par = sa != sb ? (sa < sb ? a : b) : (a < b ? a : b);
    double mid[3];
    for (int k = 0; k < 3; k++) mid[k] = 0.5 * (X(w, a)[k] + X(w, b)[k]);
    int32_t m = aug_work_node(w, mid, par);
    if (m < 0) return AUG_ENOMEM;
    aug_work_creators(w, m, (int32_t[2]){a, b}, 2);
    if (w->m.ne + ns + 1 > c->caplev) {
        int64_t cap = 2 * (w->m.ne + ns + 1);
        unsigned char *l = aug_realloc(c->lev, (size_t)cap);
        if (!l) return AUG_ENOMEM;
        memset(l + c->caplev, 0, (size_t)(cap - c->caplev));
        c->lev = l, c->caplev = cap;
    }
    for (int64_t k = 0; k < ns; k++) {
        int64_t s = c->star[k];
        int32_t c1[4], c2[4];
        memcpy(c1, C(w, s), sizeof c1);
        memcpy(c2, c1, sizeof c2);
        for (int j = 0; j < 4; j++) {
            if (c1[j] == b) c1[j] = m; /* the child keeping a */
            if (c2[j] == a) c2[j] = m; /* the child keeping b */
        }
        int32_t mat = w->m.mat[s], own = w->own[s];
        double a0 = w->area0[s];
        unsigned char l = c->lev[s];
        int rc = aug_work_set(w, s, c1);
        if (rc) return rc;
        int64_t s2 = aug_work_add(w, c2, mat, a0);
        if (s2 < 0) return AUG_ENOMEM;
        w->own[s2] = own;
        c->lev[s] = c->lev[s2] = (unsigned char)(l < 255 ? l + 1 : l);
        if (l + 1 < c->o->max_level3 && ((rc = push(c, s)) || (rc = push(c, s2)))) return rc;
    }
    c->st->bisections++;
    return 0;
}

/* the worst aspect around edge {a, b} now, and after splitting it at its midpoint;
   both 0 (no split) when a tet around it belongs to a cut element a later step
   re-writes (w->keep) */
static int trial(ctx3 *c, int32_t a, int32_t b, double *now, double *after)
{
    aug_work *w = c->w;
    int64_t ns = star(c, a, b);
    if (ns < 0) return AUG_ENOMEM;
    double mid[3];
    for (int k = 0; k < 3; k++) mid[k] = 0.5 * (X(w, a)[k] + X(w, b)[k]);
    *now = *after = 0;
    for (int64_t k = 0; k < ns; k++) { /* a tet a later cut step re-writes stays whole */
        int32_t o = w->own[c->star[k]];
        if (w->keep && o >= 0 && o < w->nkeep && w->keep[o] > w->step) return 0;
    }
    for (int64_t k = 0; k < ns; k++) {
        const int32_t *v = C(w, c->star[k]);
        const double *p[4], *q1[4], *q2[4];
        for (int j = 0; j < 4; j++) {
            p[j] = q1[j] = q2[j] = X(w, v[j]);
            if (v[j] == b) q1[j] = mid;
            if (v[j] == a) q2[j] = mid;
        }
        *now = fmax(*now, tet_aspect(p[0], p[1], p[2], p[3]));
        *after = fmax(*after, fmax(tet_aspect(q1[0], q1[1], q1[2], q1[3]), tet_aspect(q2[0], q2[1], q2[2], q2[3])));
    }
    return 0;
}

/* split the edge of t, longest first, whose split improves the worst tet around
   it; 1 when none does */
static int improve(ctx3 *c, int64_t t)
{
    aug_work *w = c->w;
    const int32_t *v = C(w, t);
    int32_t e[6][2];
    double l[6];
    int n = 0;
    for (int i = 0; i < 4; i++)
        for (int j = i + 1; j < 4; j++) e[n][0] = v[i], e[n][1] = v[j], l[n] = len2(w, v[i], v[j]), n++;
    for (int i = 1; i < 6; i++) /* longest first */
        for (int j = i; j > 0 && l[j] > l[j - 1]; j--) {
            double x = l[j];
            l[j] = l[j - 1], l[j - 1] = x;
            int32_t a = e[j][0], b = e[j][1];
            e[j][0] = e[j - 1][0], e[j][1] = e[j - 1][1], e[j - 1][0] = a, e[j - 1][1] = b;
        }
    for (int i = 0; i < 6; i++) {
        double now, after;
        int rc = trial(c, e[i][0], e[i][1], &now, &after);
        if (rc) return rc;
        if (after < now * (1 - 1e-9)) return split(c, e[i][0], e[i][1]);
    }
    return 1;
}

/* 3-D conformal edge bisection (no thesis counterpart; [Rivara-Levin 1992] in its
   unguarded form made slivers worse): for each bad seed tet, and its bad children
   up to max_level3 levels, improve() splits the first edge, longest first, whose
   split lowers the worst R / (3 r) around it; tets no split improves are left
   (skipped_corner); stops adding nodes at the cap (capped). */
int aug_bisect3d(aug_work *w, const int64_t *seeds, int64_t nseed, const aug_refine_opt *o,
                 const aug_parent_rule *pr, aug_bisect_stats *st, aug_err *e)
{
    memset(st, 0, sizeof *st);
    ctx3 c;
    memset(&c, 0, sizeof c);
    c.w = w, c.o = o, c.pr = pr, c.st = st;
    int rc = 0;
    int64_t cap = w->max_new > 0 ? w->max_new : o->max_new > 0 ? o->max_new : 200000;
    c.caplev = w->m.ne + 1024;
    c.lev = aug_calloc((size_t)c.caplev, 1);
    if (!c.lev) goto nomem;
    for (int64_t i = 0; i < nseed && o->max_level3 > 0; i++)
        if (aug_bisect3d_bad(w, seeds[i], o) && push(&c, seeds[i])) goto nomem;
    for (int64_t head = 0; head < c.nq; head++) {
        int64_t t = c.q[head] >> 20, ver = c.q[head] & 0xfffff;
        if ((w->ver[t] & 0xfffff) != ver || c.lev[t] >= o->max_level3 || !aug_bisect3d_bad(w, t, o)) continue;
        if (w->m.nn - w->nn_begin >= cap) {
            st->capped++;
            continue;
        }
        rc = improve(&c, t);
        if (rc == 1) {
            st->skipped_corner++; /* no split around it improves it */
            rc = 0;
        }
        if (rc) break;
    }
    free(c.q);
    free(c.lev);
    free(c.star);
    if (rc == AUG_ENOMEM) goto nomem0;
    if (rc) return aug_err_set(e, rc, -1, "MDLT", "3-D bisection: a tet is not manifold");
    return 0;
nomem:
    free(c.q);
    free(c.lev);
    free(c.star);
nomem0:
    return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
}
