/* Layout and structure checks of DOFM KMAT FVEC FACT pATH fELD payloads
   (formats/stream.md 6.1-6.4, 7.3, 7.6), for readers that only look at them. */
#include <stdlib.h>
#include <string.h>
#include "aug_stats.h"

#define BAD(...) aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type, __VA_ARGS__)
#define DATA(...) aug_err_set(e, AUG_EDATA, rec->index, rec->type, __VA_ARGS__)

/* colptr[n+1] from 0 to nnz, non-decreasing; rowind < n, strictly increasing
   within a column; if diag_first, column j starts with row j (FACT: D(j,j)).
   c is positioned at colptr, rowind follows it. */
static int check_csc(aug_cur c, int64_t n, int64_t nnz, int diag_first, const aug_rec *rec,
                     aug_err *e)
{
    aug_cur ri = c;
    ri.pos += 8 * ((uint64_t)n + 1);
    int64_t prev = aug_cur_i64(&c);
    if (prev != 0) return DATA("colptr[0] = %lld, not 0", (long long)prev);
    for (int64_t j = 0; j < n; j++) {
        int64_t p = aug_cur_i64(&c);
        if (p < prev || p > nnz)
            return DATA("colptr[%lld] = %lld out of order", (long long)j + 1, (long long)p);
        if (diag_first && p == prev)
            return DATA("column %lld has no diagonal entry", (long long)j);
        int32_t last = -1;
        for (int64_t k = prev; k < p; k++) {
            int32_t r = aug_cur_i32(&ri);
            if (r < 0 || r >= n || r <= last)
                return DATA("column %lld: row index %d out of range or order", (long long)j, (int)r);
            if (diag_first && k == prev && r != j)
                return DATA("column %lld does not start with its diagonal", (long long)j);
            last = r;
        }
        prev = p;
    }
    if (prev != nnz) return DATA("colptr[n] = %lld, not nnz = %lld", (long long)prev, (long long)nnz);
    return 0;
}

static int check_dofm(const aug_rec *rec, aug_err *e)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t dim = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t ndof = aug_cur_i64(&c), nfree = aug_cur_i64(&c);
    if (dim != 2 && dim != 3) return BAD("dimension %d is neither 2 nor 3", (int)dim);
    if (ndof < 0 || nfree < 0 || nfree > ndof || !aug_cur_has(&c, (uint64_t)ndof, 4) ||
        c.len - c.pos != (uint64_t)ndof * 4)
        return BAD("ndof %lld, nfree %lld do not match the payload", (long long)ndof,
                   (long long)nfree);
    int32_t next = 0;
    for (int64_t i = 0; i < ndof; i++) {
        int32_t f = aug_cur_i32(&c);
        if (f != -1 && f != next)
            return DATA("map[%lld] = %d: free indices must count up from 0", (long long)i, (int)f);
        if (f >= 0) next++;
    }
    if (next != nfree) return DATA("map has %d free DOFs, nfree says %lld", (int)next, (long long)nfree);
    return 0;
}

static int check_kmat(const aug_rec *rec, aug_err *e)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t n = aug_cur_i64(&c), nnz = aug_cur_i64(&c);
    if (n < 0 || nnz < 0 || n > INT32_MAX || !aug_cur_has(&c, (uint64_t)n + 1, 8) ||
        !aug_cur_has(&c, (uint64_t)nnz, 12) ||
        c.len - c.pos != 8 * ((uint64_t)n + 1) + 12 * (uint64_t)nnz)
        return BAD("n %lld, nnz %lld do not match the payload", (long long)n, (long long)nnz);
    return check_csc(c, n, nnz, 0, rec, e);
}

static int check_fvec(const aug_rec *rec, aug_err *e)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t n = aug_cur_i64(&c);
    if (n < 0 || !aug_cur_has(&c, (uint64_t)n, 8) || c.len - c.pos != 8 * (uint64_t)n)
        return BAD("n %lld does not match the payload", (long long)n);
    return 0;
}

static int check_fact(const aug_rec *rec, aug_err *e)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int64_t n = aug_cur_i64(&c), nnz = aug_cur_i64(&c);
    aug_cur_i32(&c);
    aug_cur_i32(&c);
    if (n < 0 || nnz < 0 || n > INT32_MAX || !aug_cur_has(&c, (uint64_t)n, 4) ||
        !aug_cur_has(&c, (uint64_t)nnz, 12) ||
        c.len - c.pos != 4 * (uint64_t)n + 8 * ((uint64_t)n + 1) + 12 * (uint64_t)nnz)
        return BAD("n %lld, nnz %lld do not match the payload", (long long)n, (long long)nnz);
    unsigned char *seen = aug_calloc((size_t)n, 1);
    if (!seen) return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    for (int64_t i = 0; i < n; i++) {
        int32_t p = aug_cur_i32(&c);
        if (p < 0 || p >= n || seen[p]) {
            free(seen);
            return DATA("perm is not a permutation (perm[%lld] = %d)", (long long)i, (int)p);
        }
        seen[p] = 1;
    }
    free(seen);
    return check_csc(c, n, nnz, 1, rec, e);
}

static int check_path(const aug_rec *rec, aug_err *e)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t dim = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int64_t nseg = aug_cur_i64(&c);
    if (dim != 2 && dim != 3) return BAD("dimension %d is neither 2 nor 3", (int)dim);
    if (nseg < 0 || !aug_cur_has(&c, (uint64_t)nseg, 16 * (uint64_t)dim) ||
        c.len - c.pos != 16 * (uint64_t)dim * (uint64_t)nseg)
        return BAD("segment count %lld does not match the payload", (long long)nseg);
    return 0;
}

static int check_feld(const aug_rec *rec, aug_err *e)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    aug_cur_i32(&c);
    int32_t dim = aug_cur_i32(&c);
    int64_t count = aug_cur_i64(&c);
    int32_t indexed = aug_cur_i32(&c);
    aug_cur_i32(&c);
    if (dim != 2 && dim != 3) return BAD("dimension %d is neither 2 nor 3", (int)dim);
    if (indexed != 0 && indexed != 1) return BAD("indexed flag %d is neither 0 nor 1", (int)indexed);
    uint64_t per = 8 * (uint64_t)dim + 4 * (uint64_t)indexed;
    if (count < 0 || count > INT32_MAX || !aug_cur_has(&c, (uint64_t)count, per) ||
        c.len - c.pos != per * (uint64_t)count)
        return BAD("count %lld does not match the payload", (long long)count);
    for (int64_t i = 0; i < count * indexed; i++) {
        int32_t v = aug_cur_i32(&c);
        if (v < 0) return DATA("node[%lld] = %d is negative", (long long)i, (int)v);
    }
    return 0;
}

int aug_check_payload(const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    const char *t = rec->type;
    if (!memcmp(t, "DOFM", 4)) return check_dofm(rec, e);
    if (!memcmp(t, "KMAT", 4)) return check_kmat(rec, e);
    if (!memcmp(t, "FVEC", 4)) return check_fvec(rec, e);
    if (!memcmp(t, "FACT", 4)) return check_fact(rec, e);
    if (!memcmp(t, "pATH", 4)) return check_path(rec, e);
    if (!memcmp(t, "fELD", 4)) return check_feld(rec, e);
    return 0;
}
