/* Reaction forces: element-wise (M a + D v + K u - f) on the constrained DOFs
   against the product with the globally assembled K and M over every DOF, the
   set resultants, the rEAC codec and its refusals, and the tracker of the
   elements touching constrained DOFs through replayed mesh changes. */
#include "t.h"
#include "fem_mesh.h"
#include "aug_cut.h"

static cholmod_common cm;

static double wave(int64_t i, double s) { return sin(s + 0.37 * (double)i) + 0.1 * cos(3.1 * s * (double)i); }

/* a mesh with constraints (non-zero values at the first node), loads on every
   third DOF (some of them constrained) and the material's density */
static void scene(aug_mesh *m, int dim)
{
    if (dim == 3) tm_box(m, 3, 2, 2, 1.5, 1, 1, 100.0, 0.3);
    else tm_rect(m, 4, 3, 2, 1.5, 50.0, 0.25, 0.1);
    m->mats[0].rho = 2.5;
    tm_fix_plane(m, 0, 0.0, NULL);
    m->fix_val[0] = 0.01, m->fix_val[1] = -0.02;
    int64_t nd = m->nn * dim, k = 0;
    m->load_dof = malloc((size_t)nd * sizeof *m->load_dof);
    m->load_val = malloc((size_t)nd * sizeof *m->load_val);
    for (int64_t i = 1; i < nd; i += 3) m->load_dof[k] = (int32_t)i, m->load_val[k++] = wave(i, 0.3);
    m->nload = k;
    m->have |= AUG_HAVE_LOAD;
}

/* y = A x for a matrix over every DOF (identity numbering) */
static cholmod_sparse *full_matrix(const aug_mesh *m, int which)
{
    int64_t nd = m->nn * m->dim;
    int32_t *id = malloc((size_t)nd * sizeof *id);
    for (int64_t i = 0; i < nd; i++) id[i] = (int32_t)i;
    aug_mesh free_m = *m;
    free_m.nfix = 0;    /* aug_assemble takes map as the numbering; no DOF is left out */
    aug_err e;
    cholmod_sparse *A = aug_assemble(&free_m, id, nd, which, &cm, &e);
    free(id);
    return A;
}

static void check_against_global(int dim, int dynamic, int lumped)
{
    aug_mesh m;
    scene(&m, dim);
    int64_t nd = m.nn * dim;
    double *u = malloc((size_t)nd * sizeof *u), *v = malloc((size_t)nd * sizeof *v),
           *a = malloc((size_t)nd * sizeof *a), *y = malloc((size_t)nd * sizeof *y),
           *t = malloc((size_t)nd * sizeof *t), *z = malloc((size_t)nd * sizeof *z);
    for (int64_t i = 0; i < nd; i++) u[i] = 1e-2 * wave(i, 1.1), v[i] = wave(i, 2.3), a[i] = wave(i, 0.7);
    double alpha = 0.3, beta = 0.02;
    cholmod_sparse *K = full_matrix(&m, AUG_MAT_K), *M = full_matrix(&m, lumped ? AUG_MAT_ML : AUG_MAT_M);
    T_CHECK(K && M, "assembly failed");
    if (!K || !M) return;
    /* y = K (u + beta v) + M (a + alpha v) in the dynamic case, K u in statics */
    for (int64_t i = 0; i < nd; i++) t[i] = u[i] + (dynamic ? beta * v[i] : 0);
    tm_symv(K, t, y);
    if (dynamic) {
        for (int64_t i = 0; i < nd; i++) t[i] = a[i] + alpha * v[i];
        tm_symv(M, t, z);
        for (int64_t i = 0; i < nd; i++) y[i] += z[i];
    }
    int32_t *el;
    int64_t nel = aug_react_elements(&m, &el);
    T_CHECK(nel > 0 && nel < m.ne, "%lld of %lld elements touch a constrained DOF", (long long)nel,
            (long long)m.ne);
    double *r = malloc((size_t)m.nfix * sizeof *r);
    aug_react_dyn dyn = {v, a, alpha, beta, lumped};
    aug_reactions(&m, el, nel, u, dynamic ? &dyn : NULL, r);
    double scale = 0, err = 0;
    for (int64_t k = 0; k < m.nfix; k++) {
        int32_t d = m.fix_dof[k];
        int64_t q = aug_find_i32(m.load_dof, m.nload, d);
        double ref = y[d] - (q >= 0 ? m.load_val[q] : 0);
        scale = fmax(scale, fabs(ref));
        err = fmax(err, fabs(r[k] - ref));
    }
    T_CHECK(err <= 1e-13 * scale && scale > 0, "dim %d dynamic %d lumped %d: |r - ref| %.3g of %.3g", dim,
            dynamic, lumped, err, scale);
    free(el), free(r), free(u), free(v), free(a), free(y), free(t), free(z);
    cholmod_free_sparse(&K, &cm);
    cholmod_free_sparse(&M, &cm);
    aug_mesh_free(&m);
}

static void test_reactions_equal_global_product(void)
{
    for (int dim = 2; dim <= 3; dim++) {
        check_against_global(dim, 0, 0);
        check_against_global(dim, 1, 0);
        check_against_global(dim, 1, 1);
    }
}

/* the elements listed are exactly those with a node in the fix list */
static void test_elements_touching(void)
{
    aug_mesh m;
    scene(&m, 3);
    int32_t *el;
    int64_t nel = aug_react_elements(&m, &el), k = 0;
    for (int64_t e = 0; e < m.ne; e++) {
        int t = 0;
        for (int a = 0; a < 4; a++)
            for (int c = 0; c < 3; c++) t |= aug_find_i32(m.fix_dof, m.nfix, m.conn[e * 4 + a] * 3 + c) >= 0;
        if (!t) continue;
        T_CHECK(k < nel && el[k] == e, "element %lld touches a constrained DOF, not listed", (long long)e);
        k++;
    }
    T_CHECK(k == nel, "%lld listed, %lld touch", (long long)nel, (long long)k);
    free(el);
    aug_mesh_free(&m);
}

static void add_set(aug_mesh *m, const char *name, const int32_t *nodes, int64_t n)
{
    m->sets = realloc(m->sets, (size_t)(m->nset + 1) * sizeof *m->sets);
    aug_set *s = &m->sets[m->nset++];
    memset(s, 0, sizeof *s);
    snprintf(s->name, AUG_NAME, "%s", name);
    s->n = n;
    s->nodes = malloc((size_t)(n ? n : 1) * sizeof *s->nodes);
    memcpy(s->nodes, nodes, (size_t)n * sizeof *nodes);
}

/* statics: the reactions balance every load (rigid translations are in the
   null space of K, and K u = f on the free rows); the set resultants are the
   sums over the set's constrained DOFs; a set without one is left out */
static void test_resultants_and_balance(void)
{
    aug_mesh m;
    scene(&m, 2);
    int32_t *map = malloc((size_t)m.nn * 2 * sizeof *map);
    int64_t nfree = aug_dofmap(&m, map);
    aug_err e;
    cholmod_sparse *K = aug_assemble(&m, map, nfree, AUG_MAT_K, &cm, &e);
    double *f = malloc((size_t)nfree * sizeof *f), *x = malloc((size_t)nfree * sizeof *x),
           *u = malloc((size_t)m.nn * 2 * sizeof *u);
    aug_load_vector(&m, map, nfree, f, &e);
    cholmod_factor *L = aug_analyze(K, &cm, &e);
    aug_factorize(K, L, &m, map, &cm, &e);
    aug_solve(K, L, f, x, NULL, &cm, &e);
    aug_expand_field(&m, map, x, u);
    int32_t low[2] = {0, 5}, free_only[2] = {6, 7}, all_left[4] = {0, 5, 10, 15};
    add_set(&m, "low", low, 2);
    add_set(&m, "inner", free_only, 2);
    add_set(&m, "left", all_left, 4);
    int32_t *el;
    int64_t nel = aug_react_elements(&m, &el);
    aug_reaction q;
    memset(&q, 0, sizeof q);
    T_CHECK(aug_reaction_compute(&q, &m, el, nel, u, NULL, &e) == 0, "%s", e.msg);
    T_CHECK(q.nset == 2 && !strcmp(q.name[0], "low") && !strcmp(q.name[1], "left"), "sets: %lld",
            (long long)q.nset);
    double fsum[2] = {0, 0}, rabs = 0;
    for (int64_t k = 0; k < m.nload; k++) fsum[m.load_dof[k] % 2] += m.load_val[k];
    for (int64_t k = 0; k < q.n; k++) rabs += fabs(q.r[k]);
    for (int c = 0; c < 2; c++) {
        T_CHECK(fabs(q.total[c] + fsum[c]) <= 1e-12 * rabs, "component %d: total %.17g, loads %.17g", c,
                q.total[c], fsum[c]);
        double lo = 0;
        for (int64_t k = 0; k < q.n; k++)
            if (q.dof[k] % 2 == c && (q.dof[k] / 2 == 0 || q.dof[k] / 2 == 5)) lo += q.r[k];
        T_CHECK(fabs(q.res[c] - lo) <= 1e-15 * rabs, "low[%d] %.17g, sum %.17g", c, q.res[c], lo);
        T_CHECK(fabs(q.res[2 + c] - q.total[c]) <= 1e-15 * rabs, "left holds every constrained DOF");
    }
    aug_reaction_free(&q);
    free(el), free(map), free(f), free(x), free(u);
    cholmod_free_factor(&L, &cm);
    cholmod_free_sparse(&K, &cm);
    aug_mesh_free(&m);
}

/* the payload of q as its writer frames it, read back from a memory stream */
static int one_record(const aug_reaction *q, unsigned char **p, uint64_t *len)
{
    aug_err e;
    char *buf = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&buf, &n);
    aug_writer *w = aug_writer_open(f, "test", &e);
    int rc = !w || aug_write_reaction(w, 4, q, &e) || aug_writer_close(w, &e);
    aug_writer_free(w);
    fclose(f);
    FILE *g = fmemopen(buf, n, "r");
    aug_reader *r = rc ? NULL : aug_reader_open(g, "mem", &e);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    for (rc = -1; r && aug_read(r, &rec, &e) == 1;)
        if (!memcmp(rec.type, "rEAC", 4) && (*p = malloc(rec.len)))
            memcpy(*p, rec.data, rec.len), *len = rec.len, rc = 0;
    aug_rec_free(&rec);
    aug_reader_free(r);
    fclose(g);
    free(buf);
    return rc;
}

static int check_bytes(unsigned char *p, uint64_t len, aug_err *e)
{
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    memcpy(rec.type, "rEAC", 5);
    rec.step = 4;
    rec.data = p;
    rec.len = len;
    return aug_check_payload(&rec, e);
}

static void test_codec_round_trip_and_refusals(void)
{
    int32_t dof[4] = {0, 1, 6, 7};
    double r[4] = {1.5, -2, 0.25, 3}, res[4] = {1.5, -2, 1.75, 1};
    char names[2][AUG_NAME] = {"first", "second"};
    aug_reaction q = {2, 3, 0.125, 4, dof, r, {1.75, 1, 0}, 2, names, res, 0, 0};
    unsigned char *p = NULL;
    uint64_t len = 0;
    T_CHECK(one_record(&q, &p, &len) == 0 && len == 32 + 48 + 16 + 2 * 80, "write: %llu bytes",
            (unsigned long long)len);
    if (!p) return;
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    memcpy(rec.type, "rEAC", 5);
    rec.data = p, rec.len = len, rec.step = 4;
    aug_reaction b;
    memset(&b, 0, sizeof b);
    aug_err e;
    T_CHECK(aug_read_reaction(&rec, &b, &e) == 0, "read: %s", e.msg);
    T_CHECK(b.dim == 2 && b.frame == 3 && b.time == 0.125 && b.n == 4 && b.nset == 2 &&
                !memcmp(b.dof, dof, sizeof dof) && !memcmp(b.r, r, sizeof r) &&
                !memcmp(b.res, res, sizeof res) && !strcmp(b.name[1], "second") && b.total[1] == 1,
            "read back differs");
    aug_reaction_free(&b);
    /* damaged copies: each refused by the check on its own */
    struct { const char *what; uint64_t at; int32_t i; int code; } bad_i[] = {
        {"dim 4", 0, 4, AUG_EPAYLOAD}, {"frame -1", 4, -1, AUG_EDATA},
        {"DOFs not increasing", 32 + 8, 0, AUG_EDATA}, {"negative DOF", 32, -3, AUG_EDATA},
        {"n one too many", 16, 5, AUG_EPAYLOAD}, {"nset one too few", 24, 1, AUG_EPAYLOAD}};
    unsigned char *c = malloc(len + 8);
    for (size_t k = 0; k < sizeof bad_i / sizeof *bad_i; k++) {
        memcpy(c, p, len);
        memcpy(c + bad_i[k].at, &bad_i[k].i, 4);
        T_CHECK(check_bytes(c, len, &e) == bad_i[k].code, "%s accepted (%s)", bad_i[k].what, e.msg);
    }
    double nan = NAN;
    uint64_t at_f[] = {8, 32 + 16 + 8, 32 + 48 + 8, 32 + 48 + 16 + 64 + 8};
    for (size_t k = 0; k < sizeof at_f / sizeof *at_f; k++) {
        memcpy(c, p, len);
        memcpy(c + at_f[k], &nan, 8);
        T_CHECK(check_bytes(c, len, &e) == AUG_EDATA, "NaN at byte %llu accepted", (unsigned long long)at_f[k]);
    }
    memcpy(c, p, len);
    memcpy(c + 96 + 80, "first", 6);              /* the second set named as the first */
    T_CHECK(check_bytes(c, len, &e) == AUG_EDATA && strstr(e.msg, "named twice"), "a repeated name: %s", e.msg);
    memcpy(c, p, len);
    memset(c + 96, 'x', AUG_NAME);                /* the first name without its NUL */
    T_CHECK(check_bytes(c, len, &e) == AUG_EDATA, "an unterminated name accepted");
    memcpy(c, p, len);
    c[96] = 0;                                    /* an empty name */
    T_CHECK(check_bytes(c, len, &e) == AUG_EDATA, "an empty name accepted");
    memcpy(c, p, len);
    T_CHECK(check_bytes(c, len - 8, &e) == AUG_EPAYLOAD, "a short payload accepted");
    T_CHECK(check_bytes(c, len, &e) == 0, "the intact copy refused: %s", e.msg);
    /* the writer refuses a non-finite reaction */
    r[2] = INFINITY;
    FILE *f = tmpfile();
    aug_writer *w = aug_writer_open(f, "test", &e);
    T_CHECK(aug_write_reaction(w, 1, &q, &e) == AUG_EDATA, "an infinite reaction was written");
    aug_writer_free(w);
    fclose(f);
    free(c);
    free(p);
}

/* ---- the tracker through replayed steps ---- */

typedef struct feed {
    FILE *f;
    aug_writer *w;
} feed;

/* the records of one step: its MDLT (d may be NULL) and BDLT (b may be NULL) */
static void put_step(feed *s, const aug_mesh *m, aug_mdelta *d, aug_bdelta *b)
{
    aug_err e;
    if (d) T_CHECK(aug_write_mdelta(s->w, m->dim, m->nv, d, &e) == 0, "MDLT: %s", e.msg);
    if (b) T_CHECK(aug_write_bdelta(s->w, b, &e) == 0, "BDLT: %s", e.msg);
}

/* the tracker's list equals the full scan of the replayed mesh, and the DOFs
   it requests cover the output's and every node of those elements */
static void check_tracker(aug_react *rs, aug_replay *rp, int step)
{
    aug_err e;
    int32_t want_out[2] = {1, 2};
    const int32_t *out = want_out;
    int64_t nout = 2;
    T_CHECK(aug_react_out_dofs(rs, &out, &nout, &e) == 0, "step %d: %s", step, e.msg);
    int32_t *el;
    const aug_mesh *m = &rp->mesh;
    int64_t nel = aug_react_elements(m, &el);
    T_CHECK(nel == rs->nel && !memcmp(el, rs->elems, (size_t)nel * 4), "step %d: %lld elements tracked, %lld touch",
            step, (long long)rs->nel, (long long)nel);
    for (int64_t k = 0; k < 2; k++) T_CHECK(aug_find_i32(out, nout, want_out[k]) >= 0, "output DOF lost");
    for (int64_t t = 0; t < nel; t++)
        for (int a = 0; a < m->nv; a++)
            for (int c = 0; c < m->dim; c++) {
                int64_t id = aug_replay_index(rp, m->conn[(int64_t)el[t] * m->nv + a], c);
                T_CHECK(id < 0 || aug_find_i32(out, nout, (int32_t)id) >= 0,
                        "step %d: index %lld of element %d not requested", step, (long long)id, el[t]);
            }
    for (int64_t k = 1; k < nout; k++) T_CHECK(out[k] > out[k - 1], "requested DOFs not increasing");
    free(el);
}

/* the first element holding node p and no other constrained node (cn) */
static int64_t lone_element(const aug_mesh *m, int32_t p, const unsigned char *cn)
{
    for (int64_t e = 0; e < m->ne; e++) {
        int has = 0, other = 0;
        for (int a = 0; a < m->nv; a++) {
            int32_t v = m->conn[e * m->nv + a];
            has |= v == p;
            other |= v != p && cn[v];
        }
        if (has && !other) return e;
    }
    return -1;
}

static void test_tracker_follows_steps(void)
{
    aug_mesh m;
    tm_box(&m, 2, 2, 2, 1, 1, 1, 100.0, 0.3);
    tm_fix_plane(&m, 2, 0.0, NULL);
    aug_err e;
    feed s = {tmpfile(), NULL};
    s.w = aug_writer_open(s.f, "test", &e);
    T_CHECK(aug_mesh_write(s.w, &m, &e) == 0, "mesh: %s", e.msg);
    unsigned char *cn = calloc((size_t)m.nn + 8, 1);
    for (int64_t k = 0; k < m.nfix; k++) cn[m.fix_dof[k] / 3] = 1;
    /* step 1: element e1 leaves (its one constrained node p becomes a new node
       at p's place whose parent is free), element e0 is added again (joins) */
    int32_t p = 1, top = (int32_t)(m.nn - 1);
    int64_t e1 = lone_element(&m, p, cn);
    T_CHECK(e1 >= 0, "no element with node 1 alone constrained");
    int32_t par1[1] = {top}, el1[1] = {(int32_t)e1}, conn1[4], add1[4], mat1[1] = {0};
    memcpy(conn1, m.conn + e1 * 4, sizeof conn1);
    for (int a = 0; a < 4; a++)
        if (conn1[a] == p) conn1[a] = (int32_t)m.nn;
    int64_t e0 = lone_element(&m, 0, cn);
    memcpy(add1, m.conn + e0 * 4, sizeof add1);
    double x1[3];
    memcpy(x1, m.x + p * 3, sizeof x1);
    aug_mdelta d1 = {1, 1, par1, x1, 1, el1, conn1, 1, add1, mat1, 0};
    put_step(&s, &m, &d1, NULL);
    /* step 2: an element of the top layer re-wired to a new node that the
       step's BDLT constrains (joins); step 3: BDLT constrains an old free node */
    int64_t nn2 = m.nn + 1, e2 = -1;
    for (int64_t e = 0; e < m.ne && e2 < 0; e++) {
        int any = 0, hastop = 0;
        for (int a = 0; a < 4; a++) any |= cn[m.conn[e * 4 + a]], hastop |= m.conn[e * 4 + a] == top;
        if (!any && hastop && e != e1) e2 = e;
    }
    int32_t par2[1] = {top}, el2[1] = {(int32_t)e2}, conn2[4];
    memcpy(conn2, m.conn + e2 * 4, sizeof conn2);
    for (int a = 0; a < 4; a++)
        if (conn2[a] == top) conn2[a] = (int32_t)nn2;
    double x2[3];
    memcpy(x2, m.x + top * 3, sizeof x2);
    aug_mdelta d2 = {2, 1, par2, x2, 1, el2, conn2, 0, NULL, NULL, 0};
    int32_t fd2[3] = {(int32_t)nn2 * 3, (int32_t)nn2 * 3 + 1, (int32_t)nn2 * 3 + 2};
    double fv2[3] = {0, 0, 0.5};
    aug_bdelta b2 = {2, 3, fd2, fv2, 0, NULL, NULL, 0, 0};
    put_step(&s, &m, &d2, &b2);
    int32_t fd3[1] = {13 * 3 + 1};   /* the centre node of the 3x3x3 grid */
    double fv3[1] = {0.25};
    aug_bdelta b3 = {3, 1, fd3, fv3, 0, NULL, NULL, 0, 0};
    put_step(&s, &m, NULL, &b3);
    T_CHECK(aug_writer_close(s.w, &e) == 0, "close: %s", e.msg);
    aug_writer_free(s.w);
    rewind(s.f);
    aug_reader *r = aug_reader_open(s.f, "tmp", &e);
    aug_replay rp;
    aug_replay_init(&rp);
    aug_react rs;
    aug_react_init(&rs, &rp);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    int32_t last = 0;
    int64_t n_at[4] = {0};
    while (r && aug_read(r, &rec, &e) == 1) {
        if (rec.step > last) {  /* the previous step is complete (step 0: the mesh) */
            T_CHECK(aug_replay_start(&rp, &e) == 0, "start: %s", e.msg);
            check_tracker(&rs, &rp, last);
            n_at[last] = rs.nel;
            last = rec.step;
        }
        T_CHECK(aug_replay_add(&rp, &rec, &e) == 0, "replay %s: %s", rec.type, e.msg);
    }
    check_tracker(&rs, &rp, last);
    n_at[last] = rs.nel;
    T_CHECK(last == 3 && n_at[1] == n_at[0] && n_at[2] == n_at[1] + 1 && n_at[3] > n_at[2],
            "elements per step %lld %lld %lld %lld", (long long)n_at[0], (long long)n_at[1],
            (long long)n_at[2], (long long)n_at[3]);
    aug_rec_free(&rec);
    aug_reader_free(r);
    aug_react_free(&rs);
    aug_replay_free(&rp);
    fclose(s.f);
    free(cn);
    aug_mesh_free(&m);
}

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(test_reactions_equal_global_product);
    T_RUN(test_elements_touching);
    T_RUN(test_resultants_and_balance);
    T_RUN(test_codec_round_trip_and_refusals);
    T_RUN(test_tracker_follows_steps);
    cholmod_finish(&cm);
    T_EXIT();
}
