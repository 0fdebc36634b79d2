/* Matrix-family codecs (formats/stream.md 6.1-6.3): DOFM (DOF numbering), KMAT
   (sparse symmetric matrix, upper triangle) and FVEC (vector over the free DOFs). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

#define BAD(...) aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type, __VA_ARGS__)
#define DATA(...) aug_err_set(e, AUG_EDATA, rec->index, rec->type, __VA_ARGS__)
#define NOMEM() aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory")

/* DOFM: i32 dim, i32 0, i64 ndof, i64 nfree, i32 map[ndof] */
int aug_write_dofmap(aug_writer *w, const aug_mesh *m, const int32_t *map, int64_t nfree,
                     aug_err *e)
{
    aug_err_clear(e);
    aug_buf b;
    aug_buf_init(&b);
    int64_t nd = m->nn * m->dim;
    aug_buf_i32(&b, m->dim);
    aug_buf_i32(&b, 0);
    aug_buf_i64(&b, nd);
    aug_buf_i64(&b, nfree);
    aug_buf_i32v(&b, map, (size_t)nd);
    return aug_buf_write(w, "DOFM", AUG_NOSTEP, &b, e);
}

/* map[dof] in {-1} u {0..nfree-1}, the free indices 0, 1, 2, ... in dof order */
int aug_read_dofmap(const aug_rec *rec, int *dim, int64_t *ndof, int64_t *nfree,
                    int32_t **map, aug_err *e)
{
    aug_err_clear(e);
    *map = NULL;
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t d = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t nd = aug_cur_i64(&c), nf = aug_cur_i64(&c);
    if (!c.ok || (d != 2 && d != 3)) return BAD("dimension %d is neither 2 nor 3", (int)d);
    if (nd < 0 || nd > INT32_MAX || nd % d || c.len - c.pos != (uint64_t)nd * 4)
        return BAD("dof count %lld does not match the payload", (long long)nd);
    if (nf < 0 || nf > nd) return BAD("free dof count %lld of %lld", (long long)nf, (long long)nd);
    int32_t *mp = aug_malloc((size_t)nd * sizeof *mp);
    if (!mp) return NOMEM();
    aug_cur_i32v(&c, mp, (uint64_t)nd);
    int64_t k = 0;
    for (int64_t i = 0; i < nd; i++) {
        if (mp[i] == -1) continue;
        if (mp[i] != k) {
            int32_t got = mp[i];
            free(mp);
            return DATA("dof %lld maps to %d, expected -1 or %lld", (long long)i, (int)got,
                        (long long)k);
        }
        k++;
    }
    if (k != nf) {
        free(mp);
        return DATA("map numbers %lld free dofs, header says %lld", (long long)k, (long long)nf);
    }
    *dim = d;
    *ndof = nd;
    *nfree = nf;
    *map = mp;
    return 0;
}

/* KMAT: i32 which, i32 stype, i64 n, i64 nnz, i64 colptr[n+1], i32 rowind[nnz],
   f64 value[nnz]; columns written with rows increasing (sorted here if A is not). */
int aug_write_sparse(aug_writer *w, int which, const cholmod_sparse *A, aug_err *e)
{
    aug_err_clear(e);
    long idx = aug_writer_count(w);
    if (A->itype != CHOLMOD_INT || A->xtype != CHOLMOD_REAL || A->dtype != CHOLMOD_DOUBLE ||
        A->nrow != A->ncol || A->stype != 1)
        return aug_err_set(e, AUG_EUSAGE, idx, "KMAT",
                           "matrix must be real, square, int-indexed, upper triangle stored");
    const int *Ap = A->p, *Ai = A->i, *Anz = A->nz;
    const double *Ax = A->x;
    int64_t n = (int64_t)A->ncol, nnz = 0;
    int64_t *cp = aug_malloc((size_t)(n + 1) * sizeof *cp);
    if (!cp) return aug_err_set(e, AUG_ENOMEM, idx, "KMAT", "out of memory");
    cp[0] = 0;
    size_t maxcol = 0;
    for (int64_t j = 0; j < n; j++) {
        int64_t len = A->packed ? Ap[j + 1] - Ap[j] : Anz[j];
        if ((size_t)len > maxcol) maxcol = (size_t)len;
        cp[j + 1] = cp[j] + len;
    }
    nnz = cp[n];
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, which);
    aug_buf_i32(&b, 1);
    aug_buf_i64(&b, n);
    aug_buf_i64(&b, nnz);
    aug_buf_i64v(&b, cp, (size_t)n + 1);
    free(cp);
    if (A->sorted) {
        for (int64_t j = 0; j < n; j++)
            aug_buf_i32v(&b, Ai + Ap[j], (size_t)(A->packed ? Ap[j + 1] - Ap[j] : Anz[j]));
        for (int64_t j = 0; j < n; j++)
            aug_buf_f64v(&b, Ax + Ap[j], (size_t)(A->packed ? Ap[j + 1] - Ap[j] : Anz[j]));
        return aug_buf_write(w, "KMAT", AUG_NOSTEP, &b, e);
    }
    /* unsorted: sort (row, position) keys per column; rows pass, then values pass */
    int32_t *key = aug_malloc((maxcol ? maxcol : 1) * 2 * sizeof *key);
    if (!key) {
        aug_buf_free(&b);
        return aug_err_set(e, AUG_ENOMEM, idx, "KMAT", "out of memory");
    }
    for (int pass = 0; pass < 2; pass++)
        for (int64_t j = 0; j < n; j++) {
            int len = A->packed ? Ap[j + 1] - Ap[j] : Anz[j];
            for (int q = 0; q < len; q++) key[2 * q] = Ai[Ap[j] + q], key[2 * q + 1] = Ap[j] + q;
            qsort(key, (size_t)len, 2 * sizeof *key, aug_cmp_i32);
            for (int q = 0; q < len; q++) {
                if (pass == 0) aug_buf_i32(&b, key[2 * q]);
                else aug_buf_f64(&b, Ax[key[2 * q + 1]]);
            }
        }
    free(key);
    return aug_buf_write(w, "KMAT", AUG_NOSTEP, &b, e);
}

cholmod_sparse *aug_read_sparse(const aug_rec *rec, int *which, cholmod_common *cm,
                                aug_err *e)
{
    aug_err_clear(e);
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t wh = aug_cur_i32(&c), stype = aug_cur_i32(&c);
    int64_t n = aug_cur_i64(&c), nnz = aug_cur_i64(&c);
    if (!c.ok || wh < AUG_MAT_K || wh > AUG_MAT_A) {
        BAD("unknown matrix kind %d", (int)wh);
        return NULL;
    }
    if (stype != 1) {
        BAD("stype %d: only the upper triangle (1) is defined", (int)stype);
        return NULL;
    }
    if (n < 0 || n >= INT32_MAX || nnz < 0 || nnz > INT32_MAX ||
        !aug_cur_has(&c, (uint64_t)n + 1, 8) ||
        c.len - c.pos != ((uint64_t)n + 1) * 8 + (uint64_t)nnz * 12) {
        BAD("sizes n = %lld, nnz = %lld do not match the payload", (long long)n, (long long)nnz);
        return NULL;
    }
    cholmod_sparse *A = cholmod_allocate_sparse((size_t)n, (size_t)n, (size_t)nnz, 1, 1, 1,
                                                CHOLMOD_REAL, cm);
    if (!A) {
        NOMEM();
        return NULL;
    }
    int *Ap = A->p, *Ai = A->i;
    double *Ax = A->x;
    for (int64_t j = 0; j <= n; j++) {
        int64_t v = aug_cur_i64(&c);
        if ((j == 0 && v != 0) || (j > 0 && (v < Ap[j - 1] || v > nnz)) || (j == n && v != nnz)) {
            DATA("column pointer %lld = %lld is out of order", (long long)j, (long long)v);
            cholmod_free_sparse(&A, cm);
            return NULL;
        }
        Ap[j] = (int)v;
    }
    aug_cur_i32v(&c, Ai, (uint64_t)nnz);
    aug_cur_f64v(&c, Ax, (uint64_t)nnz);
    for (int64_t j = 0; j < n; j++)
        for (int p = Ap[j]; p < Ap[j + 1]; p++) {
            const char *why = NULL;
            if (Ai[p] < 0 || Ai[p] > j) why = "outside the upper triangle";
            else if (p > Ap[j] && Ai[p] <= Ai[p - 1]) why = "not increasing in its column";
            else if (!isfinite(Ax[p])) why = "not finite";
            if (why) {
                DATA("entry (%d, %lld) is %s", (int)Ai[p], (long long)j, why);
                cholmod_free_sparse(&A, cm);
                return NULL;
            }
        }
    if (which) *which = wh;
    return A;
}

/* TYPE: i32 kind, i32 0, i64 n, f64 v[n] (FVEC and vectors of the same layout) */
int aug_write_vector(aug_writer *w, const char *type, int32_t step, int32_t kind,
                     const double *v, int64_t n, aug_err *e)
{
    aug_err_clear(e);
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, kind);
    aug_buf_i32(&b, 0);
    aug_buf_i64(&b, n);
    aug_buf_f64v(&b, v, (size_t)n);
    return aug_buf_write(w, type, step, &b, e);
}

int aug_read_vector(const aug_rec *rec, int32_t *kind, int64_t *n, double **v, aug_err *e)
{
    aug_err_clear(e);
    *v = NULL;
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t k = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t len = aug_cur_i64(&c);
    if (!c.ok || len < 0 || len > INT32_MAX || c.len - c.pos != (uint64_t)len * 8)
        return BAD("vector length %lld does not match the payload", (long long)len);
    /* 6.3: an FVEC's kind 0 is the only one (a kind 5 passed stats and
       refine, and solve-aug blamed the UPDT after it) */
    if (!memcmp(rec->type, "FVEC", 4) && k != 0) return DATA("kind %d (0, the load, is the only kind)", (int)k);
    double *x = aug_malloc((size_t)len * sizeof *x);
    if (!x) return NOMEM();
    aug_cur_f64v(&c, x, (uint64_t)len);
    for (int64_t i = 0; i < len; i++)
        if (!isfinite(x[i])) {
            free(x);
            return DATA("entry %lld is not finite", (long long)i);
        }
    *kind = k;
    *n = len;
    *v = x;
    return 0;
}

static int dofm_check(const aug_rec *rec, aug_err *e)
{
    int dim;
    int64_t nd, nf;
    int32_t *map;
    int rc = aug_read_dofmap(rec, &dim, &nd, &nf, &map, e);
    free(map);
    return rc;
}

static int dofm_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    if (dofm_check(rec, e)) return e->code;
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t dim = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t ndof = aug_cur_i64(&c), nfree = aug_cur_i64(&c);
    aug_txt_header(o, rec);
    fprintf(o, "  dim %d\n  ndof %lld\n  nfree %lld\n", (int)dim, (long long)ndof,
            (long long)nfree);
    aug_txt_i32s(o, "map", &c, (uint64_t)ndof);
    return 0;
}

int aug_kmat_info(const aug_rec *rec, int32_t *which, int32_t *stype, int64_t *n, int64_t *nnz)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    *which = aug_cur_i32(&c), *stype = aug_cur_i32(&c);
    *n = aug_cur_i64(&c), *nnz = aug_cur_i64(&c);
    return c.ok ? 0 : -1;
}

static int kmat_check(const aug_rec *rec, aug_err *e)
{
    cholmod_common cm;
    aug_cholmod_start(&cm);
    cholmod_sparse *A = aug_read_sparse(rec, NULL, &cm, e);
    int rc = A ? 0 : e->code;
    cholmod_free_sparse(&A, &cm);
    cholmod_finish(&cm);
    return rc;
}

static int kmat_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    if (kmat_check(rec, e)) return e->code;
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t which = aug_cur_i32(&c), stype = aug_cur_i32(&c);
    int64_t n = aug_cur_i64(&c), nnz = aug_cur_i64(&c);
    static const char *names[] = {"stiffness K", "consistent mass M", "lumped mass", "effective A"};
    aug_txt_header(o, rec);
    fprintf(o, "  which %d (%s)\n  stype %d\n  n %lld\n  nnz %lld\n", (int)which,
            which >= 0 && which <= 3 ? names[which] : "unknown", (int)stype, (long long)n,
            (long long)nnz);
    aug_txt_i64s(o, "colptr", &c, (uint64_t)n + 1);
    aug_txt_i32s(o, "rowind", &c, (uint64_t)nnz);
    aug_txt_f64s(o, "value", &c, (uint64_t)nnz);
    return 0;
}

static int fvec_check(const aug_rec *rec, aug_err *e)
{
    int32_t kind;
    int64_t n;
    double *v;
    int rc = aug_read_vector(rec, &kind, &n, &v, e);
    free(v);
    return rc;
}

static int fvec_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    if (fvec_check(rec, e)) return e->code;
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t kind = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t n = aug_cur_i64(&c);
    aug_txt_header(o, rec);
    fprintf(o, "  kind %d\n  n %lld\n", (int)kind, (long long)n);
    aug_txt_f64s(o, "v", &c, (uint64_t)n);
    return 0;
}

const aug_codec aug_codec_dofm = {"lib/fem/matrix_rec.c", dofm_check, dofm_dump};
const aug_codec aug_codec_kmat = {"lib/fem/matrix_rec.c", kmat_check, kmat_dump};
const aug_codec aug_codec_fvec = {"lib/fem/matrix_rec.c", fvec_check, fvec_dump};
