/* Sub-domains of paper 004 sec. 3 ("material-aware domain decomposition"):
   elements grouped by material, optionally split into slabs. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_msim.h"

void aug_mpart_free(aug_mpart *p)
{
    free(p->group), free(p->axis), free(p->lo), free(p->width);
    memset(p, 0, sizeof *p);
}

/* material index named by tok (its name or its id), -1 when none */
static int find_mat(const aug_mesh *m, const char *tok, size_t n)
{
    for (int i = 0; i < m->nmat; i++)
        if (strlen(m->mats[i].name) == n && !strncmp(m->mats[i].name, tok, n)) return i;
    char buf[32], *end;
    if (n == 0 || n >= sizeof buf) return -1;
    memcpy(buf, tok, n), buf[n] = 0;
    long id = strtol(buf, &end, 10);
    if (*end) return -1;
    for (int i = 0; i < m->nmat; i++)
        if (m->mats[i].id == id) return i;
    return -1;
}

static int groups(aug_mpart *p, const aug_mesh *m, const char *spec, aug_err *e)
{
    for (int i = 0; i < m->nmat; i++) p->group[i] = -1;
    if (!spec || !strcmp(spec, "material")) {
        for (int i = 0; i < m->nmat; i++) p->group[i] = i;
        p->ngroup = m->nmat;
        return 0;
    }
    if (!strcmp(spec, "one")) {
        for (int i = 0; i < m->nmat; i++) p->group[i] = 0;
        p->ngroup = 1;
        return 0;
    }
    int g = 0;
    const char *s = spec;
    for (;;) {
        size_t n = strcspn(s, ",/");
        int k = find_mat(m, s, n);
        if (k < 0)
            return aug_err_set(e, AUG_EUSAGE, -1, "MATL", "--domains: no material '%.*s'", (int)n, s);
        if (p->group[k] >= 0)
            return aug_err_set(e, AUG_EUSAGE, -1, "MATL", "--domains: material '%s' in two groups",
                               m->mats[k].name);
        p->group[k] = g;
        s += n;
        if (!*s) break;
        if (*s++ == '/') g++;
    }
    for (int i = 0; i < m->nmat; i++)
        if (p->group[i] < 0)
            return aug_err_set(e, AUG_EUSAGE, -1, "MATL", "--domains: material '%s' in no group",
                               m->mats[i].name);
    p->ngroup = g + 1;
    return 0;
}

static void centroid(const aug_mesh *m, int64_t e, double c[3])
{
    c[0] = c[1] = c[2] = 0;
    for (int k = 0; k < m->nv; k++)
        for (int j = 0; j < m->dim; j++) c[j] += m->x[(int64_t)m->conn[e * m->nv + k] * m->dim + j] / m->nv;
}

int aug_mpart_init(aug_mpart *p, const aug_mesh *m, const char *spec, int split, aug_err *e)
{
    aug_err_clear(e);
    memset(p, 0, sizeof *p);
    if (split < 1) return aug_err_set(e, AUG_EUSAGE, -1, "", "--split %d: need >= 1", split);
    p->split = split, p->dim = m->dim, p->nv = m->nv;
    int nm = m->nmat > 0 ? m->nmat : 1;
    p->group = malloc((size_t)nm * sizeof *p->group);
    p->axis = calloc((size_t)nm, sizeof *p->axis);
    p->lo = calloc((size_t)nm, sizeof *p->lo);
    p->width = calloc((size_t)nm, sizeof *p->width);
    if (!p->group || !p->axis || !p->lo || !p->width) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    if (groups(p, m, spec, e)) return e->code;
    p->nd = p->ngroup * split;
    if (split == 1) return 0;
    /* each group's bounding box over its element centroids */
    double (*bb)[6] = malloc((size_t)p->ngroup * sizeof *bb);
    if (!bb) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    for (int g = 0; g < p->ngroup; g++)
        for (int j = 0; j < 3; j++) bb[g][j] = INFINITY, bb[g][3 + j] = -INFINITY;
    for (int64_t el = 0; el < m->ne; el++) {
        double c[3];
        centroid(m, el, c);
        int g = p->group[m->mat[el]];
        for (int j = 0; j < m->dim; j++) bb[g][j] = fmin(bb[g][j], c[j]), bb[g][3 + j] = fmax(bb[g][3 + j], c[j]);
    }
    for (int g = 0; g < p->ngroup; g++) {
        int ax = 0;
        for (int j = 1; j < m->dim; j++)
            if (bb[g][3 + j] - bb[g][j] > bb[g][3 + ax] - bb[g][ax]) ax = j;
        p->axis[g] = ax;
        p->lo[g] = bb[g][ax];
        p->width[g] = isfinite(bb[g][ax]) ? (bb[g][3 + ax] - bb[g][ax]) / split : 0;
    }
    free(bb);
    return 0;
}

/* group * split + slab of the element's centroid (clamped to the slabs) */
int aug_mpart_domain(const aug_mpart *p, const aug_mesh *m, int64_t e)
{
    int g = p->group[m->mat[e]];
    if (p->split == 1) return g;
    double c[3];
    centroid(m, e, c);
    int k = p->width[g] > 0 ? (int)floor((c[p->axis[g]] - p->lo[g]) / p->width[g]) : 0;
    if (k < 0) k = 0;
    if (k >= p->split) k = p->split - 1;
    return g * p->split + k;
}
