/* Round trips of the matrix-phase records DOFM KMAT FVEC FACT, and rejection of
   damaged payloads. */
#include "t.h"
#include "fem_mesh.h"

static cholmod_common cm;

/* next record of reader r into rec; 1 when there is one */
static int next(aug_reader *r, aug_rec *rec)
{
    aug_err e;
    return aug_read(r, rec, &e) == 1;
}

static cholmod_factor *factor_of(cholmod_sparse *K, int simplicial)
{
    cm.supernodal = simplicial ? CHOLMOD_SIMPLICIAL : CHOLMOD_SUPERNODAL;
    cholmod_factor *L = cholmod_analyze(K, &cm);
    cholmod_factorize(K, L, &cm);
    cm.supernodal = CHOLMOD_AUTO;
    return L;
}

static void test_records_roundtrip(void)
{
    aug_mesh m;
    tm_box(&m, 3, 2, 4, 1, 1, 2, 100.0, 0.3);
    tm_fix_plane(&m, 2, 0.0, NULL);
    int32_t *map = malloc((size_t)m.nn * 3 * sizeof *map);
    int64_t nfree = aug_dofmap(&m, map);
    aug_err e;
    cholmod_sparse *K = aug_assemble(&m, map, nfree, AUG_MAT_K, &cm, &e);
    T_CHECK(K != NULL, "assemble: %s", e.msg);
    if (!K) return;
    double *f = malloc((size_t)nfree * sizeof *f);
    for (int64_t i = 0; i < nfree; i++) f[i] = sin(1.0 + i);
    cholmod_factor *L = factor_of(K, 0);
    T_CHECK(cm.status == CHOLMOD_OK && L->is_super, "supernodal factor: status %d", cm.status);

    FILE *fp = tmpfile();
    aug_writer *w = aug_writer_open(fp, "test", &e);
    T_CHECK(aug_write_dofmap(w, &m, map, nfree, &e) == 0, "DOFM: %s", e.msg);
    T_CHECK(aug_write_sparse(w, AUG_MAT_K, K, &e) == 0, "KMAT: %s", e.msg);
    T_CHECK(aug_write_vector(w, "FVEC", AUG_NOSTEP, 0, f, nfree, &e) == 0, "FVEC: %s", e.msg);
    T_CHECK(aug_write_factor(w, L, &cm, &e) == 0, "FACT: %s", e.msg);
    T_CHECK(L->is_super, "aug_write_factor changed the caller's factor");
    T_CHECK(aug_writer_close(w, &e) == 0, "close: %s", e.msg);
    aug_writer_free(w);
    rewind(fp);

    aug_reader *r = aug_reader_open(fp, "tmp", &e);
    T_CHECK(r != NULL, "reopen: %s", e.msg);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    int dim = 0;
    int64_t ndof = 0, nf2 = 0, nv = 0;
    int32_t *map2 = NULL, kind = -1;
    double *f2 = NULL;
    cholmod_sparse *K2 = NULL;
    cholmod_factor *L2 = NULL;
    int which = -1;
    next(r, &rec); /* pROv is not written by this test: first is DOFM */
    T_CHECK(aug_read_dofmap(&rec, &dim, &ndof, &nf2, &map2, &e) == 0, "read DOFM: %s", e.msg);
    T_CHECK(dim == 3 && ndof == m.nn * 3 && nf2 == nfree, "DOFM header");
    T_CHECK(map2 && memcmp(map, map2, (size_t)ndof * 4) == 0, "DOFM map differs");
    next(r, &rec);
    K2 = aug_read_sparse(&rec, &which, &cm, &e);
    T_CHECK(K2 && which == AUG_MAT_K, "read KMAT: %s", e.msg);
    if (K2) {
        cholmod_sparse *D = cholmod_add(K, K2, (double[2]){1, 0}, (double[2]){-1, 0}, 1, 1, &cm);
        T_CHECK(cholmod_norm_sparse(D, 1, &cm) == 0, "KMAT values differ");
        T_CHECK(cholmod_nnz(K2, &cm) == cholmod_nnz(K, &cm), "KMAT nnz differs");
        cholmod_free_sparse(&D, &cm);
    }
    next(r, &rec);
    T_CHECK(aug_read_vector(&rec, &kind, &nv, &f2, &e) == 0, "read FVEC: %s", e.msg);
    T_CHECK(nv == nfree && kind == 0 && memcmp(f, f2, (size_t)nv * 8) == 0, "FVEC differs");
    next(r, &rec);
    L2 = aug_read_factor(&rec, &cm, &e);
    T_CHECK(L2 != NULL, "read FACT: %s", e.msg);
    if (L2) {
        T_CHECK(cholmod_check_factor(L2, &cm), "rebuilt factor fails cholmod_check_factor");
        T_CHECK(!L2->is_super && !L2->is_ll && L2->ordering == L->ordering, "factor kind/ordering");
        cholmod_dense *b = cholmod_zeros(nfree, 1, CHOLMOD_REAL, &cm);
        memcpy(b->x, f, (size_t)nfree * 8);
        cholmod_dense *x1 = cholmod_solve(CHOLMOD_A, L, b, &cm);
        cholmod_dense *x2 = cholmod_solve(CHOLMOD_A, L2, b, &cm);
        double d = 0, s = 0;
        for (int64_t i = 0; i < nfree; i++) {
            d = fmax(d, fabs(((double *)x1->x)[i] - ((double *)x2->x)[i]));
            s = fmax(s, fabs(((double *)x1->x)[i]));
        }
        T_CHECK(d <= 1e-12 * s, "solve with the rebuilt factor differs by %g (scale %g)", d, s);
        /* and the residual of the rebuilt factor's solve against K itself */
        double *Kx = malloc((size_t)nfree * 8);
        tm_symv(K, x2->x, Kx);
        for (int64_t i = 0; i < nfree; i++) Kx[i] -= f[i];
        T_CHECK(tm_norm(Kx, nfree) <= 1e-12 * tm_norm(f, nfree), "residual %g",
                tm_norm(Kx, nfree) / tm_norm(f, nfree));
        free(Kx);
        cholmod_free_dense(&b, &cm);
        cholmod_free_dense(&x1, &cm);
        cholmod_free_dense(&x2, &cm);
    }
    T_CHECK(aug_read(r, &rec, &e) == 0, "expected TAIL");
    aug_rec_free(&rec);
    aug_reader_free(r);
    fclose(fp);
    free(map);
    free(map2);
    free(f);
    free(f2);
    cholmod_free_sparse(&K, &cm);
    cholmod_free_sparse(&K2, &cm);
    cholmod_free_factor(&L, &cm);
    cholmod_free_factor(&L2, &cm);
    aug_mesh_free(&m);
}

/* rebuilt factor x = K^-1 f relative residual (NAN if solve failed) */
static double rebuilt_residual(const cholmod_factor *L0, const cholmod_sparse *K, const double *f)
{
    aug_err e;
    FILE *fp = tmpfile();
    aug_writer *w = aug_writer_open(fp, "t", &e);
    if (aug_write_factor(w, L0, &cm, &e) || aug_writer_close(w, &e)) return NAN;
    aug_writer_free(w);
    rewind(fp);
    aug_reader *r = aug_reader_open(fp, "t", &e);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    next(r, &rec);
    cholmod_factor *L = aug_read_factor(&rec, &cm, &e);
    double res = NAN;
    if (L && cholmod_check_factor(L, &cm)) {
        int64_t n = (int64_t)K->nrow;
        cholmod_dense *b = cholmod_zeros(n, 1, CHOLMOD_REAL, &cm);
        memcpy(b->x, f, (size_t)n * 8);
        cholmod_dense *x = cholmod_solve(CHOLMOD_A, L, b, &cm);
        double *Kx = malloc((size_t)n * 8);
        tm_symv(K, x->x, Kx);
        for (int64_t i = 0; i < n; i++) Kx[i] -= f[i];
        res = tm_norm(Kx, n) / tm_norm(f, n);
        free(Kx);
        cholmod_free_dense(&b, &cm);
        cholmod_free_dense(&x, &cm);
    }
    cholmod_free_factor(&L, &cm);
    aug_rec_free(&rec);
    aug_reader_free(r);
    fclose(fp);
    return res;
}

/* FACT from a simplicial LDL', a simplicial LL' and a supernodal factor of a
   2-D K: each rebuilt factor solves K x = f to round-off */
static void test_fact_all_factor_kinds(void)
{
    aug_mesh m;
    tm_rect(&m, 6, 3, 2, 1, 10.0, 0.25, 0.1);
    tm_fix_plane(&m, 0, 0.0, NULL);
    int32_t *map = malloc((size_t)m.nn * 2 * sizeof *map);
    int64_t nfree = aug_dofmap(&m, map);
    aug_err e;
    cholmod_sparse *K = aug_assemble(&m, map, nfree, AUG_MAT_K, &cm, &e);
    double *f = malloc((size_t)nfree * 8);
    for (int64_t i = 0; i < nfree; i++) f[i] = cos(0.3 * i);
    cholmod_factor *Ls = factor_of(K, 1), *Lp = factor_of(K, 0);
    cm.final_ll = 1;
    cholmod_factor *Ll = factor_of(K, 1);
    cm.final_ll = 0;
    T_CHECK(!Ls->is_super && !Ls->is_ll && Lp->is_super && Ll->is_ll && !Ll->is_super,
            "factor kinds not as requested");
    double r1 = rebuilt_residual(Ls, K, f), r2 = rebuilt_residual(Lp, K, f),
           r3 = rebuilt_residual(Ll, K, f);
    T_CHECK(r1 < 1e-13 && r2 < 1e-13 && r3 < 1e-13, "residuals %g %g %g", r1, r2, r3);
    cholmod_free_factor(&Ls, &cm);
    cholmod_free_factor(&Lp, &cm);
    cholmod_free_factor(&Ll, &cm);
    cholmod_free_sparse(&K, &cm);
    free(map);
    free(f);
    aug_mesh_free(&m);
}

/* damaged payloads are refused with a message, never crash */
static void test_damaged_payloads(void)
{
    aug_err e;
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    rec.index = 3;
    memcpy(rec.type, "FACT", 5);
    /* n = 2, nnz = 3, perm {0, 0} (not a permutation) */
    unsigned char buf[256];
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i64(&b, 2);
    aug_buf_i64(&b, 3);
    aug_buf_i32(&b, 2);
    aug_buf_i32(&b, 0);
    aug_buf_i32(&b, 0);
    aug_buf_i32(&b, 0);
    int64_t cp[3] = {0, 2, 3};
    aug_buf_i64v(&b, cp, 3);
    int32_t ri[3] = {0, 1, 1};
    aug_buf_i32v(&b, ri, 3);
    double v[3] = {2, 0.5, 1.5};
    aug_buf_f64v(&b, v, 3);
    memcpy(buf, b.p, b.len);
    rec.data = buf;
    rec.len = b.len;
    cholmod_factor *L = aug_read_factor(&rec, &cm, &e);
    T_CHECK(!L && e.code == AUG_EDATA && strstr(e.msg, "permutation"), "bad perm: %s", e.msg);
    int32_t perm_ok[2] = {1, 0};
    memcpy(buf + 24, perm_ok, 8);
    L = aug_read_factor(&rec, &cm, &e);
    T_CHECK(L != NULL, "good FACT refused: %s", e.msg);
    cholmod_free_factor(&L, &cm);
    /* row index above n */
    int32_t bad_row = 7;
    memcpy(buf + 24 + 8 + 24 + 4, &bad_row, 4);
    L = aug_read_factor(&rec, &cm, &e);
    T_CHECK(!L && e.code == AUG_EDATA, "bad row accepted");
    /* truncated */
    rec.len -= 8;
    L = aug_read_factor(&rec, &cm, &e);
    T_CHECK(!L && e.code == AUG_EPAYLOAD, "short payload accepted");
    aug_buf_free(&b);

    /* KMAT with an entry below the diagonal */
    memcpy(rec.type, "KMAT", 5);
    aug_buf_init(&b);
    aug_buf_i32(&b, 0);
    aug_buf_i32(&b, 1);
    aug_buf_i64(&b, 2);
    aug_buf_i64(&b, 2);
    aug_buf_i64v(&b, (int64_t[3]){0, 2, 2}, 3);
    aug_buf_i32v(&b, (int32_t[2]){0, 1}, 2);
    aug_buf_f64v(&b, (double[2]){1, 2}, 2);
    rec.data = b.p;
    rec.len = b.len;
    cholmod_sparse *A = aug_read_sparse(&rec, NULL, &cm, &e);
    T_CHECK(!A && e.code == AUG_EDATA && strstr(e.msg, "upper"), "lower entry: %s", e.msg);
    aug_buf_free(&b);

    /* DOFM whose free indices skip */
    memcpy(rec.type, "DOFM", 5);
    aug_buf_init(&b);
    aug_buf_i32(&b, 2);
    aug_buf_i32(&b, 0);
    aug_buf_i64(&b, 4);
    aug_buf_i64(&b, 3);
    aug_buf_i32v(&b, (int32_t[4]){0, -1, 2, 3}, 4);
    rec.data = b.p;
    rec.len = b.len;
    int dim;
    int64_t nd, nf;
    int32_t *map = NULL;
    T_CHECK(aug_read_dofmap(&rec, &dim, &nd, &nf, &map, &e) == AUG_EDATA && !map, "DOFM gap accepted");
    aug_buf_free(&b);
}

/* read the single FACT of a stream written by aug_write_factor(L) */
static cholmod_factor *through_record(const cholmod_factor *L)
{
    aug_err e;
    FILE *fp = tmpfile();
    aug_writer *w = aug_writer_open(fp, "t", &e);
    aug_write_factor(w, L, &cm, &e);
    aug_writer_close(w, &e);
    aug_writer_free(w);
    rewind(fp);
    aug_reader *r = aug_reader_open(fp, "t", &e);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    next(r, &rec);
    cholmod_factor *F = aug_read_factor(&rec, &cm, &e);
    aug_rec_free(&rec);
    aug_reader_free(r);
    fclose(fp);
    return F;
}

/* the supernodal factor written directly equals CHOLMOD's own conversion to
   simplicial LDL' (cholmod_change_factor): same pattern, values to round-off */
static void test_fact_supernodal_equals_cholmod_conversion(void)
{
    aug_mesh m;
    tm_box(&m, 4, 3, 5, 1, 1, 1.5, 7.0, 0.3);
    tm_fix_plane(&m, 2, 0.0, NULL);
    int32_t *map = malloc((size_t)m.nn * 3 * sizeof *map);
    int64_t nfree = aug_dofmap(&m, map);
    aug_err e;
    cholmod_sparse *K = aug_assemble(&m, map, nfree, AUG_MAT_K, &cm, &e);
    cholmod_factor *L = factor_of(K, 0);
    cholmod_factor *C = cholmod_copy_factor(L, &cm);
    cholmod_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, C, &cm);
    cholmod_factor *A = through_record(L), *B = through_record(C);
    T_CHECK(L->is_super && A && B, "factors");
    if (A && B) {
        int *ap = A->p, *bp = B->p, *ai = A->i, *bi = B->i;
        double *ax = A->x, *bx = B->x, dmax = 0;
        int same = A->n == B->n && ap[A->n] == bp[B->n] && !memcmp(A->Perm, B->Perm, A->n * 4);
        for (size_t j = 0; same && j <= A->n; j++) same = ap[j] == bp[j];
        for (int q = 0; same && q < ap[A->n]; q++) {
            same = ai[q] == bi[q];
            dmax = fmax(dmax, fabs(ax[q] - bx[q]) / (fabs(bx[q]) + 1e-300));
        }
        T_CHECK(same, "pattern differs from cholmod_change_factor's");
        T_CHECK(dmax <= 4e-16, "values differ by %g relative", dmax);
    }
    cholmod_free_factor(&A, &cm);
    cholmod_free_factor(&B, &cm);
    cholmod_free_factor(&C, &cm);
    cholmod_free_factor(&L, &cm);
    cholmod_free_sparse(&K, &cm);
    free(map);
    aug_mesh_free(&m);
}

/* every allocation through aug_malloc failing in turn: each call either
   succeeds or reports AUG_ENOMEM, and frees what it had (ASan build: no leak) */
static void test_allocation_failures(void)
{
    aug_mesh m;
    tm_box(&m, 2, 2, 3, 1, 1, 1.5, 3.0, 0.3);
    tm_fix_plane(&m, 2, 0.0, NULL);
    int32_t *map = malloc((size_t)m.nn * 3 * sizeof *map);
    int64_t n = aug_dofmap(&m, map);
    aug_err e;
    cholmod_sparse *K0 = aug_assemble(&m, map, n, AUG_MAT_K, &cm, &e);
    cholmod_factor *L0 = factor_of(K0, 0);
    /* the FACT, DOFM and FVEC records to read back */
    FILE *fp = tmpfile();
    aug_writer *w = aug_writer_open(fp, "t", &e);
    double *f = calloc((size_t)n, sizeof *f);
    aug_write_factor(w, L0, &cm, &e);
    aug_write_dofmap(w, &m, map, n, &e);
    aug_write_vector(w, "FVEC", AUG_NOSTEP, 0, f, n, &e);
    aug_writer_close(w, &e);
    aug_writer_free(w);
    rewind(fp);
    aug_reader *r = aug_reader_open(fp, "t", &e);
    aug_rec rf, rd, rv;
    memset(&rf, 0, sizeof rf);
    memset(&rd, 0, sizeof rd);
    memset(&rv, 0, sizeof rv);
    next(r, &rf);
    next(r, &rd);
    next(r, &rv);
    int bad = 0, succeeded = 0;
    for (long k = 0; k < 40; k++) {
        int ok = 1;
        aug_fail_after(k);
        cholmod_sparse *K = aug_assemble(&m, map, n, k % 2 ? AUG_MAT_K : AUG_MAT_M, &cm, &e);
        if (!K && e.code != AUG_ENOMEM) bad++;
        ok &= K != NULL;
        cholmod_free_sparse(&K, &cm);
        aug_fail_after(k);
        int rc = aug_load_vector(&m, map, n, f, &e);
        if (rc && rc != AUG_ENOMEM) bad++;
        aug_fail_after(k);
        rc = aug_check_support(&m, &e);
        if (rc && rc != AUG_ENOMEM) bad++;
        ok &= rc == 0;
        aug_fail_after(k);
        cholmod_factor *L = aug_read_factor(&rf, &cm, &e);
        if (!L && e.code != AUG_ENOMEM) bad++;
        ok &= L != NULL;
        cholmod_free_factor(&L, &cm);
        int dim;
        int64_t nd, nf, nv;
        int32_t *mp = NULL, kind;
        double *v = NULL;
        aug_fail_after(k);
        rc = aug_read_dofmap(&rd, &dim, &nd, &nf, &mp, &e);
        if (rc && rc != AUG_ENOMEM) bad++;
        free(mp);
        aug_fail_after(k);
        rc = aug_read_vector(&rv, &kind, &nv, &v, &e);
        if (rc && rc != AUG_ENOMEM) bad++;
        free(v);
        FILE *sink = tmpfile();
        aug_fail_after(-1);
        aug_writer *ws = aug_writer_open(sink, "t", &e);
        aug_fail_after(k);
        rc = aug_write_factor(ws, L0, &cm, &e);
        if (rc && rc != AUG_ENOMEM) bad++;
        aug_fail_after(-1);
        aug_writer_free(ws);
        fclose(sink);
        succeeded += ok;
    }
    aug_fail_after(-1);
    T_CHECK(bad == 0, "%d failures reported with a code other than AUG_ENOMEM", bad);
    T_CHECK(succeeded > 0, "no call succeeded within 40 allocations");
    aug_rec_free(&rf);
    aug_rec_free(&rd);
    aug_rec_free(&rv);
    aug_reader_free(r);
    fclose(fp);
    free(f);
    free(map);
    cholmod_free_sparse(&K0, &cm);
    cholmod_free_factor(&L0, &cm);
    aug_mesh_free(&m);
}

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(test_records_roundtrip);
    T_RUN(test_fact_all_factor_kinds);
    T_RUN(test_fact_supernodal_equals_cholmod_conversion);
    T_RUN(test_damaged_payloads);
    T_RUN(test_allocation_failures);
    cholmod_finish(&cm);
    T_EXIT();
}
