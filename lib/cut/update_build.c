/* Cut-matrix numbering and the principal submatrix update of one cut step
   (AMPS paper eq. 3.1; formats/stream.md 7.2). */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

int64_t aug_cut_index(const aug_mesh *m, int64_t nn0, const int32_t *map0, int64_t nfree0,
                      int64_t node, int c)
{
    if (node < nn0) return map0[node * m->dim + c];
    return nfree0 + (node - nn0) * m->dim + c;
}

typedef struct bstate {
    const aug_mesh *A;
    int64_t nnb;
    const aug_bdelta *bc;
} bstate;


static int fixed_prev(const bstate *s, int32_t dof, double *v)
{
    return dof < s->nnb * s->A->dim && aug_mesh_fixed(s->A, dof, v);
}

static int fixed_now(const bstate *s, int32_t dof, double *v)
{
    if (s->bc) {
        int64_t k = aug_find_i32(s->bc->fix_dof, s->bc->nfix, dof);
        if (k >= 0) {
            if (v) *v = s->bc->fix_val[k];
            return 1;
        }
    }
    return aug_mesh_fixed(s->A, dof, v);
}

static double load_prev(const bstate *s, int32_t dof)
{
    return dof < s->nnb * s->A->dim ? aug_mesh_load(s->A, dof) : 0.0;
}

static double load_now(const bstate *s, int32_t dof)
{
    if (s->bc) {
        int64_t k = aug_find_i32(s->bc->load_dof, s->bc->nload, dof);
        if (k >= 0) return s->bc->load_val[k];
    }
    return aug_mesh_load(s->A, dof);
}

/* element stiffness of the element with connectivity conn and material mat in A */
static void stiffness(const aug_mesh *A, const int32_t *conn, int32_t mat, double *Ke)
{
    aug_mesh t;
    double x[12];
    int32_t c[4] = {0, 1, 2, 3}, mt = mat;
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
    aug_elem_stiffness(&t, 0, Ke);
}

typedef struct hent {
    int64_t idx;
    int32_t dof;
} hent;

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

#define NOMEM() aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory")

/* K_t = [K_{t-1} 0; 0 I_k] - Hbar (E + [0 0; 0 I_k]) Hbar', i.e.
   E = -(K_t - [K_{t-1} 0; 0 0]) on Hbar, and df = f_t - [f_{t-1}; 0] on Hbar,
   summed over the elements whose connectivity or constraint state changed. */
int aug_update_build_after(const aug_mesh *A, int64_t nnb, int64_t neb, const int32_t *oldconn,
                           const aug_mdelta *d, const aug_bdelta *bc, int64_t nn0,
                           const int32_t *map0, int64_t nfree0, aug_update *u, aug_err *e)
{
    aug_err_clear(e);
    aug_update_init(u);
    u->step = d->step;
    int dim = A->dim, nv = A->nv, nd = nv * dim;
    if (A->nn - nnb != d->nnew || A->ne - neb != d->nadd)
        return aug_err_set(e, AUG_EUSAGE, -1, "UPDT", "mesh does not match its delta");
    if (bc)
        for (int64_t i = 0; i < bc->nfix; i++)
            if (bc->fix_dof[i] < 0 || bc->fix_dof[i] >= A->nn * dim)
                return aug_err_set(e, AUG_EDATA, -1, "BDLT", "constraint dof %d out of range",
                                   (int)bc->fix_dof[i]);
    bstate st = {A, nnb, bc};
    int64_t nprev = nfree0 + dim * (nnb - nn0), k = dim * d->nnew;
    int32_t *el = NULL;
    hent *h = NULL;
    unsigned char *mark = NULL;
    double *E = NULL, *fo = NULL, *fn = NULL;
    int64_t nel = 0, capel = d->nmod + d->nadd + 16;
    el = aug_malloc((size_t)capel * sizeof *el);
    if (!el) goto nomem;
    for (int64_t i = 0; i < d->nmod; i++) el[nel++] = d->elem[i];
    for (int64_t i = neb; i < A->ne; i++) el[nel++] = (int32_t)i;
    if (bc && bc->nfix) {
        mark = aug_calloc((size_t)A->nn, 1);
        if (!mark) goto nomem;
        for (int64_t i = 0; i < bc->nfix; i++) mark[bc->fix_dof[i] / dim] = 1;
        for (int64_t i = 0; i < A->ne; i++) {
            int hit = 0;
            for (int a = 0; a < nv; a++) hit |= mark[A->conn[i * nv + a]];
            if (!hit) continue;
            if (nel == capel) {
                capel *= 2;
                int32_t *q = aug_realloc(el, (size_t)capel * sizeof *q);
                if (!q) goto nomem;
                el = q;
            }
            el[nel++] = (int32_t)i;
        }
    }
    qsort(el, (size_t)nel, sizeof *el, aug_cmp_i32);
    {
        int64_t w = 0;
        for (int64_t i = 0; i < nel; i++)
            if (w == 0 || el[w - 1] != el[i]) el[w++] = el[i];
        nel = w;
    }
    /* H: old matrix indices of the nodes of changed elements, of changed loads
       and constraints, except identity rows that stay as they were */
    int64_t nh = 0, caph = nel * 2 * nd + (bc ? bc->nfix + bc->nload : 0) + 1;
    h = aug_malloc((size_t)caph * sizeof *h);
    if (!h) goto nomem;
#define ADD_DOF(DOF)                                                                          \
    do {                                                                                      \
        int32_t dof_ = (DOF);                                                                 \
        int64_t g_ = aug_cut_index(A, nn0, map0, nfree0, dof_ / dim, dof_ % dim);             \
        double vp_ = 0, vn_ = 0;                                                              \
        if (g_ < 0 || g_ >= nprev) break;                                                     \
        if (fixed_prev(&st, dof_, &vp_) && fixed_now(&st, dof_, &vn_) && vp_ == vn_) break;   \
        h[nh].idx = g_;                                                                       \
        h[nh++].dof = dof_;                                                                   \
    } while (0)
    for (int64_t q = 0; q < nel; q++) {
        int32_t i = el[q];
        int64_t mp = aug_find_i32(d->elem, d->nmod, i);
        const int32_t *oc = mp >= 0 ? oldconn + mp * nv : (i < neb ? A->conn + (int64_t)i * nv : NULL);
        for (int a = 0; a < nv; a++)
            for (int c = 0; c < dim; c++) {
                if (oc && oc[a] < nnb) ADD_DOF(oc[a] * dim + c);
                int32_t nb = A->conn[(int64_t)i * nv + a];
                if (nb < nnb) ADD_DOF(nb * dim + c);
            }
    }
    if (bc) {
        for (int64_t i = 0; i < bc->nfix; i++)
            if (bc->fix_dof[i] < nnb * dim) ADD_DOF(bc->fix_dof[i]);
        for (int64_t i = 0; i < bc->nload; i++)
            if (bc->load_dof[i] < nnb * dim) ADD_DOF(bc->load_dof[i]);
    }
#undef ADD_DOF
    qsort(h, (size_t)nh, sizeof *h, cmp_hent);
    {
        int64_t w = 0;
        for (int64_t i = 0; i < nh; i++)
            if (w == 0 || h[w - 1].idx != h[i].idx) h[w++] = h[i];
        nh = w;
    }
    int64_t m = nh, s = m + k;
    if (s > (1 << 20)) {
        free(el);
        free(h);
        free(mark);
        return aug_err_set(e, AUG_EDATA, -1, "UPDT", "update of order %lld is too large",
                           (long long)s);
    }
    E = aug_calloc((size_t)(s * s) + 1, sizeof *E);
    fo = aug_calloc((size_t)s + 1, sizeof *fo);
    fn = aug_calloc((size_t)s + 1, sizeof *fn);
    u->H = aug_malloc((size_t)m * sizeof *u->H + 1);
    u->df = aug_calloc((size_t)s + 1, sizeof *u->df);
    if (!E || !fo || !fn || !u->H || !u->df) goto nomem;
    for (int64_t q = 0; q < nel; q++) {
        int32_t i = el[q];
        int64_t mp = aug_find_i32(d->elem, d->nmod, i);
        const int32_t *oc = mp >= 0 ? oldconn + mp * nv : (i < neb ? A->conn + (int64_t)i * nv : NULL);
        const int32_t *nc = A->conn + (int64_t)i * nv;
        double Ko[144], Kn[144];
        int64_t pos[12];
        int fr[12];
        double val[12];
        for (int pass = 0; pass < 2; pass++) {
            const int32_t *cc = pass == 0 ? oc : nc;
            double *K = pass == 0 ? Ko : Kn;
            double sign = pass == 0 ? 1.0 : -1.0;
            double *lift = pass == 0 ? fo : fn;
            if (!cc) continue;
            if (pass == 1 && oc && memcmp(oc, nc, (size_t)nv * sizeof *nc) == 0)
                memcpy(Kn, Ko, sizeof Kn);
            else
                stiffness(A, cc, A->mat[i], K);
            for (int a = 0; a < nv; a++)
                for (int c = 0; c < dim; c++) {
                    int l = a * dim + c;
                    int32_t dof = cc[a] * dim + c;
                    int64_t g = aug_cut_index(A, nn0, map0, nfree0, cc[a], c);
                    int con = pass == 0 ? fixed_prev(&st, dof, &val[l]) : fixed_now(&st, dof, &val[l]);
                    fr[l] = g >= 0 && !con;
                    pos[l] = fr[l] ? hpos(h, m, nprev, g) : -1;
                    if (!con) val[l] = 0;
                }
            for (int b = 0; b < nd; b++) {
                if (fr[b]) {
                    for (int a = 0; a < nd; a++)
                        if (fr[a] && pos[a] <= pos[b]) E[pos[a] + pos[b] * s] += sign * K[a + b * nd];
                } else if (val[b] != 0) {
                    for (int a = 0; a < nd; a++)
                        if (fr[a]) lift[pos[a]] -= K[a + b * nd] * val[b];
                }
            }
        }
    }
    for (int64_t p = 0; p < s; p++) {
        int32_t dof;
        if (p < m) {
            dof = h[p].dof;
            u->H[p] = (int32_t)h[p].idx;
        } else {
            int64_t r = p - m;
            dof = (int32_t)((nnb + r / dim) * dim + r % dim);
        }
        double vp = 0, vn = 0;
        int fp = p < m && fixed_prev(&st, dof, &vp), fw = fixed_now(&st, dof, &vn);
        if (fw && !fp) E[p + p * s] -= 1.0;
        if (p >= m) u->df[p] = fw ? vn : load_now(&st, dof) + fn[p];
        else if (!fp && !fw) u->df[p] = (load_now(&st, dof) - load_prev(&st, dof)) + (fn[p] - fo[p]);
        else if (!fp && fw) u->df[p] = vn - (load_prev(&st, dof) + fo[p]);
        else u->df[p] = vn - vp;
    }
    for (int64_t j = 0; j < s; j++)
        for (int64_t i = j + 1; i < s; i++) E[i + j * s] = E[j + i * s];
    /* drop the old indices whose row of E and load change are exactly zero
       (e.g. neighbours whose couplings all go to constrained DOFs) */
    int64_t *keep = aug_malloc((size_t)s * sizeof *keep + 1), nk = 0;
    if (!keep) goto nomem;
    for (int64_t p = 0; p < s; p++) {
        int nz = p >= m || u->df[p] != 0;
        for (int64_t q = 0; q < s && !nz; q++) nz = E[p + q * s] != 0;
        if (nz) keep[nk++] = p;
    }
    if (nk < s) {
        int64_t m2 = 0;
        for (int64_t a = 0; a < nk; a++) {
            if (keep[a] < m) u->H[m2++] = u->H[keep[a]];
            u->df[a] = u->df[keep[a]];
        }
        /* in place, in increasing target order: every source lies at or after its target */
        for (int64_t b = 0; b < nk; b++)
            for (int64_t a = 0; a < nk; a++) E[a + b * nk] = E[keep[a] + keep[b] * s];
        m = m2;
        s = nk;
    }
    free(keep);
    u->m = (int32_t)m;
    u->k = (int32_t)k;
    u->E = E;
    free(el);
    free(h);
    free(mark);
    free(fo);
    free(fn);
    return 0;
nomem:
    free(el);
    free(h);
    free(mark);
    free(E);
    free(fo);
    free(fn);
    aug_update_free(u);
    return NOMEM();
}

int aug_update_build_bc(const aug_mesh *before, const aug_mdelta *d, const aug_bdelta *bc,
                        int64_t nn0, const int32_t *map0, int64_t nfree0, aug_update *u,
                        aug_err *e)
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
        rc = aug_update_build_after(&t, before->nn, before->ne, old, d, bc, nn0, map0, nfree0, u, e);
    free(old);
    aug_mesh_free(&t);
    return rc;
nomem:
    free(old);
    aug_mesh_free(&t);
    return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory");
}

int aug_update_build(const aug_mesh *before, const aug_mdelta *d, int64_t nn0,
                     const int32_t *map0, int64_t nfree0, aug_update *u, aug_err *e)
{
    return aug_update_build_bc(before, d, NULL, nn0, map0, nfree0, u, e);
}
