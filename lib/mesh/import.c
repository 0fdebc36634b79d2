/* Import of a tagged mesh (gmsh tags, physical groups) into struct aug_mesh:
   compact renumbering, materials, named sets, orientation. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_scene.h"

typedef struct tagidx {
    size_t tag;
    int64_t i;
} tagidx;

static int cmp_tagidx(const void *a, const void *b)
{
    size_t x = ((const tagidx *)a)->tag, y = ((const tagidx *)b)->tag;
    return x < y ? -1 : x > y;
}

/* position of tag in the sorted v[n], or -1 */
static int64_t find(const tagidx *v, int64_t n, size_t tag)
{
    int64_t lo = 0, hi = n - 1;
    while (lo <= hi) {
        int64_t mid = lo + (hi - lo) / 2;
        if (v[mid].tag == tag) return mid;
        if (v[mid].tag < tag) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}

/* sorted (tag, index) pairs; the duplicated tag in *dup (0 if none) */
static tagidx *sorted_tags(const size_t *tags, size_t n, size_t *dup)
{
    tagidx *v = aug_malloc((n ? n : 1) * sizeof *v);
    if (!v) return NULL;
    for (size_t i = 0; i < n; i++) v[i].tag = tags[i], v[i].i = (int64_t)i;
    qsort(v, n, sizeof *v, cmp_tagidx);
    *dup = 0;
    for (size_t i = 1; i < n; i++)
        if (v[i].tag == v[i - 1].tag) {
            *dup = v[i].tag;
            break;
        }
    return v;
}

void aug_group_name(const aug_tagged_group *g, char name[AUG_NAME])
{
    if (g->name[0]) {
        memcpy(name, g->name, AUG_NAME);
        name[AUG_NAME - 1] = 0;
    } else {
        snprintf(name, AUG_NAME, "physical_%d_%d", g->dim, g->tag);
    }
}

/* groups in ascending (dim, tag) order */
typedef struct grpkey {
    int dim, tag, i;
} grpkey;

static int cmp_group(const void *a, const void *b)
{
    const grpkey *x = a, *y = b;
    if (x->dim != y->dim) return x->dim < y->dim ? -1 : 1;
    if (x->tag != y->tag) return x->tag < y->tag ? -1 : 1;
    return x->i < y->i ? -1 : x->i > y->i;
}

static int *group_order(const aug_tagged *t)
{
    int n = t->ngroup;
    grpkey *k = aug_malloc((size_t)(n ? n : 1) * sizeof *k);
    int *ord = aug_malloc((size_t)(n ? n : 1) * sizeof *ord);
    if (!k || !ord) {
        free(k);
        free(ord);
        return NULL;
    }
    for (int i = 0; i < n; i++) k[i].dim = t->groups[i].dim, k[i].tag = t->groups[i].tag, k[i].i = i;
    qsort(k, (size_t)n, sizeof *k, cmp_group);
    for (int i = 0; i < n; i++) ord[i] = k[i].i;
    free(k);
    return ord;
}

typedef struct work {
    tagidx *nodes, *elems;
    int32_t *newid;      /* original node index -> kept index, -1 if unused */
    int *ord;
    unsigned char *mark;
} work;

static void work_free(work *w)
{
    free(w->nodes);
    free(w->elems);
    free(w->newid);
    free(w->ord);
    free(w->mark);
}

#define ERR(code, ...) (aug_err_set(e, code, -1, "", __VA_ARGS__))
#define NOMEM() ERR(AUG_ENOMEM, "out of memory")

/* nodes and connectivity: the used nodes in ascending tag order */
static int import_nodes(const aug_tagged *t, work *w, aug_mesh *m, aug_err *e)
{
    size_t dup;
    int nv = m->nv, dim = m->dim;
    w->nodes = sorted_tags(t->node_tags, t->nnode, &dup);
    if (!w->nodes) return NOMEM();
    if (dup) return ERR(AUG_EDATA, "node tag %zu appears twice", dup);
    w->elems = sorted_tags(t->elem_tags, t->nelem, &dup);
    if (!w->elems) return NOMEM();
    if (dup) return ERR(AUG_EDATA, "element tag %zu appears twice", dup);
    w->newid = aug_malloc((t->nnode ? t->nnode : 1) * sizeof(int32_t));
    m->conn = aug_malloc(t->nelem * nv * sizeof(int32_t));
    if (!w->newid || !m->conn) return NOMEM();
    for (size_t i = 0; i < t->nnode; i++) w->newid[i] = -1;
    for (size_t k = 0; k < t->nelem; k++) {
        const size_t *ct = t->conn_tags + (size_t)w->elems[k].i * nv;
        for (int j = 0; j < nv; j++) {
            int64_t p = find(w->nodes, (int64_t)t->nnode, ct[j]);
            if (p < 0)
                return ERR(AUG_EDATA, "element %zu (gmsh tag %zu) refers to node tag %zu, which is not in the file",
                           k, w->elems[k].tag, ct[j]);
            int64_t orig = w->nodes[p].i;
            w->newid[orig] = 0;
            m->conn[k * nv + j] = (int32_t)orig;
        }
    }
    int64_t nn = 0;
    for (size_t p = 0; p < t->nnode; p++)
        if (w->newid[w->nodes[p].i] == 0) nn++;
    m->x = aug_malloc((size_t)(nn ? nn : 1) * dim * sizeof(double));
    if (!m->x) return NOMEM();
    nn = 0;
    for (size_t p = 0; p < t->nnode; p++) {
        int64_t orig = w->nodes[p].i;
        if (w->newid[orig] != 0) continue;
        const double *c = t->xyz + 3 * orig;
        if (!isfinite(c[0]) || !isfinite(c[1]) || !isfinite(c[2]))
            return ERR(AUG_EDATA, "node %lld (gmsh tag %zu) has a non-finite coordinate",
                       (long long)nn, w->nodes[p].tag);
        for (int d = 0; d < 3; d++)
            if (!(fabs(c[d]) <= AUG_COORD_MAX))
                return ERR(AUG_EDATA, "node %lld (gmsh tag %zu) has a coordinate %g beyond 1e30 in magnitude",
                           (long long)nn, w->nodes[p].tag, c[d]);
        for (int d = 0; d < dim; d++) m->x[nn * dim + d] = c[d];
        w->newid[orig] = (int32_t)nn++;
    }
    for (size_t i = 0; i < t->nelem * nv; i++) m->conn[i] = w->newid[m->conn[i]];
    m->nn = nn;
    m->ne = (int64_t)t->nelem;
    if (dim == 2) { /* plane mesh: z constant */
        double zmin = INFINITY, zmax = -INFINITY;
        for (size_t p = 0; p < t->nnode; p++) {
            int64_t orig = w->nodes[p].i;
            if (w->newid[orig] < 0) continue;
            double z = t->xyz[3 * orig + 2];
            zmin = fmin(zmin, z);
            zmax = fmax(zmax, z);
        }
        if (zmax - zmin > 1e-9 * aug_mesh_extent(m))
            return ERR(AUG_EDATA, "triangle mesh is not plane: z ranges over [%.17g, %.17g]", zmin, zmax);
    }
    return 0;
}

/* materials: physical groups of the mesh's dimension, then "default" */
static int import_materials(const aug_tagged *t, work *w, aug_mesh *m, aug_err *e)
{
    int nmg = 0, gdim = m->etype == AUG_MEM3 ? 2 : m->dim; /* a membrane's groups are surfaces */
    for (int i = 0; i < t->ngroup; i++) nmg += t->groups[i].dim == gdim;
    m->mats = aug_calloc((size_t)nmg + 1, sizeof *m->mats);
    m->mat = aug_malloc((size_t)m->ne * sizeof(int32_t));
    if (!m->mats || !m->mat) return NOMEM();
    for (int64_t k = 0; k < m->ne; k++) m->mat[k] = -1;
    int im = 0;
    char name[AUG_NAME];
    for (int o = 0; o < t->ngroup; o++) {
        const aug_tagged_group *g = &t->groups[w->ord[o]];
        if (g->dim != gdim) continue;
        /* groups that share a name are one material, the first one's tag its id */
        aug_group_name(g, name);
        int at = 0;
        while (at < im && strcmp(m->mats[at].name, name) != 0) at++;
        aug_material *a = &m->mats[at];
        if (at == im) {
            a->id = g->tag;
            memcpy(a->name, name, AUG_NAME);
            im++;
        }
        for (size_t j = 0; j < g->nelem; j++) {
            int64_t k = find(w->elems, m->ne, g->elem_tags[j]);
            if (k < 0) continue;
            if (m->mat[k] >= 0 && m->mat[k] != at)
                return ERR(AUG_EDATA, "element %lld (gmsh tag %zu) is in two physical groups, '%s' and '%s'",
                           (long long)k, w->elems[k].tag, m->mats[m->mat[k]].name, a->name);
            m->mat[k] = at;
        }
    }
    int need_default = 0;
    for (int64_t k = 0; k < m->ne; k++)
        if (m->mat[k] < 0) m->mat[k] = im, need_default = 1;
    if (need_default) {
        m->mats[im].id = 0;
        strcpy(m->mats[im].name, "default");
        im++;
    }
    for (int i = 0; i < im; i++) {
        m->mats[i].E = AUG_DEFAULT_E;
        m->mats[i].nu = AUG_DEFAULT_NU;
        m->mats[i].rho = AUG_DEFAULT_RHO;
        m->mats[i].t = AUG_DEFAULT_T;
    }
    m->nmat = im;
    return 0;
}

/* hex8: refuse a hex whose scaled Jacobian is <= 0 at a corner; with
   reorient, one negative at every corner (a mirrored hex) is flipped by
   exchanging its bottom and top faces (0123 4567 -> 4567 0123) */
static int hex_orientation(int reorient, work *w, aug_mesh *m, int64_t k, aug_err *e)
{
    int32_t *c = m->conn + k * 8;
    int corner;
    double sj = aug_hex_scaled_jacobian(m, k, &corner);
    if (sj > 64 * DBL_EPSILON) return 0;
    if (reorient) {
        for (int a = 0; a < 4; a++) {
            int32_t t = c[a];
            c[a] = c[a + 4];
            c[a + 4] = t;
        }
        int at;
        double flipped = aug_hex_scaled_jacobian(m, k, &at);
        if (flipped > 64 * DBL_EPSILON) return 0;
        for (int a = 0; a < 4; a++) {
            int32_t t = c[a];
            c[a] = c[a + 4];
            c[a + 4] = t;
        }
    }
    return ERR(AUG_EDATA, "element %lld (gmsh tag %zu) is inverted or degenerate (scaled Jacobian %.6g at corner %d)%s",
               (long long)k, w->elems[k].tag, sj, corner,
               reorient ? ": mirroring it does not help" : "");
}

/* refuse inverted (or, with reorient, flip them) and degenerate elements */
static int import_orientation(int reorient, work *w, aug_mesh *m, aug_err *e)
{
    int nv = m->nv, dim = m->dim, mdim = nv == 3 ? 2 : 3; /* of the measure: area or volume */
    for (int64_t k = 0; k < m->ne; k++) {
        if (nv == 8) {
            if (hex_orientation(reorient, w, m, k, e)) return e->code;
            continue;
        }
        int32_t *c = m->conn + k * nv;
        double l = 0;
        for (int i = 0; i < nv; i++)
            for (int j = i + 1; j < nv; j++) {
                double s = 0;
                for (int d = 0; d < dim; d++) {
                    double h = m->x[(size_t)c[i] * dim + d] - m->x[(size_t)c[j] * dim + d];
                    s += h * h;
                }
                l = fmax(l, sqrt(s));
            }
        double v = aug_elem_measure(m, k);
        const char *what = mdim == 3 ? "volume" : "area";
        /* an element whose measure is below the normal doubles (edges under
           ~1e-102 in 3-D) has none the FEM can compute: not "degenerate",
           too small (a tet of edge 1e-110 read "volume 0") */
        if (l > 0 && !(pow(l, mdim) >= DBL_MIN))
            return ERR(AUG_EDATA, "element %lld (gmsh tag %zu) is too small for double precision (longest edge "
                       "%.6g: its %s underflows)", (long long)k, w->elems[k].tag, l, what);
        if (!(fabs(v) > 64 * DBL_EPSILON * pow(l, mdim)))
            return ERR(AUG_EDATA, "element %lld (gmsh tag %zu) is degenerate (%s %.6g)", (long long)k,
                       w->elems[k].tag, what, v);
        if (v < 0) {
            if (!reorient)
                return ERR(AUG_EDATA, "element %lld (gmsh tag %zu) is inverted (%s %.6g)", (long long)k,
                           w->elems[k].tag, what, v);
            int32_t s = c[nv - 1];
            c[nv - 1] = c[nv - 2];
            c[nv - 2] = s;
        }
    }
    return 0;
}

static int add_set(aug_mesh *m, const char *name, const unsigned char *mark, aug_err *e)
{
    int64_t n = 0;
    for (int64_t i = 0; i < m->nn; i++) n += mark[i] != 0;
    aug_set *s = &m->sets[m->nset];
    memset(s, 0, sizeof *s);
    s->nodes = aug_malloc((size_t)(n ? n : 1) * sizeof(int32_t));
    if (!s->nodes) return NOMEM();
    snprintf(s->name, AUG_NAME, "%s", name);
    for (int64_t i = 0; i < m->nn; i++)
        if (mark[i]) s->nodes[s->n++] = (int32_t)i;
    m->nset++;
    return 0;
}

/* sets: physical groups of any dimension (merged by name), then "boundary" */
static int import_sets(const aug_tagged *t, work *w, aug_mesh *m, aug_err *e)
{
    m->sets = aug_calloc((size_t)t->ngroup + 1, sizeof *m->sets);
    w->mark = aug_malloc((size_t)(m->nn ? m->nn : 1));
    if (!m->sets || !w->mark) return NOMEM();
    char name[AUG_NAME], other[AUG_NAME];
    for (int o = 0; o < t->ngroup; o++) {
        aug_group_name(&t->groups[w->ord[o]], name);
        if (aug_mesh_set(m, name)) continue; /* merged into an earlier group */
        memset(w->mark, 0, (size_t)m->nn);
        for (int q = o; q < t->ngroup; q++) {
            const aug_tagged_group *g = &t->groups[w->ord[q]];
            aug_group_name(g, other);
            if (strcmp(name, other) != 0) continue;
            for (size_t j = 0; j < g->nnode; j++) {
                int64_t p = find(w->nodes, (int64_t)t->nnode, g->node_tags[j]);
                if (p >= 0 && w->newid[w->nodes[p].i] >= 0) w->mark[w->newid[w->nodes[p].i]] = 1;
            }
        }
        if (add_set(m, name, w->mark, e)) return e->code;
    }
    if (!aug_mesh_set(m, "boundary")) {
        if (aug_mesh_boundary_nodes(m, w->mark) < 0) return NOMEM();
        if (add_set(m, "boundary", w->mark, e)) return e->code;
    }
    return 0;
}

int aug_import(const aug_tagged *t, int reorient, aug_mesh *m, aug_err *e)
{
    aug_err_clear(e);
    aug_mesh_init(m);
    if (!aug_etype_nv(t->etype))
        return ERR(AUG_EUSAGE, "element type %d is not tet4, hex8, tri3 or mem3", t->etype);
    if (t->nelem == 0) return ERR(AUG_EDATA, "the mesh has no elements");
    if (t->nelem > INT32_MAX || t->nnode > INT32_MAX)
        return ERR(AUG_EDATA, "the mesh is too large (%zu nodes, %zu elements)", t->nnode, t->nelem);
    m->etype = t->etype;
    m->nv = aug_etype_nv(t->etype);
    m->dim = aug_etype_dim(t->etype);
    work w;
    memset(&w, 0, sizeof w);
    int rc = import_nodes(t, &w, m, e);
    if (!rc) rc = !(w.ord = group_order(t)) ? NOMEM() : 0;
    if (!rc) rc = import_materials(t, &w, m, e);
    if (!rc) rc = import_orientation(reorient, &w, m, e);
    if (!rc) rc = import_sets(t, &w, m, e);
    work_free(&w);
    if (rc) {
        aug_mesh_free(m);
        return rc;
    }
    m->have = AUG_HAVE_NODE | AUG_HAVE_MATL | AUG_HAVE_ELEM;
    return 0;
}
