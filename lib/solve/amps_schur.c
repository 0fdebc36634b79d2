/* AMPS steps 3 and 5 (paper 001 table 1): the Schur complement S2 = I - Gbar Ebar
   of eqs. 3.8 and 3.21 on the active positions, LU-factored with LAPACK, and the
   factorization carried from step to step.

   A grows in activation order and Gbar_AA never changes (the memo is fixed
   for a base), so a step changes S2 only in the columns whose Ebar column it
   touched (its own positions) and in the rows and columns of newly active
   positions. Columns before the first changed one keep their pivots and L, U
   entries; the new rows are solved against U11; the trailing block gets the
   usual right-looking block update and a fresh partial-pivoting LU. The cut
   front moves on, so the re-eliminated block stays a small part of S2. S2
   itself is not kept beside its factors: the columns the update needs are
   formed again from the memo's H'K^-1H and Ebar_AA (s2_column), so that
   only the LU grows with the square of |A|. */
#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

/* multipliers of the new rows against the kept pivots above this bound
   (those pivots were chosen without the new rows) force a full factorization */
#define GROWTH_MAX 1e3
/* update_lu out of memory (below any dgetrf argument number) */
#define LU_NOMEM (-1000)

void aug_schur_init(aug_schur *s)
{
    memset(s, 0, sizeof *s);
    s->rcond = NAN;
}

void aug_schur_free(aug_schur *s)
{
    int wr = s->want_rcond;
    free(s->A);
    free(s->act);
    free(s->gi);
    free(s->rs);
    aug_map_free(s->S2, (size_t)s->scap * (size_t)s->scap * sizeof *s->S2);
    free(s->cs);
    free(s->ipiv);
    free(s->ep);
    free(s->ei);
    free(s->ex);
    aug_schur_init(s);
    s->want_rcond = wr;
}

/* 1 / sigma_q for a new DOF q at position p: Kbar = blkdiag(K, Sigma) with
   sigma_q = |K_t(q,q)| = |1 - Ebar(p,p)| when it activates, instead of the
   I_k of paper 001 eq. 3.7. Gbar(q,q) = 1/sigma_q turns S2's row q into
   (e_q' - Ebar(p,:)) / sigma_q, the right-hand side into dF_q / sigma_q and
   leaves a2 as it was: a row scaling of S2. With I_k the rows of new DOFs are
   ||K|| (kPa stiffness times the element size) against O(1) for the base
   rows, and partial pivoting then picks pivots from them whatever the base
   rows hold: on a three-material sphere (E 1e3..1e6, nu 0.49) the residual
   grew to 2e5 x refactor's within 24 steps; scaled, it stays within 50 x. */
static double new_scale(const aug_ecol *E, int32_t p)
{
    double d = 1.0;
    for (int32_t t = 0; t < E->nz; t++)
        if (E->i[t] == p) d = fabs(1.0 - E->x[t]);
    return d > 0 && isfinite(d) ? 1.0 / d : 1.0;
}

/* positions whose Ebar column became nonzero join A (in activation order).
   A position with Ebar(:,p) = 0 (a load-only change, or a new DOF copied from a
   constrained one: an identity row in both Kbar and K_t) has S2(:,p) = e_p and
   decouples; constraints arrive as identity rows (formats/stream.md 7.2), not in
   the saddle-point form of sec. 3.4 (eqs. 3.28-3.32). Only a column changed since
   the last factorization can have become nonzero. */
static int activate(aug_schur *s, const aug_memo *M, const aug_cum *c)
{
    if (s->pcap < c->cap) {
        unsigned char *a = aug_realloc(s->act, (size_t)c->cap);
        if (!a) return -1;
        memset(a + s->pcap, 0, (size_t)(c->cap - s->pcap));
        s->act = a;
        s->pcap = c->cap;
    }
    for (int64_t p = 0; p < c->ns; p++) {
        if (s->act[p] || c->mod[p] <= s->stamp || !aug_cum_coupled(c, p)) continue;
        if (s->na == s->acap) {
            int64_t nc = s->acap ? 2 * s->acap : 64;
            int32_t *A = aug_realloc(s->A, (size_t)nc * sizeof *A);
            if (!A) return -1;
            s->A = A;
            int32_t *gi = aug_realloc(s->gi, (size_t)nc * sizeof *gi);
            if (!gi) return -1;
            s->gi = gi;
            double *rs = aug_realloc(s->rs, (size_t)nc * sizeof *rs);
            if (!rs) return -1;
            s->rs = rs;
            s->acap = nc;
        }
        s->gi[s->na] = c->S[p] < c->nb ? M->cpos[p] : -1;
        s->rs[s->na] = c->S[p] < c->nb ? 1.0 : new_scale(&c->E[p], (int32_t)p);
        s->A[s->na++] = (int32_t)p;
        s->act[p] = 1;
    }
    return 0;
}

/* the LU array of order at least need, keeping the leading nlu block */
static int grow(aug_schur *s, int64_t need)
{
    if (need <= s->scap) return 0;
    int64_t nc = aug_sq_cap(s->scap, need);
    double *cs = aug_realloc(s->cs, (size_t)nc * sizeof *cs);
    if (cs) s->cs = cs;
    int *ipiv = aug_realloc(s->ipiv, (size_t)nc * sizeof *ipiv);
    if (ipiv) s->ipiv = ipiv;
    if (!cs || !ipiv) return -1;
    double *LU = aug_sq_grow(s->S2, s->scap, nc, s->nlu);
    if (!LU) return -1;
    s->S2 = LU;
    s->scap = nc;
    return 0;
}

/* out[r] = S2(r, b) for r0 <= r < na (paper 001 eq. 3.21 on A): S2 = I -
   Gbar_AA Ebar_AA, Gbar = blkdiag(H'K^-1H, I_k) (eq. 3.7: Kbar^-1 =
   blkdiag(K^-1, I)), 0 between a base and a new DOF; the rows of new DOFs
   then scaled by 1/sigma (new_scale). Row by row: row r of
   H'K^-1H is the memo's column gi[r] (G is symmetric), read where column b
   of Ebar_AA has entries, subtracted in the order of its list. wq, wv:
   workspace of the list's length. */
static void s2_column(const aug_schur *s, const aug_memo *M, int64_t b, int64_t r0, double *out,
                      int32_t *wq, double *wv)
{
    int64_t nq = 0, t0 = s->ep[b], t1 = s->ep[b + 1];
    for (int64_t t = t0; t < t1; t++) {
        int32_t gq = s->gi[s->ei[t]];
        if (gq >= 0) wq[nq] = gq, wv[nq++] = s->ex[t];
    }
    for (int64_t r = r0; r < s->na; r++) {
        int32_t a = s->gi[r];
        double acc = r == b;
        if (a >= 0) {
            const double *Gr = M->G + (int64_t)a * M->mcap;
            for (int64_t k = 0; k < nq; k++) acc -= wv[k] * Gr[wq[k]];
        }
        out[r] = acc;
    }
    for (int64_t t = t0; t < t1; t++) { /* a new DOF q: Gbar(:, q) = e_q */
        int32_t q = s->ei[t];
        if (s->gi[q] < 0 && q >= r0) out[q] -= s->ex[t];
    }
    for (int64_t r = r0; r < s->na; r++) /* rows of new DOFs by 1/sigma (new_scale) */
        if (s->gi[r] < 0) out[r] *= s->rs[r];
}

/* workspace for s2_column (wq, wv: the longest list of Ebar_AA) and for
   update_lu's row interchanges (sw: 3 na indices, tmp: na values) */
typedef struct s2_work {
    int32_t *wq;
    double *wv;
    int32_t *sw;
    double *tmp;
} s2_work;

static void s2_work_free(s2_work *w)
{
    free(w->wq), free(w->wv), free(w->sw), free(w->tmp);
}

static int s2_work_new(const aug_schur *s, s2_work *w)
{
    int64_t len = 1;
    for (int64_t b = 0; b < s->na; b++)
        if (s->ep[b + 1] - s->ep[b] > len) len = s->ep[b + 1] - s->ep[b];
    w->wq = aug_malloc((size_t)len * sizeof *w->wq);
    w->wv = aug_malloc((size_t)len * sizeof *w->wv);
    w->sw = aug_malloc((size_t)(3 * s->na + 1) * sizeof *w->sw);
    w->tmp = aug_malloc((size_t)(s->na + 1) * sizeof *w->tmp);
    return w->wq && w->wv && w->sw && w->tmp ? 0 : -1;
}

/* Ebar_AA column lists, rows increasing in activation order: changed columns
   (chg) gathered anew from Ebar's columns through qa (position -> index in A),
   the others kept */
static int elists(aug_schur *s, const aug_cum *c, const unsigned char *chg, int64_t n0)
{
    int64_t n1 = s->na, nz = 0;
    int64_t *ep = aug_malloc((size_t)(n1 + 1) * sizeof *ep);
    int64_t cap = s->ecap > 256 ? s->ecap : 256;
    int32_t *ei = aug_malloc((size_t)cap * sizeof *ei);
    double *ex = aug_malloc((size_t)cap * sizeof *ex);
    int32_t *qa = aug_malloc((size_t)(c->ns + 1) * sizeof *qa);
    if (!ep || !ei || !ex || !qa) goto nomem;
    for (int64_t p = 0; p < c->ns; p++) qa[p] = -1;
    for (int64_t q = 0; q < n1; q++) qa[s->A[q]] = (int32_t)q;
    for (int64_t b = 0; b < n1; b++) {
        int32_t pb = s->A[b];
        const aug_ecol *E = &c->E[pb];
        int64_t len = b < n0 && !chg[b] ? s->ep[b + 1] - s->ep[b] : E->nz;
        ep[b] = nz;
        if (nz + len > cap) {
            while (nz + len > cap) cap *= 2;
            int32_t *i2 = aug_realloc(ei, (size_t)cap * sizeof *i2);
            if (!i2) goto nomem;
            ei = i2;
            double *x2 = aug_realloc(ex, (size_t)cap * sizeof *x2);
            if (!x2) goto nomem;
            ex = x2;
        }
        if (b < n0 && !chg[b]) {
            memcpy(ei + nz, s->ei + s->ep[b], (size_t)len * sizeof *ei);
            memcpy(ex + nz, s->ex + s->ep[b], (size_t)len * sizeof *ex);
            nz += len;
            continue;
        }
        for (int32_t t = 0; t < E->nz; t++) {
            int32_t q = qa[E->i[t]];
            double v = E->x[t];
            if (q < 0 || v == 0) continue;
            /* insertion by row: the column is short */
            int64_t k = nz++;
            while (k > ep[b] && ei[k - 1] > q) ei[k] = ei[k - 1], ex[k] = ex[k - 1], k--;
            ei[k] = q, ex[k] = v;
        }
    }
    ep[n1] = nz;
    free(qa);
    free(s->ep), free(s->ei), free(s->ex);
    s->ep = ep, s->ei = ei, s->ex = ex, s->ecap = cap;
    s->nnzE = nz;
    return 0;
nomem:
    free(ep), free(ei), free(ex), free(qa);
    return -1;
}

/* P S2 = L U from scratch (LAPACK dgetrf, partial pivoting) into S2; k0 = 0 */
static int full_lu(aug_schur *s, const aug_memo *M, const s2_work *W, int64_t n1)
{
    int64_t ld = s->scap;
    for (int64_t b = 0; b < n1; b++) s2_column(s, M, b, 0, s->S2 + b * ld, W->wq, W->wv);
    s->k0 = 0;
    s->nkept = 0;
    return LAPACKE_dgetrf_work(LAPACK_COL_MAJOR, (lapack_int)n1, (lapack_int)n1, s->S2, (lapack_int)ld,
                          s->ipiv);
}

/* the row interchanges (sa[t], sb[t]), t = 0..ns-1 in this order, applied to
   the columns c0..c0+nc of LU: the same moves as one cblas_dswap per
   interchange (the same bits), but column by column through one gather,
   where a dswap of a row strides ld doubles (a page apart at ld >= 512) and
   the interchanges of one step were the largest part of S2's upkeep on the
   liver. idx, tmp: workspace for the rows between the first and last one
   moved. */
static void swap_rows(double *LU, int64_t ld, int64_t c0, int64_t nc, const int32_t *sa,
                      const int32_t *sb, int64_t ns, int32_t *idx, double *tmp)
{
    int64_t lo = INT64_MAX, hi = -1;
    for (int64_t t = 0; t < ns; t++) {
        int64_t a = sa[t] < sb[t] ? sa[t] : sb[t], b = sa[t] < sb[t] ? sb[t] : sa[t];
        if (a < lo) lo = a;
        if (b > hi) hi = b;
    }
    if (hi < 0 || nc <= 0) return;
    int64_t len = hi + 1 - lo;
    for (int64_t r = 0; r < len; r++) idx[r] = (int32_t)(lo + r); /* row now at lo + r came from */
    for (int64_t t = 0; t < ns; t++) {
        int32_t x = idx[sa[t] - lo];
        idx[sa[t] - lo] = idx[sb[t] - lo], idx[sb[t] - lo] = x;
    }
    for (int64_t j = c0; j < c0 + nc; j++) {
        double *col = LU + j * ld;
        for (int64_t r = 0; r < len; r++) tmp[r] = col[idx[r]];
        memcpy(col + lo, tmp, (size_t)len * sizeof *tmp);
    }
}

/* the factorization of order n0 extended to n1 and re-eliminated from column k0
   (right-looking block LU, [GVL] ch. 3), P1 the first k0 row interchanges:
   new rows L21 = S2(n0:n1, 0:k0) U11^-1; the trailing block T = (P1 S2)_22 -
   L21 U12 formed, then LU-factored afresh by dgetrf and its pivots applied to
   L21. A column of T is formed one of two ways:
     - fresh (changed by the step, or new): S2's column, P1, U12 = L11^-1 of
       its first k0 rows (dtrsm), T = the rest - L21 U12 (dgemm), gathered
       into a block so that each is one BLAS 3 call;
     - kept (b < n0, S2(:, b) unchanged): U12(:, b) is the old factor's, and
       on the old rows T = P2^-1 L22 U22 (P2 the old interchanges from k0 on:
       the old factorization of T carried that far), one dtrmm over the kept
       columns of the old L22 U22, instead of the dgemm with all k0 columns
       of L21; only the new rows are formed, S2(n0:n1, b) - L21 U12(:, b).
   An 8-node step re-eliminates S2 from about 2/3 of its order while
   changing a few columns there (bunny: k0 870 of 1,281, 36 new, 411 re-
   eliminated): the dgemm of 2 nt^2 k0 and dtrsm of k0^2 nt flops over all
   of them were most of the step's S2 time. -2 when a new multiplier exceeds
   GROWTH_MAX (caller: full_lu), LU_NOMEM. flops: those this call did. */
static int update_lu(aug_schur *s, const aug_memo *M, const s2_work *W, const unsigned char *chg,
                     int64_t n0, int64_t n1, int64_t k0, double *flops)
{
    int64_t ld = s->scap, nt = n1 - k0, nn = n1 - n0, m = n0 - k0;
    double *LU = s->S2;
    int *ipiv = s->ipiv;
    int32_t *sa = W->sw, *sb = W->sw + n1, *idx = W->sw + 2 * n1;
    double *tmp = W->tmp;
    int64_t ns = 0, nf = 0, nk = 0;
    for (int64_t b = k0; b < n1; b++) chg[b] ? nf++ : nk++;
    int32_t *cf = aug_malloc((size_t)(nt + 1) * sizeof *cf), *ck = NULL;
    double *X = aug_malloc((size_t)(n1 * nf + 1) * sizeof *X);
    double *Y = aug_malloc((size_t)(m * nk + 1) * sizeof *Y);
    double *Z = aug_malloc((size_t)(nn * nk + 1) * sizeof *Z);
    int rc = 0;
    if (!cf || !X || !Y || !Z) {
        rc = LU_NOMEM;
        goto out;
    }
    ck = cf + nf;
    nf = nk = 0;
    for (int64_t b = k0; b < n1; b++) {
        if (chg[b]) cf[nf++] = (int32_t)b;
        else ck[nk++] = (int32_t)b;
    }
    for (int64_t i = n0 - 1; i >= k0; i--) /* P2, undone in this order */
        if (ipiv[i] - 1 != i) sa[ns] = (int32_t)i, sb[ns++] = ipiv[i] - 1;
    /* rows of L(:, 0:k0) back to their order after P1 */
    swap_rows(LU, ld, 0, k0, sa, sb, ns, idx, tmp);
    if (nn > 0) {
        for (int64_t b = 0; b < k0; b++) s2_column(s, M, b, n0, LU + b * ld, W->wq, W->wv);
        cblas_dtrsm(CblasColMajor, CblasRight, CblasUpper, CblasNoTrans, CblasNonUnit, (int)nn,
                    (int)k0, 1.0, LU, (int)ld, LU + n0, (int)ld);
        for (int64_t b = 0; b < k0; b++)
            for (int64_t r = n0; r < n1; r++)
                if (!(fabs(LU[r + b * ld]) <= GROWTH_MAX)) {
                    rc = -2;
                    goto out;
                }
    }
    if (nk > 0) { /* kept columns on the old rows: P2^-1 L22 U22 (L22 is overwritten only by the
                     scatter below; after the growth check, so that a full_lu wastes no dtrmm) */
        for (int64_t j = 0; j < nk; j++) {
            int64_t d = ck[j] - k0;
            const double *u = LU + k0 + ck[j] * ld;
            double *y = Y + j * m;
            memcpy(y, u, (size_t)(d + 1) * sizeof *y);
            memset(y + d + 1, 0, (size_t)(m - d - 1) * sizeof *y);
        }
        cblas_dtrmm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans, CblasUnit, (int)m, (int)nk, 1.0,
                    LU + k0 + k0 * ld, (int)ld, Y, (int)m);
        for (int64_t t = 0; t < ns; t++) sa[t] -= (int32_t)k0, sb[t] -= (int32_t)k0; /* Y's rows */
        swap_rows(Y, m, 0, nk, sa, sb, ns, idx, tmp); /* (the list is P1's from here) */
    }
    /* fresh columns, gathered into X (ld n1) */
    for (int64_t j = 0; j < nf; j++) s2_column(s, M, cf[j], 0, X + j * n1, W->wq, W->wv);
    ns = 0;
    for (int64_t i = 0; i < k0; i++)
        if (ipiv[i] - 1 != i) sa[ns] = (int32_t)i, sb[ns++] = ipiv[i] - 1;
    swap_rows(X, n1, 0, nf, sa, sb, ns, idx, tmp);
    cblas_dtrsm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans, CblasUnit, (int)k0, (int)nf, 1.0,
                LU, (int)ld, X, (int)n1);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, (int)nt, (int)nf, (int)k0, -1.0, LU + k0,
                (int)ld, X, (int)n1, 1.0, X + k0, (int)n1);
    /* kept columns on the new rows: S2(n0:n1, b) - L21 U12(:, b) */
    if (nk > 0 && nn > 0) {
        double *U = aug_malloc((size_t)(k0 * nk + 1) * sizeof *U);
        if (!U) {
            rc = LU_NOMEM;
            goto out;
        }
        for (int64_t j = 0; j < nk; j++) {
            memcpy(U + j * k0, LU + ck[j] * ld, (size_t)k0 * sizeof *U);
            s2_column(s, M, ck[j], n0, tmp, W->wq, W->wv);
            memcpy(Z + j * nn, tmp + n0, (size_t)nn * sizeof *Z);
        }
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, (int)nn, (int)nk, (int)k0, -1.0, LU + n0,
                    (int)ld, U, (int)k0, 1.0, Z, (int)nn);
        free(U);
    }
    for (int64_t j = 0; j < nf; j++) memcpy(LU + cf[j] * ld, X + j * n1, (size_t)n1 * sizeof *X);
    for (int64_t j = 0; j < nk; j++) {
        memcpy(LU + k0 + ck[j] * ld, Y + j * m, (size_t)m * sizeof *Y);
        if (nn > 0) memcpy(LU + n0 + ck[j] * ld, Z + j * nn, (size_t)nn * sizeof *Z);
    }
    lapack_int info = LAPACKE_dgetrf_work(LAPACK_COL_MAJOR, (lapack_int)nt, (lapack_int)nt,
                                     LU + k0 + k0 * ld, (lapack_int)ld, ipiv + k0);
    if (info < 0) {
        rc = (int)info;
        goto out;
    }
    ns = 0;
    for (int64_t i = 0; i < nt; i++) {
        int64_t p = ipiv[k0 + i] - 1;
        if (p != i) sa[ns] = (int32_t)(k0 + i), sb[ns++] = (int32_t)(k0 + p);
        ipiv[k0 + i] += (int)k0;
    }
    swap_rows(LU, ld, 0, k0, sa, sb, ns, idx, tmp);
    s->k0 = k0;
    s->nkept = nk;
    rc = info > 0 ? (int)(info + k0) : 0;
out:
    {
        double K = (double)k0, F = (double)nf, Kp = (double)nk, Nn = (double)nn, T = (double)nt;
        *flops = 2.0 * (double)n1 * F + K * K * (Nn + F) + 2.0 * T * F * K + Kp * (double)m * (double)m +
                 2.0 * Nn * Kp * K + 2.0 / 3.0 * T * T * T;
    }
    free(cf), free(X), free(Y), free(Z);
    return rc;
}

/* cs[b] = sum_r |S2(r, b)| (for the 1-norm of S2): changed columns anew, the
   others extended by their new rows n0..na */
static int colsums(aug_schur *s, const aug_memo *M, const s2_work *W, const unsigned char *chg,
                   int64_t n0)
{
    int64_t n1 = s->na;
    double *col = aug_malloc((size_t)(n1 + 1) * sizeof *col);
    if (!col) return -1;
    for (int64_t b = 0; b < n1; b++) {
        int64_t r0 = chg[b] ? 0 : n0;
        if (r0 == n1) continue;
        s2_column(s, M, b, r0, col, W->wq, W->wv);
        double cs = r0 ? s->cs[b] : 0;
        for (int64_t r = r0; r < n1; r++) cs += fabs(col[r]);
        s->cs[b] = cs;
    }
    free(col);
    return 0;
}

/* S2 = I - Gbar_AA Ebar_AA (paper 001 eq. 3.21 on A, table 1 step 3) brought up to
   date with c: new positions activated, Ebar_AA's changed columns listed, the LU
   updated from the first changed column (update_lu, else full_lu), the column
   sums of |S2| kept when rcond is estimated. singular: LU breakdown, rcond
   (dgecon, 1-norm) < rcond_min when estimated, or det S2 < 0. */
/* the flops of bringing the LU of S2 from order n0 to n1, re-eliminated
   from column k0 (update_lu; k0 = 0: full_lu): the nt = n1 - k0 columns
   formed (2 n1 nt), L21 and U12 (k0^2 (n1 - n0) + k0^2 nt), the trailing
   update (2 nt^2 k0) and its LU (2/3 nt^3) */
double aug_s2_flops(int64_t n0, int64_t n1, int64_t k0)
{
    double nt = (double)(n1 - k0), kk = (double)k0;
    if (k0 == 0) n0 = 0;
    return 2.0 * (double)n1 * nt + kk * kk * ((double)(n1 - n0) + nt) + 2.0 * nt * nt * kk + 2.0 / 3.0 * nt * nt * nt;
}

int aug_schur_factor(aug_schur *s, const aug_memo *M, const aug_cum *c, double rcond_min,
                     aug_err *e)
{
    s->singular = 0;
    s->flops = 0;
    s->rcond = NAN;
    s->detsign = 1;
    if (c->napply < s->stamp || s->na > c->ns) aug_schur_free(s); /* a different cum */
    int64_t n0 = s->na;
    if (activate(s, M, c)) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (S2)");
    int64_t n1 = s->na, ld;
    unsigned char *chg = NULL;
    s2_work W = {0};
    if (n1 == 0) goto done;
    if (grow(s, n1)) goto nomem;
    chg = aug_malloc((size_t)n1);
    if (!chg) goto nomem;
    int64_t k0 = s->nlu == n0 ? n0 : 0;
    for (int64_t b = 0; b < n1; b++) {
        chg[b] = b >= n0 || c->mod[s->A[b]] > s->stamp;
        if (chg[b] && b < k0) k0 = b;
    }
    if (elists(s, c, chg, n0) || s2_work_new(s, &W)) goto nomem;
    if ((s->want_rcond || rcond_min > 0) && colsums(s, M, &W, chg, n0)) goto nomem;
    if (k0 == n1 && s->nlu == n1) { /* nothing changed */
        free(chg);
        s2_work_free(&W);
        goto done;
    }
    double fl = aug_s2_flops(0, n1, 0);
    int info = k0 > 0 ? update_lu(s, M, &W, chg, n0, n1, k0, &fl) : full_lu(s, M, &W, n1);
    s->flops = fl;
    if (info == -2) info = full_lu(s, M, &W, n1), s->flops += aug_s2_flops(0, n1, 0);
    free(chg);
    chg = NULL;
    if (info == LU_NOMEM) goto nomem;
    s2_work_free(&W);
    if (info < 0) return aug_err_set(e, AUG_EUSAGE, -1, "UPDT", "dgetrf: argument %d", -info);
    s->stamp = c->napply;
    if (info > 0) {
        s->nlu = 0;
        s->singular = 1;
        s->rcond = 0;
        return 0;
    }
    /* the entries this factorization wrote, finite (else singular): the rows
       n0.. of the columns before s->k0 (L21, all of them after full_lu) and
       every row of the columns from s->k0 on. The rest is an earlier step's
       checked factor. So dgetrf and dgetrs run as LAPACKE's _work entries,
       without the O(n1^2) NaN scans of the checked ones (which read the
       whole S2 on every solve), and a NaN from the memo makes the step
       singular, not an error or a NaN field (solve_amps amps_nonfinite_s2). */
    ld = s->scap;
    for (int64_t b = 0; b < n1 && !s->singular; b++)
        for (int64_t r = b < s->k0 ? n0 : 0; r < n1; r++)
            if (!isfinite(s->S2[r + b * ld])) {
                s->singular = 1;
                break;
            }
    if (s->singular) {
        s->nlu = 0;
        s->rcond = NAN;
        return 0;
    }
    s->nlu = n1;
done:
    s->stamp = c->napply;
    if (n1 == 0) return 0;
    ld = s->scap;
    int sign = 1;
    for (int64_t i = 0; i < n1; i++) {
        if (s->S2[i + i * ld] < 0) sign = -sign;
        if (s->ipiv[i] != i + 1) sign = -sign;
    }
    s->detsign = sign;
    if (s->want_rcond || rcond_min > 0) {
        double anorm = 0, rc = 0;
        for (int64_t b = 0; b < n1; b++)
            if (s->cs[b] > anorm) anorm = s->cs[b];
        /* own 64-byte aligned workspaces: OpenBLAS's kernels round differently
           with the alignment of LAPACKE's malloc'ed ones (last-bit noise) */
        void *w = NULL, *iw = NULL;
        if (posix_memalign(&w, 64, (size_t)(4 * n1) * sizeof(double)) ||
            posix_memalign(&iw, 64, (size_t)n1 * sizeof(lapack_int))) {
            free(w);
            return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
        }
        LAPACKE_dgecon_work(LAPACK_COL_MAJOR, '1', (lapack_int)n1, s->S2, (lapack_int)ld, anorm,
                            &rc, w, iw);
        free(w);
        free(iw);
        s->rcond = rc;
        if (rc < rcond_min) s->singular = 1;
    }
    /* det S2 = det Gbar det M (M: Schur complement of K_t on A, SPD iff K_t is) */
    if (sign < 0) s->singular = 1;
    return 0;
nomem:
    free(chg);
    s2_work_free(&W);
    aug_schur_free(s);
    return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (S2 %lld)", (long long)n1);
}

/* x := S2^-1 x with the LU factors (dgetrs; paper 001 eq. 3.8, table 1 step 5).
   The _work entry: LAPACKE_dgetrs first reads all of S2 for NaN (as many
   reads as the solve itself, on every solve) and on a NaN returned without
   solving, x unchanged. aug_schur_factor leaves a finite factor or marks
   the step singular. */
void aug_schur_solve(const aug_schur *s, double *x)
{
    int64_t na = s->na;
    if (na == 0) return;
    for (int64_t q = 0; q < na; q++) x[q] *= s->rs[q]; /* the rows new_scale scaled */
    LAPACKE_dgetrs_work(LAPACK_COL_MAJOR, 'N', (lapack_int)na, 1, s->S2, (lapack_int)s->scap, s->ipiv, x,
                   (lapack_int)na);
}

/* x := S2'^-1 x for the alternative pivot of paper 001 eqs. 3.16-3.17: its
   matrix Ebar Gbar - I is -S2' (Gbar and Ebar are symmetric), so the LU of
   the row-scaled R S2 serves it transposed: S2' = (R S2)' R^-1, S2'^-1 x =
   R (R S2)'^-1 x (dgetrs 'T', then the rows new_scale scaled). */
void aug_schur_solve_t(const aug_schur *s, double *x)
{
    int64_t na = s->na;
    if (na == 0) return;
    LAPACKE_dgetrs_work(LAPACK_COL_MAJOR, 'T', (lapack_int)na, 1, s->S2, (lapack_int)s->scap, s->ipiv, x,
                   (lapack_int)na);
    for (int64_t q = 0; q < na; q++) x[q] *= s->rs[q];
}
