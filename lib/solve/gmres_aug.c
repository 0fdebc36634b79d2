/* The unsymmetric augmented method of paper 000: GMRES on the implicit Schur
   complement H R^-1 J (eq. 17) with sparse closures in solution steps 1-3
   (sec. 3.3), D and tridiagonal SPAI preconditioners (sec. 3.5). */
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

struct aug_gmres {
    int prec, restart, maxit;
    double tol;
    int iters, converged;
    int stalled;         /* the last gmres() run stopped on the stall guard */
    int whole;           /* the last step's output set: 1 the whole field
                            was computed (its round stalled, or no Schur
                            tolerance learnt yet), 0 its values only; -1
                            no output set */
    double sscale;       /* Schur tolerance / tol of the last solve whose
                            whole field met tol (round_done); 0: none yet */
    double *spai;        /* tridiagonal S ~ K_0^-1: column j holds S(j-1,j), S(j,j), S(j+1,j) */
    int64_t nspai;
    /* per step */
    int64_t ns, n;
    int64_t *Jp;
    int32_t *Ji;
    double *Jx;
    int64_t jcap;
    int32_t *rows;       /* struct(J), ascending */
    int64_t nrows;
    int32_t *c1, *c2, *c12;
    int64_t n1, n2, n12;
    double *sig;         /* per position p of S: Kbar's diagonal on a new DOF,
                            |K_t(q,q)| (1 if 0), 1 on a base DOF (setup) */
    double *M;           /* preconditioner H'SJ, LU */
    int *ipiv;
    int prec_ok;
    double *b, *y;       /* n_t and n_b scratch */
    unsigned char *mark;
};

aug_gmres *aug_gmres_new(int prec, int restart, int maxit, double tol, aug_err *e)
{
    aug_gmres *g = aug_calloc(1, sizeof *g);
    if (!g) {
        aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        return NULL;
    }
    g->prec = prec, g->restart = restart > 0 ? restart : 50, g->maxit = maxit, g->tol = tol;
    return g;
}

static void free_step(aug_gmres *g)
{
    free(g->Jp), free(g->Ji), free(g->Jx), free(g->rows), free(g->c1), free(g->c2), free(g->c12);
    free(g->M), free(g->ipiv), free(g->b), free(g->y), free(g->mark), free(g->sig);
    g->sig = NULL;
    g->Jp = NULL, g->Ji = NULL, g->Jx = NULL, g->rows = NULL, g->c1 = g->c2 = g->c12 = NULL;
    g->M = NULL, g->ipiv = NULL, g->b = g->y = NULL, g->mark = NULL, g->jcap = 0;
}

void aug_gmres_free(aug_gmres *g)
{
    if (!g) return;
    free_step(g);
    free(g->spai);
    free(g);
}

int aug_gmres_iters(const aug_gmres *g) { return g->iters; }
int aug_gmres_converged(const aug_gmres *g) { return g->converged; }
int aug_gmres_whole(const aug_gmres *g) { return g->whole; }
int64_t aug_gmres_closure_j(const aug_gmres *g) { return g->n1; }
int64_t aug_gmres_closure_h(const aug_gmres *g) { return g->n2; }

/* K(:,a)' K(:,b) of a K stored with both triangles, columns sorted */
static double dot_cols(const cholmod_sparse *K, int64_t a, int64_t b)
{
    const int *Kp = K->p, *Ki = K->i;
    const double *Kx = K->x;
    int p = Kp[a], q = Kp[b];
    double s = 0;
    while (p < Kp[a + 1] && q < Kp[b + 1]) {
        if (Ki[p] < Ki[q]) p++;
        else if (Ki[p] > Ki[q]) q++;
        else s += Kx[p++] * Kx[q++];
    }
    return s;
}

/* K(i, j), 0 when not stored */
static double entry(const cholmod_sparse *K, int64_t i, int64_t j)
{
    const int *Kp = K->p, *Ki = K->i;
    for (int k = Kp[j]; k < Kp[j + 1]; k++)
        if (Ki[k] == i) return ((const double *)K->x)[k];
    return 0;
}

/* column j of S minimizes ||K S(:,j) - e_j||_2 over rows {j-1, j, j+1}: the 3x3
   (or 2x2) normal equations (paper 000 sec. 3.5, [Benson-Frederickson 1982]),
   S(j,j) = 1/K(j,j) alone when they are singular; K with both triangles */
int aug_gmres_set_base(aug_gmres *g, const aug_base *b, const cholmod_sparse *K, aug_err *e)
{
    (void)b;
    if (g->prec != AUG_PREC_SPAI || g->spai) return 0;
    int64_t n = (int64_t)K->ncol;
    g->spai = aug_calloc((size_t)(3 * n + 3), sizeof *g->spai);
    if (!g->spai) return aug_err_set(e, AUG_ENOMEM, -1, "KMAT", "out of memory (SPAI)");
    g->nspai = n;
    for (int64_t j = 0; j < n; j++) {
        int64_t c[3], k = 0;
        for (int64_t d = -1; d <= 1; d++)
            if (j + d >= 0 && j + d < n) c[k++] = j + d;
        double C[9], r[3];
        for (int64_t p = 0; p < k; p++) {
            r[p] = entry(K, j, c[p]);
            for (int64_t q = 0; q < k; q++) C[p + 3 * q] = dot_cols(K, c[p], c[q]);
        }
        lapack_int ipv[3];
        if (LAPACKE_dgesv(LAPACK_COL_MAJOR, (lapack_int)k, 1, C, 3, ipv, r, 3) != 0) {
            for (int64_t p = 0; p < k; p++) r[p] = c[p] == j ? 1.0 / entry(K, j, j) : 0;
        }
        for (int64_t p = 0; p < k; p++) g->spai[j * 3 + (c[p] - j + 1)] = r[p];
    }
    return 0;
}

/* S(r, i) of the S ~ Kbar^-1 in the preconditioner H'SJ (paper 000 sec. 3.5):
   D^-1 of P K_b P' = L D L' at i's permuted position (1 on new DOFs), or the
   tridiagonal SPAI (identity beyond K_b) */
static double sapprox(const aug_gmres *g, const aug_base *b, int64_t r, int64_t i)
{
    if (g->prec == AUG_PREC_D) return r == i ? (i < b->n ? 1.0 / aug_base_d(b, b->pinv[i]) : 1.0) : 0;
    if (i >= g->nspai || r >= g->nspai) return r == i;
    return g->spai[i * 3 + (r - i + 1)];
}

/* out = H' Kbar^-1 J v (paper 000 eq. 20): forward over closure(J), backward over
   closure(H); on new DOFs Kbar^-1 = 1 / sig (setup) */
static void apply_a(aug_gmres *g, const aug_base *b, const aug_cum *c, const double *v, double *out)
{
    double *bb = g->b, *y = g->y;
    for (int64_t t = 0; t < g->nrows; t++) bb[g->rows[t]] = 0;
    for (int64_t p = 0; p < g->ns; p++)
        for (int64_t k = g->Jp[p]; k < g->Jp[p + 1]; k++) bb[g->Ji[k]] += g->Jx[k] * v[p];
    for (int64_t t = 0; t < g->n12; t++) y[g->c12[t]] = 0;
    for (int64_t t = 0; t < g->nrows; t++)
        if (g->rows[t] < c->nb) y[b->pinv[g->rows[t]]] = bb[g->rows[t]];
    aug_ldl_lsolve(b, g->c1, g->n1, y);
    aug_ldl_dsolve(b, g->c1, g->n1, y);
    aug_ldl_ltsolve(b, g->c2, g->n2, y);
    for (int64_t p = 0; p < g->ns; p++) {
        int32_t i = c->S[p];
        out[p] = i < c->nb ? y[b->pinv[i]] : bb[i] / g->sig[p];
    }
}

/* v := (H'SJ)^-1 v by the LU of setup (nothing without a preconditioner) */
static int prec_solve(const aug_gmres *g, double *v)
{
    if (g->prec == AUG_PREC_NONE || !g->prec_ok) return 0;
    return LAPACKE_dgetrs(LAPACK_COL_MAJOR, 'N', (lapack_int)g->ns, 1, g->M, (lapack_int)g->ns,
                          g->ipiv, v, (lapack_int)g->ns);
}

/* merge two ascending lists */
static int64_t merge(const int32_t *a, int64_t na, const int32_t *bl, int64_t nb, int32_t *out)
{
    int64_t i = 0, j = 0, k = 0;
    while (i < na || j < nb) {
        if (j >= nb || (i < na && a[i] < bl[j])) out[k++] = a[i++];
        else if (i >= na || bl[j] < a[i]) out[k++] = bl[j++];
        else out[k++] = a[i++], j++;
    }
    return k;
}

/* J = K_t Hbar (paper 000 eqs. 4-6; paper 001 eq. 3.37), struct(J), closure(J)
   and closure(H) (paper 000 sec. 3.3.1, thm 3), and the preconditioner H'SJ
   LU-factored densely (sec. 3.5) */
static int setup(aug_gmres *g, const aug_base *b, const aug_cum *c, const aug_cutmat *m, aug_err *e)
{
    free_step(g);
    int64_t ns = c->ns, n = c->n, cmax = aug_cutmat_colmax(m);
    g->ns = ns, g->n = n;
    g->Jp = aug_malloc((size_t)(ns + 1) * sizeof *g->Jp);
    g->jcap = ns * 64 + cmax;
    g->Ji = aug_malloc((size_t)g->jcap * sizeof *g->Ji);
    g->Jx = aug_malloc((size_t)g->jcap * sizeof *g->Jx);
    g->b = aug_calloc((size_t)n + 1, sizeof *g->b);
    g->y = aug_calloc((size_t)b->n + 1, sizeof *g->y);
    g->mark = aug_calloc((size_t)(n > b->n ? n : b->n) + 1, 1);
    g->rows = aug_malloc((size_t)n * sizeof *g->rows);
    g->c1 = aug_malloc((size_t)b->n * sizeof *g->c1 + 4);
    g->c2 = aug_malloc((size_t)b->n * sizeof *g->c2 + 4);
    g->c12 = aug_malloc((size_t)b->n * sizeof *g->c12 + 4);
    int32_t *idx = aug_malloc((size_t)cmax * sizeof *idx);
    double *val = aug_malloc((size_t)cmax * sizeof *val);
    if (!g->Jp || !g->Ji || !g->Jx || !g->b || !g->y || !g->mark || !g->rows || !g->c1 || !g->c2 ||
        !g->c12 || !idx || !val)
        goto nomem;
    g->Jp[0] = 0;
    for (int64_t p = 0; p < ns; p++) {
        int64_t nz = aug_cutmat_column(m, c->S[p], idx, val, g->b);
        if (g->Jp[p] + nz > g->jcap) {
            g->jcap = 2 * (g->Jp[p] + nz);
            int32_t *Ji = aug_realloc(g->Ji, (size_t)g->jcap * sizeof *Ji);
            double *Jx = Ji ? aug_realloc(g->Jx, (size_t)g->jcap * sizeof *Jx) : NULL;
            if (Ji) g->Ji = Ji;
            if (!Jx) goto nomem;
            g->Jx = Jx;
        }
        memcpy(g->Ji + g->Jp[p], idx, (size_t)nz * sizeof *idx);
        memcpy(g->Jx + g->Jp[p], val, (size_t)nz * sizeof *val);
        g->Jp[p + 1] = g->Jp[p] + nz;
    }
    /* Kbar = blkdiag(K_b, Sigma), sigma_q = |K_t(q,q)| on the new DOFs (all
       of them in S: any block there keeps K_t = Kbar off S), not the I of
       paper 000: with I the Schur system's rows of new DOFs are K_t's scale
       (E times the element size) against O(1) for the base rows, and GMRES,
       not invariant under row scaling, failed once E was in pascals (the
       brick at E = 1e9: relres 1.5 after 3 iterations, converged at 1e6;
       as amps_schur.c new_scale) */
    g->sig = aug_malloc((size_t)(ns + 1) * sizeof *g->sig);
    if (!g->sig) goto nomem;
    for (int64_t p = 0; p < ns; p++) {
        g->sig[p] = 1;
        if (c->S[p] < c->nb) continue;
        for (int64_t t = g->Jp[p]; t < g->Jp[p + 1]; t++)
            if (g->Ji[t] == c->S[p] && g->Jx[t] != 0) g->sig[p] = fabs(g->Jx[t]);
    }
    /* struct(J) and the closures (paper 000 sec. 3.3) */
    g->nrows = 0;
    for (int64_t k = 0; k < g->Jp[ns]; k++)
        if (!g->mark[g->Ji[k]]) g->mark[g->Ji[k]] = 1, g->rows[g->nrows++] = g->Ji[k];
    for (int64_t t = 0; t < g->nrows; t++) g->mark[g->rows[t]] = 0;
    int32_t *st = aug_malloc((size_t)(g->nrows + ns + 1) * sizeof *st);
    if (!st) goto nomem;
    int64_t k = 0;
    for (int64_t t = 0; t < g->nrows; t++)
        if (g->rows[t] < c->nb) st[k++] = b->pinv[g->rows[t]];
    g->n1 = aug_ldl_closure(b, st, k, g->c1, g->mark);
    k = 0;
    for (int64_t p = 0; p < ns; p++)
        if (c->S[p] < c->nb) st[k++] = b->pinv[c->S[p]];
    g->n2 = aug_ldl_closure(b, st, k, g->c2, g->mark);
    free(st);
    g->n12 = merge(g->c1, g->n1, g->c2, g->n2, g->c12);
    /* preconditioner H' S J (sec. 3.5), dense LU */
    g->prec_ok = 0;
    if (g->prec != AUG_PREC_NONE && ns > 0) {
        g->M = aug_calloc((size_t)(ns * ns), sizeof *g->M);
        g->ipiv = aug_malloc((size_t)ns * sizeof *g->ipiv);
        if (!g->M || !g->ipiv) goto nomem;
        for (int64_t bq = 0; bq < ns; bq++)
            for (int64_t t = g->Jp[bq]; t < g->Jp[bq + 1]; t++) {
                int64_t i = g->Ji[t];
                for (int64_t d = -1; d <= 1; d++) {
                    int64_t r = i + d;
                    if (r < 0 || r >= c->n || r >= c->pcap || c->pos[r] < 0) continue;
                    double s = i < c->nb ? sapprox(g, b, r, i) : r == i ? 1.0 / g->sig[c->pos[i]] : 0;
                    if (s != 0) g->M[c->pos[r] + bq * ns] += s * g->Jx[t];
                }
            }
        g->prec_ok = LAPACKE_dgetrf(LAPACK_COL_MAJOR, (lapack_int)ns, (lapack_int)ns, g->M,
                                    (lapack_int)ns, g->ipiv) == 0;
    }
    free(idx), free(val);
    return 0;
nomem:
    free(idx), free(val);
    return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (gmres)");
}

static double nrm2(const double *v, int64_t n)
{
    double s = 0;
    for (int64_t i = 0; i < n; i++) s += v[i] * v[i];
    return sqrt(s);
}

/* restarted GMRES(restart) with right preconditioning, modified Gram-Schmidt and
   Givens rotations ([Saad] ch. 6, 9) on A x = rhs, A = H'Kbar^-1J (apply_a), from
   x (warm) or from 0; each cycle ends at the estimate |s_j+1| <= tol ||rhs||, and
   converged is set on the true residual ||rhs - A x|| <= tol ||rhs|| after a
   cycle; at most g->maxit iterations in all (g->iters accumulates). A
   guarded run (guard: a warm round at a tighter tolerance, round_done, or
   an output set's round at the learnt Schur tolerance) also stops, not
   converged (g->stalled), after
   three cycles in a row that each lower the true residual by less than 1%:
   the tolerance is then below what the rounding of A x allows, and the
   iterations up to maxit would buy nothing (sphere3, 8-node step: 10,000
   iterations in 15.7 s ending at a worse K_t residual than 300; one such
   cycle alone is no sign: the next may gain) */
static int gmres(aug_gmres *g, const aug_base *b, const aug_cum *c, const double *rhs, double *x,
                 double tol, int warm, int guard)
{
    int64_t n = g->ns;
    int mr = g->restart;
    double *V = aug_malloc((size_t)(n * (mr + 1) + 1) * sizeof *V);
    double *H = aug_calloc((size_t)((mr + 1) * mr + 1), sizeof *H);
    double *cs = aug_malloc((size_t)(3 * mr + 3) * sizeof *cs), *sn = cs + mr + 1, *s = sn + mr + 1;
    double *w = aug_malloc((size_t)(2 * n + 1) * sizeof *w), *z = w + n;
    if (!V || !H || !cs || !w) {
        free(V), free(H), free(cs), free(w);
        return -1;
    }
    double bn = nrm2(rhs, n);
    if (bn == 0) bn = 1;
    g->converged = g->stalled = 0;
    if (warm) {
        apply_a(g, b, c, x, w);
        for (int64_t k = 0; k < n; k++) w[k] = rhs[k] - w[k];
    } else {
        for (int64_t i = 0; i < n; i++) x[i] = 0;
        memcpy(w, rhs, (size_t)n * sizeof *w);
    }
    double beta = nrm2(w, n);
    if (beta <= tol * bn) g->converged = 1;
    int stall = 0;
    while (!g->converged && g->iters < g->maxit) {
        double beta0 = beta;
        for (int64_t i = 0; i < n; i++) V[i] = w[i] / beta;
        memset(s, 0, (size_t)(mr + 1) * sizeof *s);
        s[0] = beta;
        int j = 0;
        for (; j < mr && g->iters < g->maxit; j++) {
            memcpy(z, V + j * n, (size_t)n * sizeof *z);
            prec_solve(g, z);
            double *vj1 = V + (j + 1) * n;
            apply_a(g, b, c, z, vj1);
            for (int i = 0; i <= j; i++) { /* modified Gram-Schmidt */
                double h = 0;
                for (int64_t k = 0; k < n; k++) h += vj1[k] * V[i * n + k];
                H[i + j * (mr + 1)] = h;
                for (int64_t k = 0; k < n; k++) vj1[k] -= h * V[i * n + k];
            }
            double hn = nrm2(vj1, n);
            H[j + 1 + j * (mr + 1)] = hn;
            if (hn > 0)
                for (int64_t k = 0; k < n; k++) vj1[k] /= hn;
            for (int i = 0; i < j; i++) {
                double *h0 = H + i + j * (mr + 1), t = cs[i] * h0[0] + sn[i] * h0[1];
                h0[1] = -sn[i] * h0[0] + cs[i] * h0[1];
                h0[0] = t;
            }
            double *hj = H + j + j * (mr + 1), den = hypot(hj[0], hj[1]);
            cs[j] = den > 0 ? hj[0] / den : 1, sn[j] = den > 0 ? hj[1] / den : 0;
            hj[0] = den, hj[1] = 0;
            s[j + 1] = -sn[j] * s[j];
            s[j] = cs[j] * s[j];
            g->iters++;
            if (fabs(s[j + 1]) <= tol * bn || hn == 0) {
                j++;
                break;
            }
        }
        /* x += M^-1 V y, H y = s */
        for (int i = j - 1; i >= 0; i--) {
            double t = s[i];
            for (int k = i + 1; k < j; k++) t -= H[i + k * (mr + 1)] * s[k];
            s[i] = H[i + i * (mr + 1)] != 0 ? t / H[i + i * (mr + 1)] : 0;
        }
        memset(z, 0, (size_t)n * sizeof *z);
        for (int i = 0; i < j; i++)
            for (int64_t k = 0; k < n; k++) z[k] += s[i] * V[i * n + k];
        prec_solve(g, z);
        for (int64_t k = 0; k < n; k++) x[k] += z[k];
        apply_a(g, b, c, x, w);
        for (int64_t k = 0; k < n; k++) w[k] = rhs[k] - w[k];
        beta = nrm2(w, n);
        if (beta <= tol * bn) g->converged = 1;
        stall = guard && !g->converged && beta > 0.99 * beta0 ? stall + 1 : 0;
        if (beta == 0 || stall == 3) {
            g->stalled = stall == 3;
            break;
        }
    }
    free(V), free(H), free(cs), free(w);
    return 0;
}

/* y (permuted) = D^-1 L^-1 P g over the merged closure; g over K_t indices
   (only base DOFs are read) */
static void forward_c12(aug_gmres *g, const aug_base *b)
{
    aug_ldl_lsolve(b, g->c12, g->n12, g->y);
    aug_ldl_dsolve(b, g->c12, g->n12, g->y);
}

/* After a round of GMRES at the Schur tolerance *stol whose field has K_t's
   relative residual rr: 1 to stop (converged: rr <= tol, whatever the
   round's own test said), 0 to go on warm with *stol times 0.5 tol / rr.
   The Schur system's residual maps back to K_t through K (a factor up to
   cond(K)), so --tol, a residual of K_t as for pcg, needs a tighter Schur
   tolerance (paper 000 sec. 3.2 stops on the Schur residual). A round that
   ran out of iterations or stagnated (gmres) ends it; so do 9 rounds or a
   tolerance below 1e-15. */
static int round_done(aug_gmres *g, double rr, double *stol, int outer)
{
    if (rr <= g->tol) {
        g->converged = 1;
        g->sscale = *stol / g->tol;
        return 1;
    }
    if (!g->converged || !(rr < INFINITY)) return g->converged = 0, 1;
    *stol *= 0.5 * g->tol / rr;
    if (*stol < 1e-15 || outer == 8) return g->converged = 0, 1;
    return 0;
}

/* One step of paper 000 sec. 3.2: setup; solution step 1 rhs = H'Kbar^-1 f_t =
   H'a_b + H'K^-1 P_S dF over closure(H) (eqs. 17-18); step 2 GMRES on eq. 17;
   step 3 a1 = [a_b; 0] + Kbar^-1 (P_S dF - J a2) (eq. 16) over the closure of out
   (all of L when out is NULL), a2 on S (eq. 9). Whole-field solves resume steps
   2-3 warm until relres(K_t) <= tol (round_done), else converged = 0. An
   output set, whose K_t residual would need the whole field, takes one
   round at the Schur tolerance that last met tol on a whole field (its
   rest, solver.c fill_rest, is one: aug_gmres_solve_general); until one
   has, the step solves the whole field. */
int aug_gmres_step(aug_gmres *g, const aug_base *b, const aug_cum *c, aug_cutmat *m,
                   const int32_t *out, int64_t nout, double *u, double times[4], aug_err *e)
{
    double t0 = 1e3 * aug_now();
    int asked = out != NULL;
    if (out && !(g->sscale > 0)) out = NULL, nout = 0;
    if (setup(g, b, c, m, e)) return e->code;
    double t1 = 1e3 * aug_now();
    int64_t ns = c->ns;
    double *rhs = aug_malloc((size_t)(2 * ns + 1) * sizeof *rhs), *a2 = rhs + ns;
    if (!rhs) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    /* solution step 1: H'Kbar^-1 f_t = H'a_b + H'K^-1 P_S dF (closure of H) */
    double *y = g->y;
    for (int64_t t = 0; t < g->n12; t++) y[g->c12[t]] = 0;
    for (int64_t p = 0; p < ns; p++)
        if (c->S[p] < c->nb) y[b->pinv[c->S[p]]] = c->dF[p];
    aug_ldl_lsolve(b, g->c2, g->n2, y);
    aug_ldl_dsolve(b, g->c2, g->n2, y);
    aug_ldl_ltsolve(b, g->c2, g->n2, y);
    for (int64_t p = 0; p < ns; p++) {
        int32_t i = c->S[p];
        rhs[p] = i < c->nb ? b->a[i] + y[b->pinv[i]] : c->dF[p] / g->sig[p];
    }
    double t2 = 1e3 * aug_now(), t3 = t2, ts = 0, stol = g->tol * (out ? g->sscale : 1);
    g->iters = 0;
    for (int outer = 0;; outer++) {
    /* solution step 2: GMRES on eq. 17 */
    double tg = 1e3 * aug_now();
    if (gmres(g, b, c, rhs, a2, stol, outer > 0, outer > 0 || out)) {
        free(rhs);
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (gmres)");
    }
    t3 = 1e3 * aug_now();
    ts += t3 - tg;
    /* solution step 3: a1 = [a_b; 0] + Kbar^-1 (P_S dF - J a2) (eq. 16) */
    double *bb = g->b;
    for (int64_t t = 0; t < g->nrows; t++) bb[g->rows[t]] = 0;
    for (int64_t p = 0; p < ns; p++) bb[c->S[p]] = 0;
    for (int64_t p = 0; p < ns; p++) {
        bb[c->S[p]] += c->dF[p];
        for (int64_t k = g->Jp[p]; k < g->Jp[p + 1]; k++) bb[g->Ji[k]] -= g->Jx[k] * a2[p];
    }
    for (int64_t t = 0; t < g->n12; t++) y[g->c12[t]] = 0;
    for (int64_t t = 0; t < g->nrows; t++)
        if (g->rows[t] < c->nb) y[b->pinv[g->rows[t]]] = bb[g->rows[t]];
    for (int64_t p = 0; p < ns; p++)
        if (c->S[p] < c->nb) y[b->pinv[c->S[p]]] = bb[c->S[p]];
    forward_c12(g, b);
    if (out) {
        int32_t *st = aug_malloc((size_t)(nout + 1) * sizeof *st), *q = aug_malloc((size_t)(b->n + 1) * sizeof *q);
        if (!st || !q) {
            free(st), free(q), free(rhs);
            return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
        }
        int64_t k = 0;
        for (int64_t t = 0; t < nout; t++)
            if (out[t] < c->nb) st[k++] = b->pinv[out[t]];
        /* y is zero outside closure(c12): clear the rest of the output closure */
        int64_t nq = aug_ldl_closure(b, st, k, q, g->mark);
        for (int64_t t = 0; t < nq; t++) g->mark[q[t]] = 1;
        for (int64_t t = 0; t < g->n12; t++) g->mark[g->c12[t]] = 0;
        for (int64_t t = 0; t < nq; t++)
            if (g->mark[q[t]]) y[q[t]] = 0, g->mark[q[t]] = 0;
        aug_ldl_ltsolve(b, q, nq, y);
        for (int64_t t = 0; t < nout; t++) {
            int64_t i = out[t];
            if (i < c->nb && (i >= c->pcap || c->pos[i] < 0)) u[i] = b->a[i] + y[b->pinv[i]];
        }
        free(st), free(q);
    } else {
        for (int64_t j = 0; j < b->n; j++) g->mark[j] = 0;
        for (int64_t t = 0; t < g->n12; t++) g->mark[g->c12[t]] = 1;
        for (int64_t j = 0; j < b->n; j++)
            if (!g->mark[j]) y[j] = 0;
        for (int64_t t = 0; t < g->n12; t++) g->mark[g->c12[t]] = 0;
        aug_ldl_ltsolve(b, NULL, 0, y);
        for (int64_t i = 0; i < c->nb; i++)
            if (i >= c->pcap || c->pos[i] < 0) u[i] = b->a[i] + y[b->pinv[i]];
    }
    for (int64_t p = 0; p < ns; p++) u[c->S[p]] = a2[p];
    /* an output set's round that stalls above the learnt Schur tolerance
       (S grown since it was learnt: the liver's 8-node steps 7-8 ran to
       --maxit, 2000 iterations in 4.9 s, and were called not converged at
       relres 8.5e-9) cannot tell whether its values meet --tol: the step
       goes on as a whole-field solve from there, warm, its rounds deciding
       on K_t's residual and learning the Schur tolerance anew; the step
       then has its whole field (aug_gmres_whole: solver.c fills in no
       rest around the output values, a second solve whose field mixed
       with this one's read relres 2e-7 on the liver's surface set) */
    if (out && g->stalled && m) {
        out = NULL, nout = 0;
        continue;
    }
    if (out || !m || round_done(g, aug_cutmat_relres(m, u), &stol, outer)) break;
    }
    g->whole = asked ? out == NULL : -1;
    free(rhs);
    times[0] = t1 - t0, times[1] = t2 - t1, times[2] = ts, times[3] = 1e3 * aug_now() - t2 - ts;
    return 0;
}

/* the set-up of a step for aug_gmres_solve_general: this step's J and
   preconditioner */
int aug_gmres_prepare(aug_gmres *g, const aug_base *b, const aug_cum *c, const aug_cutmat *m,
                      aug_err *e)
{
    return setup(g, b, c, m, e);
}

int aug_gmres_solve_general(aug_gmres *g, const aug_base *b, const aug_cum *c, aug_cutmat *m,
                            const double *r, double *x, aug_err *e)
{
    int64_t ns = c->ns;
    double *rhs = aug_malloc((size_t)(2 * ns + 1) * sizeof *rhs), *a2 = rhs + ns;
    double *work = aug_malloc((size_t)(b->n + 1) * sizeof *work);
    double *t = aug_malloc((size_t)(2 * c->n + 1) * sizeof *t), *res = t + c->n;
    if (!rhs || !work || !t) {
        free(rhs), free(work), free(t);
        return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
    }
    aug_ldl_solve_full(b, r, x, work);
    for (int64_t i = c->nb; i < c->n; i++) x[i] = r[i];
    for (int64_t p = 0; p < ns; p++) rhs[p] = c->S[p] < c->nb ? x[c->S[p]] : x[c->S[p]] / g->sig[p];
    g->iters = 0;
    double stol = g->tol;
    for (int outer = 0;; outer++) {
        gmres(g, b, c, rhs, a2, stol, outer > 0, outer > 0);
        memcpy(t, r, (size_t)c->n * sizeof *t);
        for (int64_t p = 0; p < ns; p++)
            for (int64_t k = g->Jp[p]; k < g->Jp[p + 1]; k++) t[g->Ji[k]] -= g->Jx[k] * a2[p];
        aug_ldl_solve_full(b, t, x, work);
        for (int64_t i = c->nb; i < c->n; i++) x[i] = t[i];
        for (int64_t p = 0; p < ns; p++) x[c->S[p]] = a2[p];
        if (!m || round_done(g, aug_cutmat_residual_b(m, x, r, res), &stol, outer)) break;
    }
    free(rhs), free(work), free(t);
    return 0;
}
