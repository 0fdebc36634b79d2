/* libFuzzer target: every record's codec (formats/stream.md 3.3) on its own:
   check, dump, and the typed reader; what a reader accepts is written again
   by its typed writer and must be read back and pass the check. */
#include <stdlib.h>
#include <string.h>
#include "fuzz_util.h"

typedef int (*put_fn)(aug_writer *w, const void *obj, aug_err *e);

/* obj through put into a one-record stream, then read back and checked */
static void roundtrip(const char *type, put_fn put, const void *obj)
{
    char *buf = NULL;
    size_t len = 0;
    aug_err e;
    FILE *f = open_memstream(&buf, &len);
    if (!f) return;
    aug_writer *w = aug_writer_open(f, "fuzz", &e);
    int rc = w ? put(w, obj, &e) : AUG_ENOMEM;
    if (!rc) rc = aug_writer_close(w, &e);
    aug_writer_free(w);
    fclose(f);
    if (rc && rc != AUG_ENOMEM) fuzz_fail("%s: its writer refuses what its reader accepted: %s", type, e.msg);
    FILE *g = rc ? NULL : fmemopen(buf, len, "rb");
    aug_reader *r = g ? aug_reader_open(g, "roundtrip", &e) : NULL;
    if (g && !r) fuzz_fail("%s: the written stream does not open: %s", type, e.msg);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    while (r && (rc = aug_read(r, &rec, &e)) == 1)
        if (aug_check_payload(&rec, &e)) fuzz_fail("%s: written by its codec, fails its check: %s", type, e.msg);
    if (r && rc < 0) fuzz_fail("%s: the written stream does not read back: %s", type, e.msg);
    if (r) fuzz_close(r, g, &rec);
    free(buf);
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
static int put_kv(aug_writer *w, const void *o, aug_err *e)
{
    const step_obj *s = o;
    return aug_write_kv(w, s->type, s->step, &s->kv, e);
}
static int put_mesh(aug_writer *w, const void *o, aug_err *e)
{
    return aug_mesh_write(w, ((const step_obj *)o)->m, e);
}

static int is(const aug_rec *rec, const char *type) { return !memcmp(rec->type, type, 4); }

/* the matrix family and the factor */
static void typed_matrix(const aug_rec *rec, cholmod_common *cm)
{
    aug_err e;
    sparse_obj s = {0, NULL, NULL, cm};
    vec_obj v;
    memset(&v, 0, sizeof v);
    v.type = rec->type;
    v.step = rec->step;
    if (is(rec, "KMAT") && (s.A = aug_read_sparse(rec, &s.which, cm, &e))) {
        roundtrip("KMAT", put_sparse, &s);
        cholmod_free_sparse(&s.A, cm);
    } else if (is(rec, "FACT") && (s.L = aug_read_factor(rec, cm, &e))) {
        roundtrip("FACT", put_factor, &s);
        cholmod_free_factor(&s.L, cm);
    } else if (is(rec, "FVEC") && !aug_read_vector(rec, &v.kind, &v.n, &v.v, &e)) {
        roundtrip("FVEC", put_vector, &v);
    } else if (is(rec, "DOFM") && !aug_read_dofmap(rec, &v.dim, &v.n, &v.nfree, &v.idx, &e)) {
        if (v.dim > 0 && v.n % v.dim == 0) roundtrip("DOFM", put_dofmap, &v);
    } else if (is(rec, "fELD")) {
        if (!aug_read_field(rec, &v.kind, &v.dim, &v.n, &v.idx, &v.v, &e)) roundtrip("fELD", put_field, &v);
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
        if (!aug_read_mdelta(rec, s.dim, s.nv, &s.d, &e)) roundtrip("MDLT", put_mdelta, &s);
    } else if (is(rec, "UPDT")) {
        if (!aug_read_update(rec, &s.u, &e)) roundtrip("UPDT", put_update, &s);
    } else if (is(rec, "BDLT")) {
        if (!aug_read_bdelta(rec, &s.b, &e)) roundtrip("BDLT", put_bdelta, &s);
    } else if (is(rec, "pATH")) {
        if (!aug_read_path(rec, &s.p, &e)) roundtrip("pATH", put_path, &s);
    } else if (is(rec, "cOND") || is(rec, "sTAt") || is(rec, "tIMe") || is(rec, "qUAl")) {
        if (!aug_read_kv(rec, &s.kv, &e)) roundtrip(rec->type, put_kv, &s);
    } else if (is(rec, "pROv")) {
        aug_read_prov(rec, &text, &e);
    }
    free(text);
    aug_mdelta_free(&s.d);
    aug_update_free(&s.u);
    aug_bdelta_free(&s.b);
    aug_pathrec_free(&s.p);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    FILE *f;
    aug_reader *r = fuzz_open(data, size, &f);
    if (!r) return 0;
    aug_err e;
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    aug_mesh dm, mm;  /* the dump's mesh, the typed readers' mesh */
    aug_mesh_init(&dm);
    aug_mesh_init(&mm);
    cholmod_common cm;
    aug_cholmod_start(&cm);
    aug_dump_head(fuzz_devnull(), r, &e);
    int mesh_ok = 1;
    while (aug_read(r, &rec, &e) == 1) {
        int checked = aug_check_payload(&rec, &e) == 0;
        int dumped = aug_dump_rec(fuzz_devnull(), &dm, &rec, &e) == 0;
        if (dumped && !checked)
            fuzz_fail("%s: dumped but refused by its check", rec.type);
        if (aug_mesh_is_record(rec.type)) mesh_ok = mesh_ok && !aug_mesh_absorb(&mm, &rec, &e);
        else typed_matrix(&rec, &cm), typed_step(&rec, &dm);
    }
    step_obj s;
    memset(&s, 0, sizeof s);
    s.m = &mm;
    if (mesh_ok && mm.have && !aug_mesh_validate(&mm, &e)) roundtrip("mesh", put_mesh, &s);
    aug_mesh_free(&dm);
    aug_mesh_free(&mm);
    cholmod_finish(&cm);
    fuzz_close(r, f, &rec);
    return 0;
}
