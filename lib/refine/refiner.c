/* The refine filter's state across steps: the cut's view and the refined view of
   the mesh, each cut step folded with its refinement into one MDLT (+ BDLT, UPDT
   by AMPS eq. 3.1), and the step's quality figures (thesis 003, sec. 5.1-5.3). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "aug_cut.h"
#include "aug_refine.h"

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return 1e3 * (double)ts.tv_sec + 1e-6 * (double)ts.tv_nsec;
}

void aug_refine_opt_default(aug_refine_opt *o)
{
    memset(o, 0, sizeof *o);
    o->max_aspect = 3;
    o->min_angle = 20; /* beyond the thesis (aspect alone passes 1-degree angles); 0: the thesis */
    o->max_aspect3 = 3;
    o->max_level3 = 3;
    o->flip = 1;
    o->max_new = 0; /* automatic: 1000 + 100 per element of the step's region */
}

/* a[0..need) available (doubling from 1024), new entries -1 */
int aug_refine_grow_i32(int32_t **a, int64_t *cap, int64_t need)
{
    if (need <= *cap) return 0;
    int64_t c = *cap ? *cap : 1024;
    while (c < need) c *= 2;
    int32_t *p = aug_realloc(*a, (size_t)c * sizeof *p);
    if (!p) return -1;
    for (int64_t i = *cap; i < c; i++) p[i] = -1;
    *a = p;
    *cap = c;
    return 0;
}

/* the cut view's per-element arrays (carea0, cel) for ne elements */
static int grow_cut(aug_refiner *r, int64_t ne)
{
    if (ne <= r->capce) return 0;
    int64_t c = r->capce ? r->capce : 1024;
    while (c < ne) c *= 2;
    double *a = aug_realloc(r->carea0, (size_t)c * sizeof *a);
    if (!a) return -1;
    r->carea0 = a;
    int32_t *l = aug_realloc(r->cel, (size_t)c * sizeof *l);
    if (!l) return -1;
    r->cel = l;
    r->capce = c;
    return 0;
}

int aug_refiner_init(aug_refiner *r, const aug_mesh *m, const aug_refine_opt *o, aug_err *e)
{
    memset(r, 0, sizeof *r);
    if (o) r->opt = *o;
    else aug_refine_opt_default(&r->opt);
    if (m->etype == AUG_MEM3) { /* aug_refine_step_mem3: the cut view, the base, the maps */
        if (aug_mesh_copy(&r->cut, m) || aug_mesh_copy(&r->base, m) || aug_refine_mem3_init(r)) goto nomem;
        r->nn0 = m->nn;
        r->map0 = aug_malloc((size_t)(m->nn * m->dim + 1) * sizeof *r->map0);
        if (!r->map0) goto nomem;
        r->nfree0 = aug_dofmap(m, r->map0);
        return 0;
    }
    if (!((m->dim == 2 && m->nv == 3) || (m->dim == 3 && m->nv == 4)))
        return aug_err_set(e, AUG_EDATA, -1, "ELEM", "refine needs tri3 or tet4 elements (a %s mesh is not refined)",
                           aug_etype_name(m->etype));
    int rc;
    if (aug_mesh_copy(&r->cut, m) || aug_mesh_copy(&r->base, m)) goto nomem;
    if ((rc = aug_work_init(&r->work, m))) {
        if (rc == AUG_ENOMEM) goto nomem;
        return aug_err_set(e, rc, -1, "ELEM", "mesh is not manifold (an edge of three triangles)");
    }
    if (m->dim == 2) {
        if (aug_edgemap_init(&r->cadj, (size_t)(2 * m->ne))) goto nomem;
        for (int64_t t = 0; t < m->ne; t++)
            for (int i = 0; i < 3; i++)
                if (aug_edgemap_link(&r->cadj, m->conn[3 * t + i], m->conn[3 * t + (i + 1) % 3],
                                     (int32_t)t) == -1)
                    goto nomem;
    }
    if (grow_cut(r, m->ne) || aug_refine_grow_i32(&r->cnode, &r->capc, m->nn)) goto nomem;
    for (int64_t t = 0; t < m->ne; t++) {
        r->carea0[t] = r->work.area0[t];
        r->cel[t] = (int32_t)t;
    }
    for (int64_t i = 0; i < m->nn; i++) r->cnode[i] = (int32_t)i;
    r->nn0 = m->nn;
    r->map0 = aug_malloc((size_t)(m->nn * m->dim + 1) * sizeof *r->map0);
    if (!r->map0) goto nomem;
    r->nfree0 = aug_dofmap(m, r->map0);
    return 0;
nomem:
    aug_refiner_free(r);
    return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
}

void aug_refiner_free(aug_refiner *r)
{
    aug_mesh_free(&r->cut);
    aug_mesh_free(&r->base);
    aug_work_free(&r->work);
    aug_edgemap_free(&r->cadj);
    free(r->carea0);
    free(r->cel);
    free(r->cnode);
    free(r->own);
    free(r->corig);
    free(r->borig);
    free(r->cre3);
    free(r->conn0);
    free(r->map0);
    free(r->last);
    memset(r, 0, sizeof *r);
}

int aug_refiner_plan(aug_refiner *r, const aug_mdelta *d, aug_err *e)
{
    for (int64_t i = 0; i < d->nmod; i++) {
        int64_t t = d->elem[i];
        if (t < 0) return aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: changed element %d out of range",
                                      (int)d->step, (int)t);
        if (t >= r->nlast) {
            int64_t c = r->nlast ? r->nlast : 1024;
            while (c <= t) c *= 2;
            int32_t *p = aug_realloc(r->last, (size_t)c * sizeof *p);
            if (!p) return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
            for (int64_t k = r->nlast; k < c; k++) p[k] = -1;
            r->last = p;
            r->nlast = c;
        }
        if (d->step > r->last[t]) r->last[t] = d->step;
    }
    return 0;
}

/* parent scores of the base mesh's nodes: FIXD components first, then sets and
   output membership (aug_parent_rule) */
static int32_t *scores(const aug_mesh *m)
{
    int32_t *s = aug_calloc((size_t)m->nn + 1, sizeof *s);
    if (!s) return NULL;
    for (int64_t i = 0; i < m->nfix; i++) s[m->fix_dof[i] / m->dim] += 1024;
    for (int k = 0; k < m->nset; k++)
        for (int64_t i = 0; i < m->sets[k].n; i++)
            if ((s[m->sets[k].nodes[i]] & 1023) < 1000) s[m->sets[k].nodes[i]] += 8;
    if (m->out_kind != AUG_OUT_ALL)
        for (int64_t i = 0; i < m->nout; i++) s[m->out_nodes[i]] |= 1;
    return s;
}

/* The constraints a step adds (BDLT: --constrain, --drag, a piece dropped
   or pinned) name the cut's nodes; the nodes refine made (midpoints,
   centroids, copies: aug_work_creators) lie among them and were left free:
   a box constrained by cut kept 108 of its 577 refined nodes free (|u| up
   to 8e-4 where cut alone gives 0), a dropped piece of the liver six (0.043).
   Such a node takes, per component, the constraint all the nodes it was
   made from have after the step (refine(1): a node on an edge of the fixed
   boundary is fixed), at their mean value (exact for a midpoint under a
   linear or uniform prescribed motion), in node order (its makers come
   first). The state before the step is the base's FIXD, a node new in this
   step inheriting its parent's (formats/stream.md 7.1). A node made at an
   earlier step and constrained then follows its makers when this step
   prescribes one of them anew (a second --constrain of the set with
   another value, --drag): the square's right edge moved from (0.01, 0) to
   (0.05, 0.02) at step 3 left two midpoints refined at step 1 at (0.01, 0). */
int aug_refine_fix_made(const aug_mesh *base, int64_t nn, const int32_t *parent, int64_t pbase,
                        const int32_t *cre, int64_t ncre, aug_bdelta *out, aug_err *e)
{
    int dim = base->dim;
    int64_t nb = base->nn;
    double *v = aug_malloc((size_t)(nn * dim + 1) * sizeof *v);
    if (!v) return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
    for (int64_t j = 0; j < nn; j++)
        for (int c = 0; c < dim; c++) {
            double x;
            int32_t p = j < nb ? -1 : parent[j - pbase];
            v[j * dim + c] = j < nb ? (aug_mesh_fixed(base, (int32_t)(j * dim + c), &x) ? x : NAN)
                                    : (p >= 0 && p < j ? v[(int64_t)p * dim + c] : NAN);
        }
    unsigned char *chg = aug_calloc((size_t)(nn * dim + 1), 1); /* prescribed by this step */
    if (!chg) {
        free(v);
        return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
    }
    for (int64_t i = 0; i < out->nfix; i++)
        if (out->fix_dof[i] >= 0 && out->fix_dof[i] < nn * dim)
            v[out->fix_dof[i]] = out->fix_val[i], chg[out->fix_dof[i]] = 1;
    int rc = 0;
    for (int64_t j = 0; j < nn && !rc && j < ncre; j++) {
        const int32_t *cr = cre + j * 4;
        if (cr[0] < 0) continue;
        for (int c = 0; c < dim && !rc; c++) {
            int64_t dj = j * dim + c;
            double sum = 0;
            int k = 0, moved = 0;
            for (; k < 4 && cr[k] >= 0; k++) {
                double y = v[(int64_t)cr[k] * dim + c];
                if (isnan(y)) break;
                sum += y;
                moved |= chg[(int64_t)cr[k] * dim + c];
            }
            if ((k < 4 && cr[k] >= 0) || (!isnan(v[dj]) && (!moved || v[dj] == sum / k))) continue;
            v[dj] = sum / k, chg[dj] = 1;
            if (aug_bdelta_fix(out, (int32_t)dj, sum / k))
                rc = aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
        }
    }
    free(v);
    free(chg);
    return rc;
}

static int fix_inserted(const aug_refiner *r, aug_bdelta *out, aug_err *e)
{
    const aug_work *W = &r->work;
    return aug_refine_fix_made(&r->base, W->m.nn, W->parent, W->nn_begin, W->cre, W->m.nn, out, e);
}

static int translate_bc(const aug_refiner *r, const aug_bdelta *bc, aug_bdelta *out, aug_err *e)
{
    int dim = r->cut.dim;
    aug_bdelta_init(out);
    out->step = bc->step;
    for (int pass = 0; pass < 2; pass++) {
        int64_t n = pass ? bc->nload : bc->nfix;
        const int32_t *dof = pass ? bc->load_dof : bc->fix_dof;
        const double *val = pass ? bc->load_val : bc->fix_val;
        for (int64_t i = 0; i < n; i++) {
            int64_t node = dof[i] / dim;
            if (dof[i] < 0 || node >= r->cut.nn || r->cnode[node] < 0)
                return aug_err_set(e, AUG_EDATA, -1, "BDLT", "step %d: dof %d is not in the mesh",
                                   (int)bc->step, (int)dof[i]);
            int32_t nd = r->cnode[node] * dim + dof[i] % dim;
            if (pass ? aug_bdelta_load(out, nd, val[i]) : aug_bdelta_fix(out, nd, val[i]))
                return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
        }
    }
    int rc = bc->nfix > 0 ? fix_inserted(r, out, e) : 0;
    aug_bdelta_finish(out);
    return rc;
}

/* which of the n old elements (connectivity oldc in mesh m) holds point p */
static int64_t holder(const aug_mesh *m, const int32_t *oldc, int64_t n, const double *p)
{
    int dim = m->dim, nv = m->nv;
    int64_t best = -1;
    double bb = -INFINITY;
    for (int64_t k = 0; k < n; k++) {
        const int32_t *v = oldc + k * nv;
        double lam = INFINITY;
        if (dim == 2) {
            const double *a = m->x + 2 * v[0], *b = m->x + 2 * v[1], *c = m->x + 2 * v[2];
            double A = aug_orient2d(a, b, c);
            lam = fmin(aug_orient2d(b, c, p), fmin(aug_orient2d(c, a, p), aug_orient2d(a, b, p))) / A;
        } else {
            double J[3][3], y[3];
            const double *x0 = m->x + 3 * v[0];
            for (int r = 0; r < 3; r++) {
                for (int c = 0; c < 3; c++) J[r][c] = m->x[3 * v[c + 1] + r] - x0[r];
                y[r] = p[r] - x0[r];
            }
            double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                         J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
            double l[4], s = 0;
            for (int c = 0; c < 3; c++) { /* Cramer */
                double M[3][3];
                memcpy(M, J, sizeof M);
                for (int r = 0; r < 3; r++) M[r][c] = y[r];
                l[c + 1] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
                            M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                            M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) / det;
                s += l[c + 1];
            }
            l[0] = 1 - s;
            for (int c = 0; c < 4; c++) lam = fmin(lam, l[c]);
        }
        if (lam > bb) bb = lam, best = k;
    }
    return best;
}

/* quality figures of the elements list (n) of mesh m with original measures a0:
   mean and max aspect (thesis 003 eq. 3.10 in 2-D, R / (3 r) in 3-D), mean area
   ratio |A| / A_0 (thesis sec. 5.2) and least angle */
static void qfig(const aug_mesh *m, const int32_t *list, int64_t n, const double *a0, double *mean,
                 double *max, double *ar, double *mina)
{
    *mean = *max = *ar = 0;
    *mina = n ? 180 : 0;
    for (int64_t i = 0; i < n; i++) {
        aug_quality q;
        aug_elem_quality(m, list[i], &q);
        *mean += q.aspect;
        *max = fmax(*max, q.aspect);
        *ar += fabs(q.measure) / a0[i];
        *mina = fmin(*mina, q.min_angle);
    }
    if (n) *mean /= (double)n, *ar /= (double)n;
}

/* One cut step refined (thesis 003 ch. 3.2-3.3, ACDM): the cut's MDLT applied to
   the cut view; its region re-triangulated (aug_refine_region2d, 2-D) or carried
   over (aug_refine_map3d, 3-D); what is still bad among the elements the step
   wrote bisected (aug_bisect2d / aug_bisect3d); the result folded into one MDLT
   against the base (+ BDLT, and its UPDT, paper 001 eq. 3.1, when u != NULL);
   quality figures of the cut's pieces and of the folded step (thesis secs. 5.2-5.3). */
int aug_refine_step(aug_refiner *r, const aug_mdelta *d, const aug_bdelta *bc, const double *seg,
                    int64_t nseg, aug_mdelta *out, aug_bdelta *outbc, aug_update *u,
                    aug_refine_q *q, aug_err *e)
{
    double t0 = now_ms();
    memset(q, 0, sizeof *q);
    aug_mdelta_init(out);
    if (outbc) aug_bdelta_init(outbc);
    aug_mesh *C = &r->cut;
    aug_work *W = &r->work;
    int nv = C->nv, dim = C->dim, rc = 0;
    int64_t nnc = C->nn, nec = C->ne;
    int32_t *oldc = NULL, *list = NULL, *score = NULL;
    double *la0 = NULL, *olda0 = NULL;
    for (int64_t i = 0; i < d->nmod; i++)
        if (d->elem[i] < 0 || d->elem[i] >= nec)
            return aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: changed element %d out of range",
                               (int)d->step, (int)d->elem[i]);
    oldc = aug_malloc((size_t)(d->nmod * nv + 1) * sizeof *oldc);
    olda0 = aug_malloc((size_t)(d->nmod + 1) * sizeof *olda0);
    if (!oldc || !olda0) goto nomem;
    for (int64_t i = 0; i < d->nmod; i++) {
        memcpy(oldc + i * nv, C->conn + (int64_t)d->elem[i] * nv, (size_t)nv * sizeof *oldc);
        olda0[i] = r->carea0[d->elem[i]];
    }
    if ((rc = aug_mesh_apply(C, d, e))) goto out;
    if (grow_cut(r, C->ne) || aug_refine_grow_i32(&r->cnode, &r->capc, C->nn)) goto nomem;
    for (int64_t i = nnc; i < C->nn; i++) r->cnode[i] = -1;
    if (dim == 2) {
        for (int64_t i = 0; i < d->nmod; i++)
            for (int j = 0; j < 3; j++)
                aug_edgemap_unlink(&r->cadj, oldc[3 * i + j], oldc[3 * i + (j + 1) % 3], d->elem[i]);
        for (int64_t i = 0; i < d->nmod + d->nadd; i++) {
            int32_t t = i < d->nmod ? d->elem[i] : (int32_t)(nec + i - d->nmod);
            for (int j = 0; j < 3; j++) {
                int lk = aug_edgemap_link(&r->cadj, C->conn[3 * t + j], C->conn[3 * t + (j + 1) % 3], t);
                if (lk == -1) goto nomem;
                if (lk == -2) {
                    rc = aug_err_set(e, AUG_EDATA, -1, "MDLT",
                                     "step %d: the cut mesh has an edge of three triangles",
                                     (int)d->step);
                    goto out;
                }
            }
        }
    }
    /* the cut's pieces: original measure from the old element holding them; figures */
    int64_t np = d->nmod + d->nadd;
    list = aug_malloc((size_t)(np + 1) * sizeof *list);
    la0 = aug_malloc((size_t)(np + 1) * sizeof *la0);
    if (!list || !la0) goto nomem;
    for (int64_t i = 0; i < np; i++) {
        int32_t t = i < d->nmod ? d->elem[i] : (int32_t)(nec + i - d->nmod);
        double cen[3] = {0, 0, 0};
        for (int j = 0; j < nv; j++)
            for (int c = 0; c < dim; c++) cen[c] += C->x[(int64_t)C->conn[t * nv + j] * dim + c] / nv;
        int64_t k = holder(C, oldc, d->nmod, cen);
        list[i] = t;
        la0[i] = k >= 0 ? olda0[k] : fabs(aug_elem_measure(C, t));
    }
    for (int64_t i = 0; i < np; i++) r->carea0[list[i]] = la0[i];
    qfig(C, list, np, la0, &q->aspect_mean0, &q->aspect_max0, &q->area_ratio0, &q->min_angle0);
    q->written0 = np;
    q->cut_added = d->nadd;
    q->cut_nodes = d->nnew;

    aug_work_begin(W, d->step);
    double t1 = now_ms();
    if (dim == 2) rc = aug_refine_region2d(r, d, oldc, nnc, nec, seg, nseg, q, e);
    else rc = aug_refine_map3d(r, d, oldc, nnc, nec, q, e);
    if (rc) goto out;
    double t2 = now_ms();
    q->t_cdt = t2 - t1;
    /* ACDM: bisect what is still bad among the elements this step wrote */
    int64_t ns = 0;
    int64_t *seeds = aug_malloc((size_t)(W->m.ne - W->ne_begin + W->nmod + 1) * sizeof *seeds);
    if (!seeds) goto nomem;
    for (int64_t i = 0; i < W->nmod; i++) seeds[ns++] = W->mod[i];
    for (int64_t t = W->ne_begin; t < W->m.ne; t++) seeds[ns++] = t;
    score = scores(&r->base);
    if (!score) {
        free(seeds);
        goto nomem;
    }
    aug_parent_rule pr = {score, r->base.nn};
    aug_bisect_stats bs;
    W->keep = r->last;
    W->nkeep = r->nlast;
    W->max_new = r->opt.max_new > 0 ? r->opt.max_new : aug_refine_default_cap(q->region > 0 ? q->region : d->nmod, dim);
    rc = dim == 2 ? aug_bisect2d(W, seeds, ns, &r->opt, &pr, &bs, e)
                  : aug_bisect3d(W, seeds, ns, &r->opt, &pr, &bs, e);
    free(seeds);
    if (rc) goto out;
    q->bisections = bs.bisections;
    q->flips = bs.flips;
    q->capped = bs.capped;
    if (dim == 3) { /* cut elements whose work element was split are refined now */
        for (int64_t t = 0; t < W->m.ne; t++) {
            if (W->stamp[t] != W->step) continue;
            int32_t c = W->own[t];
            if (c >= 0 && r->cel[c] != (int32_t)t) r->cel[c] = -1;
        }
    }
    q->t_bisect = now_ms() - t2;

    if ((rc = aug_work_delta(W, d->step, d->flags, out, NULL, e))) goto out;
    if (bc && outbc && (rc = translate_bc(r, bc, outbc, e))) goto out;
    double t3 = now_ms();
    if (u && (rc = aug_update_build_bc(&r->base, out, bc ? outbc : NULL, r->nn0, r->map0, r->nfree0,
                                       r->dyn, u, e)))
        goto out;
    q->t_update = now_ms() - t3;
    if ((rc = aug_mesh_apply(&r->base, out, e))) goto out;
    if (bc && outbc && ((rc = aug_mesh_apply_bc(&r->base, outbc, e)) || (rc = aug_mesh_apply_bc(C, bc, e))))
        goto out;

    /* figures of the folded step's elements */
    free(list);
    free(la0);
    np = out->nmod + out->nadd;
    list = aug_malloc((size_t)(np + 1) * sizeof *list);
    la0 = aug_malloc((size_t)(np + 1) * sizeof *la0);
    if (!list || !la0) goto nomem;
    /* bad_left: elements left bad in shape, also those --area-ratio kept
       from refinement (its limit made them "not bad" to the bisection:
       bad_left 0 beside aspect_max 56.8 on the square) */
    aug_refine_opt shape = r->opt;
    shape.area_ratio = 0;
    for (int64_t i = 0; i < np; i++) {
        list[i] = i < out->nmod ? out->elem[i] : (int32_t)(W->ne_begin + i - out->nmod);
        la0[i] = W->area0[list[i]];
        /* (3-D: bad_left read 0 whatever was left above the bounds) */
        if (dim == 2 ? aug_bisect2d_bad(W, list[i], &shape) : aug_bisect3d_bad(W, list[i], &shape)) q->bad_left++;
    }
    qfig(&W->m, list, np, la0, &q->aspect_mean, &q->aspect_max, &q->area_ratio, &q->min_angle);
    q->written = np;
    q->added = out->nadd;
    q->nodes = out->nnew;
    q->t_total = now_ms() - t0;
    rc = 0;
    goto out;
nomem:
    rc = aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
out:
    free(oldc);
    free(olda0);
    free(list);
    free(la0);
    free(score);
    return rc;
}

int aug_refine_bc_only(aug_refiner *r, int32_t step, const aug_bdelta *bc, aug_bdelta *outbc,
                       aug_update *u, aug_err *e)
{
    int rc = translate_bc(r, bc, outbc, e);
    if (rc) return rc;
    outbc->step = step;
    if (u) {
        aug_mdelta d0;
        aug_mdelta_init(&d0);
        d0.step = step;
        /* empty arrays, not NULL: memcpy of zero bytes from NULL is undefined */
        int32_t i0[1] = {0};
        double x0[3] = {0, 0, 0};
        d0.parent = d0.elem = d0.conn = d0.conn_add = d0.mat_add = i0;
        d0.x = x0;
        if ((rc = aug_update_build_bc(&r->base, &d0, outbc, r->nn0, r->map0, r->nfree0, r->dyn, u, e)))
            return rc;
    }
    if ((rc = aug_mesh_apply_bc(&r->base, outbc, e))) return rc;
    return aug_mesh_apply_bc(&r->cut, bc, e);
}

void aug_refine_q_kv(const aug_refine_q *q, int dim, aug_kv *qual, aug_kv *time)
{
    aug_kv_init(qual, "refine");
    /* the quality of the elements a step wrote; over none (a blade still
       outside the mesh) there is none: left out, not 0, which read as a
       zero-degree element */
    if (q->written > 0) {
        aug_kv_set(qual, "aspect_mean", q->aspect_mean);
        aug_kv_set(qual, "aspect_max", q->aspect_max);
        aug_kv_set(qual, "area_ratio", q->area_ratio);
        aug_kv_set(qual, dim == 2 ? "min_angle" : "min_dihedral", q->min_angle);
    }
    if (q->written0 > 0) {
        aug_kv_set(qual, "aspect_mean0", q->aspect_mean0);
        aug_kv_set(qual, "aspect_max0", q->aspect_max0);
        aug_kv_set(qual, "area_ratio0", q->area_ratio0);
        aug_kv_set(qual, dim == 2 ? "min_angle0" : "min_dihedral0", q->min_angle0);
    }
    aug_kv_set(qual, "intersected", (double)q->intersected);
    aug_kv_set(qual, "region", (double)q->region);
    aug_kv_set(qual, "elems_added", (double)q->added);
    aug_kv_set(qual, "nodes_added", (double)q->nodes);
    aug_kv_set(qual, "cut_elems", (double)q->cut_added);
    aug_kv_set(qual, "cut_nodes", (double)q->cut_nodes);
    aug_kv_set(qual, "bad_left", (double)q->bad_left);
    aug_kv_set(qual, "bisections", (double)q->bisections);
    aug_kv_set(qual, "flips", (double)q->flips);
    aug_kv_set(qual, "capped", (double)q->capped);
    aug_kv_init(time, "refine");
    aug_kv_set(time, "time_ms", q->t_total);
    aug_kv_set(time, "remesh_ms", q->t_cdt);
    aug_kv_set(time, "bisect_ms", q->t_bisect);
    aug_kv_set(time, "update_ms", q->t_update);
    /* refine's own work (re-mesh and bisection) per intersected element */
    aug_kv_set(time, "ms_per_elem", q->intersected ? (q->t_cdt + q->t_bisect) / (double)q->intersected : 0);
}
