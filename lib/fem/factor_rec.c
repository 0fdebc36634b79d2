/* FACT record: CHOLMOD's packed simplicial LDL' factor P K P' = L D L' and its
   reconstruction as a cholmod_factor (formats/stream.md 6.4). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

#define DATA(...) aug_err_set(e, AUG_EDATA, rec->index, rec->type, __VA_ARGS__)

static int cmp_pair(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* payload buffer of exactly the record's size: no reallocation of 10^8 bytes */
static void reserve(aug_buf *b, size_t n)
{
    aug_buf_init(b);
    b->p = aug_malloc(n ? n : 1);
    b->cap = b->p ? n : 0;
    b->failed = !b->p;
}

static int finish(aug_writer *w, aug_buf *b, aug_err *e)
{
    return aug_buf_write(w, "FACT", AUG_NOSTEP, b, e);
}

static void put_header(aug_buf *b, const cholmod_factor *L, int64_t nnz, const int64_t *cp)
{
    aug_buf_i64(b, (int64_t)L->n);
    aug_buf_i64(b, nnz);
    aug_buf_i32(b, L->ordering);
    aug_buf_i32(b, 0);
    aug_buf_i32v(b, L->Perm, L->n);
    aug_buf_i64v(b, cp, L->n + 1);
}

/* Columns of a simplicial LDL' factor S: column j = D(j,j) at row j, then the
   rows of L(:,j) below the diagonal, increasing. */
static int write_simplicial(aug_writer *w, const cholmod_factor *S, aug_err *e)
{
    long idx = aug_writer_count(w);
    int64_t n = (int64_t)S->n;
    const int *Sp = S->p, *Si = S->i, *Snz = S->nz;
    const double *Sx = S->x;
    int64_t *cp = aug_malloc((size_t)(n + 1) * sizeof *cp);
    if (!cp) return aug_err_set(e, AUG_ENOMEM, idx, "FACT", "out of memory");
    cp[0] = 0;
    int unsorted = 0, maxcol = 0;
    for (int64_t j = 0; j < n; j++) {
        cp[j + 1] = cp[j] + Snz[j];
        if (Snz[j] > maxcol) maxcol = Snz[j];
        if (Snz[j] < 1 || Si[Sp[j]] != j) unsorted = 1;
        for (int q = Sp[j] + 1; q < Sp[j] + Snz[j]; q++)
            if (Si[q] <= Si[q - 1]) unsorted = 1;
    }
    aug_buf b;
    reserve(&b, 24 + (size_t)n * 4 + (size_t)(n + 1) * 8 + (size_t)cp[n] * 12);
    put_header(&b, S, cp[n], cp);
    free(cp);
    if (!unsorted) {
        for (int64_t j = 0; j < n; j++) aug_buf_i32v(&b, Si + Sp[j], (size_t)Snz[j]);
        for (int64_t j = 0; j < n; j++) aug_buf_f64v(&b, Sx + Sp[j], (size_t)Snz[j]);
    } else { /* after row updates a column may be out of order: sort (row, position) */
        int *key = aug_malloc((size_t)(maxcol ? maxcol : 1) * 2 * sizeof *key);
        if (!key) {
            aug_buf_free(&b);
            return aug_err_set(e, AUG_ENOMEM, idx, "FACT", "out of memory");
        }
        for (int pass = 0; pass < 2; pass++)
            for (int64_t j = 0; j < n; j++) {
                for (int q = 0; q < Snz[j]; q++)
                    key[2 * q] = Si[Sp[j] + q], key[2 * q + 1] = Sp[j] + q;
                qsort(key, (size_t)Snz[j], 2 * sizeof *key, cmp_pair);
                for (int q = 0; q < Snz[j]; q++) {
                    if (pass == 0) aug_buf_i32(&b, key[2 * q]);
                    else aug_buf_f64(&b, Sx[key[2 * q + 1]]);
                }
            }
        free(key);
    }
    return finish(w, &b, e);
}

/* Where write_supernodal puts the payload: a buffer (deflated records) or
   straight to the stream in parts (no copy of 10^8 bytes). */
typedef struct sink {
    aug_writer *w;
    aug_buf b;
    int stream, rc;
    aug_err *e;
} sink;

static void sink_put(sink *k, const void *p, size_t n, size_t size)
{
    if (k->rc) return;
    if (k->stream) k->rc = aug_write_part(k->w, p, n, size, k->e);
    else if (size == 4) aug_buf_i32v(&k->b, p, n);
    else aug_buf_i64v(&k->b, p, n); /* 8-byte elements, byte order only */
}

/* Supernodal LL' written as LDL' without converting L: column j = k1 + jj of
   supernode s holds rows Ls[pi + jj ..] and values Lx[px + jj*nsrow + jj ..];
   D(j,j) = L(j,j)^2 and L_ldl(i,j) = L(i,j) / L(j,j) (what cholmod_change_factor
   computes, [CHOLMOD] cholmod_change_factor). Returns 1 when the supernodal
   rows are not increasing (the caller converts instead). */
static int write_supernodal(aug_writer *w, const cholmod_factor *L, aug_err *e)
{
    long idx = aug_writer_count(w);
    int64_t n = (int64_t)L->n, ns = (int64_t)L->nsuper;
    const int *Super = L->super, *Lpi = L->pi, *Lpx = L->px, *Ls = L->s;
    const double *Lx = L->x;
    int64_t *cp = aug_malloc((size_t)(n + 1) * sizeof *cp);
    double *col = aug_malloc((size_t)(n ? n : 1) * sizeof *col);
    if (!cp || !col) {
        free(cp), free(col);
        return aug_err_set(e, AUG_ENOMEM, idx, "FACT", "out of memory");
    }
    cp[0] = 0;
    for (int64_t s = 0; s < ns; s++) {
        int k1 = Super[s], k2 = Super[s + 1], psi = Lpi[s], nsrow = Lpi[s + 1] - psi;
        for (int jj = 0; jj < k2 - k1; jj++) {
            if (Ls[psi + jj] != k1 + jj) goto unsorted;
            cp[k1 + jj + 1] = cp[k1 + jj] + (nsrow - jj);
        }
        for (int q = psi + 1; q < psi + nsrow; q++)
            if (Ls[q] <= Ls[q - 1]) goto unsorted;
    }
    size_t len = 24 + (size_t)n * 4 + (size_t)(n + 1) * 8 + (size_t)cp[n] * 12;
    sink k = {.w = w, .stream = aug_writer_deflate_min(w) == 0, .e = e};
    if (k.stream) k.rc = aug_write_begin(w, "FACT", AUG_NOSTEP, len, e);
    else reserve(&k.b, len);
    int64_t head[2] = {n, cp[n]};
    int32_t ord[2] = {L->ordering, 0};
    sink_put(&k, head, 2, 8);
    sink_put(&k, ord, 2, 4);
    sink_put(&k, L->Perm, (size_t)n, 4);
    sink_put(&k, cp, (size_t)n + 1, 8);
    free(cp);
    for (int64_t s = 0; s < ns; s++) {
        int k1 = Super[s], k2 = Super[s + 1], psi = Lpi[s], nsrow = Lpi[s + 1] - psi;
        for (int jj = 0; jj < k2 - k1; jj++) sink_put(&k, Ls + psi + jj, (size_t)(nsrow - jj), 4);
    }
    for (int64_t s = 0; s < ns; s++) {
        int k1 = Super[s], k2 = Super[s + 1], nsrow = Lpi[s + 1] - Lpi[s];
        for (int jj = 0; jj < k2 - k1; jj++) {
            const double *x = Lx + Lpx[s] + (size_t)jj * nsrow + jj;
            double ljj = x[0];
            col[0] = ljj * ljj;
            for (int q = 1; q < nsrow - jj; q++) col[q] = x[q] / ljj;
            sink_put(&k, col, (size_t)(nsrow - jj), 8);
        }
    }
    free(col);
    if (k.stream) return k.rc ? k.rc : aug_write_end(w, e);
    return finish(w, &k.b, e);
unsorted:
    free(cp);
    free(col);
    return 1;
}

/* Any numeric factor as FACT: simplicial LDL' directly, supernodal LL' by
   write_supernodal, otherwise (simplicial LL', or supernodal rows out of order)
   a copy converted by cholmod_change_factor; the caller's L is not changed. */
int aug_write_factor(aug_writer *w, const cholmod_factor *L, cholmod_common *cm,
                     aug_err *e)
{
    aug_err_clear(e);
    long idx = aug_writer_count(w);
    if (L->xtype != CHOLMOD_REAL || L->itype != CHOLMOD_INT || L->minor < L->n)
        return aug_err_set(e, AUG_EUSAGE, idx, "FACT",
                           "factor must be numeric, real, int-indexed and complete");
    if (!L->is_super && !L->is_ll) return write_simplicial(w, L, e);
    if (L->is_super) {
        int rc = write_supernodal(w, L, e);
        if (rc != 1) return rc;
    }
    cholmod_factor *S = cholmod_copy_factor((cholmod_factor *)L, cm);
    if (!S || !cholmod_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, S, cm)) {
        cholmod_free_factor(&S, cm);
        return aug_err_set(e, AUG_ENOMEM, idx, "FACT",
                           "converting the factor to simplicial LDL' failed (CHOLMOD status %d)",
                           cm->status);
    }
    int rc = write_simplicial(w, S, e);
    cholmod_free_factor(&S, cm);
    return rc;
}

/* Validate the payload, then: cholmod_allocate_factor (symbolic simplicial),
   Perm and ColCount from the record, cholmod_change_factor to a packed
   simplicial LDL' numeric factor, and p, i, x, nz filled from the record. */
cholmod_factor *aug_read_factor(const aug_rec *rec, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    aug_cur c;
    aug_cur_init(&c, rec);
    int64_t n = aug_cur_i64(&c), nnz = aug_cur_i64(&c);
    int32_t ordering = aug_cur_i32(&c);
    aug_cur_i32(&c);
    if (!c.ok || n < 0 || n >= INT32_MAX || nnz < n || nnz > INT32_MAX ||
        !aug_cur_has(&c, (uint64_t)n, 12) ||
        c.len - c.pos != (uint64_t)n * 4 + ((uint64_t)n + 1) * 8 + (uint64_t)nnz * 12) {
        aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type,
                    "sizes n = %lld, nnz = %lld do not match the payload", (long long)n,
                    (long long)nnz);
        return NULL;
    }
    int32_t *perm = aug_malloc((size_t)(n ? n : 1) * sizeof *perm);
    int64_t *cp = aug_malloc((size_t)(n + 1) * sizeof *cp);
    char *seen = aug_calloc((size_t)(n ? n : 1), 1);
    cholmod_factor *L = NULL;
    if (!perm || !cp || !seen) {
        aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
        goto fail;
    }
    aug_cur_i32v(&c, perm, (uint64_t)n);
    for (int64_t j = 0; j < n; j++) {
        if (perm[j] < 0 || perm[j] >= n || seen[perm[j]]) {
            DATA("perm[%lld] = %d: not a permutation", (long long)j, (int)perm[j]);
            goto fail;
        }
        seen[perm[j]] = 1;
    }
    aug_cur_i64v(&c, cp, (uint64_t)n + 1);
    if (cp[0] != 0 || cp[n] != nnz) {
        DATA("column pointers do not span 0..%lld", (long long)nnz);
        goto fail;
    }
    for (int64_t j = 0; j < n; j++)
        if (cp[j + 1] - cp[j] < 1 || cp[j + 1] - cp[j] > n - j) {
            DATA("column %lld has %lld entries", (long long)j, (long long)(cp[j + 1] - cp[j]));
            goto fail;
        }
    L = cholmod_allocate_factor((size_t)n, cm);
    if (!L) {
        aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory (CHOLMOD)");
        goto fail;
    }
    L->ordering = ordering;
    int *Perm = L->Perm, *CC = L->ColCount;
    for (int64_t j = 0; j < n; j++) Perm[j] = perm[j], CC[j] = (int)(cp[j + 1] - cp[j]);
    if (!cholmod_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, L, cm) ||
        (L->nzmax < (size_t)nnz && !cholmod_reallocate_factor((size_t)nnz, L, cm))) {
        aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory (CHOLMOD status %d)",
                    cm->status);
        goto fail;
    }
    int *Lp = L->p, *Li = L->i, *Lnz = L->nz;
    double *Lx = L->x;
    for (int64_t j = 0; j <= n; j++) Lp[j] = (int)cp[j];
    for (int64_t j = 0; j < n; j++) Lnz[j] = (int)(cp[j + 1] - cp[j]);
    aug_cur_i32v(&c, Li, (uint64_t)nnz);
    aug_cur_f64v(&c, Lx, (uint64_t)nnz);
    for (int64_t j = 0; j < n; j++) {
        /* K0 (or A) is positive definite: every D(j,j) > 0 (a negative one
           was refused by solve-aug without the record, passed by stats) */
        if (Li[Lp[j]] != j || !isfinite(Lx[Lp[j]]) || !(Lx[Lp[j]] > 0)) {
            DATA("column %lld does not start with a finite positive D(j,j) (%g)", (long long)j,
                 Li[Lp[j]] == j ? Lx[Lp[j]] : NAN);
            goto fail;
        }
        for (int q = Lp[j] + 1; q < Lp[j + 1]; q++)
            if (Li[q] <= Li[q - 1] || Li[q] >= n || !isfinite(Lx[q])) {
                DATA("column %lld: row %d out of order or range, or value not finite",
                     (long long)j, Li[q]);
                goto fail;
            }
    }
    L->minor = (size_t)n;
    free(perm);
    free(cp);
    free(seen);
    return L;
fail:
    cholmod_free_factor(&L, cm);
    free(perm);
    free(cp);
    free(seen);
    return NULL;
}

int aug_fact_info(const aug_rec *rec, int64_t *n, int64_t *nnz, int32_t *ordering)
{
    aug_cur c;
    aug_cur_init(&c, rec);
    *n = aug_cur_i64(&c), *nnz = aug_cur_i64(&c);
    *ordering = aug_cur_i32(&c);
    return c.ok ? 0 : -1;
}

static int fact_check(const aug_rec *rec, aug_err *e)
{
    cholmod_common cm;
    aug_cholmod_start(&cm);
    cholmod_factor *L = aug_read_factor(rec, &cm, e);
    int rc = L ? 0 : e->code;
    cholmod_free_factor(&L, &cm);
    cholmod_finish(&cm);
    return rc;
}

static int fact_dump(FILE *o, aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    if (fact_check(rec, e)) return e->code;
    aug_cur c;
    aug_cur_init(&c, rec);
    int64_t n = aug_cur_i64(&c), nnz = aug_cur_i64(&c);
    int32_t ord = aug_cur_i32(&c);
    aug_cur_i32(&c);
    aug_txt_header(o, rec);
    fprintf(o, "  n %lld\n  nnz %lld\n  ordering %d (%s)\n", (long long)n, (long long)nnz,
            (int)ord, aug_ordering_name(ord));
    aug_txt_i32s(o, "perm", &c, (uint64_t)n);
    aug_txt_i64s(o, "colptr", &c, (uint64_t)n + 1);
    aug_txt_i32s(o, "rowind", &c, (uint64_t)nnz);
    aug_txt_f64s(o, "value", &c, (uint64_t)nnz);
    return 0;
}

const aug_codec aug_codec_fact = {"lib/fem/factor_rec.c", fact_check, fact_dump};
