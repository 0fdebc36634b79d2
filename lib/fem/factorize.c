/* CHOLMOD analysis and numeric factorization of K with augcut's choices of
   ordering and factor kind; a not positive definite K is named down to the node. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

const char *aug_ordering_name(int ordering)
{
    switch (ordering) {
    case CHOLMOD_NATURAL: return "natural";
    case CHOLMOD_GIVEN: return "given";
    case CHOLMOD_AMD: return "amd";
    case CHOLMOD_METIS: return "metis";
    case CHOLMOD_NESDIS: return "nesdis";
    case CHOLMOD_COLAMD: return "colamd";
    case CHOLMOD_POSTORDERED: return "postordered";
    default: return "unknown";
    }
}

/* AUG_ORDER_AUTO leaves CHOLMOD's default strategy (AMD, and METIS too when
   AMD's fill is high; the better one is kept); AMD / METIS force one method
   (postordered). simplicial: simplicial LDL'; otherwise supernodal LL'
   (cm->final_ll = 0; [CHOLMOD] user guide, cholmod_common). */
void aug_factor_options(cholmod_common *cm, int ordering, int simplicial)
{
    cm->nmethods = 0;
    if (ordering == AUG_ORDER_AMD || ordering == AUG_ORDER_METIS) {
        cm->nmethods = 1;
        cm->method[0].ordering = ordering == AUG_ORDER_AMD ? CHOLMOD_AMD : CHOLMOD_METIS;
        cm->postorder = 1;
    }
    cm->supernodal = simplicial ? CHOLMOD_SIMPLICIAL : CHOLMOD_SUPERNODAL;
    cm->final_ll = 0;
}

/* symbolic factor of K with the ordering options of cm (cholmod_analyze,
   [CHOLMOD]); NULL with e filled on failure */
cholmod_factor *aug_analyze(cholmod_sparse *K, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    cholmod_factor *L = cholmod_analyze(K, cm);
    if (!L || cm->status < CHOLMOD_OK) {
        aug_err_set(e, cm->status == CHOLMOD_OUT_OF_MEMORY ? AUG_ENOMEM : AUG_EDATA, -1, "",
                    "CHOLMOD analysis failed (status %d)", cm->status);
        cholmod_free_factor(&L, cm);
        return NULL;
    }
    return L;
}

/* The mean closure work of a supernodal symbolic factor: the entries of L
   that a sparse forward (or back) substitution from one unit vector e_j
   touches, sum over the etree ancestors k of j (j included) of nnz(L(:,k)),
   averaged over j (paper 000 thm 3: the reach of e_j is its etree path; the
   AMPS step of paper 001 sweeps the closure of its rows' pattern, sec. 3.3).
   Equal to (1/n) sum_k nnz(L(:,k)) |subtree(k)|. The column etree of a
   supernodal L: column j of supernode s has parent j + 1, the last column
   the first row below s's diagonal block; nnz(L(:,j)) the rows of s from j
   on (the relaxed pattern, explicit zeros included: what the AMPS base
   holds, ldl_sparse.c simplicial_of). -1 if L is not supernodal or on
   allocation failure. */
double aug_closure_work(const cholmod_factor *L)
{
    if (!L->is_super || L->n == 0) return -1;
    int64_t n = (int64_t)L->n, ns = (int64_t)L->nsuper;
    const int *sup = L->super, *pi = L->pi, *si = L->s;
    int64_t *size = aug_malloc((size_t)n * sizeof *size);
    int32_t *par = aug_malloc((size_t)n * sizeof *par);
    if (!size || !par) {
        free(size), free(par);
        return -1;
    }
    for (int64_t s = 0; s < ns; s++) {
        int64_t k0 = sup[s], k1 = sup[s + 1], nc = k1 - k0, nr = pi[s + 1] - pi[s];
        for (int64_t j = k0; j < k1 - 1; j++) par[j] = (int32_t)(j + 1);
        par[k1 - 1] = nr > nc ? si[pi[s] + nc] : -1;
    }
    for (int64_t j = 0; j < n; j++) size[j] = 1;
    double w = 0;
    for (int64_t s = 0; s < ns; s++) {
        int64_t k0 = sup[s], nr = pi[s + 1] - pi[s];
        for (int64_t j = k0; j < sup[s + 1]; j++) {
            /* children precede parents: size[j] is whole here */
            w += (double)(nr - (j - k0)) * (double)size[j];
            if (par[j] > j) size[par[j]] += size[j];
        }
    }
    free(size), free(par);
    return w / (double)n;
}

/* --ordering auto (paper 001 sec. 3.3 and README "Ordering"): the step of an
   augmented method costs one back-substitution over L (the full field) plus
   sparse sweeps over the closure of the changed rows (the forward solve of
   H's rows, the memo of the new ones, the deferred back-substitution of the
   closure), so the base's ordering is chosen by lnz + AUG_ORDER_SWEEPS times
   the mean closure work (aug_closure_work), AMD against METIS, not by fill
   alone. Nested dissection keeps the elimination tree balanced and the
   paths short: the beam h=256 in 5-tet cells, AMD nnz(L) 0.87M with a mean
   closure 6,654 columns, METIS 1.39M and 828, an AMPS step 14.4 -> 3.8 ms
   and the full solve 2.95 -> 2.37 ms; CHOLMOD's own choice (AMD unless its
   fill is high) took AMD there and on the bunny (METIS: less fill, closure
   2,361 -> 1,227 columns, step 12.0 -> 8.6 ms). Below AUG_ORDER_CHOICE_MIN
   DOFs, for --simplicial and for a forced ordering, aug_analyze as set;
   when CHOLMOD makes either symbolic factor simplicial (cm->supernodal
   CHOLMOD_AUTO), the least fill. */
#define AUG_ORDER_SWEEPS 4
#define AUG_ORDER_CHOICE_MIN 2000
cholmod_factor *aug_analyze_steps(cholmod_sparse *K, int ordering, cholmod_common *cm, aug_err *e)
{
    if (ordering != AUG_ORDER_AUTO || cm->supernodal == CHOLMOD_SIMPLICIAL ||
        (int64_t)K->nrow < AUG_ORDER_CHOICE_MIN)
        return aug_analyze(K, cm, e);
    static const int cand[2] = {CHOLMOD_AMD, CHOLMOD_METIS};
    int nm = cm->nmethods, ord = cm->method[0].ordering, po = cm->postorder;
    cholmod_factor *L[2] = {NULL, NULL};
    double lnz[2] = {0, 0}, fl[2] = {0, 0}, w[2] = {-1, -1};
    for (int c = 0; c < 2; c++) {
        cm->nmethods = 1, cm->method[0].ordering = cand[c], cm->postorder = 1;
        L[c] = cholmod_analyze(K, cm);
        if (!L[c] || cm->status < CHOLMOD_OK) {
            cholmod_free_factor(&L[c], cm);
            if (cm->status == CHOLMOD_OUT_OF_MEMORY) break;
            continue; /* METIS may refuse a graph: AMD stands */
        }
        lnz[c] = cm->lnz, fl[c] = cm->fl, w[c] = aug_closure_work(L[c]);
    }
    cm->nmethods = nm, cm->method[0].ordering = ord, cm->postorder = po;
    if (!L[0] && !L[1]) return aug_analyze(K, cm, e);
    /* by fill alone when CHOLMOD made either symbolic factor simplicial
       (cm->supernodal CHOLMOD_AUTO on a small or sparse factor) */
    int both = w[0] >= 0 && w[1] >= 0;
    double c0 = lnz[0] + (both ? AUG_ORDER_SWEEPS * w[0] : 0), c1 = lnz[1] + (both ? AUG_ORDER_SWEEPS * w[1] : 0);
    int b = !L[0] || (L[1] && c1 < c0);
    cholmod_free_factor(&L[!b], cm);
    cm->lnz = lnz[b], cm->fl = fl[b];
    cm->status = CHOLMOD_OK;
    return L[b];
}

/* Name the free DOF f: node, component, and the node's connected component. */
static void describe_dof(const aug_mesh *m, const int32_t *map, int64_t f, char *s, size_t n)
{
    int64_t nd = m->nn * m->dim, dof = -1;
    for (int64_t i = 0; i < nd && dof < 0; i++)
        if (map[i] == f) dof = i;
    if (dof < 0) {
        snprintf(s, n, "free DOF %lld", (long long)f);
        return;
    }
    int64_t node = dof / m->dim, nodes = 0, first = -1, el0 = -1;
    int32_t *comp = aug_malloc((size_t)m->nn * sizeof *comp);
    if (comp && aug_mesh_components(m, comp) >= 0 && comp[node] >= 0) {
        for (int64_t i = 0; i < m->nn; i++)
            if (comp[i] == comp[node]) {
                nodes++;
                if (first < 0) first = i;
            }
        for (int64_t el = 0; el < m->ne && el0 < 0; el++)
            if (comp[m->conn[el * m->nv]] == comp[node]) el0 = el;
    }
    free(comp);
    if (el0 >= 0)
        snprintf(s, n, "free DOF %lld = node %lld %c, in a component of %lld nodes (node %lld, "
                       "material %s)",
                 (long long)f, (long long)node, "xyz"[dof % m->dim], (long long)nodes,
                 (long long)first, m->mats[m->mat[el0]].name);
    else
        snprintf(s, n, "free DOF %lld = node %lld %c", (long long)f, (long long)node,
                 "xyz"[dof % m->dim]);
}

/* P K P' = L L' (supernodal) or L D L' (simplicial) by cholmod_factorize
   ([CHOLMOD]). CHOLMOD reports a non-positive pivot in LL' (status
   CHOLMOD_NOT_POSDEF, column L->minor); a simplicial LDL' only stops at a zero
   pivot, so D > 0 is checked here. The failing column j of P K P' is the free DOF
   Perm[j]; m and map (both may be NULL) name its node. */
int aug_factorize(cholmod_sparse *K, cholmod_factor *L, const aug_mesh *m, const int32_t *map,
                  cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    int ok = cholmod_factorize(K, L, cm);
    if (!ok || (cm->status < CHOLMOD_OK))
        return aug_err_set(e, cm->status == CHOLMOD_OUT_OF_MEMORY ? AUG_ENOMEM : AUG_EDATA, -1,
                           "", "CHOLMOD factorization failed (status %d)", cm->status);
    size_t bad = L->minor;
    if (bad >= L->n && !L->is_super && !L->is_ll) {
        const int *Lp = L->p;
        const double *Lx = L->x;
        for (size_t j = 0; j < L->n && bad >= L->n; j++)
            if (!(Lx[Lp[j]] > 0)) bad = j;
    }
    if (bad >= L->n) return 0;
    int64_t f = ((const int *)L->Perm)[bad];
    char what[256];
    if (m && map) describe_dof(m, map, f, what, sizeof what);
    else snprintf(what, sizeof what, "free DOF %lld", (long long)f);
    return aug_err_set(e, AUG_ESINGULAR, -1, "",
                       "K is not positive definite: pivot %zu of the factor (%s)", bad, what);
}
