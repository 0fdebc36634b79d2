/* libFuzzer target: every record's codec (formats/stream.md 3.3) on its own:
   check, dump, and the typed reader; what a reader accepts is written again
   by its typed writer and must be read back and pass the check. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "fuzz_util.h"

typedef int (*put_fn)(aug_writer *w, const void *obj, aug_err *e);

/* obj through put into a one-record stream (deflated from 64 bytes on when
   deflate is set), read back and checked; returns the stream (free it) */
static char *roundtrip(const char *type, put_fn put, const void *obj, int deflate, size_t *len)
{
    char *buf = NULL;
    aug_err e;
    *len = 0;
    FILE *f = open_memstream(&buf, len);
    if (!f) return NULL;
    aug_writer *w = aug_writer_open(f, "fuzz", &e);
    if (w && deflate) aug_writer_deflate(w, 64);
    int rc = w ? put(w, obj, &e) : AUG_ENOMEM;
    if (!rc) rc = aug_writer_close(w, &e);
    aug_writer_free(w);
    fclose(f);
    if (rc && rc != AUG_ENOMEM) fuzz_fail("%s: its writer refuses what its reader accepted: %s", type, e.msg);
    if (rc) {
        free(buf);
        return NULL;
    }
    fuzz_in in;
    if (fuzz_open(&in, buf, *len, &e)) fuzz_fail("%s: the written stream does not open: %s", type, e.msg);
    while ((rc = aug_read(in.r, &in.rec, &e)) == 1)
        if (aug_check_payload(&in.rec, &e)) fuzz_fail("%s: written by its codec, fails its check: %s", type, e.msg);
    if (rc < 0) fuzz_fail("%s: the written stream does not read back: %s", type, e.msg);
    fuzz_close(&in);
    return buf;
}

static void roundtrip1(const char *type, put_fn put, const void *obj, int deflate)
{
    size_t len;
    free(roundtrip(type, put, obj, deflate, &len));
}

/* the same object stored in another order must be written byte for byte alike */
static void same(const char *type, char *a, size_t na, char *b, size_t nb)
{
    if (a && b && (na != nb || memcmp(a, b, na)))
        fuzz_fail("%s: written differently when its columns are stored out of order", type);
    free(a);
    free(b);
}

/* reverse the entries of every column p[j] .. p[j] + cnt(j) (rows and values together) */
static void reverse_columns(const int *p, const int *nz, int packed, int *i, double *x, size_t n)
{
    for (size_t j = 0; j < n; j++)
        for (int a = p[j], z = p[j] + (packed ? p[j + 1] - p[j] : nz[j]) - 1; a < z; a++, z--) {
            int t = i[a];
            double v = x[a];
            i[a] = i[z], x[a] = x[z];
            i[z] = t, x[z] = v;
        }
}

typedef struct sparse_obj {
    int which;
    cholmod_sparse *A;
    cholmod_factor *L;
    cholmod_common *cm;
} sparse_obj;

static int put_sparse(aug_writer *w, const void *o, aug_err *e)
{
    const sparse_obj *s = o;
    return aug_write_sparse(w, s->which, s->A, e);
}

static int put_factor(aug_writer *w, const void *o, aug_err *e)
{
    const sparse_obj *s = o;
    return aug_write_factor(w, s->L, s->cm, e);
}

typedef struct vec_obj {
    const char *type;
    int32_t step, kind;
    int dim;
    int64_t n, nfree;
    int32_t *idx;
    double *v;
} vec_obj;

static int put_vector(aug_writer *w, const void *o, aug_err *e)
{
    const vec_obj *v = o;
    return aug_write_vector(w, v->type, v->step, v->kind, v->v, v->n, e);
}

static int put_field(aug_writer *w, const void *o, aug_err *e)
{
    const vec_obj *v = o;
    return aug_write_field(w, v->step, v->kind, v->dim, v->n, v->idx, v->v, e);
}

static int put_dofmap(aug_writer *w, const void *o, aug_err *e)
{
    const vec_obj *v = o;
    aug_mesh m;
    aug_mesh_init(&m);
    m.dim = v->dim;
    m.nn = v->n / v->dim;
    return aug_write_dofmap(w, &m, v->idx, v->nfree, e);
}

typedef struct step_obj {
    int dim, nv;
    const char *type;
    int32_t step;
    aug_mdelta d;
    aug_update u;
    aug_bdelta b;
    aug_pathrec p;
    aug_kv kv;
    aug_reaction q;
    aug_moderec mode;
    const aug_mesh *m;
} step_obj;

static int put_mdelta(aug_writer *w, const void *o, aug_err *e)
{
    const step_obj *s = o;
    return aug_write_mdelta(w, s->dim, s->nv, &s->d, e);
}
static int put_update(aug_writer *w, const void *o, aug_err *e)
{
    return aug_write_update(w, &((const step_obj *)o)->u, e);
}
static int put_bdelta(aug_writer *w, const void *o, aug_err *e)
{
    return aug_write_bdelta(w, &((const step_obj *)o)->b, e);
}
static int put_path(aug_writer *w, const void *o, aug_err *e)
{
    return aug_write_path(w, &((const step_obj *)o)->p, e);
}
static int put_reaction(aug_writer *w, const void *o, aug_err *e)
{
    const step_obj *s = o;
    return aug_write_reaction(w, s->step, &s->q, e);
}
static int put_mode(aug_writer *w, const void *o, aug_err *e)
{
    const step_obj *s = o;
    return aug_write_mode(w, s->step, &s->mode, e);
}
static int put_kv(aug_writer *w, const void *o, aug_err *e)
{
    const step_obj *s = o;
    return aug_write_kv(w, s->type, s->step, &s->kv, e);
}
static int put_prov(aug_writer *w, const void *o, aug_err *e)
{
    char *argv[] = {(char *)o};
    return aug_write_prov(w, 1, argv, e);
}
static int put_plan(aug_writer *w, const void *o, aug_err *e)
{
    const int32_t *fl = o;
    return aug_write_plan(w, fl[0], fl[1], e);
}
static int put_mesh(aug_writer *w, const void *o, aug_err *e)
{
    return aug_mesh_write(w, ((const step_obj *)o)->m, e);
}

static int is(const aug_rec *rec, const char *type) { return !memcmp(rec->type, type, 4); }

/* a KMAT of a positive definite K factored as factor does it (supernodal LL'
   or simplicial LDL'), written as FACT and read back */
static void factor_kmat(cholmod_sparse *A, cholmod_common *cm, int simplicial)
{
    aug_err e;
    if (A->nrow > 2000) return;
    aug_factor_options(cm, AUG_ORDER_AMD, simplicial);
    sparse_obj s = {0, NULL, aug_analyze(A, cm, &e), cm};
    int ok = s.L && !aug_factorize(A, s.L, NULL, NULL, cm, &e);
    /* a finite K may overflow in its factor: factor's business (issue 12, item 3), not the codec's */
    for (size_t k = 0; ok && s.L->is_super && k < s.L->xsize; k++) ok = isfinite(((double *)s.L->x)[k]);
    for (size_t j = 0; ok && !s.L->is_super && j < s.L->n; j++)
        for (int q = 0; ok && q < ((int *)s.L->nz)[j]; q++) ok = isfinite(((double *)s.L->x)[((int *)s.L->p)[j] + q]);
    if (ok) roundtrip1("FACT (factored)", put_factor, &s, 0);
    cholmod_free_factor(&s.L, cm);
}

/* the matrix family and the factor */
static void typed_matrix(const aug_rec *rec, cholmod_common *cm)
{
    aug_err e;
    sparse_obj s = {0, NULL, NULL, cm};
    vec_obj v;
    memset(&v, 0, sizeof v);
    v.type = rec->type;
    v.step = rec->step;
    size_t na, nb;
    if (is(rec, "KMAT") && (s.A = aug_read_sparse(rec, &s.which, cm, &e))) {
        char *a = roundtrip("KMAT", put_sparse, &s, 0, &na);
        reverse_columns(s.A->p, s.A->nz, s.A->packed, s.A->i, s.A->x, s.A->ncol);
        s.A->sorted = 0;
        same("KMAT", a, na, roundtrip("KMAT", put_sparse, &s, 0, &nb), nb);
        reverse_columns(s.A->p, s.A->nz, s.A->packed, s.A->i, s.A->x, s.A->ncol);
        s.A->sorted = 1;
        factor_kmat(s.A, cm, (int)(rec->index % 2));
        cholmod_free_sparse(&s.A, cm);
    } else if (is(rec, "FACT") && (s.L = aug_read_factor(rec, cm, &e))) {
        char *a = roundtrip("FACT", put_factor, &s, rec->index % 2, &na);
        reverse_columns(s.L->p, s.L->nz, 0, s.L->i, s.L->x, s.L->n);
        same("FACT", a, na, roundtrip("FACT", put_factor, &s, rec->index % 2, &nb), nb);
        cholmod_free_factor(&s.L, cm);
    } else if (is(rec, "FVEC") && !aug_read_vector(rec, &v.kind, &v.n, &v.v, &e)) {
        roundtrip1("FVEC", put_vector, &v, rec->index % 2);
    } else if (is(rec, "DOFM") && !aug_read_dofmap(rec, &v.dim, &v.n, &v.nfree, &v.idx, &e)) {
        if (v.dim > 0 && v.n % v.dim == 0) roundtrip1("DOFM", put_dofmap, &v, rec->index % 2);
    } else if (is(rec, "fELD")) {
        if (!aug_read_field(rec, &v.kind, &v.dim, &v.n, &v.idx, &v.v, &e)) roundtrip1("fELD", put_field, &v, rec->index % 2);
    }
    free(v.idx);
    free(v.v);
}

/* the step family and the named-value records; MDLT needs the mesh's sizes */
static void typed_step(const aug_rec *rec, const aug_mesh *m)
{
    aug_err e;
    step_obj s;
    memset(&s, 0, sizeof s);
    s.type = rec->type;
    s.step = rec->step;
    aug_mdelta_init(&s.d);
    aug_update_init(&s.u);
    aug_bdelta_init(&s.b);
    char *text = NULL;
    if (is(rec, "MDLT") && (m->have & (AUG_HAVE_NODE | AUG_HAVE_ELEM)) == (AUG_HAVE_NODE | AUG_HAVE_ELEM)) {
        s.dim = m->dim, s.nv = m->nv;
        if (!aug_read_mdelta(rec, s.dim, s.nv, &s.d, &e)) roundtrip1("MDLT", put_mdelta, &s, rec->index % 2);
    } else if (is(rec, "UPDT")) {
        if (!aug_read_update(rec, &s.u, &e)) roundtrip1("UPDT", put_update, &s, rec->index % 2);
    } else if (is(rec, "BDLT")) {
        if (!aug_read_bdelta(rec, &s.b, &e)) roundtrip1("BDLT", put_bdelta, &s, rec->index % 2);
    } else if (is(rec, "pATH")) {
        if (!aug_read_path(rec, &s.p, &e)) roundtrip1("pATH", put_path, &s, rec->index % 2);
    } else if (is(rec, "rEAC")) {
        if (!aug_read_reaction(rec, &s.q, &e)) roundtrip1("rEAC", put_reaction, &s, rec->index % 2);
    } else if (is(rec, "MODE")) {
        if (!aug_read_mode(rec, &s.mode, &e)) roundtrip1("MODE", put_mode, &s, rec->index % 2);
    } else if (is(rec, "cOND") || is(rec, "sTAt") || is(rec, "tIMe") || is(rec, "qUAl")) {
        if (!aug_read_kv(rec, &s.kv, &e)) roundtrip1(rec->type, put_kv, &s, rec->index % 2);
    } else if (is(rec, "pROv") && !aug_read_prov(rec, &text, &e)) {
        roundtrip1("pROv", put_prov, text, rec->index % 2);
    } else if (is(rec, "pLAN")) {
        int32_t fl[2];
        if (!aug_read_plan(rec, &fl[0], &fl[1], &e)) roundtrip1("pLAN", put_plan, fl, rec->index % 2);
    }
    free(text);
    aug_mdelta_free(&s.d);
    aug_update_free(&s.u);
    aug_bdelta_free(&s.b);
    aug_pathrec_free(&s.p);
    aug_reaction_free(&s.q);
    aug_moderec_free(&s.mode);
}

/* the payload through the check and dump of another record type whose length
   bounds it meets (chosen by its index and length): codecs must refuse what
   is not theirs without reading past it */
static void confused(const aug_rec *rec, aug_mesh *m)
{
    size_t n = 0, k;
    while (aug_rectype_at(n)) n++;
    const aug_rectype *t = aug_rectype_at(k = (size_t)(rec->index + rec->len) % n);
    for (size_t i = 1; i < n && (rec->len < t->minlen || rec->len > t->maxlen); i++)
        t = aug_rectype_at((k + i) % n);
    if (rec->len < t->minlen || rec->len > t->maxlen) return;
    aug_rec c = *rec;
    aug_err e;
    memcpy(c.type, t->type, 5);
    aug_check_payload(&c, &e);
    aug_dump_rec(fuzz_devnull(), m, &c, &e);
}

/* records passed through byte for byte (aug_write_rec of a copy, as a tool
   holding a step does) make a stream that reads back whole */
static void pass_through(fuzz_in *in)
{
    char *buf = NULL;
    size_t len = 0;
    aug_err e;
    aug_rec copy;
    FILE *f = open_memstream(&buf, &len);
    aug_writer *w = f ? aug_writer_open(f, "fuzz", &e) : NULL;
    while (w && aug_read(in->r, &in->rec, &e) == 1)
        if (!aug_rec_copy(&copy, &in->rec, &e)) {
            aug_write_rec(w, &copy, &e);
            aug_rec_free(&copy);
        }
    int whole = w && !aug_writer_close(w, &e);
    aug_writer_free(w);
    if (f) fclose(f);
    fuzz_in q;
    int rc = whole ? fuzz_open(&q, buf, len, &e) : 0;
    while (whole && rc == 0 && (rc = aug_read(q.r, &q.rec, &e)) == 1) rc = 0;
    if (whole && rc != 0) fuzz_fail("records passed through do not read back: %s", e.msg);
    if (whole) fuzz_close(&q);
    free(buf);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_in in;
    aug_err e;
    if (fuzz_open(&in, data, size, &e)) return 0;
    aug_mesh dm, mm;  /* the dump's mesh, the typed readers' mesh */
    aug_mesh_init(&dm);
    aug_mesh_init(&mm);
    cholmod_common cm;
    aug_cholmod_start(&cm);
    aug_dump_head(fuzz_devnull(), in.r, &e);
    int mesh_ok = 1, rc;
    aug_mesh xm;  /* the mesh of the confused dumps */
    aug_mesh_init(&xm);
    while ((rc = aug_read(in.r, &in.rec, &e)) == 1) {
        int checked = aug_check_payload(&in.rec, &e) == 0;
        int dumped = aug_dump_rec(fuzz_devnull(), &dm, &in.rec, &e) == 0;
        if (dumped && !checked)
            fuzz_fail("%s: dumped but refused by its check", in.rec.type);
        if (aug_mesh_is_record(in.rec.type)) mesh_ok = mesh_ok && !aug_mesh_absorb(&mm, &in.rec, &e);
        else typed_matrix(&in.rec, &cm), typed_step(&in.rec, &dm);
        confused(&in.rec, &xm);
    }
    if (rc == 0) { /* TAIL, as stats --dump ends */
        aug_check_payload(&in.rec, &e);
        aug_dump_rec(fuzz_devnull(), &dm, &in.rec, &e);
    }
    aug_mesh_free(&xm);
    step_obj s;
    memset(&s, 0, sizeof s);
    s.m = &mm;
    if (mesh_ok && mm.have && !aug_mesh_validate(&mm, &e)) roundtrip1("mesh", put_mesh, &s, size % 2);
    aug_mesh_free(&dm);
    aug_mesh_free(&mm);
    cholmod_finish(&cm);
    fuzz_close(&in);
    if (!fuzz_open(&in, data, size, &e)) {
        pass_through(&in);
        fuzz_close(&in);
    }
    return 0;
}
