/* A cut step on a membrane (mem3) sheet refined in each triangle's own plane:
   longest-edge bisection and flips between coplanar triangles, neither of
   which changes the sheet's shape (thesis 003 secs. 3.2.2-3.3). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_refine.h"

static void sub(const double *a, const double *b, double *r) { r[0] = a[0] - b[0], r[1] = a[1] - b[1], r[2] = a[2] - b[2]; }
static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross(const double *a, const double *b, double *r)
{
    r[0] = a[1] * b[2] - a[2] * b[1], r[1] = a[2] * b[0] - a[0] * b[2], r[2] = a[0] * b[1] - a[1] * b[0];
}

/* triangle t of the edit in its own plane: edge lengths L[k] of (c[k], c[k+1]),
   aspect = l_max / l_min (thesis 003 eq. 3.10), the least angle (degrees),
   the unit normal; returns the local index of the longest edge */
static int tri_geom(const aug_edit *ed, int64_t t, double *aspect, double *amin, double *n)
{
    const int32_t *c = aug_edit_conn(ed, t);
    double v[3][3], L[3];
    for (int k = 0; k < 3; k++) {
        sub(aug_edit_x(ed, c[(k + 1) % 3]), aug_edit_x(ed, c[k]), v[k]);
        L[k] = sqrt(dot(v[k], v[k]));
    }
    int lo = 0, hi = 0;
    for (int k = 1; k < 3; k++) lo = L[k] < L[lo] ? k : lo, hi = L[k] > L[hi] ? k : hi;
    *aspect = L[hi] / L[lo];
    *amin = 180;
    for (int k = 0; k < 3; k++) { /* the angle at c[k] between v[k] and -v[k-1] */
        const double *p = v[k], *q = v[(k + 2) % 3];
        double cs = -dot(p, q) / (L[k] * L[(k + 2) % 3]);
        *amin = fmin(*amin, acos(fmax(-1, fmin(1, cs))) * 180 / M_PI);
    }
    cross(v[0], v[2], n);
    double l = sqrt(dot(n, n));
    for (int k = 0; k < 3; k++) n[k] = -n[k] / l;
    return hi;
}

/* bad: aspect > max_aspect or least angle < min_angle (each when > 0, the
   angle only when --min-angle was given: bisection with flips in each
   triangle's plane cannot flip across a fold of the sheet, and does not
   reach 20 degrees there) */
static int bad(const aug_edit *ed, int64_t t, const aug_refine_opt *o, int *longest)
{
    double a, m, n[3];
    *longest = tri_geom(ed, t, &a, &m, n);
    return (o->max_aspect > 0 && a > o->max_aspect) || (o->min_angle_given && o->min_angle > 0 && m < o->min_angle);
}

/* the other triangle on edge (p, q) than t, -1 for a boundary edge */
static int64_t across(const aug_edit *ed, int64_t t, int32_t p, int32_t q)
{
    const aug_adj *adj = ed->adj;
    for (int32_t i = 0; i < adj->cnt[p]; i++) {
        int32_t s = adj->list[p][i];
        const int32_t *c = aug_edit_conn(ed, s);
        if (s != t && (c[0] == q || c[1] == q || c[2] == q)) return s;
    }
    return -1;
}

/* Lawson's flip of edge (p, q) of triangle t = (r, p, q) (Lepp-Delaunay,
   thesis 003 sec. 3.3): with (q, p, s) across it in the same plane (normals
   within 1e-10) and s inside the circle of r, p, q (the angles at r and s
   sum above 180 degrees), pq becomes rs: (r, p, s), (r, s, q), in that
   plane, so the sheet is unchanged; then the new edges opposite r. */
static int legalize(aug_edit *ed, int64_t t, int32_t r, int depth, int64_t *flips)
{
    if (depth > 64) return 0;
    const int32_t *c = aug_edit_conn(ed, t);
    int k = c[0] == r ? 0 : c[1] == r ? 1 : 2;
    int32_t p = c[(k + 1) % 3], q = c[(k + 2) % 3];
    int64_t u = across(ed, t, p, q);
    if (u < 0) return 0;
    const int32_t *cu = aug_edit_conn(ed, u);
    int32_t s = cu[0] != p && cu[0] != q ? cu[0] : cu[1] != p && cu[1] != q ? cu[1] : cu[2];
    double a0, m0, n0[3], a1, m1, n1[3];
    tri_geom(ed, t, &a0, &m0, n0);
    tri_geom(ed, u, &a1, &m1, n1);
    if (dot(n0, n1) < 1 - 1e-10) return 0;
    const double *X[4] = {aug_edit_x(ed, r), aug_edit_x(ed, p), aug_edit_x(ed, q), aug_edit_x(ed, s)};
    double e1[3], e2[3], f1[3], f2[3];
    sub(X[1], X[0], e1), sub(X[2], X[0], e2), sub(X[1], X[3], f1), sub(X[2], X[3], f2);
    double ar = acos(fmax(-1, fmin(1, dot(e1, e2) / sqrt(dot(e1, e1) * dot(e2, e2)))));
    double as = acos(fmax(-1, fmin(1, dot(f1, f2) / sqrt(dot(f1, f1) * dot(f2, f2)))));
    if (!(ar + as > M_PI * (1 + 1e-12))) return 0;
    int32_t t0[3] = {r, p, s}, t1[3] = {r, s, q};
    if (aug_edit_set(ed, t, t0) || aug_edit_set(ed, u, t1)) return -1;
    ++*flips;
    if (legalize(ed, t, r, depth + 1, flips) || legalize(ed, u, r, depth + 1, flips)) return -1;
    return 0;
}

/* Rivara's longest-edge propagation path from t (thesis 003 sec. 3.2.2,
   fig. 3.12): from a triangle to the one across its longest edge until that
   edge is the longest of both or on the boundary (a cut's lip, the sheet's
   edge), the terminal edge (pa, pb) to bisect; -1 when the path runs longer
   than 64 */
static int lepp(const aug_edit *ed, int64_t t, int32_t *pa, int32_t *pb)
{
    int64_t cur = t;
    for (int step = 0; step < 64; step++) {
        double a, m, n[3];
        int k = tri_geom(ed, cur, &a, &m, n);
        const int32_t *c = aug_edit_conn(ed, cur);
        int32_t x = c[k], y = c[(k + 1) % 3];
        int64_t nb = across(ed, cur, x, y);
        if (nb < 0) { /* a terminal edge on the boundary: its midpoint is on the sheet's edge */
            *pa = x, *pb = y;
            return 0;
        }
        int kn = tri_geom(ed, nb, &a, &m, n);
        const int32_t *cn = aug_edit_conn(ed, nb);
        int32_t xn = cn[kn], yn = cn[(kn + 1) % 3];
        if ((xn == x && yn == y) || (xn == y && yn == x)) {
            *pa = x, *pb = y;
            return 0;
        }
        cur = nb;
    }
    return -1;
}

/* the triangles of node r, legalized (after r split an edge) */
static int legalize_star(aug_edit *ed, int32_t r, int64_t *flips)
{
    int32_t star[64];
    int n = 0;
    for (int32_t i = 0; i < ed->adj->cnt[r] && n < 64; i++) star[n++] = ed->adj->list[r][i];
    for (int i = 0; i < n; i++) {
        const int32_t *c = aug_edit_conn(ed, star[i]);
        if ((c[0] == r || c[1] == r || c[2] == r) && legalize(ed, star[i], r, 0, flips)) return -1;
    }
    return 0;
}

/* the maps of the intact mesh: cut-view node and element i are base i */
int aug_refine_mem3_init(aug_refiner *r)
{
    const aug_mesh *m = &r->base;
    if (aug_refine_grow_i32(&r->cnode, &r->capc, m->nn + 1) || aug_refine_grow_i32(&r->cel, &r->capce, m->ne + 1) ||
        aug_refine_grow_i32(&r->own, &r->capown, m->ne + 1))
        return -1;
    for (int64_t i = 0; i < m->nn; i++) r->cnode[i] = (int32_t)i;
    for (int64_t t = 0; t < m->ne; t++) r->cel[t] = r->own[t] = (int32_t)t;
    return 0;
}

/* One cut step on mem3 (aug_refine_step's contract): the cut's MDLT d is
   replayed into an edit of r->base through the maps of cut-view nodes and
   elements to base ones (r->cnode, r->cel; a triangle refine changed at an
   earlier step cannot be re-cut, AUG_EDATA, as for tets), bc's DOFs mapped
   the same way; then, worst first among the triangles the step wrote and
   those refinement makes, a bad triangle (bad) has the terminal edge of its
   longest-edge propagation path (lepp) bisected at the midpoint
   (aug_split_edge: both triangles on it, the new node's parent the less
   constrained end; a lip's half keeps its side, so the cut stays open and
   its chords stay edges, in halves), until it is good, and the star of the new node
   legalized by coplanar flips -- thesis 003 fig. 3.12's recursive local
   bisection with Lepp-Delaunay flips, measured in each triangle's plane. Stops at max_new new nodes (capped). The folded MDLT out, its
   UPDT (eq. 3.1, when u != NULL), the quality figures q. */
int aug_refine_step_mem3(aug_refiner *r, const aug_mdelta *d, const aug_bdelta *bc, aug_mdelta *out,
                         aug_bdelta *outbc, aug_update *u, aug_refine_q *q, aug_err *e)
{
    aug_err_clear(e);
    memset(q, 0, sizeof *q);
    aug_mdelta_init(out);
    aug_mesh *B = &r->base;
    aug_adj adj;
    aug_edit ed;
    int32_t *old = NULL;
    int64_t *work = NULL, nw = 0, capw = 0;
    int rc = 0;
    if (aug_adj_build(&adj, B)) return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
    aug_edit_init(&ed, B, &adj);
    aug_mesh *C = &r->cut;
    int64_t nnc = C->nn, nec = C->ne;
    if (aug_refine_grow_i32(&r->cnode, &r->capc, nnc + d->nnew + 1) || aug_refine_grow_i32(&r->cel, &r->capce, nec + d->nadd + 1)) goto nomem;
    for (int64_t i = 0; i < d->nmod; i++)
        if (d->elem[i] < 0 || d->elem[i] >= nec || r->cel[d->elem[i]] < 0) {
            rc = aug_err_set(e, AUG_EDATA, -1, "MDLT",
                             d->elem[i] < 0 || d->elem[i] >= nec
                                 ? "step %d: changed element %d out of range"
                                 : "step %d: the cut changes triangle %d, which refine changed at an earlier "
                                   "step (re-cutting refined triangles of a membrane is not supported)",
                             (int)d->step, (int)d->elem[i]);
            goto done;
        }
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t par = d->parent[i] >= 0 && d->parent[i] < nnc + i ? r->cnode[d->parent[i]] : -1;
        if (par < 0) {
            rc = aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: bad parent of new node %lld", (int)d->step,
                             (long long)i);
            goto done;
        }
        int32_t b = aug_edit_node(&ed, d->x + i * 3, par);
        if (b < 0) goto nomem;
        r->cnode[nnc + i] = b;
    }
    int32_t mc[3];
    for (int64_t i = 0; i < d->nmod + d->nadd; i++) {
        const int32_t *c = i < d->nmod ? d->conn + i * 3 : d->conn_add + (i - d->nmod) * 3;
        for (int k = 0; k < 3; k++) {
            if (c[k] < 0 || c[k] >= nnc + d->nnew) {
                rc = aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: element node %d out of range", (int)d->step,
                                 (int)c[k]);
                goto done;
            }
            mc[k] = r->cnode[c[k]];
        }
        if (i < d->nmod) {
            if (aug_edit_set(&ed, r->cel[d->elem[i]], mc)) goto nomem;
        } else {
            int64_t b = aug_edit_elem(&ed, mc, d->mat_add[i - d->nmod]);
            if (b < 0 || aug_refine_grow_i32(&r->own, &r->capown, b + 1)) goto nomem;
            r->cel[nec + i - d->nmod] = (int32_t)b;
            r->own[b] = (int32_t)(nec + i - d->nmod);
        }
    }
    if ((rc = aug_mesh_apply(C, d, e))) goto done;
    capw = d->nmod + d->nadd + 64;
    work = aug_malloc((size_t)capw * sizeof *work);
    if (!work) goto nomem;
    for (int64_t i = 0; i < d->nmod; i++) work[nw++] = r->cel[d->elem[i]];
    for (int64_t i = 0; i < d->nadd; i++) work[nw++] = B->ne + i;
    double a, m, n[3];
    for (int64_t i = 0; i < nw; i++) {
        tri_geom(&ed, work[i], &a, &m, n);
        q->aspect_mean0 += a / (double)nw, q->aspect_max0 = fmax(q->aspect_max0, a);
        q->min_angle0 = i ? fmin(q->min_angle0, m) : m;
    }
    q->intersected = q->region = d->nmod;
    q->cut_added = d->nadd, q->cut_nodes = d->nnew;
    int64_t budget = r->opt.max_new > 0 ? r->opt.max_new : 1000 + 100 * (d->nmod + d->nadd), nodes0 = ed.nnew;
    for (int64_t k = 0; k < nw; k++) {
        int lng;
        int64_t t = work[k];
        if (!bad(&ed, t, &r->opt, &lng)) continue;
        int32_t pa, pb;
        if (lepp(&ed, t, &pa, &pb)) continue;
        if (ed.nnew - nodes0 >= budget) {
            q->capped = 1;
            break;
        }
        int32_t nr = aug_split_edge(&ed, NULL, pa, pb, 0.5, e);
        if (nr < 0) {
            rc = e->code;
            goto done;
        }
        q->bisections++;
        if (legalize_star(&ed, nr, &q->flips)) goto nomem;
        /* t again, and the star of the new node */
        if (nw + 2 + ed.adj->cnt[nr] > capw) {
            capw = 2 * (nw + 2 + ed.adj->cnt[nr]);
            int64_t *wq = aug_realloc(work, (size_t)capw * sizeof *wq);
            if (!wq) goto nomem;
            work = wq;
        }
        work[nw++] = t;
        for (int32_t i = 0; i < ed.adj->cnt[nr]; i++) work[nw++] = ed.adj->list[nr][i];
    }
    q->nodes = ed.nnew - nodes0;
    q->added = ed.nadd - d->nadd;
    /* figures of the elements the folded step writes */
    int64_t cnt = 0;
    for (int64_t i = 0; i < ed.nmod + ed.nadd; i++) {
        int64_t t = i < ed.nmod ? ed.mod_elem[i] : ed.ne0 + (i - ed.nmod);
        int lng;
        tri_geom(&ed, t, &a, &m, n);
        q->aspect_mean += a, q->aspect_max = fmax(q->aspect_max, a);
        q->min_angle = cnt ? fmin(q->min_angle, m) : m;
        q->bad_left += bad(&ed, t, &r->opt, &lng);
        cnt++;
    }
    if (cnt) q->aspect_mean /= (double)cnt;
    /* a cut-view triangle whose base triangle refinement changed is no longer mapped */
    for (int64_t i = 0; i < ed.nmod + ed.nadd; i++) {
        int64_t b = i < ed.nmod ? ed.mod_elem[i] : ed.ne0 + (i - ed.nmod);
        if (aug_refine_grow_i32(&r->own, &r->capown, b + 1)) goto nomem;
        int32_t c = r->own[b];
        if (c < 0) continue;
        const int32_t *cb = aug_edit_conn(&ed, b), *cc = C->conn + (int64_t)c * 3;
        if (cb[0] != r->cnode[cc[0]] || cb[1] != r->cnode[cc[1]] || cb[2] != r->cnode[cc[2]]) r->cel[c] = -1, r->own[b] = -1;
    }
    q->area_ratio = q->area_ratio0 = NAN; /* no original measure is kept for mem3 */
    if ((rc = aug_edit_end(&ed, d->step, out, &old, e))) goto done;
    out->flags = d->flags;
    if (outbc && bc) {
        aug_bdelta_init(outbc);
        outbc->step = bc->step;
        for (int64_t i = 0; i < bc->nfix + bc->nload && !rc; i++) {
            int32_t dof = i < bc->nfix ? bc->fix_dof[i] : bc->load_dof[i - bc->nfix];
            if (dof < 0 || dof / 3 >= C->nn) {
                rc = aug_err_set(e, AUG_EDATA, -1, "BDLT", "step %d: DOF %d out of range", (int)bc->step, (int)dof);
                goto done;
            }
            dof = r->cnode[dof / 3] * 3 + dof % 3;
            rc = i < bc->nfix ? aug_bdelta_fix(outbc, dof, bc->fix_val[i])
                              : aug_bdelta_load(outbc, dof, bc->load_val[i - bc->nfix]);
        }
        if (rc || aug_bdelta_finish(outbc)) goto nomem;
    }
    if (u && (rc = aug_update_build_bc(B, out, bc ? outbc : NULL, r->nn0, r->map0, r->nfree0, r->dyn, u, e)))
        goto done;
    if ((rc = aug_mesh_apply(B, out, e))) goto done;
    if (bc && outbc && ((rc = aug_mesh_apply_bc(B, outbc, e)) || (rc = aug_mesh_apply_bc(C, bc, e)))) goto done;
    goto done;
nomem:
    rc = aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
done:
    free(work);
    free(old);
    aug_edit_free(&ed);
    aug_adj_free(&adj);
    return rc;
}
