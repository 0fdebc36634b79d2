/* AMPS steps 4 and 6 (paper 001 table 1): the right-hand side of eqs. 3.10 and
   3.21 (with loads changed on H) and the solution by eq. 3.20 (sec. 3.1),
   back-substituting only over the closure of the requested DOFs (paper 000 thm 2). */
#include <stdlib.h>
#include <math.h>
#include <string.h>
#include "aug_solve.h"
#include "aug_par.h"

/* workspace of field_corrected, sized for K_t of order n with |S| = ns */
typedef struct aug_hcorr {
    int64_t ncap, scap;
    int32_t *pat, *qa;       /* pattern of H's rows (n), A index of a position (ns) */
    unsigned char *mark;     /* n bytes, zero between uses */
    double *xt;              /* K_t-sized values on the pattern */
    double *yd;              /* n-sized: the field of the correction */
    double *yf, *ydf;        /* n-sized: forward parts D^-1 L^-1 P H w (deferred L^-T) */
    int32_t *cset;           /* n: the closure C of the pattern in L' (deferred L^-T) */
    int *pre;                /* n: per supernode its leading columns outside C */
    double *r, *ka, *rh, *ew, *x0, *w0; /* S-sized */
} aug_hcorr;

static void hcorr_free(aug_hcorr *h)
{
    if (!h) return;
    free(h->pat), free(h->qa), free(h->mark), free(h->xt), free(h->yd);
    free(h->yf), free(h->ydf), free(h->cset), free(h->pre);
    free(h->r), free(h->ka), free(h->rh), free(h->ew), free(h->x0), free(h->w0);
    free(h);
}

static aug_hcorr *hcorr_get(aug_amps *a, int64_t n, int64_t ns)
{
    aug_hcorr *h = a->hc;
    if (!h && !(h = a->hc = aug_calloc(1, sizeof *h))) return NULL;
    if (h->ncap < n + 1) {
        free(h->pat), free(h->mark), free(h->xt), free(h->yd);
        free(h->yf), free(h->ydf), free(h->cset), free(h->pre);
        h->yd = aug_malloc((size_t)(n + 1) * sizeof *h->yd);
        h->yf = aug_malloc((size_t)(n + 1) * sizeof *h->yf);
        h->ydf = aug_malloc((size_t)(n + 1) * sizeof *h->ydf);
        h->cset = aug_malloc((size_t)(n + 1) * sizeof *h->cset);
        h->pre = aug_malloc((size_t)(n + 1) * sizeof *h->pre);
        h->pat = aug_malloc((size_t)(n + 1) * sizeof *h->pat);
        h->mark = aug_calloc((size_t)(n + 1), 1);
        h->xt = aug_malloc((size_t)(n + 1) * sizeof *h->xt);
        h->ncap = h->pat && h->mark && h->xt && h->yd && h->yf && h->ydf && h->cset && h->pre ? n + 1 : 0;
        if (!h->ncap) return NULL;
    }
    if (h->scap < ns + 1) {
        double **v[] = {&h->r, &h->ka, &h->rh, &h->ew, &h->x0, &h->w0};
        free(h->qa);
        h->qa = aug_malloc((size_t)(ns + 1) * sizeof *h->qa);
        int ok = h->qa != NULL;
        for (size_t k = 0; k < sizeof v / sizeof *v; k++) {
            free(*v[k]);
            *v[k] = aug_malloc((size_t)(ns + 1) * sizeof **v[k]);
            ok = ok && *v[k];
        }
        h->scap = ok ? ns + 1 : 0;
        if (!ok) return NULL;
    }
    return h;
}

void aug_amps_init(aug_amps *a)
{
    memset(a, 0, sizeof *a);
    aug_memo_init(&a->memo);
    aug_schur_init(&a->schur);
}

void aug_amps_free(aug_amps *a)
{
    if (a->X || a->Yw || a->Ew) {
        cholmod_common cm;
        cholmod_start(&cm);
        cholmod_free_dense(&a->X, &cm);
        cholmod_free_dense(&a->Yw, &cm);
        cholmod_free_dense(&a->Ew, &cm);
        cholmod_finish(&cm);
    }
    aug_memo_free(&a->memo);
    aug_schur_free(&a->schur);
    free(a->x);
    free(a->w);
    free(a->y);
    free(a->q);
    free(a->mark);
    free(a->ca);
    free(a->t2);
    free(a->zlo);
    free(a->lset);
    hcorr_free(a->hc);
    free(a->hcl);
    free(a->xref), free(a->rref), free(a->kref);
    memset(a, 0, sizeof *a);
}

static double now_ms(void) { return 1e3 * aug_now(); }

/* scratch: x (na), w (max(m, ns)), y/mark/q (n_b) */
static int scratch(aug_amps *a, const aug_base *b, const aug_cum *c)
{
    int64_t need = c->ns + 1;
    if (a->xcap < need) {
        free(a->x), free(a->w);
        a->x = aug_malloc((size_t)need * sizeof *a->x);
        a->w = aug_malloc((size_t)need * 2 * sizeof *a->w);
        a->xcap = a->x && a->w ? need : 0;
        if (!a->xcap) return -1;
    }
    if (a->wcap < b->n + 1) {
        free(a->y), free(a->q), free(a->mark), free(a->ca), free(a->t2), free(a->zlo), free(a->lset);
        a->y = aug_malloc((size_t)(b->n + 1) * sizeof *a->y);
        a->q = aug_malloc((size_t)(b->n + 1) * sizeof *a->q);
        a->mark = aug_calloc((size_t)(b->n + 1), 1);
        a->ca = aug_malloc((size_t)(b->n + 1) * sizeof *a->ca);
        a->t2 = aug_malloc((size_t)(b->n + 1) * sizeof *a->t2);
        a->zlo = aug_calloc((size_t)(b->n + 1), sizeof *a->zlo);
        a->lset = aug_malloc((size_t)(b->n + 1) * sizeof *a->lset);
        a->wcap = a->y && a->q && a->mark && a->ca && a->t2 && a->zlo && a->lset ? b->n + 1 : 0;
        if (!a->wcap) return -1;
    }
    return 0;
}

/* wp = Ebar x over all positions (the Ebar a2 of eq. 3.20): nonzero on A only
   (Ebar(p, b) != 0 makes p active), so S2's column lists of Ebar_AA suffice */
static void ebar_times(const aug_amps *a, const aug_cum *c, const double *x, double *wp)
{
    const aug_schur *s = &a->schur;
    for (int64_t p = 0; p < c->ns; p++) wp[p] = 0;
    for (int64_t bq = 0; bq < s->na; bq++) {
        double xb = x[bq];
        if (xb == 0) continue;
        for (int64_t t = s->ep[bq]; t < s->ep[bq + 1]; t++) wp[s->A[s->ei[t]]] += s->ex[t] * xb;
    }
}

/* hcl = closure of H in L' for the base DOFs of S (the union of their etree
   paths, paper 000 thm 3: of the memo's V columns and of the positions that
   change only the load), kept while S and the base stay */
static int h_closure(aug_amps *a, const aug_base *b, const aug_cum *c)
{
    if (a->hcl && a->hcl_b == (const void *)b && a->hcl_m == c->ns) return 0;
    free(a->hcl);
    a->hcl = aug_malloc((size_t)(2 * b->n + 2) * sizeof *a->hcl);
    if (!a->hcl) return -1;
    int32_t *start = a->hcl + b->n + 1;
    int64_t k = 0;
    for (int64_t p = 0; p < c->ns; p++)
        if (c->S[p] < c->nb) start[k++] = b->pinv[c->S[p]];
    a->nhcl = aug_ldl_closure(b, start, k, a->hcl, a->mark);
    a->hcl_b = b, a->hcl_m = c->ns;
    return 0;
}

/* out[aq] += (H'Kbar^-1 P_lo w)_aq on the base positions of A (paper 001
   eq. 3.21's H'K^-1H dF_H, and the correction's H'K^-1H r), where lo are
   the base positions of S without a memo column (their Ebar column is zero:
   loads only, amps_reach.c wants): V(:, p)' D^-1 (L^-1 P w_lo), one forward
   solve of w_lo over the closure of lo in L (paper 000 thm 3) and a dot
   product along each column's path, where G would need a V column and a row
   of G per position (bunny of bench/organs.sh, 8-node steps: a 514-node
   piece dropped at once is 1,542 positions, a memo of 381 ms on that step
   and 16-36 ms on each later one). In exact arithmetic it is what G's
   columns of those positions would add. 0, or -1 (no workspace). */
static int lo_times(aug_amps *a, const aug_base *b, const aug_cum *c, const double *w, double *out)
{
    const aug_memo *M = &a->memo;
    const aug_schur *s = &a->schur;
    if (!a->zlo || !a->lset) return -1;
    int32_t *start = a->ca; /* n_b-sized scratch, free here */
    double *z = a->zlo;     /* zero outside the closure, which holds start */
    int64_t k = 0;
    for (int64_t p = 0; p < c->ns; p++)
        if (c->S[p] < c->nb && M->cpos[p] < 0 && w[p] != 0) {
            start[k++] = b->pinv[c->S[p]];
            z[b->pinv[c->S[p]]] = w[p];
        }
    if (k == 0) return 0;
    int64_t nl = aug_ldl_closure(b, start, k, a->lset, a->mark);
    aug_ldl_lsolve_closure_super(b, a->lset, nl, z, a->t2);
    aug_ldl_dsolve(b, a->lset, nl, z);
    for (int64_t aq = 0; aq < s->na; aq++) {
        int32_t p = s->A[aq];
        if (c->S[p] >= c->nb) continue;
        int64_t j = M->cpos[p];
        double v = 0;
        for (int64_t t = M->vp[j]; t < M->vp[j + 1]; t++) v += M->vx[t] * z[M->vi[t]];
        out[aq] += v;
    }
    for (int64_t t = 0; t < nl; t++) z[a->lset[t]] = 0;
    return 0;
}

/* w = f + Ebar a2 from x = rhs = Hbar'Kbar^-1 f on A (f on S; NULL: 0), by
   the pivot of a->pivot_used. S2 (paper 001 eq. 3.8, the (1,2) block of S1
   as pivot): x := a2 = S2^-1 rhs, w = f + Ebar a2. ALT (eqs. 3.16-3.17, the
   (2,1) block): the forces a3 = -w solved for directly, (Ebar Gbar - I) a3 =
   Hbar'(f_t - fbar) + Ebar Hbar'Kbar^-1 fbar, i.e. w = f + (I - Ebar Gbar)^-1
   Ebar rhs = f + S2'^-1 Ebar rhs (aug_schur_solve_t; the same w in exact
   arithmetic, since Ebar S2^-1 = S2'^-1 Ebar); then x := w on the new DOFs of
   A (eq. 3.17: a = [a_b; 0] - Kbar^-1 Hbar a3 is w there, Kbar^-1 = I), and
   x is not a2 on base positions (no one reads it). */
static void pivot_solve(aug_amps *a, const aug_cum *c, double *x, const double *f, double *wp)
{
    const aug_schur *s = &a->schur;
    if (a->pivot_used == AUG_PIVOT_ALT) {
        ebar_times(a, c, x, wp); /* Ebar rhs: nonzero on A only */
        for (int64_t aq = 0; aq < s->na; aq++) x[aq] = wp[s->A[aq]];
        aug_schur_solve_t(s, x);
        for (int64_t aq = 0; aq < s->na; aq++) wp[s->A[aq]] = x[aq];
    } else {
        aug_schur_solve(s, x);
        ebar_times(a, c, x, wp);
    }
    if (f)
        for (int64_t p = 0; p < c->ns; p++) wp[p] += f[p];
    if (a->pivot_used == AUG_PIVOT_ALT)
        for (int64_t aq = 0; aq < s->na; aq++)
            if (c->S[s->A[aq]] >= c->nb) x[aq] = wp[s->A[aq]];
}

/* y (permuted, n_b) = D^-1 L^-1 P H w_H (eq. 3.20's Kbar^-1 Hbar before L^-T,
   paper 001). By default a forward solve of the one vector P H w over the
   closure of H (aug_ldl_lsolve_closure_super): its residual is eps |L||y|,
   while the memo's sum of columns sum_c V(:,c) w(col c) (field_memo) carries
   eps |L| sum_c |V(:,c)| |w_c|, which the large, cancelling forces Ebar a2 of
   a cut through a beam make 10-100 x refactor's residual on rows far from
   H. set = NULL: y on all n entries; else y is exact only on the closed set
   set[0..k) (the L^-T that follows reads nothing else, paper 000 thm 2) and
   on the closure of H, garbage elsewhere. The memo's way: the V columns
   added where they lie, the consecutive tail of a column (the top of the
   tree) as a dense axpy. tmp: n_b-sized workspace. -1: out of memory (the
   closure of H). */
static int v_times(aug_amps *a, const aug_base *b, const aug_cum *c, const double *wp,
                   const int32_t *set, int64_t k, double *y, double *tmp)
{
    const aug_memo *M = &a->memo;
    if (set)
        for (int64_t t = 0; t < k; t++) y[set[t]] = 0;
    else
        memset(y, 0, (size_t)b->n * sizeof *y);
    if (!a->field_memo) {
        if (h_closure(a, b, c)) return -1;
        for (int64_t t = 0; t < a->nhcl; t++) y[a->hcl[t]] = 0;
        for (int64_t p = 0; p < c->ns; p++)
            if (c->S[p] < c->nb) y[b->pinv[c->S[p]]] += wp[p];
        aug_ldl_lsolve_closure_super(b, a->hcl, a->nhcl, y, tmp);
        aug_ldl_dsolve(b, set, set ? k : 0, y);
        return 0;
    }
    for (int64_t j = 0; j < M->m; j++) {
        double wj = wp[M->col[j]];
        if (wj == 0) continue;
        int64_t t = M->vp[j], te = M->vt[j];
        for (; t < te; t++) y[M->vi[t]] += M->vx[t] * wj;
        te = M->vp[j + 1];
        if (t < te) {
            double *yt = y + M->vi[t];
            const double *vx = M->vx + t;
            for (int64_t k = 0; k < te - t; k++) yt[k] += vx[k] * wj;
        }
    }
    aug_ldl_dsolve(b, set, set ? k : 0, y);
    return 0;
}

/* x (permuted, n_b) := the base part of [a_b; 0] + Kbar^-1 P_S wp on the
   set set[0..k) closed in L': y = D^-1 V wp (v_times), then L^-T over the set
   only (paper 000 thm 2: a closed set's values need nothing outside it) */
static int closure_field(aug_amps *a, const aug_base *b, const aug_cum *c, const double *wp,
                         const int32_t *set, int64_t k, double *y)
{
    if (v_times(a, b, c, wp, set, k, y, a->t2)) return -1;
    aug_ldl_ltsolve_closure_super(b, set, k, y, a->t2);
    return 0;
}

/* closure_field over the set Q[0..nq), or over all of L when Q is NULL
   (through the supernodes, X/Yw/Ew kept in a); 0 or -1 */
static int field(aug_amps *a, const aug_base *b, const aug_cum *c, const double *wp,
                 const int32_t *Q, int64_t nq, double *y, cholmod_common *cm)
{
    if (Q) return closure_field(a, b, c, wp, Q, nq, y);
    if (v_times(a, b, c, wp, NULL, 0, y, a->t2)) return -1;
    int rc = aug_par_ltsolve_all(a->par, b, y); /* two cores when a->par is set */
    return rc <= 0 ? rc : aug_ldl_ltsolve_all(b, y, &a->X, &a->Yw, &a->Ew, cm);
}

/* out := the closure in L' (paper 000 thm 3: the union of the etree paths)
   of the permuted base DOFs among the matrix indices i1[0..n1) and
   i2[0..n2), ascending; mark (n bytes) is zero on entry and exit. A large
   closure is collected by a scan of mark instead of sorted. Returns its size. */
static int64_t closure2(const aug_base *b, int64_t nb, const int32_t *i1, int64_t n1,
                        const int32_t *i2, int64_t n2, int32_t *out, unsigned char *mark)
{
    int64_t k = 0;
    for (int l = 0; l < 2; l++)
        for (int64_t t = 0, e = l ? n2 : n1; t < e; t++) {
            int32_t i = l ? i2[t] : i1[t];
            if (i >= nb) continue;
            for (int32_t v = b->pinv[i]; v >= 0 && !mark[v]; v = b->parent[v]) mark[v] = 1, out[k++] = v;
        }
    if (k * 16 > b->n) {
        k = 0;
        for (int64_t v = 0; v < b->n; v++)
            if (mark[v]) mark[v] = 0, out[k++] = (int32_t)v;
        return k;
    }
    for (int64_t t = 0; t < k; t++) mark[out[t]] = 0;
    qsort(out, (size_t)k, sizeof *out, aug_cmp_i32);
    return k;
}

/* the normwise backward error on the rows of H at which the correction
   stops: a few units of rounding */
#define BERR_OK 4e-16

/* The residual the rows outside H carry, relative to ||f_t||: every row of
   K_t outside S is solved to the rounding of one back-substitution with the
   base's factor, which scales with the solution; the base's own solve
   a_b = K_b^-1 f_b shows its size, so that part is about
   ||f_b - K_b a_b|| ||x_t|| / (||a_b|| ||f_t||), x_t from the base DOFs of
   the field y (permuted) and the step's offsets (a_b, or a reference field:
   ref_setup), else xn when finite (the last full field of this base, when
   the field's L^-T is deferred), else ||a_b|| (an output set).
   Times floor_k; 0 when the base has no residual or floor_k is 0. */
static double relres_floor(const aug_amps *a, const aug_base *b, const aug_cum *c, const double *y,
                           double xn, double fnorm)
{
    if (!(a->floor_k > 0) || !isfinite(b->rnorm) || !(b->anorm > 0) || !(fnorm > 0)) return 0;
    double xx = 0;
    if (y)
        for (int64_t i = 0; i < c->nb; i++) {
            double v = a->ab_cur[i] + y[b->pinv[i]];
            xx += v * v;
        }
    xn = y ? sqrt(xx) : isfinite(xn) ? xn : b->anorm;
    return a->floor_k * b->rnorm * xn / (b->anorm * fnorm);
}

/* The base DOFs of S whose row of K_t is the unit row e_i' (a constrained
   DOF kept in the matrix, formats/stream.md 7.2: a piece dropped or pinned, a
   --constrain or --drag step) take x_i = f_t(i) exactly (rhs given: x_i =
   rhs_i, a general right-hand side), among the indices set[0..n) (NULL:
   those of S). AMPS computes them as a_b + y like any other base DOF, and
   where the constraint undoes the base's displacement (a dropped piece that
   hung under gravity) the two cancel: on the soft armadillo of
   tests/solve_amps_cancel.test they kept up to 1.4e-5 where the value is
   0, the step's largest difference to a fresh solve, and plain AMPS's
   err_direct was 8x refactor's relres (1.06x with this). The row's column
   is e_i too, so no other row reads x_i: the value is exact and changes
   nothing else. The correction on H still sees them as a_b + y (its sweeps
   lower the residual of the other rows of S as well: taking them exact
   there skipped a sweep on the bunny of the organs bench, and the step
   then took a refinement solve instead). */
static void unit_rows(const aug_amps *a, const aug_cum *c, const int32_t *set, int64_t n,
                      const double *rhs, double *x)
{
    const aug_cutmat *kt = a->kt;
    if (!kt || !kt->unit) return;
    if (!set)
        n = c->ns;
    for (int64_t t = 0; t < n; t++) {
        int64_t i = set ? set[t] : c->S[t];
        int64_t p = i < c->pcap ? c->pos[i] : -1;
        if ((i < c->nb || (p >= 0 && c->keep[p])) && aug_cutmat_unit(kt, i))
            x[i] = rhs ? rhs[i] : aug_cutmat_f(kt, i);
    }
}

/* The cancellation of the full field x_t = [a_b; 0] + y on base DOFs (y =
   Kbar^-1 P_S w, permuted): a->cancel = (||a_b|| + ||y||) / ||x_t||, and
   a->floor_end, relres_floor with this ||x_t||. relres_floor takes the rows
   outside S at the base's back-substitution rounding scaled to ||x_t||, as
   a fresh factorization's; but those rows are solved as a_b plus y, each
   with its own rounding, and where a cut undoes much of the base's
   displacement (a limb cut loose, a piece dropped) the two cancel and the
   rounding stays at the size of a_b and y. The armadillo (1,446 nodes, nu
   0.49), oblique plane, 48 one-node steps: from step 37 x_t shrinks, a
   fresh factorization's relres falls from 2.6e-10 to 1.3e-11, AMPS's stays
   at 1.6e-10 with relres_h at 3e-13, 12-18x refactor's. cancel tells the
   refinement gate (solver.c, refine) that the step's relres must be
   measured. With a reference field (ref_setup) xref stands for a_b. */
static void field_norms(aug_amps *a, const aug_base *b, const aug_cum *c, const double *y,
                        double fnorm)
{
    /* the unit rows (unit_rows) are taken exactly, not as a_b + y: left out
       of the three norms (a dropped piece that hung far would count as
       cancellation that no row outside S carries) */
    double xx = 0, yy = 0, aa = 0;
    const aug_cutmat *kt = a->kt;
    const double *ab = a->ab_cur;
    for (int64_t i = 0; i < c->nb; i++) {
        if (kt && aug_cutmat_unit(kt, i)) continue;
        double yi = y[b->pinv[i]], v = ab[i] + yi;
        xx += v * v, yy += yi * yi, aa += ab[i] * ab[i];
    }
    a->xnorm = sqrt(xx), a->xnorm_b = b;
    a->cancel = a->xnorm > 0 ? (sqrt(aa) + sqrt(yy)) / a->xnorm : aa + yy > 0 ? INFINITY : 1;
    a->floor_end = relres_floor(a, b, c, NULL, a->xnorm, fnorm);
}

/* The field of eq. 3.20 and its correction on the small system (paper 001
   eq. 3.8 with a residual right-hand side; issue 15 items 1 and 5), over one
   set: y (permuted, n_b) = Kbar^-1 P_S w on Q = the closure in L' of the
   base DOFs of out and, correcting, of the pattern of the rows of S (all of
   L when out is NULL), w = dF + Ebar a2. The output, the reaction DOFs the
   caller put in out, and the check all read this one back-substitution: a
   one-node output set costs the closure of the rows of S and the node's
   path, not two traversals (paper 000 thm 2).
   AMPS's field x = [a_b; 0] + Kbar^-1 P_S w satisfies every row of K_t
   outside S to the rounding of one back-substitution, so its residual r =
   f_t - K_t x lives on the rows of S: r_S = Ebar (Hbar'x - a2), the forces
   of the cut times the difference between two computations of the field on
   S, a2 from S2 (the memo's H'K^-1H) and Hbar'x from the back-substitution,
   each with its own forward error; cond(S2) and the cut forces grow as a
   cut deepens (bunny: ||r_S|| / ||f_t|| from 5e-9 to 7e-8 over 64
   one-node steps, a full LU of S2 every step the same), while the rows
   outside S stay at one back-substitution's rounding. With r on S,
   K_t^-1 P_S r = Kbar^-1 P_S (r + Ebar dz), S2 dz = (Kbar^-1 P_S r)_A
   (eqs. 3.8 and 3.15 for the right-hand side P_S r, from the memo's
   H'K^-1H): a2 += dz, dw += r + Ebar dz. As in any iterative refinement
   the field of each increment is added to the field already computed,
   never recomputed with w + dw in one back-substitution: that would bring
   back rounding of the size being removed. The residual is summed in long
   double (aug_cutmat_rows_residual). A sweep is taken while the normwise
   backward error max|r| / max(|K_t||x| + |f_t|) on those rows exceeds
   BERR_OK and the part of the relative residual on those rows, relres_h =
   ||r_H|| / ||f_t||, exceeds relres_floor (below the residual the other
   rows carry a sweep buys nothing the step's relres shows), at most
   correct_max times; one that does not lower it is undone (its increment
   never joins y), one that lowers it by less than 10% is the last.
   The full field (out NULL) defers its L^-T: the rows of S read x only on
   the closure C in L' of their pattern, so the field and each increment
   are back-substituted over C alone (aug_ldl_ltsolve_closure_super), the
   forward parts D^-1 L^-1 P H w summed beside them, and the rest of L' is
   solved once at the end from that sum with x_C given
   (aug_par_ltsolve_rest): a sweep costs a forward and a backward solve over
   closures, not a full solve (issue 15 item 1), and the rows outside S,
   each solved once, stay at one back-substitution's rounding. dw
   (S-sized) is zero when no sweep was kept. Sets ncorrect, berr_h0,
   berr_h, relres_h0, relres_h, relres_floor, t_correct, nq (|Q|; Q in a->q when out is
   given). Returns 0, -1 (memory) or -2 (the supernodal solve failed). */
static int field_corrected(aug_amps *a, const aug_base *b, const aug_cum *c, const int32_t *out,
                           int64_t nout, double *x, const double *wp, double *dw, cholmod_common *cm)
{
    a->ncorrect = 0;
    a->berr_h0 = a->berr_h = a->relres_h0 = a->relres_h = a->relres_floor = NAN;
    a->cancel = a->floor_end = NAN;
    a->t_correct = 0;
    const aug_schur *s = &a->schur;
    const aug_memo *M = &a->memo;
    int64_t ns = c->ns, na = s->na, np = 0, nc = 0;
    for (int64_t p = 0; p < ns; p++) dw[p] = 0;
    int corr = a->kt && a->correct_max > 0 && ns > 0;
    aug_hcorr *h = corr ? hcorr_get(a, c->n, ns) : NULL;
    if (corr && !h) return -1;
    double *y = a->y, tc = now_ms();
    if (corr) {
        /* the rows of S and their pattern */
        np = aug_cutmat_pattern(a->kt, c->S, ns, h->pat, h->mark);
    }
    int32_t *Q = out ? a->q : NULL;
    a->nq = out ? closure2(b, c->nb, out, nout, h ? h->pat : NULL, np, Q, a->mark) : b->n;
    /* the deferred L^-T of the full field: C = the closure of the
       pattern's base DOFs and of H (the forward solve's support) */
    int defer = corr && !out && !a->field_memo && b->Ls;
    if (defer && h_closure(a, b, c)) return -1;
    if (defer) {
        nc = closure2(b, c->nb, h->pat, np, NULL, 0, h->cset, a->mark);
        for (int64_t t = 0; t < nc; t++) a->mark[h->cset[t]] = 1;
        int64_t extra = 0;
        for (int64_t t = 0; t < a->nhcl; t++)
            if (!a->mark[a->hcl[t]]) extra++;
        for (int64_t t = 0; t < nc; t++) a->mark[h->cset[t]] = 0;
        /* hcl lies in C when every memo column is a row of S (always, but
           checked: else the old way) */
        defer = extra == 0 && aug_ldl_closure_pre(b, h->cset, nc, h->pre) == 0;
    }
    a->t_correct += now_ms() - tc;
    if (defer) {
        if (v_times(a, b, c, wp, NULL, 0, h->yf, a->t2)) return -1;
        for (int64_t t = 0; t < nc; t++) y[h->cset[t]] = h->yf[h->cset[t]];
        aug_ldl_ltsolve_closure_super(b, h->cset, nc, y, a->t2);
    } else if (field(a, b, c, wp, Q, a->nq, y, cm))
        return -2;
    if (!corr) return 0; /* (the refinement gate reads cancel only with a correction) */
    tc = now_ms();
    for (int64_t p = 0; p < ns; p++) h->qa[p] = -1;
    for (int64_t aq = 0; aq < na; aq++) h->qa[s->A[aq]] = (int32_t)aq;
    /* xt: the field on the pattern, base DOFs from y, then the increments */
    for (int64_t t = 0; t < np; t++)
        if (h->pat[t] < c->nb) h->xt[h->pat[t]] = a->ab_cur[h->pat[t]] + y[b->pinv[h->pat[t]]];
    double *yd = h->yd, prev = INFINITY, prev_rs = NAN, fnorm = aug_cutmat_fnorm(a->kt);
    /* deferred: ||x_t|| from this base's last full field, if any */
    double xn = defer && a->xnorm_b == (const void *)b ? a->xnorm : NAN;
    a->relres_floor = relres_floor(a, b, c, Q || defer ? NULL : y, xn, fnorm);
    int rc = 0;
    for (int it = 0;; it++) {
        for (int64_t t = 0; t < np; t++) {
            int32_t i = h->pat[t];
            if (i >= c->nb) {
                int32_t p = c->pos[i], aq = h->qa[p];
                h->xt[i] = (a->xnew_cur ? a->xnew_cur[i] : 0) + (aq >= 0 ? x[aq] : a->dF_cur[p] + dw[p]);
            }
        }
        aug_cutmat_rows_residual(a->kt, c->S, ns, h->xt, h->r, h->ka);
        /* a kept block (solver.c keep_blocks): K_t's unit row there is not
           the row the base's methods solve, whose solution there is 0 =
           f_t, taken exactly (unit_rows); its residual against the unit
           row would ask a sweep for what that row cannot give */
        for (int64_t p = 0; p < ns; p++)
            if (c->keep[p]) h->r[p] = 0, h->ka[p] = 0;
        double rmax = 0, kmax = 0, berr;
        for (int64_t p = 0; p < ns; p++) {
            if (fabs(h->r[p]) > rmax) rmax = fabs(h->r[p]);
            if (h->ka[p] > kmax) kmax = h->ka[p];
        }
        berr = kmax > 0 ? rmax / kmax : rmax > 0 ? INFINITY : 0;
        double rs = 0;
        for (int64_t p = 0; p < ns; p++) rs += h->r[p] * h->r[p];
        rs = fnorm > 0 ? sqrt(rs) / fnorm : sqrt(rs);
        if (it == 0) a->berr_h0 = berr, a->relres_h0 = rs;
        if (berr > prev) { /* the last sweep made it worse: undone */
            memcpy(x, h->x0, (size_t)na * sizeof *x);
            memcpy(dw, h->w0, (size_t)ns * sizeof *dw);
            a->ncorrect--;
            a->berr_h = prev, a->relres_h = prev_rs;
            break;
        }
        if (it > 0 && defer) { /* the last sweep kept: its parts join y on C and yf */
            for (int64_t t = 0; t < nc; t++) y[h->cset[t]] += yd[h->cset[t]];
            for (int64_t t = 0; t < b->n; t++) h->yf[t] += h->ydf[t];
        } else if (it > 0)
            for (int64_t t = 0; t < a->nq; t++) y[Q ? Q[t] : t] += yd[Q ? Q[t] : t];
        a->berr_h = berr, a->relres_h = rs;
        if (berr <= BERR_OK || rs <= a->relres_floor || it == a->correct_max || (it > 0 && berr > 0.9 * prev))
            break;
        prev = berr, prev_rs = rs;
        memcpy(h->x0, x, (size_t)na * sizeof *x);
        memcpy(h->w0, dw, (size_t)ns * sizeof *dw);
        /* dz = S2^-1 (Kbar^-1 P_S r)_A: H'K^-1H r on base DOFs, r itself on new ones */
        for (int64_t aq = 0; aq < na; aq++) {
            int32_t p = s->A[aq];
            if (c->S[p] >= c->nb) {
                h->rh[aq] = h->r[p];
                continue;
            }
            const double *Gp = M->G + (int64_t)M->cpos[p] * M->mcap;
            double v = 0;
            for (int64_t j = 0; j < M->m; j++) v += Gp[j] * h->r[M->col[j]];
            h->rh[aq] = v;
        }
        if (lo_times(a, b, c, h->r, h->rh)) {
            rc = -1;
            break;
        }
        pivot_solve(a, c, h->rh, h->r, h->ew); /* ew = r + Ebar dz */
        for (int64_t aq = 0; aq < na; aq++) x[aq] += h->rh[aq];
        for (int64_t p = 0; p < ns; p++) dw[p] += h->ew[p];
        /* the increment's field over Q (deferred: over C), on the pattern added to xt */
        if (defer) {
            if (v_times(a, b, c, h->ew, NULL, 0, h->ydf, a->t2)) {
                rc = -1;
                break;
            }
            for (int64_t t = 0; t < nc; t++) yd[h->cset[t]] = h->ydf[h->cset[t]];
            aug_ldl_ltsolve_closure_super(b, h->cset, nc, yd, a->t2);
        } else if (field(a, b, c, h->ew, Q, a->nq, yd, cm)) {
            rc = -2;
            break;
        }
        for (int64_t t = 0; t < np; t++)
            if (h->pat[t] < c->nb) h->xt[h->pat[t]] += yd[b->pinv[h->pat[t]]];
        a->ncorrect++;
    }
    a->t_correct += now_ms() - tc;
    if (defer && !rc && aug_par_ltsolve_rest(a->par, b, h->pre, h->yf, y)) /* the rest of L' once */
        return -1;
    if (!rc && !Q) field_norms(a, b, c, y, fnorm);
    return rc;
}

/* A reference field (issue 15 item 1). AMPS's field is [a_b; 0] +
   Kbar^-1 P_S w (eq. 3.20): the rows outside S carry the rounding of a_b and
   of the back-substitution of w's field y, each the size of the base's
   solution. Where a cut undoes much of the base's displacement (a limb cut
   loose, a heavy piece dropped) x_t is far smaller than both and the two
   cancel (field_norms, cancel): the relres then stays at the size of a_b's
   rounding, not x_t's, and the gate of solver.c measures it and refines,
   a full solve on every later step (the soft armadillo, oblique plane, 64
   one-node steps: 30 refined, cancel up to 44). Once a step was refined,
   its field xref satisfies every row to a fresh solve's rounding at the size
   of x_t; the later steps on the base take x_t = xref + delta, K_t delta =
   r = f_t - K_t xref. r lives on the rows of S (outside them K_t and f_t are
   those of the base, which xref satisfies), so delta is AMPS's solution
   with the load r on S and no base part (a_b of a zero load is 0): the same
   S2, memo and back-substitution, now of delta, whose rounding scales with
   the step's change, not with a_b. The correction on H then works on
   delta's residual as on any step's. */
static int ref_setup(aug_amps *a, const aug_base *b, const aug_cum *c)
{
    a->ref_used = 0;
    a->ab_cur = b->a, a->dF_cur = c->dF, a->xnew_cur = NULL;
    if (!a->xref || a->xref_b != (const void *)b || !a->kt || a->nref > c->n || a->nref < c->nb) return 0;
    if (a->refcap < c->n) { /* the DOFs added since the reference take 0 */
        double *x = aug_realloc(a->xref, (size_t)c->n * sizeof *x);
        if (!x) return -1;
        a->xref = x, a->refcap = c->n;
    }
    for (; a->nref < c->n; a->nref++) a->xref[a->nref] = 0;
    if (a->rrcap < c->ns + 1) {
        free(a->rref), free(a->kref);
        a->rref = aug_malloc((size_t)(c->ns + 1) * sizeof *a->rref);
        a->kref = aug_malloc((size_t)(c->ns + 1) * sizeof *a->kref);
        a->rrcap = a->rref && a->kref ? c->ns + 1 : 0;
        if (!a->rrcap) return -1;
    }
    aug_cutmat_rows_residual(a->kt, c->S, c->ns, a->xref, a->rref, a->kref);
    /* a kept block's unit row is not solved through the base (solver.c
       keep_blocks): its value stays xref's (unit_rows sets it anyway) */
    for (int64_t p = 0; p < c->ns; p++)
        if (c->keep[p]) a->rref[p] = 0;
    a->ab_cur = a->xref, a->dF_cur = a->rref, a->xnew_cur = a->xref;
    a->ref_used = 1;
    return 0;
}

int aug_amps_set_ref(aug_amps *a, const aug_base *b, const double *x, int64_t n, int32_t step)
{
    if (a->refcap < n) {
        free(a->xref);
        a->xref = aug_malloc((size_t)(n > 0 ? n : 1) * sizeof *a->xref);
        a->refcap = a->xref ? n : 0;
        if (!a->xref) {
            a->nref = 0, a->xref_b = NULL;
            return -1;
        }
    }
    memcpy(a->xref, x, (size_t)n * sizeof *x);
    a->nref = n, a->xref_b = b, a->xref_step = step;
    return 0;
}

/* the step's pivot: S2 or ALT as asked; AUTO keeps the last one used unless
   its backward error on H before correction (berr_h0) exceeded 16 BERR_OK
   and the other pivot's, when it was last used, was lower (never used: taken
   as 0, so it is tried once) */
static int pivot_choice(const aug_amps *a)
{
    if (a->pivot != AUG_PIVOT_AUTO) return a->pivot == AUG_PIVOT_ALT ? AUG_PIVOT_ALT : AUG_PIVOT_S2;
    int p = a->pivot_used == AUG_PIVOT_ALT ? AUG_PIVOT_ALT : AUG_PIVOT_S2;
    double bp = a->berr_piv[p], bo = a->berr_piv[1 - p];
    return bp > 16 * BERR_OK && bo < bp ? 1 - p : p;
}

/* One AMPS step (paper 001 table 1 steps 1-6): V, H'K^-1H and S2 brought up to
   date; a2 = S2^-1 rhs, rhs = H'a_b + H'K^-1H dF_H on base positions, dF on new
   ones (eq. 3.10 with f_t = [f_b; 0] + P_S dF); then eq. 3.20: new DOFs of A take
   a2, every other DOF (base DOFs of A too) [a_b; 0] + Kbar^-1 P_S (dF + Ebar a2),
   through one L^-T over the closure of out (all of L when out is NULL). */
/* the per-step part of AMPS (paper 001 table 1 steps 1-3 and 5): the V
   columns of the new base DOFs of S, H'K^-1H grown, S2 factored */
int aug_amps_prepare(aug_amps *a, const aug_base *b, const aug_cum *c, double rcond_min,
                     double times[3], cholmod_common *cm, aug_err *e)
{
    double t0 = now_ms();
    a->pivot_used = pivot_choice(a);
    if (scratch(a, b, c)) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    a->memo.all = a->field_memo; /* its V w needs every column */
    int rc = aug_memo_reach(&a->memo, b, c, a->par, cm, e);
    double t1 = now_ms();
    if (!rc) rc = aug_memo_grow(&a->memo, b, a->par, e);
    double t2 = now_ms();
    if (!rc) rc = aug_schur_factor(&a->schur, &a->memo, c, rcond_min, e);
    times[0] = t1 - t0, times[1] = t2 - t1, times[2] = now_ms() - t2;
    return rc;
}

int aug_amps_step(aug_amps *a, const aug_base *b, const aug_cum *c, const int32_t *out,
                  int64_t nout, double rcond_min, double *u, double times[4],
                  cholmod_common *cm, aug_err *e)
{
    int rc = aug_amps_prepare(a, b, c, rcond_min, times, cm, e);
    double t3 = now_ms();
    times[3] = 0;
    if (rc || a->schur.singular) return rc;
    rc = aug_amps_field(a, b, c, out, nout, u, cm, e);
    times[3] = now_ms() - t3;
    return rc;
}

/* steps 4-6 of aug_amps_step on the prepared S2 and memo: the solution of
   the step (eqs. 3.20-3.21) with its correction on H, over out or (NULL)
   every DOF */
int aug_amps_field(aug_amps *a, const aug_base *b, const aug_cum *c, const int32_t *out,
                   int64_t nout, double *u, cholmod_common *cm, aug_err *e)
{
    const aug_memo *M = &a->memo;
    const aug_schur *s = &a->schur;
    double *x = a->x, *wp = a->w, *y = a->y;
    if (ref_setup(a, b, c)) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    const double *dF = a->dF_cur, *ab = a->ab_cur, *xn = a->xnew_cur;
    /* rhs (eq. 3.21 with f_t = [f_b; 0] + P_S dF): on base DOFs
       H'a_b + H'K^-1H dF_H, on new DOFs dF (from a reference field: f_t =
       0 + P_S r, r = f_t - K_t xref, so no H'a_b) */
    for (int64_t aq = 0; aq < s->na; aq++) {
        int32_t p = s->A[aq];
        if (c->S[p] >= c->nb) {
            x[aq] = dF[p];
            continue;
        }
        const double *Gp = M->G + (int64_t)M->cpos[p] * M->mcap;
        double v = a->ref_used ? 0 : b->a[c->S[p]];
        for (int64_t j = 0; j < M->m; j++) v += Gp[j] * dF[M->col[j]];
        x[aq] = v;
    }
    if (lo_times(a, b, c, dF, x)) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    /* a2 = S2^-1 rhs (or eqs. 3.16-3.17's pivot), wp = dF + Ebar a2;
       eq. 3.20: a = a_b + K^-1 H wp off A */
    pivot_solve(a, c, x, dF, wp);
    double *dw = a->w + a->xcap; /* the correction's sum of w increments */
    int fc = field_corrected(a, b, c, out, nout, x, wp, dw, cm);
    if (fc == -1) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    if (fc) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "supernodal solve failed (%d)", cm->status);
    if (!isnan(a->berr_h0)) a->berr_piv[a->pivot_used] = a->berr_h0;
    int64_t cnt = out ? nout : c->n;
    for (int64_t t = 0; t < cnt; t++) {
        int64_t i = out ? out[t] : t;
        int32_t p = c->pos[i];
        /* a base DOF of A too takes its value from the back-substitution, not
           from a2: the rows of K_t across the cut then see one consistent
           field (a2 and the back-substituted value differ by the rounding of
           H'K^-1H, amplified by ||K||) */
        if (i < c->nb) u[i] = ab[i] + y[b->pinv[i]];
        else if (!s->act[p]) u[i] = (xn ? xn[i] : 0) + dF[p] + dw[p];
    }
    for (int64_t aq = 0; aq < s->na; aq++) {
        int64_t i = c->S[s->A[aq]];
        if (i >= c->nb) u[i] = (xn ? xn[i] : 0) + x[aq];
    }
    unit_rows(a, c, out, nout, NULL, u);
    a->closure_v = 0;
    for (int64_t j = 0; j < M->m; j++)
        if (M->vp[j + 1] > M->vp[j]) {
            /* |closure of H in L| = |union of the V paths| */
            for (int64_t t = M->vp[j]; t < M->vp[j + 1]; t++) {
                if (a->mark[M->vi[t]]) break;
                a->mark[M->vi[t]] = 1;
                a->closure_v++;
            }
        }
    for (int64_t j = 0; j < M->m; j++)
        for (int64_t t = M->vp[j]; t < M->vp[j + 1] && a->mark[M->vi[t]]; t++) a->mark[M->vi[t]] = 0;
    return 0;
}

/* x = K_t^-1 r by eqs. 3.8 and 3.20 with a general right-hand side (iterative
   refinement). z = D^-1 L^-1 P r once (through the supernodes when the base has
   them); Kbar^-1 r is needed on A only for the right-hand side of S2, so
   L^-T runs there over the closure of A in L' (the top of the tree); the
   correction K^-1 H Ebar a2 joins z before the one full back-substitution:
   one full solve and a little, not two. */
int aug_amps_solve_general(aug_amps *a, const aug_base *b, const aug_cum *c,
                           const double *r, double *x, cholmod_common *cm, aug_err *e)
{
    if (scratch(a, b, c)) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    const aug_schur *s = &a->schur;
    double *xa = a->x, *wp = a->w, *z = a->t2, *y = a->y;
    for (int64_t k = 0; k < b->n; k++) z[k] = r[b->perm[k]];
    if (a->par && b->Ls && b->par_plan) { /* Ls^-1 P r on two cores, then D^-1/2 */
        if (aug_par_super_solve(a->par, b->par_plan, b->Ls, AUG_PAR_L, z))
            return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
        for (int64_t k = 0; k < b->n; k++) z[k] /= b->sqrtd[k];
    } else if (b->Ls) {
        cholmod_dense B = {0};
        B.nrow = B.d = B.nzmax = (size_t)b->n, B.ncol = 1;
        B.x = z, B.xtype = CHOLMOD_REAL, B.dtype = CHOLMOD_DOUBLE;
        if (!cholmod_solve2(CHOLMOD_L, b->Ls, &B, NULL, &a->X, NULL, &a->Yw, &a->Ew, cm))
            return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "supernodal solve failed (%d)", cm->status);
        const double *u = a->X->x; /* Ls^-1 P r, and D^-1 L^-1 = D^-1/2 Ls^-1 */
        for (int64_t k = 0; k < b->n; k++) z[k] = u[k] / b->sqrtd[k];
    } else {
        aug_ldl_lsolve(b, NULL, 0, z);
        aug_ldl_dsolve(b, NULL, 0, z);
    }
    /* H'Kbar^-1 r: base positions of A from L^-T over the closure of A */
    int64_t k = 0;
    for (int64_t aq = 0; aq < s->na; aq++)
        if (c->S[s->A[aq]] < c->nb) a->q[k++] = b->pinv[c->S[s->A[aq]]];
    int64_t nca = aug_ldl_closure(b, a->q, k, a->ca, a->mark);
    for (int64_t t = 0; t < nca; t++) y[a->ca[t]] = z[a->ca[t]];
    aug_ldl_ltsolve_closure_super(b, a->ca, nca, y, x); /* x: scratch until the end */
    for (int64_t aq = 0; aq < s->na; aq++) {
        int32_t i = c->S[s->A[aq]];
        xa[aq] = i < c->nb ? y[b->pinv[i]] : r[i];
    }
    /* a2 = S2^-1 Hbar'Kbar^-1 r; x = Kbar^-1 (r + Hbar Ebar a2) */
    pivot_solve(a, c, xa, NULL, wp);
    if (v_times(a, b, c, wp, NULL, 0, y, x)) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    for (int64_t t = 0; t < b->n; t++) y[t] += z[t];
    int prc = aug_par_ltsolve_all(a->par, b, y);
    if (prc < 0 || (prc > 0 && aug_ldl_ltsolve_all(b, y, &a->X, &a->Yw, &a->Ew, cm)))
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "supernodal solve failed (%d)", cm->status);
    for (int64_t i = 0; i < c->nb; i++) x[i] = y[b->pinv[i]];
    for (int64_t i = c->nb; i < c->n; i++) x[i] = r[i];
    for (int64_t p = 0; p < c->ns; p++)
        if (c->S[p] >= c->nb) x[c->S[p]] += wp[p];
    /* S2's pivot: new DOFs of A take a2; ALT's w there (eq. 3.17) came
       without r (pivot_solve's f is NULL: r is in z on base positions), so
       they keep r + w from the loop above */
    if (a->pivot_used != AUG_PIVOT_ALT)
        for (int64_t aq = 0; aq < s->na; aq++)
            if (c->S[s->A[aq]] >= c->nb) x[c->S[s->A[aq]]] = xa[aq];
    unit_rows(a, c, NULL, 0, r, x);
    return 0;
}
