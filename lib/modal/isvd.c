/* Incremental thin SVD of displacement snapshots in Brand's factored form
   U = U0 Up (paper 004 eqs. 4-11; Brand, LAA 415 (2006) 20-30). */
#include <cblas.h>
#include <lapacke.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_modal.h"

/* residual directions below this fraction of ||u|| are rounding, not data */
#define ISVD_ZERO 1e-13
#define ROWBLK 64

/* small buffers of the work array: a (qcap), m (rmax+2), pc (qcap), K, Uk
   ((rmax+1)^2 each), sv, superb (rmax+1 each), Upn (qcap x (rmax+1)), row
   block (ROWBLK x qcap), p (n) */
typedef struct wk {
    double *a, *m, *pc, *K, *Uk, *sv, *sb, *Upn, *blk, *p;
} wk;

static wk split(const aug_isvd *s)
{
    wk w;
    int c = s->rmax + 1;
    w.a = s->work;
    w.m = w.a + s->qcap;
    w.pc = w.m + c + 1;
    w.K = w.pc + s->qcap;
    w.Uk = w.K + (size_t)c * c;
    w.sv = w.Uk + (size_t)c * c;
    w.sb = w.sv + c;
    w.Upn = w.sb + c;
    w.blk = w.Upn + (size_t)s->qcap * c;
    w.p = w.blk + (size_t)ROWBLK * s->qcap;
    return w;
}

/* empty state with room for n x qcap U0 and a rank up to rmax */
int aug_isvd_init(aug_isvd *s, int64_t n, int rmax, int qcap, double rtol, aug_err *e)
{
    aug_err_clear(e);
    memset(s, 0, sizeof *s);
    if (qcap == 0) qcap = 2 * rmax + 2;
    if (n < 1 || rmax < 1 || qcap < rmax + 1 || !(rtol >= 0 && rtol < 1))
        return aug_err_set(e, AUG_EUSAGE, -1, "", "isvd: n %lld, rank cap %d, qcap %d, rtol %g out of range",
                           (long long)n, rmax, qcap, rtol);
    s->n = n, s->rmax = rmax, s->qcap = qcap, s->rtol = rtol;
    size_t c = (size_t)rmax + 1, qc = (size_t)qcap;
    size_t nw = qc + c + 1 + qc + 2 * c * c + 2 * c + qc * c + ROWBLK * qc + (size_t)n;
    s->U0 = malloc((size_t)n * qc * sizeof *s->U0);
    s->Up = calloc(qc * c, sizeof *s->Up);
    s->Pc = calloc(qc * c, sizeof *s->Pc);
    s->S = calloc(c, sizeof *s->S);
    s->work = malloc(nw * sizeof *s->work);
    if (!s->U0 || !s->Up || !s->Pc || !s->S || !s->work) {
        aug_isvd_free(s);
        return aug_err_set(e, AUG_ENOMEM, -1, "", "isvd: out of memory (n %lld, qcap %d)", (long long)n, qcap);
    }
    s->ratio = 1;
    return 0;
}

/* the thin SVD of X = I_n: U = I, S = 1 (U0 = I, Up = I) */
int aug_isvd_identity(aug_isvd *s, int64_t n, aug_err *e)
{
    if (n > INT_MAX - 1)
        return aug_err_set(e, AUG_EUSAGE, -1, "", "isvd: an identity basis of %lld columns", (long long)n);
    if (aug_isvd_init(s, n, (int)n, (int)n + 1, 0, e)) return e->code;
    memset(s->U0, 0, (size_t)n * n * sizeof *s->U0);
    for (int64_t j = 0; j < n; j++) {
        s->U0[j + (size_t)j * n] = 1;
        s->Up[j + (size_t)j * s->qcap] = 1;
        s->S[j] = 1;
    }
    s->q = s->r = (int)n;
    s->nsnap = n;
    s->unit_up = 1;
    return 0;
}

void aug_isvd_free(aug_isvd *s)
{
    free(s->U0);
    free(s->Up);
    free(s->Pc);
    free(s->S);
    free(s->work);
    memset(s, 0, sizeof *s);
}

/* U0 <- U0 Up row block by row block (in place, O(n q r)); Pc = old Up;
   nothing when Up = I */
static void compact(aug_isvd *s)
{
    if (s->unit_up) return;
    wk w = split(s);
    int q = s->q, r = s->r, ld = s->qcap;
    int64_t n = s->n;
    for (int64_t i0 = 0; i0 < n && r > 0; i0 += ROWBLK) {
        int nb = (int)(n - i0 < ROWBLK ? n - i0 : ROWBLK);
        for (int j = 0; j < q; j++) memcpy(w.blk + (size_t)j * nb, s->U0 + (size_t)j * n + i0, nb * sizeof(double));
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, nb, r, q, 1.0, w.blk, nb, s->Up, ld, 0.0,
                    s->U0 + i0, (int)n);
    }
    memcpy(s->Pc, s->Up, (size_t)ld * (s->rmax + 1) * sizeof *s->Pc);
    s->qold = q, s->rold = r;
    memset(s->Up, 0, (size_t)ld * (s->rmax + 1) * sizeof *s->Up);
    for (int j = 0; j < r; j++) s->Up[j + (size_t)j * ld] = 1;
    s->q = r;
    s->compacted = 1;
    s->unit_up = 1;
}

/* eq. 9's deferred rotation on request */
int aug_isvd_compact(aug_isvd *s, aug_err *e)
{
    aug_err_clear(e);
    s->grew = s->compacted = 0;
    compact(s);
    return 0;
}

/* Brand's update (eqs. 4-8 rederived): a = U0'u and p0 = u - U0 a with one
   reorthogonalisation (CGS2), m = Up'a and a_perp = a - Up m (CGS2 in R^q),
   so u = U m + p with p = U0 a_perp + p0 the residual against span U. When
   ||p0|| > ISVD_ZERO ||u||, U0 gains p0/||p0|| (eq. 10); p = [U0 p0^] pc with
   pc = [a_perp; ||p0||] and rho = ||pc|| = ||p||. Then
     [X u] = [U p^] K [V 0; 0 1]',  K = [diag S, m; 0, rho]  ((r+1) x (r+1), eq. 7),
   K = Uk S' Vk' (LAPACK dgesvd, eq. 8), Up <- [Up, pc/rho] Uk (eq. 9 on the
   small factor), S <- S', both truncated to the s'_k > max(rtol, ISVD_ZERO)
   s'_1, at most rmax (eq. 11 when the rank stays). */
int aug_isvd_add(aug_isvd *s, const double *u, aug_err *e)
{
    aug_err_clear(e);
    s->grew = s->compacted = 0;
    int64_t n = s->n;
    for (int64_t i = 0; i < n; i++)
        if (!isfinite(u[i])) return aug_err_set(e, AUG_EDATA, -1, "", "isvd: snapshot %lld entry %lld not finite",
                                                (long long)s->nsnap, (long long)i);
    if (s->q == s->qcap) compact(s);
    s->unit_up = 0;
    wk w = split(s);
    int q = s->q, r = s->r, ld = s->qcap;
    double unorm = cblas_dnrm2((int)n, u, 1);
    memcpy(w.p, u, n * sizeof *w.p);
    memset(w.a, 0, (size_t)ld * sizeof *w.a);
    for (int pass = 0; pass < 2 && q > 0; pass++) {
        cblas_dgemv(CblasColMajor, CblasTrans, (int)n, q, 1.0, s->U0, (int)n, w.p, 1, 0.0, w.pc, 1);
        cblas_dgemv(CblasColMajor, CblasNoTrans, (int)n, q, -1.0, s->U0, (int)n, w.pc, 1, 1.0, w.p, 1);
        cblas_daxpy(q, 1.0, w.pc, 1, w.a, 1);
    }
    /* a_perp in pc, m in m: two passes against Up's columns */
    memcpy(w.pc, w.a, (size_t)q * sizeof *w.pc);
    memset(w.m, 0, (size_t)(r + 1) * sizeof *w.m);
    for (int pass = 0; pass < 2 && r > 0; pass++) {
        double *t = w.sv;
        cblas_dgemv(CblasColMajor, CblasTrans, q, r, 1.0, s->Up, ld, w.pc, 1, 0.0, t, 1);
        cblas_dgemv(CblasColMajor, CblasNoTrans, q, r, -1.0, s->Up, ld, t, 1, 1.0, w.pc, 1);
        cblas_daxpy(r, 1.0, t, 1, w.m, 1);
    }
    double rho0 = cblas_dnrm2((int)n, w.p, 1), aperp = q > 0 ? cblas_dnrm2(q, w.pc, 1) : 0;
    s->resid = sqrt(rho0 * rho0 + aperp * aperp);
    double tiny = ISVD_ZERO * unorm;
    int qn = q;
    if (rho0 > tiny) {
        double *col = s->U0 + (size_t)q * n;
        for (int64_t i = 0; i < n; i++) col[i] = w.p[i] / rho0;
        w.pc[q] = rho0;
        for (int j = 0; j <= r; j++) s->Up[q + (size_t)j * ld] = 0;
        qn = q + 1;
        s->grew = 1;
    } else {
        s->dropped2 += rho0;
    }
    double rho = qn > 0 ? cblas_dnrm2(qn, w.pc, 1) : 0;
    if (!(rho > tiny)) {
        s->dropped2 += rho;
        rho = 0;
    }
    /* extended small factor [Up, pc/rho] (qn x (r+1)) and K */
    for (int i = 0; i < qn; i++) s->Up[i + (size_t)r * ld] = rho > 0 ? w.pc[i] / rho : 0;
    int c = r + 1;
    memset(w.K, 0, (size_t)c * c * sizeof *w.K);
    for (int j = 0; j < r; j++) w.K[j + (size_t)j * c] = s->S[j], w.K[j + (size_t)r * c] = w.m[j];
    w.K[r + (size_t)r * c] = rho;
    double sold = 0;
    for (int j = 0; j < r; j++) sold += s->S[j];
    int info = LAPACKE_dgesvd(LAPACK_COL_MAJOR, 'A', 'N', c, c, w.K, c, w.sv, w.Uk, c, NULL, 1, w.sb);
    if (info != 0)
        return aug_err_set(e, AUG_ENOCONV, -1, "", "isvd: dgesvd of the %d x %d core failed (info %d)", c, c, info);
    int rn = 0;
    double cut = fmax(s->rtol, ISVD_ZERO) * w.sv[0];
    while (rn < c && rn < s->rmax && w.sv[rn] > cut) rn++;
    if (rn < c) s->dropped2 += w.sv[rn];
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, qn, rn, c, 1.0, s->Up, ld, w.Uk, c, 0.0, w.Upn, ld);
    for (int j = 0; j < rn; j++) memcpy(s->Up + (size_t)j * ld, w.Upn + (size_t)j * ld, qn * sizeof(double));
    for (int j = rn; j <= s->rmax; j++) memset(s->Up + (size_t)j * ld, 0, ld * sizeof(double));
    double snew = 0;
    for (int j = 0; j < rn; j++) s->S[j] = w.sv[j], snew += w.sv[j];
    for (int j = rn; j <= s->rmax; j++) s->S[j] = 0;
    s->ratio = snew > 0 ? sold / snew : 1;
    s->q = qn, s->r = rn;
    s->nsnap++;
    return 0;
}

/* Uout = U0 Up (n x r) */
void aug_isvd_basis(const aug_isvd *s, double *Uout)
{
    if (s->r == 0) return;
    if (s->unit_up) {
        memcpy(Uout, s->U0, (size_t)s->n * s->r * sizeof *Uout);
        return;
    }
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, (int)s->n, s->r, s->q, 1.0, s->U0, (int)s->n, s->Up,
                s->qcap, 0.0, Uout, (int)s->n);
}

aug_basis aug_isvd_view(const aug_isvd *s)
{
    aug_basis b = {s->n, s->q, s->r, s->U0, s->Up, s->qcap};
    return b;
}
