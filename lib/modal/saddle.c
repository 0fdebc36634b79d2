/* Coupled saddle-point system of paper 004 eq. 15/18: block descriptors and
   their caches, the compression of C's dependent rows, the slave selection
   of the constraint preconditioner (eq. 19-20), and the shared products. */
#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"
#include "aug_saddle.h"

#define ERR(e, code, ...) aug_err_set(e, code, -1, "MODE", __VA_ARGS__)

int aug_saddle_init(aug_saddle *s, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    memset(s, 0, sizeof *s);
    if (!cm) return ERR(e, AUG_EUSAGE, "saddle: no cholmod_common");
    s->cm = cm;
    return 0;
}

/* the C analysis arrays (not the blocks) */
static void free_canal(aug_saddle *s)
{
    free(s->prow); free(s->pslave); free(s->pdiag); free(s->pp); free(s->pj); free(s->px);
    free(s->drow); free(s->dcol); free(s->Uk); free(s->Ck); free(s->dslave); free(s->Rq);
    free(s->Rr); free(s->xi); free(s->xj); free(s->xv); free(s->slave_of); free(s->ginv);
    s->prow = NULL; s->pslave = NULL; s->pdiag = NULL; s->pp = NULL; s->pj = NULL; s->px = NULL;
    s->drow = NULL; s->dcol = NULL; s->Uk = NULL; s->Ck = NULL; s->dslave = NULL; s->Rq = NULL;
    s->Rr = NULL; s->xi = NULL; s->xj = NULL; s->xv = NULL; s->slave_of = NULL; s->ginv = NULL;
    s->mp = s->md = s->nd = s->k = s->nx = s->mc = 0;
    s->c_ok = 0;
}

static void free_blk(aug_sblk *b, cholmod_common *cm)
{
    cholmod_free_factor(&b->L, cm);
    cholmod_free_dense(&b->X, cm);
    cholmod_free_dense(&b->Y, cm);
    cholmod_free_dense(&b->E, cm);
    free(b->Lc); free(b->diag); free(b->rows); free(b->Sb);
    free(b->sig_p); free(b->sig_c); free(b->sig_x);
    memset(b, 0, sizeof *b);
}

void aug_saddle_free(aug_saddle *s)
{
    if (!s) return;
    for (int b = 0; b < s->nbcap; b++) free_blk(&s->blk[b], s->cm);
    free(s->blk);
    free_canal(s);
    free(s->S);
    for (int i = 0; i < 8; i++) free(s->w[i]);
    for (int i = 0; i < 6; i++) free(s->u[i]);
    cholmod_common *cm = s->cm;
    memset(s, 0, sizeof *s);
    s->cm = cm;
}

/* sizes and storage of descriptor d (block b); 0 or AUG_EUSAGE */
static int check_block(const aug_sblock *d, int b, aug_err *e)
{
    if (d->n < 1) return ERR(e, AUG_EUSAGE, "saddle: block %d has size %lld", b, (long long)d->n);
    if (!d->A == !d->Ad)
        return ERR(e, AUG_EUSAGE, "saddle: block %d needs exactly one of A (FE) and Ad (reduced)", b);
    const cholmod_sparse *A = d->A;
    if (A && ((int64_t)A->nrow != d->n || (int64_t)A->ncol != d->n || A->stype <= 0 ||
              A->xtype != CHOLMOD_REAL || A->dtype != CHOLMOD_DOUBLE || !A->packed ||
              !A->sorted || A->itype != CHOLMOD_INT))
        return ERR(e, AUG_EUSAGE, "saddle: block %d: A must be %lld x %lld, upper stored (stype 1), "
                   "real, packed, sorted", b, (long long)d->n, (long long)d->n);
    return 0;
}

/* diag(A_b) into b->diag; AUG_ESINGULAR when an entry is not positive */
static int block_diag(aug_sblk *b, int ib, aug_err *e)
{
    int64_t n = b->d.n;
    double *dg = aug_realloc(b->diag, (size_t)n * sizeof *dg);
    if (!dg) return ERR(e, AUG_ENOMEM, "saddle: out of memory");
    b->diag = dg;
    if (b->d.A) {
        const int *Ap = b->d.A->p, *Ai = b->d.A->i;
        const double *Ax = b->d.A->x;
        for (int64_t j = 0; j < n; j++) {
            dg[j] = 0;
            for (int q = Ap[j]; q < Ap[j + 1]; q++)
                if (Ai[q] == j) dg[j] = Ax[q];
        }
    } else {
        for (int64_t j = 0; j < n; j++) dg[j] = b->d.Ad[j + j * n];
    }
    for (int64_t j = 0; j < n; j++)
        if (!(dg[j] > 0))
            return ERR(e, AUG_ESINGULAR, "saddle: block %d is not positive definite "
                       "(diagonal %lld is %g)", ib, (long long)j, dg[j]);
    return 0;
}

/* Classify C's rows: private ones (a column with its only nonzero there;
   slave = the largest |entry| among them) into the CSR pp/pj/px, the others
   into D with their columns dcol. O(nnz(C) + N + m). */
static int classify(aug_saddle *s, aug_err *e)
{
    const cholmod_sparse *C = s->C;
    int m = s->m;
    int64_t N = s->N;
    const int *Cp = C->p, *Ci = C->i;
    const double *Cx = C->x;
    int *cnt = aug_calloc((size_t)N + 1, sizeof *cnt);
    int64_t *best = aug_malloc(((size_t)m + 1) * sizeof *best);
    int *pidx = aug_malloc(((size_t)m + 1) * sizeof *pidx);
    int *didx = aug_malloc(((size_t)m + 1) * sizeof *didx);
    if (!cnt || !best || !pidx || !didx) goto nomem;
    for (int64_t j = 0; j < N; j++)
        for (int q = Cp[j]; q < Cp[j + 1]; q++)
            if (Cx[q] != 0) cnt[j]++;
    for (int i = 0; i < m; i++) best[i] = -1;
    for (int64_t j = 0; j < N; j++) {
        if (cnt[j] != 1) continue;
        for (int q = Cp[j]; q < Cp[j + 1]; q++) {
            if (Cx[q] == 0) continue;
            int i = Ci[q];
            if (best[i] < 0) best[i] = j;
            else {
                /* value of the current best in row i */
                double bv = 0;
                for (int t = Cp[best[i]]; t < Cp[best[i] + 1]; t++)
                    if (Ci[t] == i) bv = Cx[t];
                if (fabs(Cx[q]) > fabs(bv)) best[i] = j;
            }
        }
    }
    int mp = 0, md = 0;
    for (int i = 0; i < m; i++) {
        pidx[i] = didx[i] = -1;
        if (best[i] >= 0) pidx[i] = mp++;
        else didx[i] = md++;
    }
    s->mp = mp;
    s->md = md;
    s->prow = aug_malloc(((size_t)mp + 1) * sizeof *s->prow);
    s->pslave = aug_malloc(((size_t)mp + 1) * sizeof *s->pslave);
    s->pdiag = aug_malloc(((size_t)mp + 1) * sizeof *s->pdiag);
    s->pp = aug_calloc((size_t)mp + 2, sizeof *s->pp);
    s->drow = aug_malloc(((size_t)md + 1) * sizeof *s->drow);
    if (!s->prow || !s->pslave || !s->pdiag || !s->pp || !s->drow) goto nomem;
    for (int i = 0; i < m; i++) {
        if (pidx[i] >= 0) {
            s->prow[pidx[i]] = i;
            s->pslave[pidx[i]] = best[i];
        } else {
            s->drow[didx[i]] = i;
        }
    }
    /* CSR of the private rows, columns ascending; dcol = columns touched by D */
    memset(cnt, 0, ((size_t)N + 1) * sizeof *cnt);  /* reused: 1 = column in D */
    for (int64_t j = 0; j < N; j++)
        for (int q = Cp[j]; q < Cp[j + 1]; q++) {
            if (Cx[q] == 0) continue;
            if (pidx[Ci[q]] >= 0) s->pp[pidx[Ci[q]] + 1]++;
            else cnt[j] = 1;
        }
    for (int i = 0; i < mp; i++) s->pp[i + 1] += s->pp[i];
    s->pj = aug_malloc(((size_t)s->pp[mp] + 1) * sizeof *s->pj);
    s->px = aug_malloc(((size_t)s->pp[mp] + 1) * sizeof *s->px);
    int nd = 0;
    for (int64_t j = 0; j < N; j++) nd += cnt[j];
    s->nd = nd;
    s->dcol = aug_malloc(((size_t)nd + 1) * sizeof *s->dcol);
    if (!s->pj || !s->px || !s->dcol) goto nomem;
    int *fill = didx;  /* reused: fill pointers of the CSR rows (m >= mp) */
    for (int i = 0; i < mp; i++) fill[i] = s->pp[i];
    nd = 0;
    for (int64_t j = 0; j < N; j++) {
        if (cnt[j]) s->dcol[nd++] = j;
        for (int q = Cp[j]; q < Cp[j + 1]; q++) {
            int pi = pidx[Ci[q]];
            if (Cx[q] == 0 || pi < 0) continue;
            s->pj[fill[pi]] = j;
            s->px[fill[pi]++] = Cx[q];
        }
    }
    for (int i = 0; i < mp; i++)
        for (int q = s->pp[i]; q < s->pp[i + 1]; q++)
            if (s->pj[q] == s->pslave[i]) s->pdiag[i] = s->px[q];
    free(cnt); free(best); free(pidx); free(didx);
    return 0;
nomem:
    free(cnt); free(best); free(pidx); free(didx);
    return ERR(e, AUG_ENOMEM, "saddle: out of memory");
}

/* Row space of D (thin SVD C_D = U S V', keep s_i > AUG_SADDLE_RTOL s_1):
   Uk, Ck = S_k V_k'; slaves of the k compressed rows by column-pivoted QR
   Ck P = Q [R11 R12] (dgeqp3), so R = Ck(:, dslave) = Q R11.
   O(md nd min(md, nd) + k^2 nd). */
static int compress_rows(aug_saddle *s, aug_err *e)
{
    int md = s->md, nd = s->nd, mn = md < nd ? md : nd;
    s->k = 0;
    if (mn == 0) return 0;
    const cholmod_sparse *C = s->C;
    const int *Cp = C->p, *Ci = C->i;
    const double *Cx = C->x;
    double *CD = aug_calloc((size_t)md * nd, sizeof *CD);
    double *U = aug_malloc((size_t)md * mn * sizeof *U);
    double *VT = aug_malloc((size_t)mn * nd * sizeof *VT);
    double *sv = aug_malloc((size_t)mn * sizeof *sv), *sb = aug_malloc((size_t)mn * sizeof *sb);
    int *dpos = aug_malloc((size_t)s->m * sizeof *dpos);
    int *jp = aug_calloc((size_t)nd, sizeof *jp);
    double *tau = aug_malloc((size_t)mn * sizeof *tau);
    int rc = 0;
    if (!CD || !U || !VT || !sv || !sb || !dpos || !jp || !tau) {
        rc = ERR(e, AUG_ENOMEM, "saddle: out of memory");
        goto out;
    }
    for (int i = 0; i < s->m; i++) dpos[i] = -1;
    for (int d = 0; d < md; d++) dpos[s->drow[d]] = d;
    for (int l = 0; l < nd; l++) {
        int64_t j = s->dcol[l];
        for (int q = Cp[j]; q < Cp[j + 1]; q++)
            if (dpos[Ci[q]] >= 0) CD[dpos[Ci[q]] + (size_t)l * md] = Cx[q];
    }
    if (LAPACKE_dgesvd(LAPACK_COL_MAJOR, 'S', 'S', md, nd, CD, md, sv, U, md, VT, mn, sb)) {
        rc = ERR(e, AUG_ESINGULAR, "saddle: SVD of the dependent constraint rows failed");
        goto out;
    }
    int k = 0;
    while (k < mn && sv[k] > AUG_SADDLE_RTOL * sv[0]) k++;
    s->k = k;
    if (k == 0) goto out;
    s->Uk = aug_malloc((size_t)md * k * sizeof *s->Uk);
    s->Ck = aug_malloc((size_t)k * nd * sizeof *s->Ck);
    s->dslave = aug_malloc((size_t)k * sizeof *s->dslave);
    s->Rq = aug_malloc((size_t)k * k * sizeof *s->Rq);
    s->Rr = aug_calloc((size_t)k * k, sizeof *s->Rr);
    if (!s->Uk || !s->Ck || !s->dslave || !s->Rq || !s->Rr) {
        rc = ERR(e, AUG_ENOMEM, "saddle: out of memory");
        goto out;
    }
    memcpy(s->Uk, U, (size_t)md * k * sizeof *U);
    for (int l = 0; l < nd; l++)
        for (int j = 0; j < k; j++) s->Ck[j + (size_t)l * k] = sv[j] * VT[j + (size_t)l * mn];
    double *QR = CD;  /* k x nd, reused */
    memcpy(QR, s->Ck, (size_t)k * nd * sizeof *QR);
    if (LAPACKE_dgeqp3(LAPACK_COL_MAJOR, k, nd, QR, k, jp, tau)) {
        rc = ERR(e, AUG_ESINGULAR, "saddle: QR of the compressed constraint rows failed");
        goto out;
    }
    for (int j = 0; j < k; j++) {
        s->dslave[j] = s->dcol[jp[j] - 1];
        for (int i = 0; i <= j; i++) s->Rr[i + (size_t)j * k] = QR[i + (size_t)j * k];
    }
    if (LAPACKE_dorgqr(LAPACK_COL_MAJOR, k, k, k, QR, k, tau)) {
        rc = ERR(e, AUG_ESINGULAR, "saddle: QR of the compressed constraint rows failed");
        goto out;
    }
    memcpy(s->Rq, QR, (size_t)k * k * sizeof *QR);
out:
    free(CD); free(U); free(VT); free(sv); free(sb); free(dpos); free(jp); free(tau);
    return rc;
}

/* slave_of, X (private rows on dense slave columns); O(N + nnz(C_P)) */
static int slaves(aug_saddle *s, aug_err *e)
{
    s->mc = s->mp + s->k;
    s->slave_of = aug_malloc(((size_t)s->N + 1) * sizeof *s->slave_of);
    s->ginv = aug_malloc(((size_t)s->N + 1) * sizeof *s->ginv);
    if (!s->slave_of || !s->ginv) return ERR(e, AUG_ENOMEM, "saddle: out of memory");
    for (int64_t j = 0; j < s->N; j++) s->slave_of[j] = -1;
    for (int i = 0; i < s->mp; i++) s->slave_of[s->pslave[i]] = i;
    for (int j = 0; j < s->k; j++) s->slave_of[s->dslave[j]] = s->mp + j;
    int nx = 0;
    for (int q = 0; s->pp && q < s->pp[s->mp]; q++) nx += s->slave_of[s->pj[q]] >= s->mp;
    s->xi = aug_malloc(((size_t)nx + 1) * sizeof *s->xi);
    s->xj = aug_malloc(((size_t)nx + 1) * sizeof *s->xj);
    s->xv = aug_malloc(((size_t)nx + 1) * sizeof *s->xv);
    if (!s->xi || !s->xj || !s->xv) return ERR(e, AUG_ENOMEM, "saddle: out of memory");
    nx = 0;
    for (int i = 0; i < s->mp; i++)
        for (int q = s->pp[i]; q < s->pp[i + 1]; q++)
            if (s->slave_of[s->pj[q]] >= s->mp) {
                s->xi[nx] = i;
                s->xj[nx] = (int)(s->slave_of[s->pj[q]] - s->mp);
                s->xv[nx++] = s->px[q];
            }
    s->nx = nx;
    return 0;
}

/* Block b's compressed rows (ascending) and the signature of its entries in
   the private rows; keeps the Schur contribution when the block is unchanged
   (keep) and the signature equals the stored one. mark: 3 m ints, the
   first m the compressed index of each private row (-1 else), the next m
   initialised to -1. O(nnz(C_b) + r log r + nd), r rows touched. */
static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

static int block_rows(aug_saddle *s, aug_sblk *b, int keep, int *mark, int stamp, aug_err *e)
{
    int64_t lo = b->off, hi = b->off + b->d.n;
    const cholmod_sparse *C = s->C;
    int nr = 0, touches = 0;
    int *rows = NULL, *sp = NULL, *sc = NULL;
    double *sx = NULL;
    int nsig = 0;
    if (C) {
        const int *Cp = C->p, *Ci = C->i;
        const double *Cx = C->x;
        const int *pidx = mark;  /* m: compressed index of private rows, -1 else */
        int *seen = mark + s->m;  /* m: the last block that listed the row */
        int *list = mark + 2 * (size_t)s->m, np = 0;
        for (int64_t j = lo; j < hi; j++)
            for (int q = Cp[j]; q < Cp[j + 1]; q++) {
                int i = Ci[q];
                if (Cx[q] == 0 || pidx[i] < 0 || seen[i] == stamp) continue;
                seen[i] = stamp;
                list[np++] = pidx[i];
            }
        qsort(list, (size_t)np, sizeof *list, cmp_int);
        for (int l = 0; l < s->nd; l++)
            if (s->dcol[l] >= lo && s->dcol[l] < hi) touches = s->k > 0;
        nr = np + (touches ? s->k : 0);
        rows = aug_malloc(((size_t)nr + 1) * sizeof *rows);
        sp = aug_malloc(((size_t)np + 1) * sizeof *sp);
        if (!rows || !sp) goto nomem;
        int t = np, ns = 0;
        sp[0] = 0;
        for (int r = 0; r < np; r++) {
            int pi = rows[r] = list[r];
            for (int q = s->pp[pi]; q < s->pp[pi + 1]; q++) ns += s->pj[q] >= lo && s->pj[q] < hi;
        }
        sc = aug_malloc(((size_t)ns + 1) * sizeof *sc);
        sx = aug_malloc(((size_t)ns + 1) * sizeof *sx);
        if (!sc || !sx) goto nomem;
        ns = 0;
        for (int r = 0; r < np; r++) {
            int pi = rows[r];
            for (int q = s->pp[pi]; q < s->pp[pi + 1]; q++)
                if (s->pj[q] >= lo && s->pj[q] < hi) {
                    sc[ns] = (int)(s->pj[q] - lo);
                    sx[ns++] = s->px[q];
                }
            sp[r + 1] = ns;
        }
        nsig = np;
        for (int j = 0; touches && j < s->k; j++) rows[t++] = s->mp + j;
    }
    int same = keep && b->sc_ok && !touches && !b->touches_d && nsig == b->sig_n &&
               b->sig_p && sp && !memcmp(sp, b->sig_p, ((size_t)nsig + 1) * sizeof *sp) &&
               !memcmp(sc, b->sig_c, (size_t)sp[nsig] * sizeof *sc) &&
               !memcmp(sx, b->sig_x, (size_t)sp[nsig] * sizeof *sx);
    if (!same) {
        b->sc_ok = 0;
        free(b->Sb);
        b->Sb = NULL;
    }
    free(b->rows); free(b->sig_p); free(b->sig_c); free(b->sig_x);
    b->rows = rows; b->sig_p = sp; b->sig_c = sc; b->sig_x = sx;
    b->nr = nr;
    b->sig_n = nsig;
    b->touches_d = touches;
    return 0;
nomem:
    free(rows); free(sp); free(sc); free(sx);
    return ERR(e, AUG_ENOMEM, "saddle: out of memory");
}

static int grow_work(aug_saddle *s, aug_err *e)
{
    size_t n = (size_t)s->N + 1, mm = (size_t)(s->m > s->mc ? s->m : s->mc) + 1;
    for (int i = 0; i < 8; i++) {
        double *p = aug_realloc(s->w[i], n * sizeof *p);
        if (!p) return ERR(e, AUG_ENOMEM, "saddle: out of memory");
        s->w[i] = p;
    }
    for (int i = 0; i < 6; i++) {
        double *p = aug_realloc(s->u[i], mm * sizeof *p);
        if (!p) return ERR(e, AUG_ENOMEM, "saddle: out of memory");
        s->u[i] = p;
    }
    return 0;
}

/* Copy the descriptors; invalidate what changed; redo C's analysis when C
   or a block changed (see aug_saddle.h). */
int aug_saddle_set(aug_saddle *s, int nb, const aug_sblock *b, cholmod_sparse *C, int c_changed,
                   aug_err *e)
{
    aug_err_clear(e);
    if (nb < 1 || !b) return ERR(e, AUG_EUSAGE, "saddle: need at least one block");
    int64_t N = 0;
    for (int i = 0; i < nb; i++) {
        if (check_block(&b[i], i, e)) return e->code;
        N += b[i].n;
    }
    if (N > INT32_MAX) return ERR(e, AUG_EUSAGE, "saddle: %lld unknowns is too many", (long long)N);
    if (C && ((int64_t)C->ncol != N || C->stype != 0 || C->xtype != CHOLMOD_REAL ||
              C->dtype != CHOLMOD_DOUBLE || !C->packed || C->itype != CHOLMOD_INT))
        return ERR(e, AUG_EUSAGE, "saddle: C must be real, packed, unsymmetric (stype 0) with "
                   "%lld columns (the sum of the block sizes), not %zu", (long long)N,
                   C ? C->ncol : 0);
    if (nb > s->nbcap) {
        aug_sblk *nbk = aug_realloc(s->blk, (size_t)nb * sizeof *nbk);
        if (!nbk) return ERR(e, AUG_ENOMEM, "saddle: out of memory");
        memset(nbk + s->nbcap, 0, (size_t)(nb - s->nbcap) * sizeof *nbk);
        s->blk = nbk;
        s->nbcap = nb;
    }
    for (int i = nb; i < s->nbcap; i++) free_blk(&s->blk[i], s->cm);
    int changed = c_changed || C != s->C || nb != s->nb || N != s->N || !s->c_ok;
    int *keep = aug_malloc((size_t)nb * sizeof *keep);
    if (!keep) return ERR(e, AUG_ENOMEM, "saddle: out of memory");
    int64_t off = 0;
    for (int i = 0; i < nb; i++) {
        aug_sblk *k = &s->blk[i];
        keep[i] = k->have && k->d.version == b[i].version && k->d.n == b[i].n &&
                  !k->d.A == !b[i].A;
        if (k->off != off) changed = 1;
        k->d = b[i];
        k->off = off;
        k->have = 1;
        off += b[i].n;
        if (!keep[i]) {
            changed = 1;
            k->fact_ok = 0;
            k->sc_ok = 0;
            if (block_diag(k, i, e)) {
                k->have = 0;
                free(keep);
                free_canal(s);  /* no solve before the next good set */
                return e->code;
            }
        }
    }
    s->nb = nb;
    s->N = N;
    if (!changed) {
        free(keep);
        return 0;
    }
    s->S_ok = 0;
    free_canal(s);
    s->C = C;
    s->m = C ? (int)C->nrow : 0;
    int rc = 0;
    int *mark = aug_malloc((3 * (size_t)s->m + 1) * sizeof *mark);
    if (!mark) rc = ERR(e, AUG_ENOMEM, "saddle: out of memory");
    if (!rc && C) rc = classify(s, e);
    if (!rc && C) rc = compress_rows(s, e);
    if (!rc) rc = slaves(s, e);
    if (!rc) {
        for (int i = 0; i < 2 * s->m; i++) mark[i] = -1;
        for (int i = 0; i < s->mp; i++) mark[s->prow[i]] = i;
    }
    for (int i = 0; !rc && i < nb; i++) rc = block_rows(s, &s->blk[i], keep[i], mark, i, e);
    if (!rc) rc = grow_work(s, e);
    free(mark);
    free(keep);
    if (rc) {
        free_canal(s);
        return rc;
    }
    for (int i = 0; i < nb; i++) {
        const aug_sblk *k = &s->blk[i];
        for (int64_t j = 0; j < k->d.n; j++)
            s->ginv[k->off + j] = s->slave_of[k->off + j] >= 0 ? 0 : 1 / k->diag[j];
    }
    s->c_ok = 1;
    return 0;
}

int aug_saddle_apply_A(aug_saddle *s, const double *x, double *y, aug_err *e)
{
    for (int i = 0; i < s->nb; i++) {
        aug_sblk *b = &s->blk[i];
        int n = (int)b->d.n;
        if (b->d.A) {
            if (aug_sym_mult(b->d.A, (double *)x + b->off, y + b->off, s->cm))
                return ERR(e, AUG_ENOMEM, "saddle: sparse product failed (CHOLMOD status %d)",
                           s->cm->status);
        } else {
            cblas_dsymv(CblasColMajor, CblasLower, n, 1.0, b->d.Ad, n, x + b->off, 1, 0.0,
                        y + b->off, 1);
        }
    }
    return 0;
}

void aug_saddle_cc(const aug_saddle *s, const double *x, double *y)
{
    for (int i = 0; i < s->mp; i++) {
        double t = 0;
        for (int q = s->pp[i]; q < s->pp[i + 1]; q++) t += s->px[q] * x[s->pj[q]];
        y[i] = t;
    }
    double *yk = y + s->mp;
    int k = s->k;
    for (int j = 0; j < k; j++) yk[j] = 0;
    for (int l = 0; l < s->nd && k; l++) {
        double xl = x[s->dcol[l]];
        const double *c = s->Ck + (size_t)l * k;
        for (int j = 0; j < k; j++) yk[j] += c[j] * xl;
    }
}

void aug_saddle_cct(const aug_saddle *s, const double *y, double *x)
{
    for (int i = 0; i < s->mp; i++)
        for (int q = s->pp[i]; q < s->pp[i + 1]; q++) x[s->pj[q]] += s->px[q] * y[i];
    const double *yk = y + s->mp;
    int k = s->k;
    for (int l = 0; l < s->nd && k; l++) {
        const double *c = s->Ck + (size_t)l * k;
        double t = 0;
        for (int j = 0; j < k; j++) t += c[j] * yk[j];
        x[s->dcol[l]] += t;
    }
}

void aug_saddle_compress(const aug_saddle *s, const double *g, double *gc)
{
    if (!g) {
        for (int i = 0; i < s->mc; i++) gc[i] = 0;
        return;
    }
    for (int i = 0; i < s->mp; i++) gc[i] = g[s->prow[i]];
    for (int j = 0; j < s->k; j++) {
        double t = 0;
        for (int d = 0; d < s->md; d++) t += s->Uk[d + (size_t)j * s->md] * g[s->drow[d]];
        gc[s->mp + j] = t;
    }
}

void aug_saddle_expand(const aug_saddle *s, const double *mu, double *lambda)
{
    for (int i = 0; i < s->mp; i++) lambda[s->prow[i]] = mu[i];
    for (int d = 0; d < s->md; d++) {
        double t = 0;
        for (int j = 0; j < s->k; j++) t += s->Uk[d + (size_t)j * s->md] * mu[s->mp + j];
        lambda[s->drow[d]] = t;
    }
}

static double nrm2(const double *v, int64_t n)
{
    return n > 0 ? cblas_dnrm2((int)n, v, 1) : 0;
}

int aug_saddle_residuals(aug_saddle *s, const double *r, const double *g, const double *gc,
                         const double *x, const double *mu, aug_saddle_stats *st, aug_err *e)
{
    double *r1 = s->w[6], *r2 = s->u[4], *r3 = s->u[5];
    if (aug_saddle_apply_A(s, x, r1, e)) return e->code;
    aug_saddle_cct(s, mu, r1);
    for (int64_t j = 0; j < s->N; j++) r1[j] -= r[j];
    aug_saddle_cc(s, x, r2);
    for (int i = 0; i < s->mc; i++) r2[i] -= gc[i];
    double a = nrm2(r1, s->N), c = nrm2(r2, s->mc);
    double den = hypot(nrm2(r, s->N), nrm2(gc, s->mc));
    st->relres = hypot(a, c) / (den > 0 ? den : 1);
    for (int i = 0; i < s->m; i++) r3[i] = g ? -g[i] : 0;
    if (s->C) {
        const int *Cp = s->C->p, *Ci = s->C->i;
        const double *Cx = s->C->x;
        for (int64_t j = 0; j < s->N; j++)
            for (int q = Cp[j]; q < Cp[j + 1]; q++) r3[Ci[q]] += Cx[q] * x[j];
    }
    st->gap = nrm2(r3, s->m);
    st->rank = s->k;
    st->mc = s->mc;
    st->nfactor = s->nfactor;
    st->ncontrib = s->ncontrib;
    return 0;
}
