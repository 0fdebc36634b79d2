/* stats --dump: deterministic text of every record, decoded per formats/stream.md. */
#include <cholmod.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_stats.h"

#define PER_I 10 /* integers per line of a 1-D array */
#define PER_F 4  /* floats per line of a 1-D array */

void aug_dump_init(aug_dump *d, int no_times)
{
    memset(d, 0, sizeof *d);
    d->no_times = no_times;
    aug_mesh_init(&d->mesh);
}

void aug_dump_free(aug_dump *d) { aug_mesh_free(&d->mesh); }

/* bytes as a C-like string: printable ASCII as is, \" \\ and \xNN otherwise */
static void put_esc(FILE *o, const char *s, size_t n, int quote)
{
    if (quote) fputc('"', o);
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '"' || c == '\\') fprintf(o, "\\%c", c);
        else if (c > ' ' && c < 127) fputc(c, o);
        else if (c == ' ' && quote) fputc(c, o);
        else fprintf(o, "\\x%02x", c);
    }
    if (quote) fputc('"', o);
}

static void put_name(FILE *o, const char *label, const char *s, size_t cap)
{
    fprintf(o, "  %s ", label);
    put_esc(o, s, strnlen(s, cap), 1);
    fputc('\n', o);
}

static void put_f(FILE *o, double v) { fprintf(o, "%.17g", v); }

/* 1-D arrays read from the cursor: "  label[n]" then "    i: v v v" */
static void arr_i32(FILE *o, const char *label, aug_cur *c, uint64_t n)
{
    fprintf(o, "  %s[%llu]\n", label, (unsigned long long)n);
    for (uint64_t i = 0; i < n; i++) {
        if (i % PER_I == 0) fprintf(o, "    %llu:", (unsigned long long)i);
        fprintf(o, " %d", (int)aug_cur_i32(c));
        if (i % PER_I == PER_I - 1 || i == n - 1) fputc('\n', o);
    }
}

static void arr_i64(FILE *o, const char *label, aug_cur *c, uint64_t n)
{
    fprintf(o, "  %s[%llu]\n", label, (unsigned long long)n);
    for (uint64_t i = 0; i < n; i++) {
        if (i % PER_I == 0) fprintf(o, "    %llu:", (unsigned long long)i);
        fprintf(o, " %lld", (long long)aug_cur_i64(c));
        if (i % PER_I == PER_I - 1 || i == n - 1) fputc('\n', o);
    }
}

static void arr_f64(FILE *o, const char *label, aug_cur *c, uint64_t n)
{
    fprintf(o, "  %s[%llu]\n", label, (unsigned long long)n);
    for (uint64_t i = 0; i < n; i++) {
        if (i % PER_F == 0) fprintf(o, "    %llu:", (unsigned long long)i);
        fputc(' ', o);
        put_f(o, aug_cur_f64(c));
        if (i % PER_F == PER_F - 1 || i == n - 1) fputc('\n', o);
    }
}

/* 2-D arrays, one row per line: "  label[rows x cols]" then "    r: v v v" */
static void rows_i32(FILE *o, const char *label, aug_cur *c, uint64_t rows, int cols)
{
    fprintf(o, "  %s[%llu x %d]\n", label, (unsigned long long)rows, cols);
    for (uint64_t r = 0; r < rows; r++) {
        fprintf(o, "    %llu:", (unsigned long long)r);
        for (int j = 0; j < cols; j++) fprintf(o, " %d", (int)aug_cur_i32(c));
        fputc('\n', o);
    }
}

static void rows_f64(FILE *o, const char *label, aug_cur *c, uint64_t rows, int cols)
{
    fprintf(o, "  %s[%llu x %d]\n", label, (unsigned long long)rows, cols);
    for (uint64_t r = 0; r < rows; r++) {
        fprintf(o, "    %llu:", (unsigned long long)r);
        for (int j = 0; j < cols; j++) {
            fputc(' ', o);
            put_f(o, aug_cur_f64(c));
        }
        fputc('\n', o);
    }
}

/* a cursor over an in-memory array, to print decoded structs with the same helpers */
static aug_cur mem_cur(const void *p, uint64_t bytes)
{
    aug_cur c = {p, bytes, 0, 1};
    return c;
}

static void hex(FILE *o, const aug_rec *rec)
{
    fprintf(o, "  bytes[%llu]\n", (unsigned long long)rec->len);
    for (uint64_t i = 0; i < rec->len; i++) {
        if (i % 16 == 0) fprintf(o, "    %llu:", (unsigned long long)i);
        fprintf(o, " %02x", rec->data[i]);
        if (i % 16 == 15 || i == rec->len - 1) fputc('\n', o);
    }
}

static void header(FILE *o, const aug_rec *rec)
{
    fprintf(o, "#%ld %s step=%d flags=%u len=%llu\n", rec->index, rec->type, (int)rec->step,
            (unsigned)rec->flags, (unsigned long long)rec->len);
}

int aug_dump_head(FILE *out, const aug_reader *r, aug_err *e)
{
    aug_err_clear(e);
    uint32_t minor, flags;
    uint64_t len, wl;
    aug_reader_head(r, &minor, &flags, &len, &wl);
    const char *p = aug_reader_producer(r);
    fprintf(out, "#0 HEAD step=-1 flags=%u len=%llu\n", (unsigned)flags, (unsigned long long)len);
    fprintf(out, "  major %d\n  minor %u\n", AUG_VERSION_MAJOR, (unsigned)minor);
    put_name(out, "producer", p, strlen(p));
    if (ferror(out)) return aug_err_set(e, AUG_EIO, 0, "HEAD", "write failed");
    return 0;
}

static void d_prov(FILE *o, const aug_rec *rec)
{
    const char *s = (const char *)rec->data;
    uint64_t n = rec->len, a = 0;
    fprintf(o, "  text[%llu]\n", (unsigned long long)n);
    while (a < n) {
        uint64_t b = a;
        while (b < n && s[b] != '\n') b++;
        fputs("    ", o);
        put_esc(o, s + a, (size_t)(b - a), 1);
        fputc('\n', o);
        a = b + 1;
    }
    if (n && s[n - 1] == '\n') fputs("    \"\"\n", o);
}

static void d_dofval(FILE *o, const int32_t *dof, const double *val, int64_t n)
{
    fprintf(o, "  n %lld\n", (long long)n);
    aug_cur c = mem_cur(dof, (uint64_t)n * 4);
    arr_i32(o, "dof", &c, (uint64_t)n);
    c = mem_cur(val, (uint64_t)n * 8);
    arr_f64(o, "value", &c, (uint64_t)n);
}

static void d_nodes(FILE *o, const int32_t *v, int64_t n)
{
    fprintf(o, "  n %lld\n", (long long)n);
    aug_cur c = mem_cur(v, (uint64_t)n * 4);
    arr_i32(o, "nodes", &c, (uint64_t)n);
}

/* mesh records: absorbed (and so validated) by aug_mesh_absorb, printed from the mesh */
static int d_mesh(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    if (aug_mesh_absorb(m, rec, e)) return e->code;
    header(o, rec);
    const char *t = rec->type;
    if (!memcmp(t, "NODE", 4)) {
        fprintf(o, "  dim %d\n  nn %lld\n", m->dim, (long long)m->nn);
        aug_cur c = mem_cur(m->x, (uint64_t)m->nn * m->dim * 8);
        rows_f64(o, "x", &c, (uint64_t)m->nn, m->dim);
    } else if (!memcmp(t, "MATL", 4)) {
        fprintf(o, "  nmat %d\n", m->nmat);
        for (int i = 0; i < m->nmat; i++) {
            const aug_material *a = &m->mats[i];
            fprintf(o, "  material %d\n    id %d\n", i, (int)a->id);
            fputs("  ", o);
            put_name(o, "name", a->name, AUG_NAME);
            fputs("    E ", o), put_f(o, a->E), fputc('\n', o);
            fputs("    nu ", o), put_f(o, a->nu), fputc('\n', o);
            fputs("    rho ", o), put_f(o, a->rho), fputc('\n', o);
            fputs("    t ", o), put_f(o, a->t), fputc('\n', o);
        }
    } else if (!memcmp(t, "ELEM", 4)) {
        fprintf(o, "  etype %d\n  nv %d\n  ne %lld\n", m->etype, m->nv, (long long)m->ne);
        aug_cur c = mem_cur(m->conn, (uint64_t)m->ne * m->nv * 4);
        rows_i32(o, "conn", &c, (uint64_t)m->ne, m->nv);
        c = mem_cur(m->mat, (uint64_t)m->ne * 4);
        arr_i32(o, "mat", &c, (uint64_t)m->ne);
    } else if (!memcmp(t, "nSEt", 4)) {
        const aug_set *s = &m->sets[m->nset - 1];
        put_name(o, "name", s->name, AUG_NAME);
        d_nodes(o, s->nodes, s->n);
    } else if (!memcmp(t, "FIXD", 4)) {
        d_dofval(o, m->fix_dof, m->fix_val, m->nfix);
    } else if (!memcmp(t, "LOAD", 4)) {
        d_dofval(o, m->load_dof, m->load_val, m->nload);
    } else {
        fprintf(o, "  kind %d\n", m->out_kind);
        put_name(o, "name", m->out_name, AUG_NAME);
        d_nodes(o, m->out_nodes, m->nout);
    }
    return 0;
}

/* the printers below run after aug_check_payload accepted the record */
static void d_dofm(FILE *o, const aug_rec *rec)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t dim = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t ndof = aug_cur_i64(&c), nfree = aug_cur_i64(&c);
    fprintf(o, "  dim %d\n  ndof %lld\n  nfree %lld\n", (int)dim, (long long)ndof,
            (long long)nfree);
    arr_i32(o, "map", &c, (uint64_t)ndof);
}

static void d_kmat(FILE *o, const aug_rec *rec)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t which = aug_cur_i32(&c), stype = aug_cur_i32(&c);
    int64_t n = aug_cur_i64(&c), nnz = aug_cur_i64(&c);
    static const char *names[] = {"stiffness K", "consistent mass M", "lumped mass"};
    fprintf(o, "  which %d (%s)\n  stype %d\n  n %lld\n  nnz %lld\n", (int)which,
            which >= 0 && which <= 2 ? names[which] : "unknown", (int)stype, (long long)n,
            (long long)nnz);
    arr_i64(o, "colptr", &c, (uint64_t)n + 1);
    arr_i32(o, "rowind", &c, (uint64_t)nnz);
    arr_f64(o, "value", &c, (uint64_t)nnz);
}

static void d_fvec(FILE *o, const aug_rec *rec)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t kind = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t n = aug_cur_i64(&c);
    fprintf(o, "  kind %d\n  n %lld\n", (int)kind, (long long)n);
    arr_f64(o, "v", &c, (uint64_t)n);
}

static void d_fact(FILE *o, const aug_rec *rec)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int64_t n = aug_cur_i64(&c), nnz = aug_cur_i64(&c);
    int32_t ord = aug_cur_i32(&c);
    aug_cur_i32(&c);
    fprintf(o, "  n %lld\n  nnz %lld\n  ordering %d (%s)\n", (long long)n, (long long)nnz,
            (int)ord, aug_ordering_name(ord));
    arr_i32(o, "perm", &c, (uint64_t)n);
    arr_i64(o, "colptr", &c, (uint64_t)n + 1);
    arr_i32(o, "rowind", &c, (uint64_t)nnz);
    arr_f64(o, "value", &c, (uint64_t)nnz);
}

static int d_kv(FILE *o, const aug_rec *rec, aug_err *e)
{
    aug_kv kv;
    if (aug_read_kv(rec, &kv, e)) return e->code;
    header(o, rec);
    put_name(o, "tag", kv.tag, sizeof kv.tag);
    fprintf(o, "  n %d\n", kv.n);
    for (int i = 0; i < kv.n; i++) { /* indented: a key may be called "n" too */
        fputs("    ", o);
        put_esc(o, kv.key[i], strnlen(kv.key[i], 16), 0);
        fputc(' ', o);
        put_f(o, kv.val[i]);
        fputc('\n', o);
    }
    return 0;
}

static int d_mdlt(FILE *o, const aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    if ((m->have & (AUG_HAVE_NODE | AUG_HAVE_ELEM)) != (AUG_HAVE_NODE | AUG_HAVE_ELEM))
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "mesh delta before NODE and ELEM");
    aug_mdelta d;
    if (aug_read_mdelta(rec, m->dim, m->nv, &d, e)) {
        aug_mdelta_free(&d);
        return e->code;
    }
    int dim = m->dim, nv = m->nv;
    header(o, rec);
    fprintf(o, "  nnew %lld\n", (long long)d.nnew);
    aug_cur c = mem_cur(d.parent, (uint64_t)d.nnew * 4);
    arr_i32(o, "parent", &c, (uint64_t)d.nnew);
    c = mem_cur(d.x, (uint64_t)d.nnew * dim * 8);
    rows_f64(o, "x", &c, (uint64_t)d.nnew, dim);
    fprintf(o, "  nmod %lld\n", (long long)d.nmod);
    c = mem_cur(d.elem, (uint64_t)d.nmod * 4);
    arr_i32(o, "elem", &c, (uint64_t)d.nmod);
    c = mem_cur(d.conn, (uint64_t)d.nmod * nv * 4);
    rows_i32(o, "conn", &c, (uint64_t)d.nmod, nv);
    fprintf(o, "  nadd %lld\n", (long long)d.nadd);
    c = mem_cur(d.conn_add, (uint64_t)d.nadd * nv * 4);
    rows_i32(o, "conn_add", &c, (uint64_t)d.nadd, nv);
    c = mem_cur(d.mat_add, (uint64_t)d.nadd * 4);
    arr_i32(o, "mat_add", &c, (uint64_t)d.nadd);
    fprintf(o, "  flags %d\n", (int)d.flags);
    aug_mdelta_free(&d);
    return 0;
}

static int d_bdlt(FILE *o, const aug_rec *rec, aug_err *e)
{
    aug_bdelta b;
    aug_bdelta_init(&b);
    if (aug_read_bdelta(rec, &b, e)) {
        aug_bdelta_free(&b);
        return e->code;
    }
    header(o, rec);
    fprintf(o, "  nfix %lld\n", (long long)b.nfix);
    aug_cur c = mem_cur(b.fix_dof, (uint64_t)b.nfix * 4);
    arr_i32(o, "dof", &c, (uint64_t)b.nfix);
    c = mem_cur(b.fix_val, (uint64_t)b.nfix * 8);
    arr_f64(o, "value", &c, (uint64_t)b.nfix);
    fprintf(o, "  nload %lld\n", (long long)b.nload);
    c = mem_cur(b.load_dof, (uint64_t)b.nload * 4);
    arr_i32(o, "ldof", &c, (uint64_t)b.nload);
    c = mem_cur(b.load_val, (uint64_t)b.nload * 8);
    arr_f64(o, "lvalue", &c, (uint64_t)b.nload);
    aug_bdelta_free(&b);
    return 0;
}

static int d_updt(FILE *o, const aug_rec *rec, aug_err *e)
{
    aug_update u;
    if (aug_read_update(rec, &u, e)) {
        aug_update_free(&u);
        return e->code;
    }
    uint64_t s = (uint64_t)u.m + (uint64_t)u.k;
    header(o, rec);
    fprintf(o, "  m %d\n  k %d\n", (int)u.m, (int)u.k);
    aug_cur c = mem_cur(u.H, (uint64_t)u.m * 4);
    arr_i32(o, "H", &c, (uint64_t)u.m);
    c = mem_cur(u.E, s * s * 8);
    arr_f64(o, "E", &c, s * s);
    c = mem_cur(u.df, s * 8);
    arr_f64(o, "df", &c, s);
    aug_update_free(&u);
    return 0;
}

static void d_path(FILE *o, const aug_rec *rec)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t dim = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t nseg = aug_cur_i64(&c);
    fprintf(o, "  dim %d\n  nseg %lld\n", (int)dim, (long long)nseg);
    rows_f64(o, "p", &c, (uint64_t)nseg, 2 * dim);
}

static void d_feld(FILE *o, const aug_rec *rec)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t kind = aug_cur_i32(&c), dim = aug_cur_i32(&c);
    int64_t count = aug_cur_i64(&c);
    int32_t indexed = aug_cur_i32(&c);
    aug_cur_i32(&c);
    fprintf(o, "  kind %d\n  dim %d\n  count %lld\n  indexed %d\n", (int)kind, (int)dim,
            (long long)count, (int)indexed);
    if (indexed) arr_i32(o, "node", &c, (uint64_t)count);
    rows_f64(o, "u", &c, (uint64_t)count, dim);
}

static int is(const aug_rec *rec, const char *t) { return memcmp(rec->type, t, 4) == 0; }

/* decode (and so validate) first, then print: a bad record prints nothing */
int aug_dump_record(FILE *out, aug_dump *d, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    if (d->no_times && is(rec, "tIMe")) return 0;
    int rc = 0;
    if (aug_mesh_is_record(rec->type)) rc = d_mesh(out, &d->mesh, rec, e);
    else if (is(rec, "cOND") || is(rec, "sTAt") || is(rec, "tIMe") || is(rec, "qUAl"))
        rc = d_kv(out, rec, e);
    else if (is(rec, "MDLT")) rc = d_mdlt(out, &d->mesh, rec, e);
    else if (is(rec, "UPDT")) rc = d_updt(out, rec, e);
    else if (is(rec, "BDLT")) rc = d_bdlt(out, rec, e);
    else if (aug_check_payload(rec, e)) rc = e->code;
    else {
        header(out, rec);
        if (is(rec, "pROv")) d_prov(out, rec);
        else if (is(rec, "DOFM")) d_dofm(out, rec);
        else if (is(rec, "KMAT")) d_kmat(out, rec);
        else if (is(rec, "FVEC")) d_fvec(out, rec);
        else if (is(rec, "FACT")) d_fact(out, rec);
        else if (is(rec, "pATH")) d_path(out, rec);
        else if (is(rec, "fELD")) d_feld(out, rec);
        else if (is(rec, "TAIL")) {
            aug_cur c;
            aug_cur_init(&c, rec);
            fprintf(out, "  count %llu\n", (unsigned long long)aug_cur_i64(&c));
        } else
            hex(out, rec); /* MODE (layout reserved) and unknown ancillary records */
    }
    if (rc) return rc;
    if (ferror(out)) return aug_err_set(e, AUG_EIO, rec->index, rec->type, "write failed");
    return 0;
}
