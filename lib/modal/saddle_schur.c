/* Direct solve of the coupled system (paper 004 eq. 15/18) by the dual Schur
   complement S = C_c A^-1 C_c', assembled from cached per-block parts. */
#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"
#include "aug_saddle.h"

#define ERR(e, code, ...) aug_err_set(e, code, -1, "MODE", __VA_ARGS__)
/* right-hand sides per CHOLMOD solve when forming a contribution */
#define RHS_CHUNK 64

/* A_b = L L' (CHOLMOD for FE blocks, dpotrf for reduced ones);
   AUG_ESINGULAR when A_b is not positive definite */
static int factor_block(aug_saddle *s, aug_sblk *b, int ib, aug_err *e)
{
    int n = (int)b->d.n;
    if (b->d.A) {
        cholmod_free_factor(&b->L, s->cm);
        b->L = aug_analyze(b->d.A, s->cm, e);
        if (!b->L) return ERR(e, e->code, "saddle: block %d: %s", ib, e->msg);
        if (aug_factorize(b->d.A, b->L, NULL, NULL, s->cm, e)) {
            char msg[sizeof e->msg];
            snprintf(msg, sizeof msg, "%s", e->msg);
            return ERR(e, e->code, "saddle: block %d: %s", ib, msg);
        }
    } else {
        double *Lc = aug_realloc(b->Lc, (size_t)n * n * sizeof *Lc);
        if (!Lc) return ERR(e, AUG_ENOMEM, "saddle: out of memory");
        b->Lc = Lc;
        memcpy(Lc, b->d.Ad, (size_t)n * n * sizeof *Lc);
        int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', n, Lc, n);
        if (info)
            return ERR(e, AUG_ESINGULAR, "saddle: block %d (reduced) is not positive definite "
                       "(pivot %d)", ib, info);
    }
    b->fact_ok = 1;
    s->nfactor++;
    return 0;
}

/* X = A_b^-1 B for nrhs columns (leading dimension n) in place */
static int block_solve(aug_saddle *s, aug_sblk *b, double *B, int nrhs, aug_err *e)
{
    int n = (int)b->d.n;
    if (b->d.A) {
        cholmod_dense Bd = aug_dense_view(B, (size_t)n * nrhs);
        Bd.nrow = (size_t)n;
        Bd.ncol = (size_t)nrhs;
        Bd.d = (size_t)n;
        if (!cholmod_solve2(CHOLMOD_A, b->L, &Bd, NULL, &b->X, NULL, &b->Y, &b->E, s->cm))
            return ERR(e, AUG_ENOMEM, "saddle: CHOLMOD solve failed (status %d)", s->cm->status);
        memcpy(B, b->X->x, (size_t)n * nrhs * sizeof *B);
    } else if (LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', n, nrhs, b->Lc, n, B, n)) {
        return ERR(e, AUG_EUSAGE, "saddle: dense solve failed");
    }
    return 0;
}

/* entries of compressed row q restricted to block b, (col - off, value) into
   c, v (capacity n + nd); returns the count */
static int row_entries(const aug_saddle *s, const aug_sblk *b, int q, int *c, double *v)
{
    int64_t lo = b->off, hi = b->off + b->d.n;
    int t = 0;
    if (q < s->mp) {
        for (int p = s->pp[q]; p < s->pp[q + 1]; p++)
            if (s->pj[p] >= lo && s->pj[p] < hi) {
                c[t] = (int)(s->pj[p] - lo);
                v[t++] = s->px[p];
            }
    } else {
        int j = q - s->mp;
        for (int l = 0; l < s->nd; l++)
            if (s->dcol[l] >= lo && s->dcol[l] < hi) {
                c[t] = (int)(s->dcol[l] - lo);
                v[t++] = s->Ck[j + (size_t)l * s->k];
            }
    }
    return t;
}

/* Sb = C_c,b A_b^-1 C_c,b' over the block's nr compressed rows: B = C_c,b'
   in chunks of RHS_CHUNK columns, X = A_b^-1 B (one multi-right-hand-side
   solve per chunk), Sb(:, chunk) = C_c,b X. Cost: nr / RHS_CHUNK solves of
   RHS_CHUNK columns plus O(nnz(C_c,b) nr). */
static int contrib_block(aug_saddle *s, aug_sblk *b, aug_err *e)
{
    int n = (int)b->d.n, nr = b->nr;
    free(b->Sb);
    b->Sb = NULL;
    if (nr == 0) {
        b->sc_ok = 1;
        s->ncontrib++;
        return 0;
    }
    int cs = nr < RHS_CHUNK ? nr : RHS_CHUNK;
    /* local CSR of C_c,b */
    int *lp = aug_malloc(((size_t)nr + 1) * sizeof *lp);
    int cap = n + s->nd + 1;
    int *tc = aug_malloc((size_t)cap * sizeof *tc);
    double *tv = aug_malloc((size_t)cap * sizeof *tv);
    double *B = aug_malloc((size_t)n * cs * sizeof *B);
    b->Sb = aug_malloc((size_t)nr * nr * sizeof *b->Sb);
    int *lc = NULL;
    double *lv = NULL;
    int rc = 0;
    if (!lp || !tc || !tv || !B || !b->Sb) goto nomem;
    lp[0] = 0;
    for (int r = 0; r < nr; r++) lp[r + 1] = lp[r] + row_entries(s, b, b->rows[r], tc, tv);
    lc = aug_malloc(((size_t)lp[nr] + 1) * sizeof *lc);
    lv = aug_malloc(((size_t)lp[nr] + 1) * sizeof *lv);
    if (!lc || !lv) goto nomem;
    for (int r = 0; r < nr; r++) row_entries(s, b, b->rows[r], lc + lp[r], lv + lp[r]);
    for (int c0 = 0; c0 < nr; c0 += cs) {
        int nc = nr - c0 < cs ? nr - c0 : cs;
        memset(B, 0, (size_t)n * nc * sizeof *B);
        for (int t = 0; t < nc; t++)
            for (int p = lp[c0 + t]; p < lp[c0 + t + 1]; p++) B[lc[p] + (size_t)t * n] = lv[p];
        if ((rc = block_solve(s, b, B, nc, e))) goto out;
        for (int t = 0; t < nc; t++) {
            const double *X = B + (size_t)t * n;
            double *Sc = b->Sb + (size_t)(c0 + t) * nr;
            for (int r = 0; r < nr; r++) {
                double a = 0;
                for (int p = lp[r]; p < lp[r + 1]; p++) a += lv[p] * X[lc[p]];
                Sc[r] = a;
            }
        }
    }
    for (int j = 0; j < nr; j++)
        for (int i = j + 1; i < nr; i++) {
            double a = 0.5 * (b->Sb[i + (size_t)j * nr] + b->Sb[j + (size_t)i * nr]);
            b->Sb[i + (size_t)j * nr] = b->Sb[j + (size_t)i * nr] = a;
        }
    b->sc_ok = 1;
    s->ncontrib++;
    goto out;
nomem:
    rc = ERR(e, AUG_ENOMEM, "saddle: out of memory");
out:
    free(lp); free(tc); free(tv); free(B); free(lc); free(lv);
    return rc;
}

/* factors, contributions and the Cholesky factor of S, each only if stale */
static int prepare(aug_saddle *s, aug_err *e)
{
    for (int i = 0; i < s->nb; i++) {
        aug_sblk *b = &s->blk[i];
        if (!b->fact_ok && factor_block(s, b, i, e)) return e->code;
        if (!b->sc_ok) {
            s->S_ok = 0;
            if (contrib_block(s, b, e)) return e->code;
        }
    }
    if (s->S_ok) return 0;
    int mc = s->mc;
    double *S = aug_realloc(s->S, ((size_t)mc * mc + 1) * sizeof *S);
    if (!S) return ERR(e, AUG_ENOMEM, "saddle: out of memory");
    s->S = S;
    memset(S, 0, (size_t)mc * mc * sizeof *S);
    for (int i = 0; i < s->nb; i++) {
        const aug_sblk *b = &s->blk[i];
        for (int cj = 0; cj < b->nr; cj++)
            for (int ci = 0; ci < b->nr; ci++)
                S[b->rows[ci] + (size_t)b->rows[cj] * mc] += b->Sb[ci + (size_t)cj * b->nr];
    }
    if (mc > 0) {
        int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', mc, S, mc);
        if (info)
            return ERR(e, AUG_ESINGULAR, "saddle: the Schur complement C A^-1 C' is not positive "
                       "definite (pivot %d of %d)", info, mc);
    }
    s->S_ok = 1;
    return 0;
}

/* y = A^-1 v blockwise (in place) */
static int apply_inv(aug_saddle *s, double *v, aug_err *e)
{
    for (int i = 0; i < s->nb; i++)
        if (block_solve(s, &s->blk[i], v + s->blk[i].off, 1, e)) return e->code;
    return 0;
}

/* mu = S^-1 (C_c A^-1 r - g_c), x = A^-1 (r - C_c' mu), lambda = expand(mu)
   (paper 004 eq. 18 by block elimination of x) */
int aug_saddle_schur(aug_saddle *s, const double *r, const double *g, double *x, double *lambda,
                     aug_saddle_stats *st, aug_err *e)
{
    aug_err_clear(e);
    aug_saddle_stats z = {0};
    if (!st) st = &z;
    memset(st, 0, sizeof *st);
    if (!s->c_ok) return ERR(e, AUG_EUSAGE, "saddle: no system set");
    double t0 = aug_now();
    if (prepare(s, e)) return e->code;
    double t1 = aug_now();
    int64_t N = s->N;
    int mc = s->mc;
    double *gc = s->u[0], *mu = s->u[1];
    aug_saddle_compress(s, g, gc);
    memcpy(x, r, (size_t)N * sizeof *x);
    if (apply_inv(s, x, e)) return e->code;
    aug_saddle_cc(s, x, mu);
    for (int i = 0; i < mc; i++) mu[i] -= gc[i];
    if (mc > 0 && LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', mc, 1, s->S, mc, mu, mc))
        return ERR(e, AUG_EUSAGE, "saddle: dense solve failed");
    memset(x, 0, (size_t)N * sizeof *x);
    aug_saddle_cct(s, mu, x);
    for (int64_t j = 0; j < N; j++) x[j] = r[j] - x[j];
    if (apply_inv(s, x, e)) return e->code;
    if (lambda) aug_saddle_expand(s, mu, lambda);
    double t2 = aug_now();
    if (aug_saddle_residuals(s, r, g, gc, x, mu, st, e)) return e->code;
    st->iters = 0;
    st->converged = 1;
    st->prep_ms = 1e3 * (t1 - t0);
    st->solve_ms = 1e3 * (t2 - t1);
    return 0;
}
