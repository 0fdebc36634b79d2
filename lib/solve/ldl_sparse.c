/* Sparse-RHS triangular solves on a simplicial LDL' factor over elimination-tree
   closures (paper 000 sec. 3.3 and appendix theorems 1-3; [Davis] ch. 3-4). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <cblas.h>
#include "aug_solve.h"
#include "aug_par.h"

/* parent[j] = min{i > j : L(i,j) != 0}, -1 at a root: the elimination tree of L
   (paper 000 appendix def. 2; [Liu 1990]) */
static void etree_of(aug_base *b)
{
    for (int64_t j = 0; j < b->n; j++) {
        int32_t p = -1;
        for (int k = b->Lp[j] + 1; k < b->Lp[j] + b->Lnz[j]; k++)
            if (p < 0 || b->Li[k] < p) p = b->Li[k];
        b->parent[j] = p;
    }
}

/* struct L(:,j) \ {parent} within struct L(:,parent) for every j: then the
   closure of any column set is the union of its etree paths (thm 3). */
static int etree_closed(const aug_base *b, unsigned char *mark)
{
    int ok = 1;
    for (int64_t j = 0; j < b->n && ok; j++) {
        int32_t p = b->parent[j];
        if (p < 0) {
            if (b->Lnz[j] > 1) ok = 0;
            continue;
        }
        if (p <= j) { ok = 0; break; }
        for (int k = b->Lp[p] + 1; k < b->Lp[p] + b->Lnz[p]; k++) mark[b->Li[k]] = 1;
        for (int k = b->Lp[j] + 1; k < b->Lp[j] + b->Lnz[j]; k++)
            if (b->Li[k] != p && !mark[b->Li[k]]) ok = 0;
        for (int k = b->Lp[p] + 1; k < b->Lp[p] + b->Lnz[p]; k++) mark[b->Li[k]] = 0;
    }
    return ok;
}

static int to_simplicial_ldl(cholmod_factor *L, cholmod_common *cm)
{
    if (L->is_super || L->is_ll || !L->is_monotonic)
        if (!cholmod_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, L, cm)) return -1;
    return L->itype == CHOLMOD_INT && L->xtype == CHOLMOD_REAL ? 0 : -1;
}

/* The simplicial LDL' of a supernodal L L' (rows increasing within each
   supernode, as CHOLMOD writes them), L left as it is: column j = k1 + jj of
   supernode s holds rows Ls[pi + jj ..] and values Lx[px + jj*nsrow + jj ..],
   D(j,j) = L(j,j)^2, L_ldl(i,j) = L(i,j) / L(j,j) (what cholmod_change_factor
   computes, [CHOLMOD]; lib/fem/factor_rec.c write_supernodal), built in place
   of cholmod_copy_factor + cholmod_change_factor (one pass, no copy of L).
   NULL when out of memory or the rows are out of order (the caller copies). */
static cholmod_factor *simplicial_of(const cholmod_factor *L, cholmod_common *cm)
{
    int64_t n = (int64_t)L->n, ns = (int64_t)L->nsuper, nnz = 0;
    const int *Super = L->super, *Lpi = L->pi, *Lpx = L->px, *Ls = L->s;
    const double *Lx = L->x;
    for (int64_t s = 0; s < ns; s++) {
        int k1 = Super[s], k2 = Super[s + 1], psi = Lpi[s], nsrow = Lpi[s + 1] - psi;
        for (int jj = 0; jj < k2 - k1; jj++)
            if (Ls[psi + jj] != k1 + jj) return NULL;
        for (int q = psi + 1; q < psi + nsrow; q++)
            if (Ls[q] <= Ls[q - 1]) return NULL;
        for (int jj = 0; jj < k2 - k1; jj++) nnz += nsrow - jj;
    }
    cholmod_factor *S = cholmod_allocate_factor((size_t)n, cm);
    if (!S) return NULL;
    S->ordering = L->ordering;
    int *Perm = S->Perm, *CC = S->ColCount;
    const int *P = L->Perm;
    for (int64_t s = 0; s < ns; s++)
        for (int j = Super[s]; j < Super[s + 1]; j++) CC[j] = Lpi[s + 1] - Lpi[s] - (j - Super[s]);
    for (int64_t k = 0; k < n; k++) Perm[k] = P ? P[k] : (int)k;
    if (!cholmod_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, S, cm) ||
        (S->nzmax < (size_t)nnz && !cholmod_reallocate_factor((size_t)nnz, S, cm))) {
        cholmod_free_factor(&S, cm);
        return NULL;
    }
    int *Sp = S->p, *Si = S->i, *Snz = S->nz;
    double *Sx = S->x;
    int64_t t = 0;
    for (int64_t s = 0; s < ns; s++) {
        int k1 = Super[s], k2 = Super[s + 1], psi = Lpi[s], nsrow = Lpi[s + 1] - psi;
        for (int jj = 0; jj < k2 - k1; jj++) {
            const double *x = Lx + Lpx[s] + (size_t)jj * nsrow + jj;
            double ljj = x[0];
            Sp[k1 + jj] = (int)t, Snz[k1 + jj] = nsrow - jj;
            Si[t] = Ls[psi + jj], Sx[t++] = ljj * ljj;
            for (int q = 1; q < nsrow - jj; q++) Si[t] = Ls[psi + jj + q], Sx[t++] = x[q] / ljj;
        }
    }
    Sp[n] = (int)t;
    S->minor = L->minor;
    return S;
}

static void attach(aug_base *b)
{
    cholmod_factor *L = b->L;
    b->n = (int64_t)L->n;
    b->Lp = L->p, b->Li = L->i, b->Lnz = L->nz, b->Lx = L->x;
}

/* Kb factored with the permutation perm kept as given (no postordering):
   simplicial LDL' (super = 0) or supernodal L L' (super = 1, then Ls = L D^1/2
   column for column). NULL if CHOLMOD failed or changed the permutation. */
static cholmod_factor *factor_given(const cholmod_sparse *Kb, const int32_t *perm, int super,
                                    cholmod_common *cm)
{
    int nm = cm->nmethods, sn = cm->supernodal, ord = cm->method[0].ordering, post = cm->postorder;
    cm->nmethods = 1;
    cm->method[0].ordering = CHOLMOD_GIVEN;
    cm->supernodal = super ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    cm->postorder = 0;
    cholmod_factor *L = cholmod_analyze_p((cholmod_sparse *)Kb, (int *)perm, NULL, 0, cm);
    if (L && !cholmod_factorize((cholmod_sparse *)Kb, L, cm)) cholmod_free_factor(&L, cm);
    cm->nmethods = nm, cm->supernodal = sn, cm->method[0].ordering = ord, cm->postorder = post;
    if (L && (L->minor < L->n || (super && !L->is_super))) cholmod_free_factor(&L, cm);
    for (size_t k = 0; L && k < L->n; k++)
        if (((int *)L->Perm)[k] != perm[k]) cholmod_free_factor(&L, cm);
    return L;
}

/* ||f - K x||_2 (K x by aug_sym_mult); NAN without K or f */
static double resid_norm(const cholmod_sparse *K, const double *f, const double *x, int64_t n,
                         cholmod_common *cm)
{
    if (!K || !f || (int64_t)K->ncol != n) return NAN;
    double *r = aug_malloc((size_t)(n + 1) * sizeof *r), rr = 0;
    if (!r) return NAN;
    if (aug_sym_mult((cholmod_sparse *)K, (double *)x, r, cm)) {
        free(r);
        return NAN;
    }
    for (int64_t i = 0; i < n; i++) rr += (f[i] - r[i]) * (f[i] - r[i]);
    free(r);
    return sqrt(rr);
}

/* x = K^-1 f = P' Ls^-T Ls^-1 P f (cholmod_solve2, CHOLMOD_A); 0 or -1 */
static int supernodal_solve(cholmod_factor *Ls, const double *f, double *x, cholmod_common *cm)
{
    cholmod_dense B = {0}, *X = NULL, *Y = NULL, *E = NULL;
    B.nrow = B.d = B.nzmax = Ls->n, B.ncol = 1;
    B.x = (void *)f, B.xtype = CHOLMOD_REAL, B.dtype = CHOLMOD_DOUBLE;
    /* the workspaces Y and E passed and freed here: with NULL handles this
       CHOLMOD (libcholmod.so.3) keeps its Y allocated (LeakSanitizer) */
    int ok = cholmod_solve2(CHOLMOD_A, Ls, &B, NULL, &X, NULL, &Y, &E, cm);
    if (ok) memcpy(x, X->x, Ls->n * sizeof *x);
    cholmod_free_dense(&X, cm);
    cholmod_free_dense(&Y, cm);
    cholmod_free_dense(&E, cm);
    return ok ? 0 : -1;
}

/* The base of the augmented methods: P K_b P' = L D L' simplicial (the R = L D L'
   of paper 000 eq. 12 before padding), its etree checked closed (thm 3; else
   re-factored with the same P), D > 0, a_b = K_b^-1 f_b; bases of order >=
   AUG_SUPERNODAL_MIN also keep the supernodal Ls = L D^1/2 for full solves.
   A simplicial L made from a supernodal one (simplicial_of) is closed by
   construction and not checked: column j of supernode s holds the rows of
   s from j on, its parent is j + 1 or, for the last column, the first row p
   below the diagonal block, and the supernodal symbolic factorization puts
   the rows of s beyond p's supernode among that supernode's rows (10 ms of
   each re-factorization on the 12.5k-DOF liver; solve_par's
   super_base_closed checks the claim). a_b is solved with Ls when there
   is one (the simplicial column solve took twice as long). */
aug_base *aug_base_new(cholmod_factor *L, const cholmod_sparse *Kb, const double *fb,
                       int32_t step, cholmod_common *cm, aug_err *e)
{
    aug_base *b = aug_calloc(1, sizeof *b);
    unsigned char *mark = NULL;
    double *work = NULL;
    if (!b) goto nomem;
    b->L = L;
    b->step = step;
    b->refs = 1;
    int closed = 0; /* the pattern known closed under the etree */
    /* a supernodal L becomes Ls as it is (moved, not copied); the simplicial
       LDL' is built beside it with its permutation */
    if (L->is_super && (int64_t)L->n >= AUG_SUPERNODAL_MIN && L->xtype == CHOLMOD_REAL &&
        L->minor == L->n) {
        cholmod_factor *S = simplicial_of(L, cm);
        if (S) b->Ls = L, b->L = L = S, closed = 1;
    }
    if (L->is_super && (int64_t)L->n >= AUG_SUPERNODAL_MIN && !b->Ls) {
        b->Ls = cholmod_copy_factor(L, cm);
        if (!b->Ls) goto nomem;
    }
    if (to_simplicial_ldl(L, cm)) {
        aug_err_set(e, AUG_EDATA, -1, "FACT", "factor cannot be converted to simplicial LDL'");
        goto fail;
    }
    attach(b);
    if (L->minor < L->n) {
        aug_err_set(e, AUG_ESINGULAR, -1, "FACT", "factor is not positive definite at column %d",
                    (int)L->minor);
        goto fail;
    }
    b->parent = aug_malloc((size_t)(b->n + 1) * sizeof *b->parent);
    b->perm = aug_malloc((size_t)(b->n + 1) * sizeof *b->perm);
    b->pinv = aug_malloc((size_t)(b->n + 1) * sizeof *b->pinv);
    b->a = aug_malloc((size_t)(b->n + 1) * sizeof *b->a);
    mark = aug_calloc((size_t)(b->n + 1), 1);
    work = aug_malloc((size_t)(b->n + 1) * sizeof *work);
    if (!b->parent || !b->perm || !b->pinv || !b->a || !mark || !work) goto nomem;
    const int *P = L->Perm;
    for (int64_t k = 0; k < b->n; k++) b->perm[k] = P ? P[k] : (int32_t)k;
    for (int64_t k = 0; k < b->n; k++) b->pinv[b->perm[k]] = (int32_t)k;
    etree_of(b);
    if (!closed && !etree_closed(b, mark)) {
        if (!Kb) {
            aug_err_set(e, AUG_EDATA, -1, "FACT", "factor pattern is not closed under its elimination tree");
            goto fail;
        }
        cholmod_factor *L2 = factor_given(Kb, b->perm, 0, cm);
        if (!L2 || L2->minor < L2->n) {
            if (L2) cholmod_free_factor(&L2, cm);
            aug_err_set(e, AUG_ESINGULAR, -1, "FACT", "re-factorization of the base failed");
            goto fail;
        }
        cholmod_free_factor(&b->L, cm);
        b->L = L2;
        attach(b);
        etree_of(b);
    }
    for (int64_t j = 0; j < b->n; j++)
        if (!(aug_base_d(b, j) > 0)) {
            aug_err_set(e, AUG_ESINGULAR, -1, "FACT", "D(%lld) = %g is not positive",
                        (long long)j, aug_base_d(b, j));
            goto fail;
        }
    if (!b->Ls && Kb && b->n >= AUG_SUPERNODAL_MIN) b->Ls = factor_given(Kb, b->perm, 1, cm);
    if (!b->Ls || supernodal_solve(b->Ls, fb, b->a, cm)) aug_ldl_solve_full(b, fb, b->a, work);
    b->rnorm = resid_norm(Kb, fb, b->a, b->n, cm);
    b->anorm = cblas_dnrm2((int)b->n, b->a, 1);
    if (b->Ls) {
        b->sqrtd = aug_malloc((size_t)b->n * sizeof *b->sqrtd);
        b->super_of = aug_malloc((size_t)b->n * sizeof *b->super_of);
        if (!b->sqrtd || !b->super_of) goto nomem;
        for (int64_t j = 0; j < b->n; j++) b->sqrtd[j] = sqrt(aug_base_d(b, j));
        const int *sup = b->Ls->super;
        for (size_t s = 0; s < b->Ls->nsuper; s++)
            for (int j = sup[s]; j < sup[s + 1]; j++) b->super_of[j] = (int32_t)s;
    }
    free(mark);
    free(work);
    return b;
nomem:
    aug_err_set(e, AUG_ENOMEM, -1, "FACT", "out of memory");
fail:
    free(mark);
    free(work);
    if (b) {
        b->refs = 1;
        aug_base_release(b, cm);
    } else if (L) {
        cholmod_free_factor(&L, cm);
    }
    return NULL;
}

void aug_base_release(aug_base *b, cholmod_common *cm)
{
    if (!b || --b->refs > 0) return;
    if (b->L) cholmod_free_factor(&b->L, cm);
    if (b->Ls) cholmod_free_factor(&b->Ls, cm);
    free(b->sqrtd);
    free(b->super_of);
    aug_par_plan_free(b->par_plan);
    free(b->parent);
    free(b->perm);
    free(b->pinv);
    free(b->a);
    free(b);
}

/* path = p, parent(p), ... up to its root, ascending: closure_L({p}) (paper 000
   thm 3); returns its length */
int64_t aug_ldl_path(const aug_base *b, int32_t p, int32_t *path)
{
    int64_t k = 0;
    for (int32_t v = p; v >= 0; v = b->parent[v]) path[k++] = v;
    return k;
}

/* out = closure_L(start) = union of the etree paths of start (paper 000 thm 3),
   ascending; returns its size */
int64_t aug_ldl_closure(const aug_base *b, const int32_t *start, int64_t ns, int32_t *out,
                        unsigned char *mark)
{
    int64_t k = 0;
    for (int64_t s = 0; s < ns; s++)
        for (int32_t v = start[s]; v >= 0 && !mark[v]; v = b->parent[v]) {
            mark[v] = 1;
            out[k++] = v;
        }
    for (int64_t i = 0; i < k; i++) mark[out[i]] = 0;
    qsort(out, (size_t)k, sizeof *out, aug_cmp_i32);
    return k;
}

/* x := L^-1 x, column by column in increasing order over the closed set (x is
   zero outside it, and so is L^-1 x: paper 000 thm 1) */
void aug_ldl_lsolve(const aug_base *b, const int32_t *set, int64_t k, double *x)
{
    const int *Lp = b->Lp, *Li = b->Li, *Lnz = b->Lnz;
    const double *Lx = b->Lx;
    int64_t n = set ? k : b->n;
    for (int64_t t = 0; t < n; t++) {
        int64_t j = set ? set[t] : t;
        double xj = x[j];
        if (xj == 0) continue;
        for (int q = Lp[j] + 1; q < Lp[j] + Lnz[j]; q++) x[Li[q]] -= Lx[q] * xj;
    }
}

/* x := D^-1 x over set (all columns when set is NULL) */
void aug_ldl_dsolve(const aug_base *b, const int32_t *set, int64_t k, double *x)
{
    int64_t n = set ? k : b->n;
    for (int64_t t = 0; t < n; t++) {
        int64_t j = set ? set[t] : t;
        x[j] /= b->Lx[b->Lp[j]];
    }
}

/* x := L^-T x in decreasing order over the closed set; every row read lies in
   it (paper 000 thm 2: the set's components of L^-T x need only the set) */
void aug_ldl_ltsolve(const aug_base *b, const int32_t *set, int64_t k, double *x)
{
    const int *Lp = b->Lp, *Li = b->Li, *Lnz = b->Lnz;
    const double *Lx = b->Lx;
    int64_t n = set ? k : b->n;
    for (int64_t t = n - 1; t >= 0; t--) {
        int64_t j = set ? set[t] : t;
        double s = x[j];
        for (int q = Lp[j] + 1; q < Lp[j] + Lnz[j]; q++) s -= Lx[q] * x[Li[q]];
        x[j] = s;
    }
}

/* B := T^-1 B, T lower triangular (n x n, leading dim ldt), B n x r: blocked
   by NB columns so that nearly all the work is one dgemm per block (OpenBLAS's
   dtrsm is slow for the few right-hand sides of a step) */
static void trsm_lower(int n, int r, const double *T, int ldt, double *B, int ldb)
{
    enum { NB = 64 };
    for (int k = 0; k < n; k += NB) {
        int kb = n - k < NB ? n - k : NB;
        cblas_dtrsm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans, CblasNonUnit, kb, r, 1.0,
                    T + k + (size_t)k * ldt, ldt, B + k, ldb);
        if (k + kb < n)
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n - k - kb, r, kb, -1.0,
                        T + k + kb + (size_t)k * ldt, ldt, B + k, ldb, 1.0, B + k + kb, ldb);
    }
}

/* r columns of V at once (paper 001 eq. 3.24): Ls X = E_P supernode by supernode
   over the union U of the paths, in increasing order: per supernode one triangular
   solve and one product on all r right-hand sides (a right-hand side whose path
   enters the supernode further down is zero above its entry and stays so);
   outs[q][t] = X(paths[q][t], q) D^1/2, since L = Ls D^-1/2. X is |U| x r
   row-major over U (loc: a row's place in U; every row a supernode of U
   updates is an etree ancestor, in U), so a row's r values are adjacent for
   the scatter and a step's few columns touch O(|U| r), not O(n r), memory. */
int aug_ldl_paths_solve_super(const aug_base *b, int r, const int32_t *p, int32_t *const *paths,
                              const int64_t *lens, double *const *outs)
{
    const cholmod_factor *L = b->Ls;
    const int *sup = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    int64_t ns = (int64_t)L->nsuper, nmax = 0, list_n = 0, nu = 0;
    int32_t *entry = aug_malloc((size_t)ns * sizeof *entry), *list = NULL;
    int32_t *loc = aug_malloc((size_t)b->n * sizeof *loc); /* read only on U */
    double *X = NULL, *B = NULL, *T = NULL;
    if (!entry || !loc) goto nomem;
    for (int64_t s = 0; s < ns; s++) entry[s] = -1;
    for (int q = 0; q < r; q++)
        for (int64_t t = 0; t < lens[q]; t++) {
            int32_t j = paths[q][t], s = b->super_of[j];
            if (entry[s] < 0) list_n++;
            if (entry[s] < 0 || j - sup[s] < entry[s]) entry[s] = j - sup[s];
        }
    list = aug_malloc((size_t)(list_n ? list_n : 1) * sizeof *list);
    if (!list) goto nomem;
    list_n = 0;
    for (int64_t s = 0; s < ns; s++)
        if (entry[s] >= 0) {
            list[list_n++] = (int32_t)s;
            int64_t nr = pi[s + 1] - pi[s];
            if (nr > nmax) nmax = nr;
            for (int j = sup[s] + entry[s]; j < sup[s + 1]; j++) loc[j] = (int32_t)nu++;
        }
    X = aug_calloc((size_t)(nu ? nu : 1) * (size_t)r, sizeof *X);
    B = aug_malloc((size_t)(nmax ? nmax : 1) * (size_t)r * sizeof *B);
    T = aug_malloc((size_t)(nmax ? nmax : 1) * (size_t)r * sizeof *T);
    if (!X || !B || !T) goto nomem;
    for (int q = 0; q < r; q++) X[(int64_t)loc[p[q]] * r + q] = 1.0;
    for (int64_t l = 0; l < list_n; l++) {
        int32_t s = list[l];
        int k1 = sup[s], nscol = sup[s + 1] - k1, nsrow = pi[s + 1] - pi[s], o = entry[s];
        int nc = nscol - o, nb = nsrow - nscol;
        const double *A = Lx + px[s];
        double *Xs = X + (int64_t)loc[k1 + o] * r; /* the supernode's rows of U are consecutive */
        for (int i = 0; i < nc; i++)
            for (int q = 0; q < r; q++) B[i + (int64_t)q * nc] = Xs[(int64_t)i * r + q];
        trsm_lower(nc, r, A + o + (size_t)o * nsrow, nsrow, B, nc);
        for (int i = 0; i < nc; i++)
            for (int q = 0; q < r; q++) Xs[(int64_t)i * r + q] = B[i + (int64_t)q * nc];
        if (nb == 0) continue;
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, nb, r, nc, 1.0,
                    A + nscol + (size_t)o * nsrow, nsrow, B, nc, 0.0, T, nb);
        const int *rows = Ls + pi[s] + nscol;
        for (int i = 0; i < nb; i++) {
            double *Xr = X + (int64_t)loc[rows[i]] * r;
            for (int q = 0; q < r; q++) Xr[q] -= T[i + (int64_t)q * nb];
        }
    }
    for (int q = 0; q < r; q++)
        for (int64_t t = 0; t < lens[q]; t++) {
            int32_t j = paths[q][t];
            outs[q][t] = X[(int64_t)loc[j] * r + q] * b->sqrtd[j];
        }
    free(entry), free(list), free(loc), free(X), free(B), free(T);
    return 0;
nomem:
    free(entry), free(list), free(loc), free(X), free(B), free(T);
    return -1;
}

/* 1 when the rows of the ascending etree closure set[0..k) in each supernode
   of b->Ls are a suffix of its columns (contiguous, ending at its last
   column), as the supernodal closure solves need; 0 else */
static int closure_suffixes(const aug_base *b, const int32_t *set, int64_t k)
{
    const int *sup = b->Ls->super;
    for (int64_t t = 0; t < k;) {
        int32_t s = b->super_of[set[t]];
        int64_t t1 = t;
        while (t1 + 1 < k && set[t1 + 1] < sup[s + 1]) t1++;
        if (set[t1] != sup[s + 1] - 1 || set[t1] - set[t] != t1 - t) return 0;
        t = t1 + 1;
    }
    return 1;
}

/* pre[s] = the columns of supernode s of Ls outside the ascending etree
   closure set[0..k): its leading ones, when each supernode's rows in the
   set are a suffix of its columns (closure_suffixes). 0, or -1 when they
   are not (or there is no Ls) */
int aug_ldl_closure_pre(const aug_base *b, const int32_t *set, int64_t k, int *pre)
{
    if (!b->Ls || !closure_suffixes(b, set, k)) return -1;
    const int *sup = b->Ls->super;
    for (int64_t s = 0; s < (int64_t)b->Ls->nsuper; s++) pre[s] = sup[s + 1] - sup[s];
    for (int64_t t = k - 1; t >= 0; t--) {
        int32_t s = b->super_of[set[t]];
        pre[s] = set[t] - sup[s];
    }
    return 0;
}

/* x := L^-T x = Ls^-T (D^1/2 x) on the rows of the etree closure set only (paper
   000 thm 2), supernode by supernode (dgemv + dtrsv); column by column
   (aug_ldl_ltsolve) when a supernode's rows in set are not a suffix of its columns */
void aug_ldl_ltsolve_closure_super(const aug_base *b, const int32_t *set, int64_t k, double *x,
                                   double *tmp)
{
    if (!b->Ls) {
        aug_ldl_ltsolve(b, set, k, x);
        return;
    }
    const cholmod_factor *L = b->Ls;
    const int *sup = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    /* a supernode's rows in a closure are a suffix of its columns (within a
       supernode the parent of a column is the next one); else column-wise */
    if (!closure_suffixes(b, set, k)) {
        aug_ldl_ltsolve(b, set, k, x);
        return;
    }
    for (int64_t t = 0; t < k; t++) x[set[t]] *= b->sqrtd[set[t]];
    for (int64_t t = k - 1; t >= 0;) {
        int32_t s = b->super_of[set[t]];
        int k1 = sup[s], nscol = sup[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        int64_t t0 = t;
        while (t0 > 0 && set[t0 - 1] >= k1) t0--;
        int o = set[t0] - k1, nc = nscol - o, nb = nsrow - nscol;
        const double *A = Lx + px[s];
        double *xs = x + k1 + o;
        if (nb > 0) {
            const int *rows = Ls + pi[s] + nscol;
            for (int r = 0; r < nb; r++) tmp[r] = x[rows[r]];
            cblas_dgemv(CblasColMajor, CblasTrans, nb, nc, -1.0, A + nscol + (size_t)o * nsrow, nsrow,
                        tmp, 1, 1.0, xs, 1);
        }
        cblas_dtrsv(CblasColMajor, CblasLower, CblasTrans, CblasNonUnit, nc, A + o + (size_t)o * nsrow,
                    nsrow, xs, 1);
        t = t0 - 1;
    }
}

/* x := L^-1 x = D^1/2 Ls^-1 x on the etree closure set (ascending; x zero
   outside it, and so is L^-1 x: paper 000 thm 1), supernode by supernode
   (dtrsv + dgemv, the update scattered to the rows below, which lie in the
   set); column by column (aug_ldl_lsolve) without Ls or when a supernode's
   rows in set are not a suffix of its columns. tmp: n-sized workspace. */
void aug_ldl_lsolve_closure_super(const aug_base *b, const int32_t *set, int64_t k, double *x,
                                  double *tmp)
{
    if (!b->Ls) {
        aug_ldl_lsolve(b, set, k, x);
        return;
    }
    const cholmod_factor *L = b->Ls;
    const int *sup = L->super, *pi = L->pi, *px = L->px, *Ls = L->s;
    const double *Lx = L->x;
    if (!closure_suffixes(b, set, k)) {
        aug_ldl_lsolve(b, set, k, x);
        return;
    }
    for (int64_t t = 0; t < k;) {
        int32_t s = b->super_of[set[t]];
        int k1 = sup[s], nscol = sup[s + 1] - k1, nsrow = pi[s + 1] - pi[s];
        int o = set[t] - k1, nc = nscol - o, nb = nsrow - nscol;
        const double *A = Lx + px[s];
        double *xs = x + k1 + o;
        cblas_dtrsv(CblasColMajor, CblasLower, CblasNoTrans, CblasNonUnit, nc, A + o + (size_t)o * nsrow,
                    nsrow, xs, 1);
        if (nb > 0) {
            const int *rows = Ls + pi[s] + nscol;
            cblas_dgemv(CblasColMajor, CblasNoTrans, nb, nc, 1.0, A + nscol + (size_t)o * nsrow, nsrow,
                        xs, 1, 0.0, tmp, 1);
            for (int r = 0; r < nb; r++) x[rows[r]] -= tmp[r];
        }
        t += nc;
    }
    for (int64_t t = 0; t < k; t++) x[set[t]] *= b->sqrtd[set[t]];
}

/* x := L^-T x = Ls^-T (D^1/2 x) when the supernodal factor exists */
int aug_ldl_ltsolve_all(const aug_base *b, double *x, cholmod_dense **X, cholmod_dense **Yw,
                        cholmod_dense **Ew, cholmod_common *cm)
{
    if (!b->Ls) {
        aug_ldl_ltsolve(b, NULL, 0, x);
        return 0;
    }
    for (int64_t j = 0; j < b->n; j++) x[j] *= b->sqrtd[j];
    cholmod_dense B = {0};
    B.nrow = B.d = (size_t)b->n, B.ncol = 1, B.nzmax = (size_t)b->n;
    B.x = x, B.xtype = CHOLMOD_REAL, B.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_solve2(CHOLMOD_Lt, b->Ls, &B, NULL, X, NULL, Yw, Ew, cm)) return -1;
    memcpy(x, (*X)->x, (size_t)b->n * sizeof *x);
    return 0;
}

/* x = K_b^-1 rhs = P' L^-T D^-1 L^-1 P rhs over all columns (simplicial) */
void aug_ldl_solve_full(const aug_base *b, const double *rhs, double *x, double *work)
{
    for (int64_t k = 0; k < b->n; k++) work[k] = rhs[b->perm[k]];
    aug_ldl_lsolve(b, NULL, 0, work);
    aug_ldl_dsolve(b, NULL, 0, work);
    aug_ldl_ltsolve(b, NULL, 0, work);
    for (int64_t k = 0; k < b->n; k++) x[b->perm[k]] = work[k];
}
