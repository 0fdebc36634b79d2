/* Mesh-family codecs (formats/stream.md 5): NODE MATL ELEM nSEt FIXD LOAD oUTs,
   read by absorbing into an aug_mesh (which checks them against the records
   before), written from one, checked on their own and dumped. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_mesh.h"

int aug_mesh_is_record(const char *t)
{
    static const char *types[] = {"NODE", "ELEM", "MATL", "nSEt", "FIXD", "LOAD", "oUTs", "GRAV", "FNDN"};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (memcmp(t, types[i], 4) == 0) return 1;
    return 0;
}

#define BAD(...) aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type, __VA_ARGS__)
#define DATA(...) aug_err_set(e, AUG_EDATA, rec->index, rec->type, __VA_ARGS__)
#define NOMEM() aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory")

static int absorb_node(aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t dim = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t nn = aug_cur_i64(&c);
    if (dim != 2 && dim != 3) return BAD("dimension %d is neither 2 nor 3", (int)dim);
    if (nn < 0 || nn > INT32_MAX || !aug_cur_has(&c, (uint64_t)nn * dim, 8) ||
        c.len - c.pos != (uint64_t)nn * dim * 8)
        return BAD("node count %lld does not match the payload", (long long)nn);
    m->x = aug_malloc((size_t)(nn * dim) * sizeof(double));
    if (!m->x) return NOMEM();
    aug_cur_f64v(&c, m->x, (uint64_t)nn * dim);
    for (int64_t i = 0; i < nn * dim; i++)
        if (!isfinite(m->x[i]))
            return DATA("node %lld has a non-finite coordinate", (long long)(i / dim));
        else if (!(fabs(m->x[i]) <= AUG_COORD_MAX))
            return DATA("node %lld has a coordinate %g beyond 1e30 in magnitude", (long long)(i / dim), m->x[i]);
    m->dim = dim;
    m->nn = nn;
    return 0;
}

static int absorb_matl(aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t n = aug_cur_i32(&c);
    if (n < 0 || !aug_cur_has(&c, (uint64_t)n, 104) || c.len - c.pos != (uint64_t)n * 104)
        return BAD("material count %d does not match the payload", (int)n);
    m->mats = aug_calloc((size_t)n, sizeof *m->mats);
    if (!m->mats) return NOMEM();
    for (int i = 0; i < n; i++) {
        aug_material *a = &m->mats[i];
        a->id = aug_cur_i32(&c);
        aug_cur_i32(&c);
        aug_cur_name(&c, a->name);
        a->E = aug_cur_f64(&c);
        a->nu = aug_cur_f64(&c);
        a->rho = aug_cur_f64(&c);
        a->t = aug_cur_f64(&c);
        if (!(a->E > 0) || !isfinite(a->E) || !(a->nu > -1 && a->nu < 0.5) || !(a->rho >= 0) ||
            !isfinite(a->rho) || !(a->t > 0) || !isfinite(a->t))
            return DATA("material %d (%s): need E > 0, -1 < nu < 0.5, rho >= 0, t > 0", i,
                        a->name);
    }
    m->nmat = n;
    return 0;
}

static int absorb_elem(aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    if (!(m->have & AUG_HAVE_NODE) || !(m->have & AUG_HAVE_MATL))
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "ELEM before NODE and MATL");
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t et = aug_cur_i32(&c), nv = aug_cur_i32(&c);
    int64_t ne = aug_cur_i64(&c);
    if (!aug_etype_nv(et) || nv != aug_etype_nv(et) || m->dim != aug_etype_dim(et))
        return BAD("element type %d with %d nodes in dimension %d is not supported", (int)et,
                   (int)nv, m->dim);
    if (ne < 0 || ne > INT32_MAX || !aug_cur_has(&c, (uint64_t)ne, 4 * (nv + 1)) ||
        c.len - c.pos != (uint64_t)ne * 4 * (nv + 1))
        return BAD("element count %lld does not match the payload", (long long)ne);
    m->conn = aug_malloc((size_t)(ne * nv) * sizeof(int32_t));
    m->mat = aug_malloc((size_t)ne * sizeof(int32_t));
    if (!m->conn || !m->mat) return NOMEM();
    aug_cur_i32v(&c, m->conn, (uint64_t)ne * nv);
    aug_cur_i32v(&c, m->mat, (uint64_t)ne);
    m->etype = et;
    m->nv = nv;
    m->ne = ne;
    for (int64_t i = 0; i < ne; i++) {
        for (int j = 0; j < nv; j++) {
            int32_t v = m->conn[i * nv + j];
            if (v < 0 || v >= m->nn)
                return DATA("element %lld refers to node %d of %lld", (long long)i, (int)v,
                            (long long)m->nn);
            for (int k = 0; k < j; k++)
                if (m->conn[i * nv + k] == v)
                    return DATA("element %lld repeats node %d", (long long)i, (int)v);
        }
        if (m->mat[i] < 0 || m->mat[i] >= m->nmat)
            return DATA("element %lld has material %d of %d", (long long)i, (int)m->mat[i],
                        m->nmat);
        int corner;
        if (et == AUG_HEX8) {
            double sj = aug_hex_scaled_jacobian(m, i, &corner);
            if (!(sj > 0))
                return DATA("element %lld is inverted or degenerate (scaled Jacobian %.6g at corner %d)",
                            (long long)i, sj, corner);
            continue;
        }
        double v = aug_elem_measure(m, i), lim = 0;
        if (et == AUG_MEM3) { /* |cross| / 2 is never negative: degenerate below 64 eps l^2 */
            for (int a = 0; a < 3; a++) {
                const double *p = m->x + (size_t)m->conn[i * 3 + a] * 3,
                             *q = m->x + (size_t)m->conn[i * 3 + (a + 1) % 3] * 3;
                lim = fmax(lim, 64 * DBL_EPSILON * (pow(p[0] - q[0], 2) + pow(p[1] - q[1], 2) + pow(p[2] - q[2], 2)));
            }
        }
        if (!(v > lim))
            return DATA("element %lld is inverted or degenerate (%s %.6g)", (long long)i,
                        m->nv == 4 ? "volume" : "area", v);
    }
    return 0;
}

/* read n node indices, check range and strict increase */
static int read_nodes(aug_mesh *m, aug_cur *c, int64_t n, int32_t **out, const aug_rec *rec,
                      aug_err *e)
{
    if (n < 0 || !aug_cur_has(c, (uint64_t)n, 4) || c->len - c->pos != (uint64_t)n * 4)
        return BAD("node count %lld does not match the payload", (long long)n);
    *out = aug_malloc((size_t)n * sizeof(int32_t));
    if (!*out) return NOMEM();
    aug_cur_i32v(c, *out, (uint64_t)n);
    for (int64_t i = 0; i < n; i++) {
        if ((*out)[i] < 0 || (*out)[i] >= m->nn)
            return DATA("node %d out of range", (int)(*out)[i]);
        if (i > 0 && (*out)[i] <= (*out)[i - 1]) return DATA("node list not increasing");
    }
    return 0;
}

static int absorb_set(aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    if (!(m->have & AUG_HAVE_NODE))
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "set before NODE");
    aug_cur c;
    aug_cur_init(&c, rec);
    aug_set s;
    memset(&s, 0, sizeof s);
    aug_cur_name(&c, s.name);
    s.n = aug_cur_i64(&c);
    if (aug_mesh_set(m, s.name)) return DATA("set '%s' defined twice", s.name);
    aug_set *ns = aug_realloc(m->sets, (size_t)(m->nset + 1) * sizeof *ns);
    if (!ns) return NOMEM();
    m->sets = ns;
    ns[m->nset] = s;
    ns[m->nset].n = 0;
    m->nset++;
    if (read_nodes(m, &c, s.n, &ns[m->nset - 1].nodes, rec, e)) return e->code;
    ns[m->nset - 1].n = s.n;
    return 0;
}

static int absorb_dofval(aug_mesh *m, const aug_rec *rec, int64_t *n, int32_t **dof,
                         double **val, aug_err *e)
{
    if (!(m->have & AUG_HAVE_NODE))
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "before NODE");
    aug_cur c;
    aug_cur_init(&c, rec);
    int64_t k = aug_cur_i64(&c);
    if (k < 0 || !aug_cur_has(&c, (uint64_t)k, 12) || c.len - c.pos != (uint64_t)k * 12)
        return BAD("entry count %lld does not match the payload", (long long)k);
    *dof = aug_malloc((size_t)k * sizeof(int32_t));
    *val = aug_malloc((size_t)k * sizeof(double));
    if (!*dof || !*val) return NOMEM();
    aug_cur_i32v(&c, *dof, (uint64_t)k);
    aug_cur_f64v(&c, *val, (uint64_t)k);
    for (int64_t i = 0; i < k; i++) {
        if ((*dof)[i] < 0 || (*dof)[i] >= m->nn * m->dim)
            return DATA("dof %d out of range", (int)(*dof)[i]);
        if (i > 0 && (*dof)[i] <= (*dof)[i - 1]) return DATA("dofs not increasing");
        if (!isfinite((*val)[i])) return DATA("dof %d has a non-finite value", (int)(*dof)[i]);
    }
    *n = k;
    return 0;
}

static int absorb_outs(aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    if (!(m->have & AUG_HAVE_NODE))
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "oUTs before NODE");
    aug_cur c;
    aug_cur_init(&c, rec);
    m->out_kind = aug_cur_i32(&c);
    aug_cur_i32(&c);
    aug_cur_name(&c, m->out_name);
    int64_t n = aug_cur_i64(&c);
    if (m->out_kind < AUG_OUT_ALL || m->out_kind > AUG_OUT_SET)
        return DATA("unknown output kind %d", m->out_kind);
    /* an ancillary oUTs may follow an output set made otherwise (aug_replay's --output) */
    free(m->out_nodes);
    m->out_nodes = NULL;
    m->nout = 0;
    if (read_nodes(m, &c, n, &m->out_nodes, rec, e)) return e->code;
    m->nout = n;
    return 0;
}

/* GRAV: f64 g[3], finite, |g| <= 1e12 */
static int absorb_grav(aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    double g[3];
    for (int i = 0; i < 3; i++) g[i] = aug_cur_f64(&c);
    if (!c.ok || c.pos != c.len) return BAD("payload is not 24 bytes");
    for (int i = 0; i < 3; i++)
        if (!(fabs(g[i]) <= 1e12))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "component %d is %g", i, g[i]);
    /* a load record: after NODE (3: taken before it, its 2-D check had no
       dimension); 5.8: a 2-D mesh's g[2] is 0 (factor solved one with g[2] = 5) */
    if (!(m->have & AUG_HAVE_NODE)) return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "GRAV before NODE");
    if (m->dim == 2 && g[2] != 0)
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "g[2] = %g on a 2-D mesh (must be 0)", g[2]);
    memcpy(m->grav, g, sizeof g);
    return 0;
}

/* FNDN: i32 nmat, i32 0, f64 k[nmat] after MATL (the same nmat), each
   finite, 0 <= k <= 1e300; m NULL: the payload checked alone */
static int absorb_fndn(aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t n = aug_cur_i32(&c);
    aug_cur_i32(&c);
    if (n < 0 || !aug_cur_has(&c, (uint64_t)n, 8) || c.len - c.pos != (uint64_t)n * 8)
        return BAD("material count %d does not match the payload", (int)n);
    if (m && !(m->have & AUG_HAVE_MATL)) return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "FNDN before MATL");
    if (m && n != m->nmat) return DATA("%d foundation moduli for %d materials", (int)n, m->nmat);
    for (int i = 0; i < n; i++) {
        double k = aug_cur_f64(&c);
        if (!(k >= 0 && k <= 1e300)) return DATA("material %d: foundation modulus %g (want 0 <= k, finite)", i, k);
        if (m) m->mats[i].kf = k;
    }
    return 0;
}

/* 5.9: a foundation only under a membrane (mem3), checked when both FNDN
   and ELEM are in, whichever came last, naming it (factor named no record,
   stats took it) */
static int fndn_fits(const aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    int need = AUG_HAVE_ELEM | AUG_HAVE_FNDN, i = (m->have & need) == need ? aug_mesh_fndn_misplaced(m) : -1;
    if (i >= 0)
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "material %d (%s) has a foundation: only a "
                           "membrane (mem3) mesh takes one", i, m->mats[i].name);
    return 0;
}

int aug_mesh_absorb(aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    const char *t = rec->type;
    int rc = 0, bit = 0;
    if (!memcmp(t, "NODE", 4)) rc = absorb_node(m, rec, e), bit = AUG_HAVE_NODE;
    else if (!memcmp(t, "MATL", 4)) rc = absorb_matl(m, rec, e), bit = AUG_HAVE_MATL;
    else if (!memcmp(t, "ELEM", 4)) rc = absorb_elem(m, rec, e), bit = AUG_HAVE_ELEM;
    else if (!memcmp(t, "nSEt", 4)) rc = absorb_set(m, rec, e);
    else if (!memcmp(t, "FIXD", 4))
        rc = absorb_dofval(m, rec, &m->nfix, &m->fix_dof, &m->fix_val, e), bit = AUG_HAVE_FIXD;
    else if (!memcmp(t, "LOAD", 4))
        rc = absorb_dofval(m, rec, &m->nload, &m->load_dof, &m->load_val, e), bit = AUG_HAVE_LOAD;
    else if (!memcmp(t, "oUTs", 4)) rc = absorb_outs(m, rec, e), bit = AUG_HAVE_OUTS;
    else if (!memcmp(t, "GRAV", 4)) rc = absorb_grav(m, rec, e), bit = AUG_HAVE_GRAV;
    else if (!memcmp(t, "FNDN", 4)) rc = absorb_fndn(m, rec, e), bit = AUG_HAVE_FNDN;
    else return aug_err_set(e, AUG_EUSAGE, rec->index, t, "not a mesh record");
    if (!rc) m->have |= bit;
    if (!rc && (bit == AUG_HAVE_ELEM || bit == AUG_HAVE_FNDN)) rc = fndn_fits(m, rec, e);
    return rc;
}

static int put(aug_writer *w, const char *type, aug_buf *b, aug_err *e)
{
    return aug_buf_write(w, type, AUG_NOSTEP, b, e);
}

static void put_dofval(aug_buf *b, int64_t n, const int32_t *dof, const double *val)
{
    aug_buf_i64(b, n);
    aug_buf_i32v(b, dof, (size_t)n);
    aug_buf_f64v(b, val, (size_t)n);
}

int aug_mesh_write(aug_writer *w, const aug_mesh *m, aug_err *e)
{
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, m->dim);
    aug_buf_i32(&b, 0);
    aug_buf_i64(&b, m->nn);
    aug_buf_f64v(&b, m->x, (size_t)(m->nn * m->dim));
    if (put(w, "NODE", &b, e)) return e->code;
    aug_buf_i32(&b, m->nmat);
    for (int i = 0; i < m->nmat; i++) {
        const aug_material *a = &m->mats[i];
        aug_buf_i32(&b, a->id);
        aug_buf_i32(&b, 0);
        aug_buf_name(&b, a->name);
        aug_buf_f64(&b, a->E);
        aug_buf_f64(&b, a->nu);
        aug_buf_f64(&b, a->rho);
        aug_buf_f64(&b, a->t);
    }
    if (put(w, "MATL", &b, e)) return e->code;
    aug_buf_i32(&b, m->etype);
    aug_buf_i32(&b, m->nv);
    aug_buf_i64(&b, m->ne);
    aug_buf_i32v(&b, m->conn, (size_t)(m->ne * m->nv));
    aug_buf_i32v(&b, m->mat, (size_t)m->ne);
    if (put(w, "ELEM", &b, e)) return e->code;
    for (int i = 0; i < m->nset; i++) {
        aug_buf_name(&b, m->sets[i].name);
        aug_buf_i64(&b, m->sets[i].n);
        aug_buf_i32v(&b, m->sets[i].nodes, (size_t)m->sets[i].n);
        if (put(w, "nSEt", &b, e)) return e->code;
    }
    if (m->have & AUG_HAVE_FIXD) {
        put_dofval(&b, m->nfix, m->fix_dof, m->fix_val);
        if (put(w, "FIXD", &b, e)) return e->code;
    }
    if (m->have & AUG_HAVE_LOAD) {
        put_dofval(&b, m->nload, m->load_dof, m->load_val);
        if (put(w, "LOAD", &b, e)) return e->code;
    }
    if (m->have & AUG_HAVE_GRAV) {
        aug_buf_f64v(&b, m->grav, 3);
        if (put(w, "GRAV", &b, e)) return e->code;
    }
    if (m->have & AUG_HAVE_FNDN) {
        aug_buf_i32(&b, m->nmat);
        aug_buf_i32(&b, 0);
        for (int i = 0; i < m->nmat; i++) aug_buf_f64(&b, m->mats[i].kf);
        if (put(w, "FNDN", &b, e)) return e->code;
    }
    if (m->have & AUG_HAVE_OUTS) {
        aug_buf_i32(&b, m->out_kind);
        aug_buf_i32(&b, 0);
        aug_buf_name(&b, m->out_name);
        aug_buf_i64(&b, m->nout);
        aug_buf_i32v(&b, m->out_nodes, (size_t)m->nout);
        if (put(w, "oUTs", &b, e)) return e->code;
    }
    return 0;
}


/* Checks on a record alone (no earlier records): sizes against counts, codes,
   finite values. Index ranges against NODE are checked when absorbed. */
static int check_alone(const aug_rec *rec, aug_err *e)
{
    aug_mesh m;
    aug_mesh_init(&m);
    int rc = 0;
    const char *t = rec->type;
    if (!memcmp(t, "NODE", 4) || !memcmp(t, "MATL", 4) || !memcmp(t, "GRAV", 4)) {
        rc = aug_mesh_absorb(&m, rec, e);
        aug_mesh_free(&m);
        return rc;
    }
    if (!memcmp(t, "FNDN", 4)) return absorb_fndn(NULL, rec, e);
    aug_cur c;
    aug_cur_init(&c, rec);
    if (!memcmp(t, "ELEM", 4)) {
        int32_t et = aug_cur_i32(&c), nv = aug_cur_i32(&c);
        int64_t ne = aug_cur_i64(&c);
        if (!aug_etype_nv(et) || nv != aug_etype_nv(et))
            return BAD("element type %d with %d nodes is not supported", (int)et, (int)nv);
        if (ne < 0 || ne > INT32_MAX || !aug_cur_has(&c, (uint64_t)ne, 4 * (nv + 1)) ||
            c.len - c.pos != (uint64_t)ne * 4 * (nv + 1))
            return BAD("element count %lld does not match the payload", (long long)ne);
    } else if (!memcmp(t, "nSEt", 4) || !memcmp(t, "oUTs", 4)) {
        int64_t n;
        if (!memcmp(t, "oUTs", 4)) {
            int32_t kind = aug_cur_i32(&c);
            if (kind < AUG_OUT_ALL || kind > AUG_OUT_SET) return DATA("unknown output kind %d", (int)kind);
            aug_cur_i32(&c);
        }
        c.pos += AUG_NAME;
        n = aug_cur_i64(&c);
        if (!c.ok || n < 0 || !aug_cur_has(&c, (uint64_t)n, 4) || c.len - c.pos != (uint64_t)n * 4)
            return BAD("node count %lld does not match the payload", (long long)n);
        int32_t prev = -1;
        for (int64_t i = 0; i < n; i++) {
            int32_t v = aug_cur_i32(&c);
            if (v <= prev) return DATA("node list not increasing");
            prev = v;
        }
    } else { /* FIXD LOAD */
        int64_t k = aug_cur_i64(&c);
        if (k < 0 || !aug_cur_has(&c, (uint64_t)k, 12) || c.len - c.pos != (uint64_t)k * 12)
            return BAD("entry count %lld does not match the payload", (long long)k);
        int32_t prev = -1;
        for (int64_t i = 0; i < k; i++) {
            int32_t v = aug_cur_i32(&c);
            if (v <= prev) return DATA("dofs not increasing");
            prev = v;
        }
        for (int64_t i = 0; i < k; i++)
            if (!isfinite(aug_cur_f64(&c))) return DATA("entry %lld has a non-finite value", (long long)i);
    }
    return 0;
}

static void dump_dofval(FILE *o, const int32_t *dof, const double *val, int64_t n)
{
    fprintf(o, "  n %lld\n", (long long)n);
    aug_cur c = aug_cur_mem(dof, (uint64_t)n * 4);
    aug_txt_i32s(o, "dof", &c, (uint64_t)n);
    c = aug_cur_mem(val, (uint64_t)n * 8);
    aug_txt_f64s(o, "value", &c, (uint64_t)n);
}

static void dump_nodes(FILE *o, const int32_t *v, int64_t n)
{
    fprintf(o, "  n %lld\n", (long long)n);
    aug_cur c = aug_cur_mem(v, (uint64_t)n * 4);
    aug_txt_i32s(o, "nodes", &c, (uint64_t)n);
}

/* absorbed into m (and so validated against the records before), printed from m */
static int mesh_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    if (aug_mesh_absorb(m, rec, e)) return e->code;
    aug_txt_header(o, rec);
    const char *t = rec->type;
    if (!memcmp(t, "NODE", 4)) {
        fprintf(o, "  dim %d\n  nn %lld\n", m->dim, (long long)m->nn);
        aug_cur c = aug_cur_mem(m->x, (uint64_t)m->nn * m->dim * 8);
        aug_txt_rows_f64(o, "x", &c, (uint64_t)m->nn, m->dim);
    } else if (!memcmp(t, "MATL", 4)) {
        fprintf(o, "  nmat %d\n", m->nmat);
        for (int i = 0; i < m->nmat; i++) {
            const aug_material *a = &m->mats[i];
            fprintf(o, "  material %d\n    id %d\n", i, (int)a->id);
            fputs("  ", o);
            aug_txt_name(o, "name", a->name, AUG_NAME);
            fputs("    E ", o), aug_txt_f(o, a->E), fputc('\n', o);
            fputs("    nu ", o), aug_txt_f(o, a->nu), fputc('\n', o);
            fputs("    rho ", o), aug_txt_f(o, a->rho), fputc('\n', o);
            fputs("    t ", o), aug_txt_f(o, a->t), fputc('\n', o);
        }
    } else if (!memcmp(t, "ELEM", 4)) {
        fprintf(o, "  etype %d\n  nv %d\n  ne %lld\n", m->etype, m->nv, (long long)m->ne);
        aug_cur c = aug_cur_mem(m->conn, (uint64_t)m->ne * m->nv * 4);
        aug_txt_rows_i32(o, "conn", &c, (uint64_t)m->ne, m->nv);
        c = aug_cur_mem(m->mat, (uint64_t)m->ne * 4);
        aug_txt_i32s(o, "mat", &c, (uint64_t)m->ne);
    } else if (!memcmp(t, "nSEt", 4)) {
        const aug_set *s = &m->sets[m->nset - 1];
        aug_txt_name(o, "name", s->name, AUG_NAME);
        dump_nodes(o, s->nodes, s->n);
    } else if (!memcmp(t, "FIXD", 4)) {
        dump_dofval(o, m->fix_dof, m->fix_val, m->nfix);
    } else if (!memcmp(t, "LOAD", 4)) {
        dump_dofval(o, m->load_dof, m->load_val, m->nload);
    } else if (!memcmp(t, "GRAV", 4)) {
        fputs("  g ", o), aug_txt_f(o, m->grav[0]), fputc(' ', o), aug_txt_f(o, m->grav[1]);
        fputc(' ', o), aug_txt_f(o, m->grav[2]), fputc('\n', o);
    } else if (!memcmp(t, "FNDN", 4)) {
        fprintf(o, "  nmat %d\n", m->nmat);
        for (int i = 0; i < m->nmat; i++) fprintf(o, "  k %d ", i), aug_txt_f(o, m->mats[i].kf), fputc('\n', o);
    } else {
        fprintf(o, "  kind %d\n", m->out_kind);
        aug_txt_name(o, "name", m->out_name, AUG_NAME);
        dump_nodes(o, m->out_nodes, m->nout);
    }
    return 0;
}

#define CODEC(name) const aug_codec name = {"lib/mesh/mesh_rec.c", check_alone, mesh_dump}
CODEC(aug_codec_node);
CODEC(aug_codec_matl);
CODEC(aug_codec_elem);
CODEC(aug_codec_nset);
CODEC(aug_codec_fixd);
CODEC(aug_codec_load);
CODEC(aug_codec_outs);
CODEC(aug_codec_grav);
CODEC(aug_codec_fndn);
