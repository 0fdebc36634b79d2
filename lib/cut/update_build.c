/* Cut-matrix numbering and the principal submatrix update of one cut step
   (AMPS paper eq. 3.1; formats/stream.md 7.2). */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

/* cut-matrix index of (node, c): map0 for original nodes, nfree0 + (node - nn0)
   dim + c for nodes the cut added (formats/stream.md 7.2) */
int64_t aug_cut_index(const aug_mesh *m, int64_t nn0, const int32_t *map0, int64_t nfree0,
                      int64_t node, int c)
{
    if (node < nn0) return map0[node * m->dim + c];
    return nfree0 + (node - nn0) * m->dim + c;
}

typedef struct hent {
    int64_t idx;
    int32_t dof;
} hent;

/* the state of one update's construction (aug_update_build_after) */
typedef struct ubuild {
    const aug_mesh *A;          /* the mesh after the step's MDLT */
    int64_t nnb, neb;           /* node and element counts before it */
    const int32_t *oldconn;
    const aug_mdelta *d;
    const aug_bdelta *bc;       /* the step's constraints and loads, or NULL */
    int64_t nn0, nfree0;        /* cut-matrix numbering */
    const int32_t *map0;
    aug_update *u;
    aug_err *e;
    int dim, nv, nd;
    int64_t nprev, k;           /* order of K_{t-1}; DOFs added */
    int32_t *el;                /* the elements to difference, increasing */
    int64_t nel;
    hent *h;                    /* Hbar's old indices, increasing */
    int64_t m, s;               /* |H|, |Hbar| = m + k */
    double *E, *fo, *fn;        /* E (s x s); the constrained values' lift before / after */
    const aug_dynp *dyn;        /* dynamics: E of A = cM M + cK K, with EK, EM */
    double *EK, *EM;
} ubuild;

static int fixed_prev(const ubuild *b, int32_t dof, double *v)
{
    return dof < b->nnb * b->A->dim && aug_mesh_fixed(b->A, dof, v);
}

static int fixed_now(const ubuild *b, int32_t dof, double *v)
{
    if (b->bc) {
        int64_t k = aug_find_i32(b->bc->fix_dof, b->bc->nfix, dof);
        if (k >= 0) {
            if (v) *v = b->bc->fix_val[k];
            return 1;
        }
    }
    return aug_mesh_fixed(b->A, dof, v);
}

static double load_prev(const ubuild *b, int32_t dof)
{
    return dof < b->nnb * b->A->dim ? aug_mesh_load(b->A, dof) : 0.0;
}

static double load_now(const ubuild *b, int32_t dof)
{
    if (b->bc) {
        int64_t k = aug_find_i32(b->bc->load_dof, b->bc->nload, dof);
        if (k >= 0) return b->bc->load_val[k];
    }
    return aug_mesh_load(b->A, dof);
}

/* element stiffness (and, Me non-NULL, the mass of kind lumped; be non-NULL,
   the load of the body force, aug_elem_body) of the element with
   connectivity conn and material mat in A */
static void element(const aug_mesh *A, const int32_t *conn, int32_t mat, double *Ke, double *Me,
                    int lumped, double *be)
{
    aug_mesh t;
    double x[AUG_MAX_EDOF];
    int32_t c[AUG_MAX_NV] = {0, 1, 2, 3, 4, 5, 6, 7}, mt = mat;
    memset(&t, 0, sizeof t);
    for (int a = 0; a < A->nv; a++)
        for (int k = 0; k < A->dim; k++) x[a * A->dim + k] = A->x[conn[a] * A->dim + k];
    t.dim = A->dim;
    t.etype = A->etype;
    t.nv = A->nv;
    t.nn = A->nv;
    t.x = x;
    t.ne = 1;
    t.conn = c;
    t.mat = &mt;
    t.nmat = A->nmat;
    t.mats = A->mats;
    memcpy(t.grav, A->grav, sizeof t.grav);
    aug_elem_stiffness(&t, 0, Ke);
    if (Me) aug_elem_mass(&t, 0, lumped, Me);
    if (be) aug_elem_body(&t, 0, be);
}

static int cmp_hent(const void *a, const void *b)
{
    const hent *x = a, *y = b;
    return (x->idx > y->idx) - (x->idx < y->idx);
}

/* position of matrix index g in Hbar: H by bisection, new indices after m */
static int64_t hpos(const hent *h, int64_t m, int64_t nprev, int64_t g)
{
    if (g >= nprev) return m + (g - nprev);
    int64_t lo = 0, hi = m - 1;
    while (lo <= hi) {
        int64_t mid = lo + (hi - lo) / 2;
        if (h[mid].idx == g) return mid;
        if (h[mid].idx < g) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}

/* the connectivity of element i before the step, NULL for an added one */
static const int32_t *old_conn(const ubuild *b, int32_t i)
{
    int64_t mp = aug_find_i32(b->d->elem, b->d->nmod, i);
    if (mp >= 0) return b->oldconn + mp * b->nv;
    return i < b->neb ? b->A->conn + (int64_t)i * b->nv : NULL;
}

#define NOMEM(b) aug_err_set((b)->e, AUG_ENOMEM, -1, "UPDT", "out of memory")

/* the mesh matches its delta; the constraints name DOFs of the mesh */
static int check_input(ubuild *b)
{
    const aug_bdelta *bc = b->bc;
    if (b->A->nn - b->nnb != b->d->nnew || b->A->ne - b->neb != b->d->nadd)
        return aug_err_set(b->e, AUG_EUSAGE, -1, "UPDT", "mesh does not match its delta");
    for (int64_t i = 0; bc && i < bc->nfix; i++)
        if (bc->fix_dof[i] < 0 || bc->fix_dof[i] >= b->A->nn * b->dim)
            return aug_err_set(b->e, AUG_EDATA, -1, "BDLT", "constraint dof %d out of range", (int)bc->fix_dof[i]);
    return 0;
}

/* the elements whose stiffness enters E: changed, added, and those touching
   a node the step constrains (increasing, once each) */
static int changed_elements(ubuild *b)
{
    const aug_mesh *A = b->A;
    const aug_bdelta *bc = b->bc;
    int64_t cap = b->d->nmod + b->d->nadd + 16;
    b->el = aug_malloc((size_t)cap * sizeof *b->el);
    if (!b->el) return NOMEM(b);
    for (int64_t i = 0; i < b->d->nmod; i++) b->el[b->nel++] = b->d->elem[i];
    for (int64_t i = b->neb; i < A->ne; i++) b->el[b->nel++] = (int32_t)i;
    if (bc && bc->nfix) {
        unsigned char *mark = aug_calloc((size_t)A->nn, 1);
        if (!mark) return NOMEM(b);
        for (int64_t i = 0; i < bc->nfix; i++) mark[bc->fix_dof[i] / b->dim] = 1;
        for (int64_t i = 0; i < A->ne; i++) {
            int hit = 0;
            for (int a = 0; a < b->nv; a++) hit |= mark[A->conn[i * b->nv + a]];
            if (!hit) continue;
            if (b->nel == cap) {
                int32_t *q = aug_realloc(b->el, (size_t)(cap *= 2) * sizeof *q);
                if (!q) {
                    free(mark);
                    return NOMEM(b);
                }
                b->el = q;
            }
            b->el[b->nel++] = (int32_t)i;
        }
        free(mark);
    }
    qsort(b->el, (size_t)b->nel, sizeof *b->el, aug_cmp_i32);
    int64_t w = 0;
    for (int64_t i = 0; i < b->nel; i++)
        if (w == 0 || b->el[w - 1] != b->el[i]) b->el[w++] = b->el[i];
    b->nel = w;
    return 0;
}

/* dof's old matrix index into H, unless it has none or is an identity row
   that stays as it was (constrained to the same value before and after) */
static void add_index(ubuild *b, int32_t dof)
{
    int64_t g = aug_cut_index(b->A, b->nn0, b->map0, b->nfree0, dof / b->dim, dof % b->dim);
    double vp = 0, vn = 0;
    if (g < 0 || g >= b->nprev) return;
    if (fixed_prev(b, dof, &vp) && fixed_now(b, dof, &vn) && vp == vn) return;
    b->h[b->m].idx = g;
    b->h[b->m++].dof = dof;
}

/* H: old matrix indices of the nodes of the elements (before and after), of
   changed loads and constraints (increasing, once each); Hbar = H + the k
   new DOFs */
static int index_set(ubuild *b)
{
    const aug_bdelta *bc = b->bc;
    int dim = b->dim, nv = b->nv;
    int64_t cap = b->nel * 2 * b->nd + (bc ? bc->nfix + bc->nload : 0) + 1;
    b->h = aug_malloc((size_t)cap * sizeof *b->h);
    if (!b->h) return NOMEM(b);
    for (int64_t q = 0; q < b->nel; q++) {
        int32_t i = b->el[q];
        const int32_t *oc = old_conn(b, i), *nc = b->A->conn + (int64_t)i * nv;
        for (int a = 0; a < nv; a++)
            for (int c = 0; c < dim; c++) {
                if (oc && oc[a] < b->nnb) add_index(b, oc[a] * dim + c);
                if (nc[a] < b->nnb) add_index(b, nc[a] * dim + c);
            }
    }
    for (int64_t i = 0; bc && i < bc->nfix; i++)
        if (bc->fix_dof[i] < b->nnb * dim) add_index(b, bc->fix_dof[i]);
    for (int64_t i = 0; bc && i < bc->nload; i++)
        if (bc->load_dof[i] < b->nnb * dim) add_index(b, bc->load_dof[i]);
    qsort(b->h, (size_t)b->m, sizeof *b->h, cmp_hent);
    int64_t w = 0;
    for (int64_t i = 0; i < b->m; i++)
        if (w == 0 || b->h[w - 1].idx != b->h[i].idx) b->h[w++] = b->h[i];
    b->m = w;
    b->s = b->m + b->k;
    /* E is dense (formats/stream.md 7.2): a step that changes more than
       AUG_UPDT_MAX_ORDER matrix indices (2 GiB of E; a piece of most of the
       mesh dropped, every DOF of it an identity row) is refused before it is
       allocated, written, and read by every tool downstream */
    if (b->s > AUG_UPDT_MAX_ORDER)
        return aug_err_set(b->e, AUG_EDATA, -1, "UPDT",
                           "step %d: the update changes %lld matrix indices (m %lld, k %lld), above %d: its "
                           "dense E would take %.3g GB; cut fewer nodes a step (refine: a smaller "
                           "--max-new), or --detached pin a large piece cut loose",
                           (int)b->d->step, (long long)b->s, (long long)b->m, (long long)b->k,
                           AUG_UPDT_MAX_ORDER, 8e-9 * (double)b->s * (double)b->s);
    b->E = aug_calloc((size_t)(b->s * b->s) + 1, sizeof *b->E);
    if (b->dyn) {
        b->EK = aug_calloc((size_t)(b->s * b->s) + 1, sizeof *b->EK);
        b->EM = aug_calloc((size_t)(b->s * b->s) + 1, sizeof *b->EM);
        if (!b->EK || !b->EM) return NOMEM(b);
    }
    b->fo = aug_calloc((size_t)b->s + 1, sizeof *b->fo);
    b->fn = aug_calloc((size_t)b->s + 1, sizeof *b->fn);
    b->u->H = aug_malloc((size_t)b->m * sizeof *b->u->H + 1);
    b->u->df = aug_calloc((size_t)b->s + 1, sizeof *b->u->df);
    if (!b->E || !b->fo || !b->fn || !b->u->H || !b->u->df) return NOMEM(b);
    return 0;
}

/* E += sign K_e on the element's free DOFs in Hbar (upper triangle), and
   lift -= K_e(:, j) v_j for its constrained DOFs j of value v_j (now: after
   the step, else before; lift NULL: none), lift += be (the element's
   body-force load, NULL: none) on its free DOFs: df carries fn - fo
   (formats/stream.md 5.8) */
static void add_element(ubuild *b, double *E, const int32_t *cc, int now, const double *K,
                        const double *be, double sign, double *lift)
{
    int dim = b->dim, nd = b->nd;
    int64_t pos[AUG_MAX_EDOF], s = b->s;
    int fr[AUG_MAX_EDOF];
    double val[AUG_MAX_EDOF];
    for (int a = 0; a < b->nv; a++)
        for (int c = 0; c < dim; c++) {
            int l = a * dim + c;
            int32_t dof = cc[a] * dim + c;
            int64_t g = aug_cut_index(b->A, b->nn0, b->map0, b->nfree0, cc[a], c);
            int con = now ? fixed_now(b, dof, &val[l]) : fixed_prev(b, dof, &val[l]);
            fr[l] = g >= 0 && !con;
            pos[l] = fr[l] ? hpos(b->h, b->m, b->nprev, g) : -1;
            if (!con) val[l] = 0;
        }
    for (int j = 0; j < nd; j++) {
        if (fr[j]) {
            for (int a = 0; a < nd; a++)
                if (fr[a] && pos[a] <= pos[j]) E[pos[a] + pos[j] * s] += sign * K[a + j * nd];
        } else if (val[j] != 0 && lift) {
            for (int a = 0; a < nd; a++)
                if (fr[a]) lift[pos[a]] -= K[a + j * nd] * val[j];
        }
    }
    for (int a = 0; be && lift && a < nd; a++)
        if (fr[a] && pos[a] >= 0) lift[pos[a]] += be[a];
}

/* the element's matrices into E (statics: K with the lift and the body-force
   load be; dynamics: A = cM M + cK K into E, K with them into EK, M into EM) */
static void add_matrices(ubuild *b, const int32_t *cc, int now, const double *K, const double *M,
                         const double *be, double sign, double *lift)
{
    if (!b->dyn) {
        add_element(b, b->E, cc, now, K, be, sign, lift);
        return;
    }
    double Ae[AUG_MAX_EMAT];
    for (int i = 0; i < b->nd * b->nd; i++) Ae[i] = b->dyn->cM * M[i] + b->dyn->cK * K[i];
    add_element(b, b->E, cc, now, Ae, NULL, sign, NULL);
    add_element(b, b->EK, cc, now, K, be, sign, lift);
    add_element(b, b->EM, cc, now, M, NULL, sign, NULL);
}

/* -(K_t - [K_{t-1} 0; 0 0]) on Hbar: each element's stiffness (and mass)
   before (+) and after (-), with the lifts of the constrained values into fo
   and fn */
static void stiffness_change(ubuild *b)
{
    const aug_mesh *A = b->A;
    int lumped = b->dyn && b->dyn->mass == 2;
    for (int64_t q = 0; q < b->nel; q++) {
        int32_t i = b->el[q];
        const int32_t *oc = old_conn(b, i), *nc = A->conn + (int64_t)i * b->nv;
        double Ko[AUG_MAX_EMAT], Kn[AUG_MAX_EMAT], Mo[AUG_MAX_EMAT], Mn[AUG_MAX_EMAT];
        double bo[AUG_MAX_EDOF], bn[AUG_MAX_EDOF];
        double *mo = b->dyn ? Mo : NULL, *mn = b->dyn ? Mn : NULL;
        if (oc) {
            element(A, oc, A->mat[i], Ko, mo, lumped, bo);
            add_matrices(b, oc, 0, Ko, mo, bo, 1.0, b->fo);
        }
        if (oc && memcmp(oc, nc, (size_t)b->nv * sizeof *nc) == 0) {
            memcpy(Kn, Ko, sizeof Kn);
            memcpy(bn, bo, sizeof bn);
            if (mn) memcpy(Mn, Mo, sizeof Mn);
        } else {
            element(A, nc, A->mat[i], Kn, mn, lumped, bn);
        }
        add_matrices(b, nc, 1, Kn, mn, bn, -1.0, b->fn);
    }
}

/* per position p of Hbar: H_p (its old matrix index, p < m); E_pp -= 1 where
   the step constrains a DOF that was free or is new (its row becomes an
   identity row); df_p = f_t - [f_{t-1}; 0] there, constrained values and
   their lifts included; then E symmetric from its upper triangle */
static void rows_and_rhs(ubuild *b)
{
    int64_t m = b->m, s = b->s;
    int dim = b->dim;
    for (int64_t p = 0; p < s; p++) {
        int32_t dof;
        if (p < m) {
            dof = b->h[p].dof;
            b->u->H[p] = (int32_t)b->h[p].idx;
        } else {
            int64_t r = p - m;
            dof = (int32_t)((b->nnb + r / dim) * dim + r % dim);
        }
        double vp = 0, vn = 0, *df = b->u->df;
        int fp = p < m && fixed_prev(b, dof, &vp), fw = fixed_now(b, dof, &vn);
        if (fw && !fp) {
            b->E[p + p * s] -= 1.0;
            if (b->dyn) b->EK[p + p * s] -= 1.0, b->EM[p + p * s] -= 1.0;
        }
        if (p >= m) df[p] = fw ? vn : load_now(b, dof) + b->fn[p];
        else if (!fp && !fw) df[p] = (load_now(b, dof) - load_prev(b, dof)) + (b->fn[p] - b->fo[p]);
        else if (!fp && fw) df[p] = vn - (load_prev(b, dof) + b->fo[p]);
        else df[p] = vn - vp;
    }
    double *Es[3] = {b->E, b->EK, b->EM};
    for (int c = 0; c < (b->dyn ? 3 : 1); c++)
        for (int64_t j = 0; j < s; j++)
            for (int64_t i = j + 1; i < s; i++) Es[c][i + j * s] = Es[c][j + i * s];
}

/* drop the old indices whose row of E and load change are exactly zero
   (e.g. neighbours whose couplings all go to constrained DOFs) */
static int drop_zero_rows(ubuild *b)
{
    int64_t m = b->m, s = b->s, nk = 0;
    aug_update *u = b->u;
    int64_t *keep = aug_malloc((size_t)s * sizeof *keep + 1);
    if (!keep) return NOMEM(b);
    for (int64_t p = 0; p < s; p++) {
        int nz = p >= m || u->df[p] != 0;
        for (int64_t q = 0; q < s && !nz; q++)
            nz = b->E[p + q * s] != 0 || (b->dyn && (b->EK[p + q * s] != 0 || b->EM[p + q * s] != 0));
        if (nz) keep[nk++] = p;
    }
    if (nk < s) {
        int64_t m2 = 0;
        for (int64_t a = 0; a < nk; a++) {
            if (keep[a] < m) u->H[m2++] = u->H[keep[a]];
            u->df[a] = u->df[keep[a]];
        }
        /* in place, in increasing target order: every source lies at or after its target */
        double *Es[3] = {b->E, b->EK, b->EM};
        for (int c = 0; c < (b->dyn ? 3 : 1); c++)
            for (int64_t j = 0; j < nk; j++)
                for (int64_t a = 0; a < nk; a++) Es[c][a + j * nk] = Es[c][keep[a] + keep[j] * s];
        b->m = m2;
        b->s = nk;
    }
    free(keep);
    return 0;
}

/* K_t = [K_{t-1} 0; 0 I_k] - Hbar (E + [0 0; 0 I_k]) Hbar', i.e.
   E = -(K_t - [K_{t-1} 0; 0 0]) on Hbar, and df = f_t - [f_{t-1}; 0] on Hbar,
   summed over the elements whose connectivity or constraint state changed:
   the elements, the index set, the stiffness change, the constrained rows
   and right-hand side, the zero rows dropped. */
int aug_update_build_after(const aug_mesh *A, int64_t nnb, int64_t neb, const int32_t *oldconn,
                           const aug_mdelta *d, const aug_bdelta *bc, int64_t nn0,
                           const int32_t *map0, int64_t nfree0, const aug_dynp *dyn,
                           aug_update *u, aug_err *e)
{
    aug_err_clear(e);
    aug_update_init(u);
    u->step = d->step;
    ubuild b;
    memset(&b, 0, sizeof b);
    b.A = A, b.nnb = nnb, b.neb = neb, b.oldconn = oldconn, b.d = d, b.bc = bc;
    b.nn0 = nn0, b.map0 = map0, b.nfree0 = nfree0, b.u = u, b.e = e, b.dyn = dyn;
    b.dim = A->dim, b.nv = A->nv, b.nd = A->nv * A->dim;
    b.nprev = nfree0 + b.dim * (nnb - nn0), b.k = b.dim * d->nnew;
    int rc = check_input(&b);
    if (rc) return rc;
    if (!(rc = changed_elements(&b)) && !(rc = index_set(&b))) {
        stiffness_change(&b);
        rows_and_rhs(&b);
        rc = drop_zero_rows(&b);
    }
    free(b.el);
    free(b.h);
    free(b.fo);
    free(b.fn);
    if (rc) {
        free(b.E), free(b.EK), free(b.EM);
        aug_update_free(u);
        return rc;
    }
    u->m = (int32_t)b.m;
    u->k = (int32_t)b.k;
    u->E = b.E;
    u->EK = b.EK, u->EM = b.EM;
    return 0;
}

/* the UPDT of delta d plus boundary changes bc on mesh before
   (aug_update_build_after on a copy with d applied; paper 001 eq. 3.1) */
int aug_update_build_bc(const aug_mesh *before, const aug_mdelta *d, const aug_bdelta *bc,
                        int64_t nn0, const int32_t *map0, int64_t nfree0, const aug_dynp *dyn,
                        aug_update *u, aug_err *e)
{
    aug_err_clear(e);
    aug_mesh t;
    int32_t *old = NULL;
    int rc;
    if (aug_mesh_copy(&t, before)) goto nomem;
    for (int64_t i = 0; i < d->nmod; i++)
        if (d->elem[i] < 0 || d->elem[i] >= before->ne || (i > 0 && d->elem[i] <= d->elem[i - 1])) {
            aug_mesh_free(&t);
            return aug_err_set(e, AUG_EDATA, -1, "MDLT", "changed elements not increasing or out of range");
        }
    old = aug_malloc((size_t)(d->nmod * before->nv) * sizeof *old + 1);
    if (!old) goto nomem;
    for (int64_t i = 0; i < d->nmod; i++)
        memcpy(old + i * before->nv, before->conn + (int64_t)d->elem[i] * before->nv,
               (size_t)before->nv * sizeof *old);
    rc = aug_mesh_apply(&t, d, e);
    if (!rc)
        rc = aug_update_build_after(&t, before->nn, before->ne, old, d, bc, nn0, map0, nfree0, dyn,
                                    u, e);
    free(old);
    aug_mesh_free(&t);
    return rc;
nomem:
    free(old);
    aug_mesh_free(&t);
    return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
}

/* aug_update_build_bc without boundary changes */
int aug_update_build(const aug_mesh *before, const aug_mdelta *d, int64_t nn0,
                     const int32_t *map0, int64_t nfree0, aug_update *u, aug_err *e)
{
    return aug_update_build_bc(before, d, NULL, nn0, map0, nfree0, NULL, u, e);
}
