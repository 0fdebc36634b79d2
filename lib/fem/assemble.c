/* Global stiffness / mass matrix over the free DOFs: a symbolic pass over the
   node adjacency, then a numeric scatter of element matrices in element order. */
#include <stdlib.h>
#include <string.h>
#include "aug_fem.h"

/* Node -> element incidence in CSR form (elements increasing per node). */
int aug_node_elements(const aug_mesh *m, int64_t **ptr, int32_t **ind)
{
    int64_t nn = m->nn, ne = m->ne, nv = m->nv;
    int64_t *p = aug_calloc((size_t)nn + 1, sizeof *p);
    int32_t *q = aug_malloc((size_t)(ne * nv) * sizeof *q);
    if (!p || !q) {
        free(p);
        free(q);
        return -1;
    }
    for (int64_t k = 0; k < ne * nv; k++) p[m->conn[k] + 1]++;
    for (int64_t i = 0; i < nn; i++) p[i + 1] += p[i];
    int64_t *next = aug_malloc((size_t)(nn ? nn : 1) * sizeof *next);
    if (!next) {
        free(p);
        free(q);
        return -1;
    }
    memcpy(next, p, (size_t)nn * sizeof *next);
    for (int64_t e = 0; e < ne; e++)
        for (int j = 0; j < nv; j++) q[next[m->conn[e * nv + j]]++] = (int32_t)e;
    free(next);
    *ptr = p;
    *ind = q;
    return 0;
}

/* Upper adjacency: for each node j the sorted list of nodes k <= j sharing an
   element with j (j itself included when it is in an element). */
static int upper_adjacency(const aug_mesh *m, int64_t **aptr, int32_t **aind)
{
    int64_t *ep = NULL, nn = m->nn, nv = m->nv;
    int32_t *ei = NULL, *mark = NULL, *ind = NULL;
    int64_t *ptr = NULL;
    if (aug_node_elements(m, &ep, &ei)) return -1;
    mark = aug_malloc((size_t)(nn ? nn : 1) * sizeof *mark);
    ptr = aug_malloc((size_t)(nn + 1) * sizeof *ptr);
    if (!mark || !ptr) goto fail;
    for (int64_t i = 0; i < nn; i++) mark[i] = -1;
    ptr[0] = 0;
    for (int pass = 0; pass < 2; pass++) {
        for (int64_t i = 0; i < nn; i++) mark[i] = -1;
        for (int64_t j = 0; j < nn; j++) {
            int64_t cnt = 0, start = pass ? ptr[j] : 0;
            for (int64_t t = ep[j]; t < ep[j + 1]; t++) {
                const int32_t *c = m->conn + (int64_t)ei[t] * nv;
                for (int a = 0; a < nv; a++) {
                    int32_t k = c[a];
                    if (k > j || mark[k] == (int32_t)j) continue;
                    mark[k] = (int32_t)j;
                    if (pass) { /* insertion into the sorted run */
                        int64_t s = start + cnt;
                        while (s > start && ind[s - 1] > k) ind[s] = ind[s - 1], s--;
                        ind[s] = k;
                    }
                    cnt++;
                }
            }
            if (!pass) ptr[j + 1] = ptr[j] + cnt;
        }
        if (!pass) {
            ind = aug_malloc((size_t)(ptr[nn] ? ptr[nn] : 1) * sizeof *ind);
            if (!ind) goto fail;
        }
    }
    free(ep);
    free(ei);
    free(mark);
    *aptr = ptr;
    *aind = ind;
    return 0;
fail:
    free(ep);
    free(ei);
    free(mark);
    free(ptr);
    free(ind);
    return -1;
}

/* first position t in ind[lo..hi) (sorted) with ind[t] >= k */
static int64_t find_node(const int32_t *ind, int64_t lo, int64_t hi, int32_t k)
{
    while (lo < hi) {
        int64_t mid = (lo + hi) / 2;
        if (ind[mid] < k) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* Lumped mass: diagonal, M(f,f) = sum over the elements at f of the row sums
   of their consistent mass (elem_mass.c: rho w / nv for simplices), over the
   free DOFs f. */
static cholmod_sparse *assemble_lumped(const aug_mesh *m, const int32_t *map, int64_t nfree,
                                       cholmod_common *cm, aug_err *e)
{
    cholmod_sparse *A = cholmod_allocate_sparse((size_t)nfree, (size_t)nfree, (size_t)nfree, 1, 1,
                                                1, CHOLMOD_REAL, cm);
    if (!A) {
        aug_err_set(e, AUG_ENOMEM, -1, "KMAT", "out of memory (CHOLMOD)");
        return NULL;
    }
    int *Ap = A->p, *Ai = A->i;
    double *Ax = A->x, Me[AUG_MAX_EMAT];
    for (int64_t j = 0; j <= nfree; j++) Ap[j] = (int)j;
    for (int64_t j = 0; j < nfree; j++) Ai[j] = (int)j, Ax[j] = 0;
    int d = m->dim, nv = m->nv, n = d * nv;
    for (int64_t el = 0; el < m->ne; el++) {
        aug_elem_mass(m, el, 1, Me);
        for (int a = 0; a < nv; a++)
            for (int i = 0; i < d; i++) {
                int32_t f = map[(int64_t)m->conn[el * nv + a] * d + i];
                if (f >= 0) Ax[f] += Me[(size_t)(a * d + i) * n + a * d + i];
            }
    }
    return A;
}

/* K (or M) = sum_e P_e' Ke P_e restricted to the free DOFs, upper triangle
   ([Zienkiewicz]; paper 000 sec. 3.1). Column (node j, comp c) holds the free DOFs
   of the adjacent nodes k < j, then those of j with comp <= c: row (k, i) sits at
   colptr + off[k] + lidx(k, i), where off[k] counts the free DOFs of the adjacent
   nodes before k. Sums in element order (deterministic). */
cholmod_sparse *aug_assemble(const aug_mesh *m, const int32_t *map, int64_t nfree,
                             int which, cholmod_common *cm, aug_err *e)
{
    aug_err_clear(e);
    if (which == AUG_MAT_ML) return assemble_lumped(m, map, nfree, cm, e);
    int d = m->dim, nv = m->nv, n = d * nv;
    int64_t nn = m->nn, *aptr = NULL;
    int32_t *aind = NULL, *aoff = NULL;
    unsigned char *nfc = NULL;
    cholmod_sparse *A = NULL;
    if (upper_adjacency(m, &aptr, &aind)) goto nomem;
    aoff = aug_malloc((size_t)(aptr[nn] ? aptr[nn] : 1) * sizeof *aoff);
    nfc = aug_malloc((size_t)(nn ? nn : 1));
    if (!aoff || !nfc) goto nomem;
    for (int64_t i = 0; i < nn; i++) {
        nfc[i] = 0;
        for (int c = 0; c < d; c++) nfc[i] += map[i * d + c] >= 0;
    }
    int64_t nnz = 0;
    for (int64_t j = 0; j < nn; j++) {
        int32_t off = 0;
        for (int64_t t = aptr[j]; t < aptr[j + 1]; t++) {
            aoff[t] = off;
            off += nfc[aind[t]];
        }
        /* off includes j's own free DOFs; column (j,c) has off - nfc[j] + lidx + 1
           (no entries at all when j is in no element) */
        if (aptr[j] == aptr[j + 1]) continue;
        for (int c = 0, l = 0; c < d; c++)
            if (map[j * d + c] >= 0) nnz += off - nfc[j] + (++l);
    }
    if (nnz > INT32_MAX) {
        aug_err_set(e, AUG_EUSAGE, -1, "KMAT", "matrix too large (%lld entries)", (long long)nnz);
        goto fail;
    }
    A = cholmod_allocate_sparse((size_t)nfree, (size_t)nfree, (size_t)nnz, 1, 1, 1, CHOLMOD_REAL,
                                cm);
    if (!A) goto nomem;
    int *Ap = A->p, *Ai = A->i;
    double *Ax = A->x;
    /* symbolic: column pointers and row indices */
    int64_t pos = 0;
    for (int64_t j = 0; j < nn; j++)
        for (int c = 0, l = 0; c < d; c++) {
            int32_t col = map[j * d + c];
            if (col < 0) continue;
            l++;
            Ap[col] = (int)pos;
            for (int64_t t = aptr[j]; t < aptr[j + 1]; t++) {
                int32_t k = aind[t];
                int ilim = k == j ? c : d - 1;
                for (int i = 0; i <= ilim; i++)
                    if (map[(int64_t)k * d + i] >= 0) Ai[pos++] = map[(int64_t)k * d + i];
            }
        }
    Ap[nfree] = (int)pos;
    memset(Ax, 0, (size_t)nnz * sizeof *Ax);
    /* numeric: element order, so the summation order is fixed */
    double Ke[AUG_MAX_EMAT];
    int32_t lidx[AUG_MAX_EDOF];
    for (int64_t el = 0; el < m->ne; el++) {
        const int32_t *cn = m->conn + el * nv;
        if (which == AUG_MAT_K) aug_elem_stiffness(m, el, Ke);
        else aug_elem_mass(m, el, 0, Ke);
        for (int a = 0; a < nv; a++)
            for (int i = 0, l = 0; i < d; i++)
                lidx[a * d + i] = map[(int64_t)cn[a] * d + i] >= 0 ? l++ : -1;
        for (int b = 0; b < nv; b++) {
            int32_t jb = cn[b];
            for (int a = 0; a < nv; a++) {
                int32_t ka = cn[a];
                if (ka > jb) continue;
                int64_t t = find_node(aind, aptr[jb], aptr[jb + 1], ka);
                int32_t off = aoff[t];
                for (int j = 0; j < d; j++) {
                    int32_t col = map[(int64_t)jb * d + j];
                    if (col < 0) continue;
                    int64_t base = Ap[col] + off;
                    for (int i = 0; i < d; i++) {
                        if (lidx[a * d + i] < 0 || (ka == jb && i > j)) continue;
                        Ax[base + lidx[a * d + i]] += Ke[(size_t)(b * d + j) * n + a * d + i];
                    }
                }
            }
        }
    }
    free(aptr);
    free(aind);
    free(aoff);
    free(nfc);
    return A;
nomem:
    aug_err_set(e, AUG_ENOMEM, -1, "KMAT", "out of memory");
fail:
    cholmod_free_sparse(&A, cm);
    free(aptr);
    free(aind);
    free(aoff);
    free(nfc);
    return NULL;
}
