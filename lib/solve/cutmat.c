/* The cut matrix K_t kept as K_0 plus the composed principal submatrix updates
   (formats/stream.md 7.2, AMPS eq. 3.1): residuals, --check, refactor baselines. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

int aug_cum_init(aug_cum *c, int64_t nb, aug_err *e)
{
    memset(c, 0, sizeof *c);
    c->nb = c->n = nb;
    c->pcap = nb + 64;
    c->pos = aug_malloc((size_t)c->pcap * sizeof *c->pos);
    if (!c->pos) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    for (int64_t i = 0; i < c->pcap; i++) c->pos[i] = -1;
    return 0;
}

void aug_cum_free(aug_cum *c)
{
    for (int64_t p = 0; p < c->ns; p++) free(c->E[p].i), free(c->E[p].x);
    free(c->E);
    free(c->S);
    free(c->pos);
    free(c->dF);
    free(c->mod);
    free(c->keep);
    memset(c, 0, sizeof *c);
}

/* |S restricted to base DOFs|: the m_t of paper 001 (sec. 3) */
int64_t aug_cum_morig(const aug_cum *c)
{
    int64_t k = 0;
    for (int64_t p = 0; p < c->ns; p++) k += c->S[p] < c->nb;
    return k;
}

/* capacity of S (and of Ebar's column table) at least need */
static int grow_s(aug_cum *c, int64_t need)
{
    if (need <= c->cap) return 0;
    int64_t nc = c->cap ? c->cap : 64;
    while (nc < need) nc *= 2;
    int32_t *S = aug_realloc(c->S, (size_t)nc * sizeof *S);
    if (!S) return -1;
    c->S = S;
    double *dF = aug_realloc(c->dF, (size_t)nc * sizeof *dF);
    if (!dF) return -1;
    c->dF = dF;
    int64_t *mod = aug_realloc(c->mod, (size_t)nc * sizeof *mod);
    if (!mod) return -1;
    c->mod = mod;
    unsigned char *keep = aug_realloc(c->keep, (size_t)nc);
    if (!keep) return -1;
    c->keep = keep;
    aug_ecol *E = aug_realloc(c->E, (size_t)nc * sizeof *E);
    if (!E) return -1;
    c->E = E;
    c->cap = nc;
    return 0;
}

/* the entry Ebar(r, p), inserted as 0 when absent (column p kept increasing);
   NULL when out of memory */
static double *entry(aug_cum *c, int32_t p, int32_t r)
{
    aug_ecol *e = &c->E[p];
    int32_t lo = 0, hi = e->nz;
    while (lo < hi) {
        int32_t mid = lo + (hi - lo) / 2;
        if (e->i[mid] < r) lo = mid + 1;
        else hi = mid;
    }
    if (lo < e->nz && e->i[lo] == r) return e->x + lo;
    if (e->nz == e->cap) {
        int32_t nc = e->cap ? 2 * e->cap : 16;
        int32_t *i2 = aug_realloc(e->i, (size_t)nc * sizeof *i2);
        if (!i2) return NULL;
        e->i = i2;
        double *x2 = aug_realloc(e->x, (size_t)nc * sizeof *x2);
        if (!x2) return NULL;
        e->x = x2;
        e->cap = nc;
    }
    memmove(e->i + lo + 1, e->i + lo, (size_t)(e->nz - lo) * sizeof *e->i);
    memmove(e->x + lo + 1, e->x + lo, (size_t)(e->nz - lo) * sizeof *e->x);
    e->i[lo] = r;
    e->x[lo] = 0;
    e->nz++;
    c->nnzE++;
    if (e->nz > c->enzmax) c->enzmax = e->nz;
    return e->x + lo;
}

static int grow_pos(aug_cum *c, int64_t need)
{
    if (need <= c->pcap) return 0;
    int64_t nc = c->pcap * 2 > need ? c->pcap * 2 : need;
    int32_t *p = aug_realloc(c->pos, (size_t)nc * sizeof *p);
    if (!p) return -1;
    for (int64_t i = c->pcap; i < nc; i++) p[i] = -1;
    c->pos = p;
    c->pcap = nc;
    return 0;
}

/* Ebar_cum += scatter(E + [0 0; 0 I_k]); dF += scatter(df): paper 001 eq. 3.1
   composed over steps (formats/stream.md 7.2); S grows by the step's H and k new DOFs */
int aug_cum_apply(aug_cum *c, const aug_update *u, aug_err *e)
{
    int64_t m = u->m, k = u->k, s = m + k;
    for (int64_t i = 0; i < m; i++)
        if (u->H[i] < 0 || u->H[i] >= c->n)
            return aug_err_set(e, AUG_EDATA, -1, "UPDT", "step %d: H[%lld] = %d is not below n = %lld",
                               (int)u->step, (long long)i, (int)u->H[i], (long long)c->n);
    for (int64_t i = 0; i < s * s; i++)
        if (!isfinite(u->E[i]))
            return aug_err_set(e, AUG_EDATA, -1, "UPDT", "step %d: E has a non-finite entry",
                               (int)u->step);
    for (int64_t i = 0; i < s; i++)
        if (!isfinite(u->df[i]))
            return aug_err_set(e, AUG_EDATA, -1, "UPDT", "step %d: df has a non-finite entry",
                               (int)u->step);
    if (k > INT32_MAX - c->n)
        return aug_err_set(e, AUG_EDATA, -1, "UPDT", "step %d: too many DOFs", (int)u->step);
    int64_t nadd = k;
    for (int64_t i = 0; i < m; i++) nadd += c->pos[u->H[i]] < 0;
    if (grow_s(c, c->ns + nadd) || grow_pos(c, c->n + k))
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    int32_t *map = aug_malloc((size_t)(s ? s : 1) * sizeof *map);
    if (!map) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    for (int64_t i = 0; i < s; i++) {
        int32_t idx = (int32_t)(i < m ? u->H[i] : c->n + (i - m));
        if (c->pos[idx] < 0) {
            int64_t p = c->ns++;
            c->pos[idx] = (int32_t)p;
            c->S[p] = idx;
            c->dF[p] = 0;
            c->mod[p] = 0;
            c->keep[p] = 0;
            c->E[p] = (aug_ecol){0};
        }
        map[i] = c->pos[idx];
        if (i < m && u->keep && u->keep[i]) c->keep[map[i]] = 1;
    }
    c->napply++;
    for (int64_t j = 0; j < s; j++) {
        for (int64_t i = 0; i < s; i++)
            if (u->E[i + j * s] != 0) {
                double *v = entry(c, map[j], map[i]);
                if (!v) goto nomem;
                *v += u->E[i + j * s];
                c->mod[map[i]] = c->mod[map[j]] = c->napply;
            }
        if (j >= m) {
            double *v = entry(c, map[j], map[j]);
            if (!v) goto nomem;
            *v += 1.0, c->mod[map[j]] = c->napply;
        }
        c->dF[map[j]] += u->df[j];
    }
    c->n += k;
    free(map);
    return 0;
nomem:
    free(map);
    return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
}

int aug_cutmat_init(aug_cutmat *m, const cholmod_sparse *K0, const double *f0,
                    cholmod_common *cm, aug_err *e)
{
    memset(m, 0, sizeof *m);
    if (K0->nrow != K0->ncol || K0->itype != CHOLMOD_INT || K0->xtype != CHOLMOD_REAL)
        return aug_err_set(e, AUG_EDATA, -1, "KMAT", "K0 must be square, real, int-indexed");
    m->n0 = (int64_t)K0->nrow;
    m->K0 = cholmod_copy((cholmod_sparse *)K0, 0, 1, cm);
    if (!m->K0) return aug_err_set(e, AUG_ENOMEM, -1, "KMAT", "out of memory (K0 copy)");
    cholmod_sort(m->K0, cm);
    m->f0 = aug_malloc((size_t)(m->n0 ? m->n0 : 1) * sizeof *m->f0);
    if (!m->f0) return aug_err_set(e, AUG_ENOMEM, -1, "FVEC", "out of memory");
    memcpy(m->f0, f0, (size_t)m->n0 * sizeof *m->f0);
    const int *Ap = m->K0->p;
    m->k0colmax = 1;
    for (int64_t j = 0; j < m->n0; j++)
        if (Ap[j + 1] - Ap[j] > m->k0colmax) m->k0colmax = Ap[j + 1] - Ap[j];
    return aug_cum_init(&m->cum, m->n0, e);
}

void aug_cutmat_free(aug_cutmat *m, cholmod_common *cm)
{
    if (m->K0) cholmod_free_sparse(&m->K0, cm);
    free(m->f0);
    free(m->work);
    free(m->rwork);
    free(m->unit);
    free(m->uscr);
    free(m->uval);
    free(m->uidx);
    aug_cum_free(&m->cum);
    memset(m, 0, sizeof *m);
}

double aug_cutmat_f(const aug_cutmat *m, int64_t i)
{
    const aug_cum *c = &m->cum;
    int64_t p = i < c->pcap ? c->pos[i] : -1;
    return (i < m->n0 ? m->f0[i] : 0.0) + (p >= 0 ? c->dF[p] : 0.0);
}

/* unit[] for the indices the update u touched (its H and its new DOFs): the
   only columns of K_t it changed. 0 or -1 (memory). */
static int unit_update(aug_cutmat *m, const aug_update *u)
{
    int64_t n = m->cum.n, n1 = n - u->k, need = m->k0colmax + m->cum.enzmax + 2;
    if (n > m->unitcap) {
        int64_t cap = m->unitcap ? m->unitcap : 1024;
        while (cap < n) cap *= 2;
        unsigned char *q = aug_realloc(m->unit, (size_t)cap);
        if (!q) return -1;
        memset(q + m->unitcap, 0, (size_t)(cap - m->unitcap));
        m->unit = q;
        double *w = aug_realloc(m->uscr, (size_t)cap * sizeof *w);
        if (!w) return -1;
        memset(w + m->unitcap, 0, (size_t)(cap - m->unitcap) * sizeof *w);
        m->uscr = w;
        m->unitcap = cap;
    }
    if (need > m->ubufcap) {
        double *v = aug_realloc(m->uval, (size_t)need * sizeof *v);
        if (!v) return -1;
        m->uval = v;
        int32_t *ix = aug_realloc(m->uidx, (size_t)need * sizeof *ix);
        if (!ix) return -1;
        m->uidx = ix;
        m->ubufcap = need;
    }
    for (int64_t t = 0; t < (int64_t)u->m + u->k; t++) {
        int64_t j = t < u->m ? u->H[t] : n1 + (t - u->m);
        int64_t nz = aug_cutmat_column(m, j, m->uidx, m->uval, m->uscr);
        m->unit[j] = nz == 1 && m->uidx[0] == j && m->uval[0] == 1.0;
    }
    return 0;
}

int aug_cutmat_apply(aug_cutmat *m, const aug_update *u, aug_err *e)
{
    int rc = aug_cum_apply(&m->cum, u, e);
    if (!rc && unit_update(m, u)) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    return rc;
}

/* y = K_t x = Kbar x - P_S Ebar P_S' x (paper 001 eq. 3.1) */
void aug_cutmat_mult(const aug_cutmat *m, const double *x, double *y)
{
    const int *Ap = m->K0->p, *Ai = m->K0->i;
    const double *Ax = m->K0->x;
    const aug_cum *c = &m->cum;
    for (int64_t j = 0; j < m->n0; j++) {
        double s = 0;
        for (int k = Ap[j]; k < Ap[j + 1]; k++) s += Ax[k] * x[Ai[k]];
        y[j] = s;
    }
    for (int64_t j = m->n0; j < c->n; j++) y[j] = x[j];
    for (int64_t q = 0; q < c->ns; q++) {
        double xq = x[c->S[q]];
        if (xq == 0) continue;
        const aug_ecol *E = &c->E[q];
        for (int32_t t = 0; t < E->nz; t++) y[c->S[E->i[t]]] -= E->x[t] * xq;
    }
}

/* f = f_t = [f_0; 0] + P_S dF */
void aug_cutmat_rhs(const aug_cutmat *m, double *f)
{
    memcpy(f, m->f0, (size_t)m->n0 * sizeof *f);
    for (int64_t j = m->n0; j < m->cum.n; j++) f[j] = 0;
    for (int64_t p = 0; p < m->cum.ns; p++) f[m->cum.S[p]] += m->cum.dF[p];
}

/* r = f_t - K_t x; returns ||r||_2 / ||f_t||_2 (||r||_2 when f_t = 0), NAN when
   out of memory */
double aug_cutmat_residual(aug_cutmat *m, const double *x, double *r)
{
    return aug_cutmat_residual_b(m, x, NULL, r);
}

/* r = f - K_t x over every row; the norms over every row, or (free) over
   the rows that are not unit rows (skip_unit) */
static double residual_rows(aug_cutmat *m, const double *x, const double *f, double *r, int skip_unit)
{
    int64_t n = m->cum.n;
    aug_cutmat_mult(m, x, r);
    double rr = 0, ff = 0;
    for (int64_t i = 0; i < n; i++) {
        r[i] = f[i] - r[i];
        if (skip_unit && aug_cutmat_unit(m, i)) continue;
        rr += r[i] * r[i];
        ff += f[i] * f[i];
    }
    return ff > 0 ? sqrt(rr / ff) : sqrt(rr);
}

double aug_cutmat_residual_free(aug_cutmat *m, const double *x, const double *b, double *r)
{
    return residual_rows(m, x, b, r, 1);
}

double aug_cutmat_residual_b(aug_cutmat *m, const double *x, const double *b, double *r)
{
    int64_t n = m->cum.n;
    if (!b && m->wcap < n) {
        double *w = aug_realloc(m->work, (size_t)n * sizeof *w);
        if (!w) return NAN;
        m->work = w;
        m->wcap = n;
    }
    if (!b) aug_cutmat_rhs(m, m->work);
    return residual_rows(m, x, b ? b : m->work, r, 0);
}

/* ||f_t||_2 with f_t = [f0; 0] + P_S dF: ||f0||^2 with the rows of S
   replaced (S holds each row once) */
double aug_cutmat_fnorm(const aug_cutmat *m)
{
    const aug_cum *c = &m->cum;
    double ff = 0;
    for (int64_t i = 0; i < m->n0; i++) ff += m->f0[i] * m->f0[i];
    for (int64_t p = 0; p < c->ns; p++) {
        int64_t i = c->S[p];
        double f0 = i < m->n0 ? m->f0[i] : 0, ft = f0 + c->dF[p];
        ff += ft * ft - f0 * f0;
    }
    return sqrt(ff > 0 ? ff : 0);
}

/* sqrt(sum over i in S of (f_t - K_t x)_i^2) / ||f_t||_2: relres on the rows
   where K_t differs from K_0 (row i of Kbar = its column: K_0 is kept full) */
double aug_cutmat_relres_changed(aug_cutmat *m, const double *x)
{
    const aug_cum *c = &m->cum;
    int64_t n = c->n;
    if (m->wcap < n) {
        double *w = aug_realloc(m->work, (size_t)n * sizeof *w);
        if (!w) return NAN;
        m->work = w;
        m->wcap = n;
    }
    double *f = m->work, ff = 0, rr = 0;
    aug_cutmat_rhs(m, f);
    for (int64_t i = 0; i < n; i++) ff += f[i] * f[i];
    const int *Ap = m->K0->p, *Ai = m->K0->i;
    const double *Ax = m->K0->x;
    for (int64_t p = 0; p < c->ns; p++) {
        int64_t i = c->S[p];
        double k = 0;
        if (i < m->n0)
            for (int t = Ap[i]; t < Ap[i + 1]; t++) k += Ax[t] * x[Ai[t]]; /* row i = column i */
        else
            k = x[i];
        const aug_ecol *E = &c->E[p]; /* column p: row p of the symmetric Ebar */
        for (int32_t t = 0; t < E->nz; t++) k -= E->x[t] * x[c->S[E->i[t]]];
        rr += (f[i] - k) * (f[i] - k);
    }
    return ff > 0 ? sqrt(rr / ff) : sqrt(rr);
}

/* r[t] = (f_t - K_t x)(rows[t]) and ka[t] = (|K_t| |x| + |f_t|)(rows[t]), the
   denominator of the componentwise backward error ([Higham] sec. 7.2; ka may
   be NULL); x is read on the pattern of those rows only (aug_cutmat_pattern).
   The sums are taken in long double: in double their own rounding, about
   (row length) eps |K_t||x|, is as large as the residual a correction has to
   remove (iterative refinement with an extended-precision residual,
   [Higham] sec. 12.1). */
void aug_cutmat_rows_residual(const aug_cutmat *m, const int32_t *rows, int64_t nr, const double *x,
                              double *r, double *ka)
{
    const aug_cum *c = &m->cum;
    const int *Ap = m->K0->p, *Ai = m->K0->i;
    const double *Ax = m->K0->x;
    for (int64_t t = 0; t < nr; t++) {
        int64_t i = rows[t], p = i < c->pcap ? c->pos[i] : -1;
        long double f = (i < m->n0 ? m->f0[i] : 0) + (long double)(p >= 0 ? c->dF[p] : 0), k = 0;
        double a = fabs((double)f);
        /* Kbar(i, :) x: K_0's row i is its column i */
        if (i < m->n0)
            for (int q = Ap[i]; q < Ap[i + 1]; q++) {
                long double v = (long double)Ax[q] * x[Ai[q]];
                k += v, a += fabs((double)v);
            }
        else
            k = x[i], a += fabs(x[i]);
        if (p >= 0) {
            const aug_ecol *E = &c->E[p]; /* column p: row p of the symmetric Ebar */
            for (int32_t q = 0; q < E->nz; q++) {
                long double v = (long double)E->x[q] * x[c->S[E->i[q]]];
                k -= v, a += fabs((double)v);
            }
        }
        r[t] = (double)(f - k);
        if (ka) ka[t] = a;
    }
}

/* the union of the patterns of K_t's rows rows[0..nr) (K_0's and Ebar's:
   entries that cancelled included), into out, in no particular order; mark
   (size n, 0 on entry and exit) is workspace. Returns its size. */
int64_t aug_cutmat_pattern(const aug_cutmat *m, const int32_t *rows, int64_t nr, int32_t *out,
                           unsigned char *mark)
{
    const aug_cum *c = &m->cum;
    const int *Ap = m->K0->p, *Ai = m->K0->i;
    int64_t k = 0;
#define ADD(j) do { int32_t j_ = (j); if (!mark[j_]) mark[j_] = 1, out[k++] = j_; } while (0)
    for (int64_t t = 0; t < nr; t++) {
        int64_t i = rows[t], p = i < c->pcap ? c->pos[i] : -1;
        ADD((int32_t)i);
        if (i < m->n0)
            for (int q = Ap[i]; q < Ap[i + 1]; q++) ADD(Ai[q]);
        if (p >= 0)
            for (int32_t q = 0; q < c->E[p].nz; q++) ADD(c->S[c->E[p].i[q]]);
    }
#undef ADD
    for (int64_t t = 0; t < k; t++) mark[out[t]] = 0;
    return k;
}

/* ||f_t - K_t x||_2 / ||f_t||_2 (aug_cutmat_residual into rwork) */
double aug_cutmat_relres(aug_cutmat *m, const double *x)
{
    int64_t n = m->cum.n;
    if (m->rcap < n) {
        double *r = aug_realloc(m->rwork, (size_t)n * sizeof *r);
        if (!r) return NAN;
        m->rwork = r;
        m->rcap = n;
    }
    return aug_cutmat_residual(m, x, m->rwork);
}

/* bound on the entries of a column of K_t: the longest column of K_0, the
   longest of Ebar and the diagonal */
int64_t aug_cutmat_colmax(const aug_cutmat *m)
{
    int64_t mx = 1;
    const int *Ap = m->K0->p;
    for (int64_t j = 0; j < m->n0; j++)
        if (Ap[j + 1] - Ap[j] > mx) mx = Ap[j + 1] - Ap[j];
    return mx + m->cum.enzmax + 1;
}

/* column j of K_t = Kbar(:, j) - P_S Ebar(:, pos(j)) (both triangles), rows
   increasing; rows of S that cancel to 0 are dropped; scratch (size n) is zero on
   entry and exit */
int64_t aug_cutmat_column(const aug_cutmat *m, int64_t j, int32_t *idx, double *val,
                          double *scratch)
{
    const aug_cum *c = &m->cum;
    const int *Ap = m->K0->p, *Ai = m->K0->i;
    const double *Ax = m->K0->x;
    int64_t pj = j < c->pcap ? c->pos[j] : -1, nz = 0;
    if (pj < 0) {
        if (j < m->n0)
            for (int k = Ap[j]; k < Ap[j + 1]; k++) idx[nz] = Ai[k], val[nz++] = Ax[k];
        else
            idx[nz] = (int32_t)j, val[nz++] = 1.0;
        return nz;
    }
    /* scratch (size n, zero on entry and exit): Kbar(:, j) - Ebar(:, j) */
    if (j < m->n0)
        for (int k = Ap[j]; k < Ap[j + 1]; k++) scratch[Ai[k]] = Ax[k];
    else
        scratch[j] = 1.0;
    const aug_ecol *E = &c->E[pj];
    for (int32_t t = 0; t < E->nz; t++) scratch[c->S[E->i[t]]] -= E->x[t];
    /* gather: unchanged rows of K0's column, then its rows in S, Ebar's rows
       and the diagonal where they did not cancel; sort */
    if (j < m->n0) {
        for (int k = Ap[j]; k < Ap[j + 1]; k++) {
            int i = Ai[k];
            if (c->pos[i] < 0) idx[nz] = i, val[nz++] = scratch[i], scratch[i] = 0;
        }
        for (int k = Ap[j]; k < Ap[j + 1]; k++) {
            int i = Ai[k];
            if (scratch[i] != 0) idx[nz] = i, val[nz++] = scratch[i];
            scratch[i] = 0;
        }
    }
    for (int32_t t = 0; t < E->nz; t++) {
        int32_t i = c->S[E->i[t]];
        if (scratch[i] != 0) idx[nz] = i, val[nz++] = scratch[i];
        scratch[i] = 0;
    }
    if (scratch[j] != 0) idx[nz] = (int32_t)j, val[nz++] = scratch[j];
    scratch[j] = 0;
    /* insertion sort by row (columns are short) */
    for (int64_t a = 1; a < nz; a++) {
        int32_t ti = idx[a];
        double tv = val[a];
        int64_t b = a - 1;
        while (b >= 0 && idx[b] > ti) idx[b + 1] = idx[b], val[b + 1] = val[b], b--;
        idx[b + 1] = ti, val[b + 1] = tv;
    }
    return nz;
}

/* K_t of order n + pad as CHOLMOD's upper triangle (stype 1), sorted, the pad
   columns identity; exact zeros of changed entries dropped (aug_cutmat_column) */
cholmod_sparse *aug_cutmat_sparse(const aug_cutmat *m, int64_t pad, cholmod_common *cm)
{
    const aug_cum *c = &m->cum;
    int64_t n = c->n, N = n + pad;
    int64_t cmax = aug_cutmat_colmax(m);
    int64_t nzmax = (int64_t)((int *)m->K0->p)[m->n0] / 2 + m->n0 + c->nnzE / 2 + c->ns + N;
    cholmod_sparse *A = cholmod_allocate_sparse((size_t)N, (size_t)N, (size_t)nzmax, 1, 1, 1,
                                                CHOLMOD_REAL, cm);
    int32_t *idx = aug_malloc((size_t)cmax * sizeof *idx);
    double *val = aug_malloc((size_t)cmax * sizeof *val);
    double *scr = aug_calloc((size_t)(n ? n : 1), sizeof *scr);
    if (!A || !idx || !val || !scr) goto fail;
    int *Ap = A->p, *Ai = A->i;
    double *Ax = A->x;
    int64_t nz = 0;
    for (int64_t j = 0; j < N; j++) {
        Ap[j] = (int)nz;
        int64_t k = j < n ? aug_cutmat_column(m, j, idx, val, scr) : 0;
        if (j >= n) idx[0] = (int32_t)j, val[0] = 1.0, k = 1;
        for (int64_t t = 0; t < k && idx[t] <= j; t++) {
            if (nz >= (int64_t)A->nzmax) {
                if (!cholmod_reallocate_sparse(A->nzmax * 2, A, cm)) goto fail;
                Ai = A->i, Ax = A->x;
            }
            Ai[nz] = idx[t], Ax[nz++] = val[t];
        }
    }
    Ap[N] = (int)nz;
    free(idx), free(val), free(scr);
    return A;
fail:
    free(idx), free(val), free(scr);
    if (A) cholmod_free_sparse(&A, cm);
    return NULL;
}
