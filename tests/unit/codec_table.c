/* Every record type goes through its one codec: a record of each type written by
   its writer passes its check, dumps, and read by its typed reader and written
   again gives the same payload bytes; every row of the record table has a codec. */
#include <math.h>
#include <string.h>
#include "augcut.h"
#include "aug_scene.h"
#include "fem_mesh.h"
#include "t.h"

static cholmod_common cm;

static void test_every_row_has_a_codec(void)
{
    for (size_t i = 0; aug_rectype_at(i); i++) {
        const aug_rectype *t = aug_rectype_at(i);
        T_CHECK(t->codec && t->codec->dump && t->codec->file, "%s: no codec", t->type);
        if (!t->codec) continue;
        /* only records whose layout is free text or needs the mesh lack a check */
        int nocheck = !strcmp(t->type, "pROv") || !strcmp(t->type, "MDLT");
        T_CHECK((t->codec->check == NULL) == nocheck, "%s: check %s", t->type,
                t->codec->check ? "present" : "missing");
    }
}

/* writes one record of every type but HEAD/TAIL (the writer frames those) */
static int write_all(aug_writer *w, const aug_mesh *m, const int32_t *map, int64_t nfree,
                     cholmod_sparse *K, cholmod_factor *L, const double *f, aug_err *e)
{
    char *argv[] = {"codec_table", "--opt", "v"};
    if (aug_write_prov(w, 3, argv, e) || aug_mesh_write(w, m, e) ||
        aug_write_dofmap(w, m, map, nfree, e) || aug_write_sparse(w, AUG_MAT_K, K, e) ||
        aug_write_vector(w, "FVEC", AUG_NOSTEP, 0, f, nfree, e) || aug_write_factor(w, L, &cm, e))
        return -1;
    aug_kv kv;
    aug_kv_init(&kv, "amps");
    aug_kv_set(&kv, "relres", 1e-15);
    if (aug_write_kv(w, "cOND", AUG_NOSTEP, &kv, e)) return -1;
    int32_t parent[1] = {1}, elem[1] = {0}, conn[4], hdof[2] = {3, 7};
    double x[3] = {0.25, 0.5, 0.75};
    memcpy(conn, m->conn, sizeof conn);
    conn[0] = (int32_t)m->nn;
    aug_mdelta d = {1, 1, parent, x, 1, elem, conn, 0, NULL, NULL, 0};
    double E[25], df[5];
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 5; j++) E[i + 5 * j] = 1.0 / (1 + i + j);
    for (int i = 0; i < 5; i++) df[i] = i - 2.5;
    aug_update u = {1, 2, 3, hdof, E, df, NULL, NULL, NULL};
    int32_t fd[2] = {4, 9};
    double fv[2] = {0, 0.125}, seg[6] = {0, 0, 0, 1, 1, 1};
    aug_bdelta b = {1, 2, fd, fv, 1, fd, fv, 2, 1};
    aug_pathrec p = {1, 3, 1, seg};
    double *uf = malloc((size_t)m->nn * 3 * sizeof *uf);
    for (int64_t i = 0; i < m->nn * 3; i++) uf[i] = 1e-3 * (double)i;
    int32_t nodes[2] = {0, 5}, rdof[3] = {0, 2, 7};
    double rv[3] = {0.5, -1.25, 2}, res[3] = {0.5, 0, -1.25};
    char rname[1][AUG_NAME] = {"pair"};
    aug_reaction q = {3, 0, 0, 3, rdof, rv, {0.5, 2, -1.25}, 1, rname, res, 0, 0};
    int rc = aug_write_mdelta(w, 3, 4, &d, e) || aug_write_bdelta(w, &b, e) ||
             aug_write_update(w, &u, e) || aug_write_path(w, &p, e) ||
             aug_write_field(w, 1, 0, 3, m->nn, NULL, uf, e) ||
             aug_write_field(w, 1, 0, 3, 2, nodes, uf, e) || aug_write_reaction(w, 1, &q, e) ||
             aug_write_kv(w, "sTAt", 1, &kv, e) ||
             aug_write_kv(w, "tIMe", 1, &kv, e) || aug_write_kv(w, "qUAl", 1, &kv, e);
    double sig[2] = {1.5, 0.25};
    aug_moderec mr = {0, 2, 3, AUG_MODE_SNAPSHOT, 2, 2, nodes, sig, uf};
    rc = rc || aug_write_mode(w, 1, &mr, e);
    free(uf);
    return rc ? -1 : 0;
}

/* the record decoded by its typed reader and written again by its writer */
static int rewrite(aug_writer *w, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    const char *t = rec->type;
    int rc = 0;
    if (aug_mesh_is_record(t)) return aug_mesh_absorb(m, rec, e);   /* written whole below */
    if (!strcmp(t, "pROv")) {
        char *s;
        if (aug_read_prov(rec, &s, e)) return -1;
        rc = aug_write(w, "pROv", AUG_NOSTEP, s, strlen(s), e);
        free(s);
    } else if (!strcmp(t, "DOFM")) {
        int dim;
        int64_t nd, nf;
        int32_t *map;
        if (aug_read_dofmap(rec, &dim, &nd, &nf, &map, e)) return -1;
        if (aug_mesh_write(w, m, e)) return -1;
        rc = aug_write_dofmap(w, m, map, nf, e);
        free(map);
    } else if (!strcmp(t, "KMAT")) {
        int which;
        cholmod_sparse *A = aug_read_sparse(rec, &which, &cm, e);
        if (!A) return -1;
        rc = aug_write_sparse(w, which, A, e);
        cholmod_free_sparse(&A, &cm);
    } else if (!strcmp(t, "FVEC")) {
        int32_t kind;
        int64_t n;
        double *v;
        if (aug_read_vector(rec, &kind, &n, &v, e)) return -1;
        rc = aug_write_vector(w, "FVEC", rec->step, kind, v, n, e);
        free(v);
    } else if (!strcmp(t, "FACT")) {
        cholmod_factor *L = aug_read_factor(rec, &cm, e);
        if (!L) return -1;
        rc = aug_write_factor(w, L, &cm, e);
        cholmod_free_factor(&L, &cm);
    } else if (!strcmp(t, "MDLT")) {
        aug_mdelta d;
        rc = aug_read_mdelta(rec, m->dim, m->nv, &d, e) || aug_write_mdelta(w, m->dim, m->nv, &d, e);
        aug_mdelta_free(&d);
    } else if (!strcmp(t, "UPDT")) {
        aug_update u;
        rc = aug_read_update(rec, &u, e) || aug_write_update(w, &u, e);
        aug_update_free(&u);
    } else if (!strcmp(t, "BDLT")) {
        aug_bdelta b;
        rc = aug_read_bdelta(rec, &b, e) || aug_write_bdelta(w, &b, e);
        aug_bdelta_free(&b);
    } else if (!strcmp(t, "pATH")) {
        aug_pathrec p;
        rc = aug_read_path(rec, &p, e) || aug_write_path(w, &p, e);
        aug_pathrec_free(&p);
    } else if (!strcmp(t, "fELD")) {
        int32_t kind, *nodes;
        int dim;
        int64_t n;
        double *u;
        rc = aug_read_field(rec, &kind, &dim, &n, &nodes, &u, e) ||
             aug_write_field(w, rec->step, kind, dim, n, nodes, u, e);
        free(nodes);
        free(u);
    } else if (!strcmp(t, "rEAC")) {
        aug_reaction q;
        memset(&q, 0, sizeof q);
        rc = aug_read_reaction(rec, &q, e) || aug_write_reaction(w, rec->step, &q, e);
        aug_reaction_free(&q);
    } else if (!strcmp(t, "MODE")) {
        aug_moderec q;
        rc = aug_read_mode(rec, &q, e) || aug_write_mode(w, rec->step, &q, e);
        aug_moderec_free(&q);
    } else {
        aug_kv kv;
        rc = aug_read_kv(rec, &kv, e) || aug_write_kv(w, t, rec->step, &kv, e);
    }
    return rc ? -1 : 0;
}

typedef struct recs {
    int n;
    char type[64][5];
    unsigned char *p[64];
    uint64_t len[64];
} recs;

/* read a stream: every record checked and dumped; optionally rewritten to w */
static int read_back(FILE *f, aug_writer *w, recs *out, aug_err *e)
{
    aug_reader *r = aug_reader_open(f, "mem", e);
    if (!r) return -1;
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    aug_mesh m, dm;
    aug_mesh_init(&m);
    aug_mesh_init(&dm);
    FILE *dump = fopen("/dev/null", "w");
    int rc;
    out->n = 0;
    while ((rc = aug_read(r, &rec, e)) == 1 && out->n < 64) {
        const aug_rectype *t = aug_rectype_find(rec.type);
        if (!t || aug_check_payload(&rec, e) || aug_dump_rec(dump, &dm, &rec, e) ||
            (w && rewrite(w, &m, &rec, e))) {
            rc = -1;
            break;
        }
        memcpy(out->type[out->n], rec.type, 5);
        out->p[out->n] = malloc(rec.len + 1);
        memcpy(out->p[out->n], rec.data, rec.len);
        out->len[out->n++] = rec.len;
    }
    fclose(dump);
    aug_rec_free(&rec);
    aug_reader_free(r);
    aug_mesh_free(&m);
    aug_mesh_free(&dm);
    return rc;
}

static void test_every_type_round_trips(void)
{
    aug_mesh m;
    tm_box(&m, 2, 2, 2, 1, 1, 1, 100.0, 0.3);
    tm_fix_plane(&m, 2, 0.0, NULL);
    m.sets = calloc(1, sizeof *m.sets);
    m.nset = 1;
    snprintf(m.sets[0].name, AUG_NAME, "pair");
    m.sets[0].n = 2;
    m.sets[0].nodes = malloc(2 * sizeof(int32_t));
    m.sets[0].nodes[0] = 1, m.sets[0].nodes[1] = 3;
    int32_t *map = malloc((size_t)m.nn * 3 * sizeof *map);
    int64_t nfree = aug_dofmap(&m, map);
    aug_err e;
    cholmod_sparse *K = aug_assemble(&m, map, nfree, AUG_MAT_K, &cm, &e);
    T_CHECK(K != NULL, "assemble: %s", e.msg);
    if (!K) return;
    cm.supernodal = CHOLMOD_SIMPLICIAL;
    cholmod_factor *L = cholmod_analyze(K, &cm);
    cholmod_factorize(K, L, &cm);
    double *f = malloc((size_t)nfree * sizeof *f);
    for (int64_t i = 0; i < nfree; i++) f[i] = cos(0.5 + i);
    FILE *a = tmpfile(), *b = tmpfile();
    aug_writer *w = aug_writer_open(a, "test", &e);
    T_CHECK(write_all(w, &m, map, nfree, K, L, f, &e) == 0 && aug_writer_close(w, &e) == 0,
            "write: %s", e.msg);
    aug_writer_free(w);
    rewind(a);
    recs ra, rb;
    aug_writer *w2 = aug_writer_open(b, "test", &e);
    T_CHECK(read_back(a, w2, &ra, &e) == 0, "read/rewrite: %s", e.msg);
    T_CHECK(aug_writer_close(w2, &e) == 0, "close: %s", e.msg);
    aug_writer_free(w2);
    rewind(b);
    T_CHECK(read_back(b, NULL, &rb, &e) == 0, "read rewritten: %s", e.msg);
    /* the mesh records of the rewrite come at DOFM: compare as multisets by type order */
    T_CHECK(ra.n == rb.n && ra.n >= 20, "%d records, rewritten %d", ra.n, rb.n);
    int seen[64] = {0};
    for (int i = 0; i < ra.n; i++) {
        int found = 0;
        for (int j = 0; j < rb.n && !found; j++)
            if (!seen[j] && !strcmp(ra.type[i], rb.type[j]) && ra.len[i] == rb.len[j] &&
                !memcmp(ra.p[i], rb.p[j], ra.len[i]))
                seen[j] = found = 1;
        T_CHECK(found, "record %d (%s) does not round-trip", i, ra.type[i]);
    }
    for (int i = 0; i < ra.n; i++) free(ra.p[i]);
    for (int i = 0; i < rb.n; i++) free(rb.p[i]);
    fclose(a);
    fclose(b);
    free(f);
    free(map);
    cholmod_free_factor(&L, &cm);
    cholmod_free_sparse(&K, &cm);
    aug_mesh_free(&m);
}

/* a NaN behind a valid CRC is refused by the codec of every type that carries floats */
static void test_non_finite_refused(void)
{
    double nanv = NAN;
    aug_err e;
    unsigned char buf[256];
    memset(buf, 0, sizeof buf);
    struct { const char *type; uint64_t len; uint64_t at; } c[] = {
        {"FVEC", 16 + 16, 16 + 8},          /* kind, 0, n = 2, v[1] */
        {"pATH", 16 + 32, 16 + 16},         /* dim 2, 0, nseg 1, p */
        {"UPDT", 8 + 4 + 32 + 16, 12 + 8},  /* m 1, k 1, H[1], E[4], df[2] */
        {"BDLT", 8 + 12 + 8, 8 + 4},        /* nfix 1, dof, value; nload 0 */
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        memset(buf, 0, sizeof buf);
        if (!strcmp(c[i].type, "FVEC")) buf[8] = 2;
        if (!strcmp(c[i].type, "pATH")) buf[0] = 2, buf[8] = 1;
        if (!strcmp(c[i].type, "UPDT")) buf[0] = 1, buf[4] = 1;
        if (!strcmp(c[i].type, "BDLT")) buf[0] = 1;
        aug_rec rec;
        memset(&rec, 0, sizeof rec);
        memcpy(rec.type, c[i].type, 5);
        rec.step = 1;
        rec.data = buf;
        rec.len = c[i].len;
        T_CHECK(aug_check_payload(&rec, &e) == 0, "%s: the finite record is refused: %s", c[i].type, e.msg);
        memcpy(buf + c[i].at, &nanv, 8);
        T_CHECK(aug_check_payload(&rec, &e) == AUG_EDATA, "%s: NaN accepted", c[i].type);
    }
}

/* no tool writes a non-finite number into a field: the fELD writer refuses it */
static void test_field_writer_refuses_nan(void)
{
    aug_err e;
    FILE *f = tmpfile();
    aug_writer *w = aug_writer_open(f, "test", &e);
    double u[6] = {0, 1, 2, 3, NAN, 5};
    int32_t nodes[2] = {3, 7};
    T_CHECK(aug_write_field(w, 1, 0, 3, 2, nodes, u, &e) == AUG_EDATA, "a NaN field was written");
    T_CHECK(strstr(e.msg, "node 7") != NULL, "message does not name node 7: %s", e.msg);
    u[4] = INFINITY;
    T_CHECK(aug_write_field(w, 1, 0, 3, 2, NULL, u, &e) == AUG_EDATA, "an infinite field was written");
    u[4] = 4;
    T_CHECK(aug_write_field(w, 1, 0, 3, 2, nodes, u, &e) == 0, "a finite field refused: %s", e.msg);
    aug_writer_free(w);
    fclose(f);
}

/* a node set with a repeated node is refused by the codec check on its own */
static void test_set_order_refused(void)
{
    aug_err e;
    unsigned char buf[64 + 8 + 12];
    memset(buf, 0, sizeof buf);
    memcpy(buf, "pair", 4);
    int64_t n = 3;
    int32_t nodes[3] = {1, 4, 9};
    memcpy(buf + 64, &n, 8);
    memcpy(buf + 72, nodes, 12);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    memcpy(rec.type, "nSEt", 5);
    rec.step = -1;
    rec.data = buf;
    rec.len = sizeof buf;
    T_CHECK(aug_check_payload(&rec, &e) == 0, "an increasing set refused: %s", e.msg);
    nodes[1] = 1;
    memcpy(buf + 72, nodes, 12);
    T_CHECK(aug_check_payload(&rec, &e) == AUG_EDATA, "a set with node 1 twice accepted");
}

/* an oUTs absorbed into a mesh that has an output set already (aug_replay's
   --output, then an ancillary oUTs after it) replaces the set: the ASan build
   reports a leak otherwise */
static void test_outs_replaces_output_set(void)
{
    aug_mesh m, m2;
    aug_err e;
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    tm_box(&m, 1, 1, 1, 1, 1, 1, 100.0, 0.3);
    int32_t nodes[2] = {0, 3};
    T_CHECK(aug_mesh_set_output(&m, AUG_OUT_SET, "two", nodes, 2, &e) == 0, "%s", e.msg);
    FILE *a = tmpfile();
    aug_writer *w = aug_writer_open(a, "test", &e);
    T_CHECK(aug_mesh_write(w, &m, &e) == 0 && aug_writer_close(w, &e) == 0, "write: %s", e.msg);
    aug_writer_free(w);
    rewind(a);
    aug_reader *r = aug_reader_open(a, "test", &e);
    aug_mesh_init(&m2);
    int outs = 0;
    while (r && aug_read(r, &rec, &e) == 1) {
        T_CHECK(aug_mesh_absorb(&m2, &rec, &e) == 0, "%s: %s", rec.type, e.msg);
        if (memcmp(rec.type, "oUTs", 4)) continue;
        outs++;
        T_CHECK(aug_mesh_absorb(&m2, &rec, &e) == 0 && m2.nout == 2 && m2.out_nodes[1] == 3,
                "oUTs again: %s (%lld nodes)", e.msg, (long long)m2.nout);
    }
    T_CHECK(outs == 1, "%d oUTs records", outs);
    aug_rec_free(&rec);
    aug_reader_free(r);
    fclose(a);
    aug_mesh_free(&m);
    aug_mesh_free(&m2);
}

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(test_every_row_has_a_codec);
    T_RUN(test_every_type_round_trips);
    T_RUN(test_non_finite_refused);
    T_RUN(test_field_writer_refuses_nan);
    T_RUN(test_set_order_refused);
    T_RUN(test_outs_replaces_output_set);
    cholmod_finish(&cm);
    return t_failed_cases != 0;
}
