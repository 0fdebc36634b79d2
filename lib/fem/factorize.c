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
