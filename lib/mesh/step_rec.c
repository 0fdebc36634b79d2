/* Step-family codecs (formats/stream.md 7.1, 7.2, 7.6, 7.7): MDLT (mesh delta),
   UPDT (principal submatrix update, AMPS paper 001 eq. 3.1), BDLT (constraint
   and load changes), pATH (cut geometry). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_update.h"

int aug_write_mdelta(aug_writer *w, int dim, int nv, const aug_mdelta *d, aug_err *e)
{
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i64(&b, d->nnew);
    aug_buf_i32v(&b, d->parent, (size_t)d->nnew);
    aug_buf_f64v(&b, d->x, (size_t)(d->nnew * dim));
    aug_buf_i64(&b, d->nmod);
    aug_buf_i32v(&b, d->elem, (size_t)d->nmod);
    aug_buf_i32v(&b, d->conn, (size_t)(d->nmod * nv));
    aug_buf_i64(&b, d->nadd);
    aug_buf_i32v(&b, d->conn_add, (size_t)(d->nadd * nv));
    aug_buf_i32v(&b, d->mat_add, (size_t)d->nadd);
    aug_buf_i32(&b, d->flags);
    aug_buf_i32(&b, 0);
    return aug_buf_write(w, "MDLT", d->step, &b, e);
}

#define BAD(...) aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type, __VA_ARGS__)

/* read a count followed by per-item arrays of `per` bytes in all */
static int count_ok(aug_cur *c, int64_t n, uint64_t per)
{
    return n >= 0 && n <= INT32_MAX && aug_cur_has(c, (uint64_t)n, per);
}

int aug_read_mdelta(const aug_rec *rec, int dim, int nv, aug_mdelta *d, aug_err *e)
{
    aug_err_clear(e);
    aug_mdelta_init(d);
    aug_cur c;
    aug_cur_init(&c, rec);
    d->step = rec->step;
    d->nnew = aug_cur_i64(&c);
    if (!count_ok(&c, d->nnew, 4 + 8 * (uint64_t)dim)) return BAD("bad new-node count");
    d->parent = aug_malloc((size_t)d->nnew * 4);
    d->x = aug_malloc((size_t)(d->nnew * dim) * 8);
    if (!d->parent || !d->x) goto nomem;
    aug_cur_i32v(&c, d->parent, (uint64_t)d->nnew);
    aug_cur_f64v(&c, d->x, (uint64_t)d->nnew * dim);
    for (int64_t i = 0; i < d->nnew * dim; i++)
        if (!isfinite(d->x[i]))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                               "new node %lld has a non-finite coordinate", (long long)(i / dim));
        else if (!(fabs(d->x[i]) <= AUG_COORD_MAX))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "new node %lld has a coordinate %g beyond 1e30 in magnitude",
                               (long long)(i / dim), d->x[i]);
    d->nmod = aug_cur_i64(&c);
    if (!count_ok(&c, d->nmod, 4 * (uint64_t)(nv + 1))) return BAD("bad changed-element count");
    d->elem = aug_malloc((size_t)d->nmod * 4);
    d->conn = aug_malloc((size_t)(d->nmod * nv) * 4);
    if (!d->elem || !d->conn) goto nomem;
    aug_cur_i32v(&c, d->elem, (uint64_t)d->nmod);
    aug_cur_i32v(&c, d->conn, (uint64_t)d->nmod * nv);
    d->nadd = aug_cur_i64(&c);
    if (!count_ok(&c, d->nadd, 4 * (uint64_t)(nv + 1))) return BAD("bad added-element count");
    d->conn_add = aug_malloc((size_t)(d->nadd * nv) * 4);
    d->mat_add = aug_malloc((size_t)d->nadd * 4);
    if (!d->conn_add || !d->mat_add) goto nomem;
    aug_cur_i32v(&c, d->conn_add, (uint64_t)d->nadd * nv);
    aug_cur_i32v(&c, d->mat_add, (uint64_t)d->nadd);
    d->flags = aug_cur_i32(&c);
    aug_cur_i32(&c);
    if (d->flags & ~(AUG_STEP_DETACHED | AUG_STEP_PINNED | AUG_STEP_DROPPED))
        return BAD("unknown step flags 0x%x", (unsigned)d->flags);
    if (!c.ok || c.pos != c.len) return BAD("payload size does not match its counts");
    return 0;
nomem:
    return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
}

/* UPKM: the K and M updates of a dynamic step on the UPDT's Hbar */
static int write_updkm(aug_writer *w, const aug_update *u, aug_err *e)
{
    aug_buf b;
    aug_buf_init(&b);
    size_t s = (size_t)u->m + (size_t)u->k;
    aug_buf_i32(&b, u->m);
    aug_buf_i32(&b, u->k);
    aug_buf_f64v(&b, u->EK, s * s);
    aug_buf_f64v(&b, u->EM, s * s);
    return aug_buf_write(w, "UPKM", u->step, &b, e);
}

int aug_write_update(aug_writer *w, const aug_update *u, aug_err *e)
{
    if (u->EK && write_updkm(w, u, e)) return e->code;
    aug_buf b;
    aug_buf_init(&b);
    size_t s = (size_t)u->m + (size_t)u->k;
    aug_buf_i32(&b, u->m);
    aug_buf_i32(&b, u->k);
    aug_buf_i32v(&b, u->H, (size_t)u->m);
    aug_buf_f64v(&b, u->E, s * s);
    aug_buf_f64v(&b, u->df, s);
    return aug_buf_write(w, "UPDT", u->step, &b, e);
}

int aug_read_update(const aug_rec *rec, aug_update *u, aug_err *e)
{
    aug_err_clear(e);
    aug_update_init(u);
    aug_cur c;
    aug_cur_init(&c, rec);
    u->step = rec->step;
    u->m = aug_cur_i32(&c);
    u->k = aug_cur_i32(&c);
    if (u->m < 0 || u->k < 0 || (int64_t)u->m + u->k > 1 << 20)
        return BAD("impossible sizes m = %d, k = %d", (int)u->m, (int)u->k);
    uint64_t s = (uint64_t)u->m + (uint64_t)u->k;
    if (c.len - c.pos != 4 * (uint64_t)u->m + 8 * s * s + 8 * s)
        return BAD("payload size does not match m = %d, k = %d", (int)u->m, (int)u->k);
    u->H = aug_malloc((size_t)u->m * 4);
    u->E = aug_malloc((size_t)(s * s) * 8);
    u->df = aug_malloc((size_t)s * 8);
    if (!u->H || !u->E || !u->df)
        return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    aug_cur_i32v(&c, u->H, (uint64_t)u->m);
    aug_cur_f64v(&c, u->E, s * s);
    aug_cur_f64v(&c, u->df, s);
    for (uint64_t i = 0; i < s * s; i++)
        if (!isfinite(u->E[i]) || (i < s && !isfinite(u->df[i])))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "E or df has a non-finite entry");
    for (int32_t i = 0; i < u->m; i++)
        if (u->H[i] < 0 || (i > 0 && u->H[i] <= u->H[i - 1]))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "H not increasing at %d", (int)i);
    for (uint64_t i = 0; i < s; i++)
        for (uint64_t j = 0; j < i; j++)
            if (u->E[i + j * s] != u->E[j + i * s])
                return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "E is not symmetric");
    return 0;
}

/* n x n symmetric with finite entries */
static int sym_finite(const double *A, uint64_t n)
{
    for (uint64_t j = 0; j < n; j++)
        for (uint64_t i = 0; i <= j; i++)
            if (!isfinite(A[i + j * n]) || A[i + j * n] != A[j + i * n]) return 0;
    return 1;
}

int aug_read_updkm(const aug_rec *rec, aug_update *km, aug_err *e)
{
    aug_err_clear(e);
    aug_update_init(km);
    aug_cur c;
    aug_cur_init(&c, rec);
    km->step = rec->step;
    km->m = aug_cur_i32(&c);
    km->k = aug_cur_i32(&c);
    if (km->m < 0 || km->k < 0 || (int64_t)km->m + km->k > 1 << 20)
        return BAD("impossible sizes m = %d, k = %d", (int)km->m, (int)km->k);
    uint64_t s = (uint64_t)km->m + (uint64_t)km->k;
    if (c.len - c.pos != 16 * s * s)
        return BAD("payload size does not match m = %d, k = %d", (int)km->m, (int)km->k);
    km->EK = aug_malloc((size_t)(s * s) * 8 + 1);
    km->EM = aug_malloc((size_t)(s * s) * 8 + 1);
    if (!km->EK || !km->EM) return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    aug_cur_f64v(&c, km->EK, s * s);
    aug_cur_f64v(&c, km->EM, s * s);
    if (!sym_finite(km->EK, s) || !sym_finite(km->EM, s))
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                           "EK or EM is not symmetric or has a non-finite entry");
    return 0;
}

int aug_update_attach_km(aug_update *u, aug_update *km, long km_index, const aug_rec *updt, double cM,
                         double cK, aug_err *e)
{
    aug_err_clear(e);
    if (km->step != u->step || km->m != u->m || km->k != u->k)
        return aug_err_set(e, AUG_EDATA, updt->index, updt->type,
                           "step %d, m %d, k %d, its UPKM (record %ld) step %d, m %d, k %d",
                           (int)u->step, (int)u->m, (int)u->k, km_index, (int)km->step, (int)km->m,
                           (int)km->k);
    /* 7.8: E = cM EM + cK EK off the constrained rows and columns. Those
       differ on their diagonal only, where the identity rows of A_t, K_t and
       M_t give E + 1 = cM (EM + 1) + cK (EK + 1) instead: every entry is
       compared (an EK scaled by 5 was integrated), a diagonal one against
       the nearer of the two, to 1e-9 of the largest cM EM and cK EK entries
       plus cM + cK (E, EM and EK are differences of assembled matrices) */
    int64_t s = (int64_t)u->m + u->k;
    double em = 0, ek = 0, off = 0;
    for (int64_t t = 0; t < s * s; t++) em = fmax(em, fabs(km->EM[t])), ek = fmax(ek, fabs(km->EK[t]));
    int64_t at = -1;
    for (int64_t b = 0; b < s; b++)
        for (int64_t a = 0; a < s; a++) {
            double E = u->E[a + b * s], M = km->EM[a + b * s], K = km->EK[a + b * s];
            double d = fabs(E - (cM * M + cK * K));
            if (a == b) d = fmin(d, fabs(E + 1 - (cM * (M + 1) + cK * (K + 1))));
            if (d > off) off = d, at = a + b * s;
        }
    em += 1, ek += 1;
    if (!(off <= 1e-9 * (fabs(cM) * em + fabs(cK) * ek)))
        return aug_err_set(e, AUG_EDATA, updt->index, updt->type,
                           "step %d: E is not cM EM + cK EK of its UPKM (record %ld): off by %.3g at (%lld, %lld)",
                           (int)u->step, km_index, off, (long long)(at % s), (long long)(at / s));
    free(u->EK), free(u->EM);
    u->EK = km->EK, u->EM = km->EM;
    km->EK = km->EM = NULL;
    return 0;
}

/* append n ints to a sorted array */
int aug_write_bdelta(aug_writer *w, const aug_bdelta *b, aug_err *e)
{
    aug_buf p;
    aug_buf_init(&p);
    aug_buf_i64(&p, b->nfix);
    aug_buf_i32v(&p, b->fix_dof, (size_t)b->nfix);
    aug_buf_f64v(&p, b->fix_val, (size_t)b->nfix);
    aug_buf_i64(&p, b->nload);
    aug_buf_i32v(&p, b->load_dof, (size_t)b->nload);
    aug_buf_f64v(&p, b->load_val, (size_t)b->nload);
    int rc = p.failed ? aug_err_set(e, AUG_ENOMEM, aug_writer_count(w), "BDLT", "out of memory")
                      : aug_write(w, "BDLT", b->step, p.p, p.len, e);
    aug_buf_free(&p);
    return rc;
}


static int read_list(aug_cur *c, const aug_rec *rec, int64_t *n, int32_t **d, double **v,
                     const char *what, aug_err *e)
{
    *n = aug_cur_i64(c);
    if (*n < 0 || *n > INT32_MAX || !aug_cur_has(c, (uint64_t)*n, 12))
        return BAD("bad %s count", what);
    *d = aug_malloc((size_t)*n * sizeof **d + 1);
    *v = aug_malloc((size_t)*n * sizeof **v + 1);
    if (!*d || !*v) return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    aug_cur_i32v(c, *d, (uint64_t)*n);
    aug_cur_f64v(c, *v, (uint64_t)*n);
    for (int64_t i = 0; i < *n; i++) {
        if ((*d)[i] < 0 || (i > 0 && (*d)[i] <= (*d)[i - 1]))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                               "%s dofs not strictly increasing at %lld", what, (long long)i);
        if (!((*v)[i] - (*v)[i] == 0))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "%s value not finite", what);
        if (!strcmp(what, "constraint") && !(fabs((*v)[i]) <= 1e30))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                               "constraint value %.3g beyond 1e30 (a displacement, 5.1)", (*v)[i]);
    }
    return 0;
}

int aug_read_bdelta(const aug_rec *rec, aug_bdelta *b, aug_err *e)
{
    aug_err_clear(e);
    aug_bdelta_init(b);
    aug_cur c;
    aug_cur_init(&c, rec);
    b->step = rec->step;
    int rc = read_list(&c, rec, &b->nfix, &b->fix_dof, &b->fix_val, "constraint", e);
    if (rc) return rc;
    b->capfix = b->nfix;
    rc = read_list(&c, rec, &b->nload, &b->load_dof, &b->load_val, "load", e);
    if (rc) return rc;
    b->capload = b->nload;
    if (!c.ok || c.pos != c.len) return BAD("payload size does not match its counts");
    return 0;
}


/* pATH: i32 dim, i32 0, i64 nseg, f64 seg[nseg][2][dim] */
int aug_write_path(aug_writer *w, const aug_pathrec *p, aug_err *e)
{
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, p->dim);
    aug_buf_i32(&b, 0);
    aug_buf_i64(&b, p->nseg);
    aug_buf_f64v(&b, p->seg, (size_t)(p->nseg * 2 * p->dim));
    return aug_buf_write(w, "pATH", p->step, &b, e);
}

void aug_pathrec_free(aug_pathrec *p)
{
    free(p->seg);
    memset(p, 0, sizeof *p);
}

int aug_read_path(const aug_rec *rec, aug_pathrec *p, aug_err *e)
{
    aug_err_clear(e);
    memset(p, 0, sizeof *p);
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t dim = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t nseg = aug_cur_i64(&c);
    if (dim != 2 && dim != 3) return BAD("dimension %d is neither 2 nor 3", (int)dim);
    if (!c.ok || nseg < 0 || nseg > INT32_MAX || !aug_cur_has(&c, (uint64_t)nseg, 16 * (uint64_t)dim) ||
        c.len - c.pos != 16 * (uint64_t)dim * (uint64_t)nseg)
        return BAD("segment count %lld does not match the payload", (long long)nseg);
    p->seg = aug_malloc((size_t)(nseg * 2 * dim + 1) * sizeof *p->seg);
    if (!p->seg) return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    aug_cur_f64v(&c, p->seg, (uint64_t)nseg * 2 * dim);
    for (int64_t i = 0; i < nseg * 2 * dim; i++)
        if (!isfinite(p->seg[i]))
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                               "segment %lld has a non-finite coordinate", (long long)(i / (2 * dim)));
    p->step = rec->step;
    p->dim = dim;
    p->nseg = nseg;
    return 0;
}

static int need_mesh(const aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    if ((m->have & (AUG_HAVE_NODE | AUG_HAVE_ELEM)) != (AUG_HAVE_NODE | AUG_HAVE_ELEM))
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "mesh delta before NODE and ELEM");
    return 0;
}

static int mdlt_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    if (need_mesh(m, rec, e)) return e->code;
    aug_mdelta d;
    if (aug_read_mdelta(rec, m->dim, m->nv, &d, e)) {
        aug_mdelta_free(&d);
        return e->code;
    }
    int dim = m->dim, nv = m->nv;
    aug_txt_header(o, rec);
    fprintf(o, "  nnew %lld\n", (long long)d.nnew);
    aug_cur c = aug_cur_mem(d.parent, (uint64_t)d.nnew * 4);
    aug_txt_i32s(o, "parent", &c, (uint64_t)d.nnew);
    c = aug_cur_mem(d.x, (uint64_t)d.nnew * dim * 8);
    aug_txt_rows_f64(o, "x", &c, (uint64_t)d.nnew, dim);
    fprintf(o, "  nmod %lld\n", (long long)d.nmod);
    c = aug_cur_mem(d.elem, (uint64_t)d.nmod * 4);
    aug_txt_i32s(o, "elem", &c, (uint64_t)d.nmod);
    c = aug_cur_mem(d.conn, (uint64_t)d.nmod * nv * 4);
    aug_txt_rows_i32(o, "conn", &c, (uint64_t)d.nmod, nv);
    fprintf(o, "  nadd %lld\n", (long long)d.nadd);
    c = aug_cur_mem(d.conn_add, (uint64_t)d.nadd * nv * 4);
    aug_txt_rows_i32(o, "conn_add", &c, (uint64_t)d.nadd, nv);
    c = aug_cur_mem(d.mat_add, (uint64_t)d.nadd * 4);
    aug_txt_i32s(o, "mat_add", &c, (uint64_t)d.nadd);
    fprintf(o, "  flags %d\n", (int)d.flags);
    aug_mdelta_free(&d);
    return 0;
}

static int bdlt_check(const aug_rec *rec, aug_err *e)
{
    aug_bdelta b;
    int rc = aug_read_bdelta(rec, &b, e);
    aug_bdelta_free(&b);
    return rc;
}

static int bdlt_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    aug_bdelta b;
    if (aug_read_bdelta(rec, &b, e)) {
        aug_bdelta_free(&b);
        return e->code;
    }
    aug_txt_header(o, rec);
    fprintf(o, "  nfix %lld\n", (long long)b.nfix);
    aug_cur c = aug_cur_mem(b.fix_dof, (uint64_t)b.nfix * 4);
    aug_txt_i32s(o, "dof", &c, (uint64_t)b.nfix);
    c = aug_cur_mem(b.fix_val, (uint64_t)b.nfix * 8);
    aug_txt_f64s(o, "value", &c, (uint64_t)b.nfix);
    fprintf(o, "  nload %lld\n", (long long)b.nload);
    c = aug_cur_mem(b.load_dof, (uint64_t)b.nload * 4);
    aug_txt_i32s(o, "ldof", &c, (uint64_t)b.nload);
    c = aug_cur_mem(b.load_val, (uint64_t)b.nload * 8);
    aug_txt_f64s(o, "lvalue", &c, (uint64_t)b.nload);
    aug_bdelta_free(&b);
    return 0;
}

static int updt_check(const aug_rec *rec, aug_err *e)
{
    aug_update u;
    int rc = aug_read_update(rec, &u, e);
    aug_update_free(&u);
    return rc;
}

static int updt_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    aug_update u;
    if (aug_read_update(rec, &u, e)) {
        aug_update_free(&u);
        return e->code;
    }
    uint64_t s = (uint64_t)u.m + (uint64_t)u.k;
    aug_txt_header(o, rec);
    fprintf(o, "  m %d\n  k %d\n", (int)u.m, (int)u.k);
    aug_cur c = aug_cur_mem(u.H, (uint64_t)u.m * 4);
    aug_txt_i32s(o, "H", &c, (uint64_t)u.m);
    c = aug_cur_mem(u.E, s * s * 8);
    aug_txt_f64s(o, "E", &c, s * s);
    c = aug_cur_mem(u.df, s * 8);
    aug_txt_f64s(o, "df", &c, s);
    aug_update_free(&u);
    return 0;
}

static int upkm_check(const aug_rec *rec, aug_err *e)
{
    aug_update km;
    int rc = aug_read_updkm(rec, &km, e);
    aug_update_free(&km);
    return rc;
}

static int upkm_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    aug_update km;
    if (aug_read_updkm(rec, &km, e)) {
        aug_update_free(&km);
        return e->code;
    }
    uint64_t s = (uint64_t)km.m + (uint64_t)km.k;
    aug_txt_header(o, rec);
    fprintf(o, "  m %d\n  k %d\n", (int)km.m, (int)km.k);
    aug_cur c = aug_cur_mem(km.EK, s * s * 8);
    aug_txt_f64s(o, "EK", &c, s * s);
    c = aug_cur_mem(km.EM, s * s * 8);
    aug_txt_f64s(o, "EM", &c, s * s);
    aug_update_free(&km);
    return 0;
}

static int path_check(const aug_rec *rec, aug_err *e)
{
    aug_pathrec p;
    int rc = aug_read_path(rec, &p, e);
    aug_pathrec_free(&p);
    return rc;
}

static int path_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    aug_pathrec p;
    if (aug_read_path(rec, &p, e)) {
        aug_pathrec_free(&p);
        return e->code;
    }
    aug_txt_header(o, rec);
    fprintf(o, "  dim %d\n  nseg %lld\n", p.dim, (long long)p.nseg);
    aug_cur c = aug_cur_mem(p.seg, (uint64_t)p.nseg * 2 * p.dim * 8);
    aug_txt_rows_f64(o, "p", &c, (uint64_t)p.nseg, 2 * p.dim);
    aug_pathrec_free(&p);
    return 0;
}

/* MDLT has no check on its own: its layout depends on the mesh (dim, nv) */
const aug_codec aug_codec_mdlt = {"lib/mesh/step_rec.c", NULL, mdlt_dump};
const aug_codec aug_codec_updt = {"lib/mesh/step_rec.c", updt_check, updt_dump};
const aug_codec aug_codec_upkm = {"lib/mesh/step_rec.c", upkm_check, upkm_dump};
const aug_codec aug_codec_bdlt = {"lib/mesh/step_rec.c", bdlt_check, bdlt_dump};
const aug_codec aug_codec_path = {"lib/mesh/step_rec.c", path_check, path_dump};
