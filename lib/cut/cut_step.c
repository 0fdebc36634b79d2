/* One cut step from the mesh edit to its records: MDLT applied to the mesh,
   pull forces and detached pieces as BDLT, the UPDT of AMPS eq. 3.1. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

int aug_cutter_init(aug_cutter *c, aug_mesh *m, int64_t nn0, const int32_t *map0,
                    int64_t nfree0, aug_err *e)
{
    aug_err_clear(e);
    memset(c, 0, sizeof *c);
    c->m = m;
    c->nn0 = nn0;
    c->map0 = map0;
    c->nfree0 = nfree0;
    if (aug_adj_build(&c->adj, m)) goto nomem;
    if (aug_facenbr_build(&c->fn, m, &c->adj)) goto nomem;
    aug_edit_init(&c->ed, m, &c->adj);
    return 0;
nomem:
    aug_cutter_free(c);
    return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
}

void aug_cutter_free(aug_cutter *c)
{
    aug_adj_free(&c->adj);
    aug_facenbr_free(&c->fn);
    aug_pieces_free(&c->pieces);
    aug_edit_free(&c->ed);
    memset(c, 0, sizeof *c);
}

void aug_cut_step_init(aug_cut_step *s, int32_t step)
{
    memset(s, 0, sizeof *s);
    s->step = step;
    aug_mdelta_init(&s->d);
    aug_bdelta_init(&s->bc);
    aug_update_init(&s->u);
    s->bc.step = step;
    s->bad_first = -1;
}

void aug_cut_step_free(aug_cut_step *s)
{
    aug_mdelta_free(&s->d);
    aug_bdelta_free(&s->bc);
    aug_update_free(&s->u);
    free(s->oldconn);
    free(s->seg);
    memset(s, 0, sizeof *s);
}

/* d = the edit as an MDLT; mesh += d; face neighbours refreshed */
int aug_cutter_apply(aug_cutter *c, aug_cut_step *s, aug_err *e)
{
    s->nn_before = c->m->nn;
    s->ne_before = c->m->ne;
    int rc = aug_edit_end(&c->ed, s->step, &s->d, &s->oldconn, e);
    if (!rc) rc = aug_mesh_apply(c->m, &s->d, e);
    if (rc) return rc;
    aug_edit_begin(&c->ed);
    int64_t n = s->d.nmod + s->d.nadd;
    int32_t *ch = aug_malloc((size_t)n * sizeof *ch + 1);
    if (!ch) return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
    memcpy(ch, s->d.elem, (size_t)s->d.nmod * sizeof *ch);
    for (int64_t i = 0; i < s->d.nadd; i++) ch[s->d.nmod + i] = (int32_t)(s->ne_before + i);
    rc = aug_facenbr_update(&c->fn, c->m, &c->adj, ch, n);
    free(ch);
    if (rc) return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
    /* one piece stays one piece when what the step touched still hangs together */
    if (c->one_piece && !aug_facenbr_local_connected(&c->fn, c->m->ne / 4 + 1024)) c->one_piece = 0;
    return 0;
}

/* volume (2-D: area) of piece id over that of the whole mesh */
static double piece_share(const aug_mesh *m, const aug_pieces *p, int32_t id)
{
    double v = 0, all = 0;
    for (int64_t e = 0; e < m->ne; e++) {
        double a = fabs(aug_elem_measure(m, e));
        all += a;
        if (p->piece[e] == id) v += a;
    }
    return all > 0 ? v / all : 0;
}

/* Piece id given copies of the nodes it shares with the rest of the mesh
   (node duplication, paper 001 sec. 4.3.2, as a cut separates): a sliver
   face-disconnected from the body may still hang on one of its edges or
   nodes, and dropped with those nodes kept (aug_detach_drop fixes only the
   piece's own nodes) its elements tied the body's hinge nodes to fixed ones
   by their whole stiffness and mass, a spring that pinned the body there
   (the armadillo of tests/cut_detach.test: max |u| 1.6e5 before the drop,
   2.9e4 after). Once separated the piece holds only its own nodes, and
   fixing them all removes it from K_t exactly: its rows become identity
   rows, the hinge nodes lose its contributions. The copies and re-wired
   elements join the step's MDLT (aug_mdelta_merge); the mesh, adjacency and
   face neighbours follow. 0, or an error. */
static int separate_piece(aug_cutter *c, aug_cut_step *s, const aug_pieces *pp, int32_t id, aug_err *e)
{
    aug_mesh *m = c->m;
    int nv = m->nv;
    int64_t nsh = 0;
    int32_t *sh = NULL, *old2 = NULL, *conn = aug_malloc((size_t)nv * sizeof *conn);
    unsigned char *mk = aug_piece_marks(m, pp, id); /* 3: shared with another piece */
    aug_mdelta d2;
    aug_mdelta_init(&d2);
    if (!conn || !mk) goto nomem;
    for (int64_t v = 0; v < m->nn; v++) nsh += mk[v] == 3;
    if (nsh == 0) goto done;
    sh = aug_malloc((size_t)nsh * sizeof *sh);
    if (!sh) goto nomem;
    nsh = 0;
    for (int64_t v = 0; v < m->nn; v++)
        if (mk[v] == 3) sh[nsh++] = (int32_t)v;
    /* each shared node copied once, in node order; the piece's elements re-wired to the copies */
    for (int64_t i = 0; i < nsh; i++) {
        int32_t v = sh[i], cp = aug_edit_node(&c->ed, aug_edit_x(&c->ed, v), v);
        if (cp < 0) goto nomem;
        for (int32_t t = 0; t < c->adj.cnt[v];) {
            int32_t el = c->adj.list[v][t];
            if (pp->piece[el] != id) { t++; continue; }
            memcpy(conn, aug_edit_conn(&c->ed, el), (size_t)nv * sizeof *conn);
            for (int a = 0; a < nv; a++)
                if (conn[a] == v) conn[a] = cp;
            if (aug_edit_set(&c->ed, el, conn)) goto nomem; /* el leaves v's list */
        }
    }
    int rc = aug_edit_end(&c->ed, s->step, &d2, &old2, e);
    if (!rc) rc = aug_mesh_apply(m, &d2, e);
    if (rc) goto fail;
    aug_edit_begin(&c->ed);
    if (aug_facenbr_update(&c->fn, m, &c->adj, d2.elem, d2.nmod) ||
        aug_mdelta_merge(&s->d, &s->oldconn, nv, m->dim, s->ne_before, &d2, old2))
        goto nomem;
    s->nseparated += nsh;
done:
    free(sh), free(old2), free(conn), free(mk);
    aug_mdelta_free(&d2);
    return 0;
nomem:
    aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
fail:
    free(sh), free(old2), free(conn), free(mk);
    aug_mdelta_free(&d2);
    return e->code;
}

/* bc += pull forces; while a piece is unsupported: error, or bc += its supports;
   u = the UPDT of (d, bc) (AMPS eq. 3.1); then the mesh takes bc */
int aug_cutter_update(aug_cutter *c, aug_cut_step *s, aug_err *e)
{
    aug_err_clear(e);
    int rc;
    s->bc.step = s->step;
    if (c->pull != 0 && (rc = aug_cut_pull(c->m, &c->adj, &s->d, c->pull, c->pull_dir, &s->bc, e))) return rc;
    if (aug_bdelta_finish(&s->bc)) goto nomem;
    /* a piece without support: report it, or hold it and look again */
    for (int round = 0;; round++) {
        aug_pieces *pp = &c->pieces;
        rc = c->one_piece ? aug_detach_find_one(c->m, &c->adj, &s->bc, pp, e)
                          : aug_detach_find(c->m, &c->adj, &c->fn, &s->bc, pp, e);
        if (rc) return rc;
        s->npieces = pp->np;
        c->one_piece = pp->np == 1;
        if (pp->nbad == 0) break;
        int32_t id = pp->bad[0];
        if (round == 0) {
            s->bad_first = pp->first[id];
            s->bad_size = pp->size[id];
            s->d.flags |= AUG_STEP_DETACHED;
        }
        if (c->policy == AUG_DETACH_KEEP) break;
        double share = c->policy == AUG_DETACH_AUTO ? piece_share(c->m, pp, id) : 0;
        int small = c->policy == AUG_DETACH_AUTO && share < AUG_DETACH_SHARE;
        if (c->policy == AUG_DETACH_ERROR || (c->policy == AUG_DETACH_AUTO && !small) || round > pp->np) {
            aug_err_set(e, AUG_ESINGULAR, -1, "MDLT",
                        "step %d: the piece of %lld elements holding element %d has no Dirichlet "
                        "support (%lld pieces; use --detached pin or drop)",
                        (int)s->step, (long long)pp->size[id], (int)pp->first[id], (long long)pp->np);
            if (c->policy == AUG_DETACH_AUTO)
                snprintf(e->msg + strlen(e->msg), sizeof e->msg - strlen(e->msg),
                         " (%.3g of the volume, above %g)", share, AUG_DETACH_SHARE);
            return AUG_ESINGULAR;
        }
        if (small) s->nsmall++, s->small_share += share;
        aug_bdelta add;
        aug_bdelta_init(&add);
        if (c->policy == AUG_DETACH_PIN) {
            rc = aug_detach_pin(c->m, pp, id, &s->bc, &add, e);
            s->d.flags |= AUG_STEP_PINNED;
        } else {
            rc = separate_piece(c, s, pp, id, e);
            if (!rc) rc = aug_detach_drop(c->m, pp, id, &s->bc, &add, e);
            s->d.flags |= AUG_STEP_DROPPED;
        }
        for (int64_t i = 0; rc == 0 && i < add.nfix; i++)
            if (aug_bdelta_fix(&s->bc, add.fix_dof[i], add.fix_val[i])) rc = AUG_ENOMEM;
        aug_bdelta_free(&add);
        if (rc == AUG_ENOMEM) goto nomem;
        if (rc) return rc;
        if (aug_bdelta_finish(&s->bc)) goto nomem;
    }
    rc = aug_update_build_after(c->m, s->nn_before, s->ne_before, s->oldconn, &s->d, &s->bc,
                                c->nn0, c->map0, c->nfree0, c->dyn, &s->u, e);
    if (rc) return rc;
    s->u.step = s->step;
    return aug_mesh_apply_bc(c->m, &s->bc, e);
nomem:
    return aug_err_set(e, AUG_ENOMEM, -1, "BDLT", "out of memory");
}

int aug_cut_step_write(aug_writer *w, const aug_mesh *m, const aug_cut_step *s, int stats,
                       int64_t n, double ms, aug_err *e)
{
    aug_err_clear(e);
    if (aug_write_mdelta(w, m->dim, m->nv, &s->d, e)) return e->code;
    if (!aug_bdelta_empty(&s->bc) && aug_write_bdelta(w, &s->bc, e)) return e->code;
    if (aug_write_update(w, &s->u, e)) return e->code;
    aug_pathrec p = {s->step, m->dim, s->nseg, s->seg};
    if (aug_write_path(w, &p, e)) return e->code;
    if (!stats) return 0;
    aug_kv q;
    aug_kv_init(&q, "cut");
    aug_kv_set(&q, "m", s->u.m);
    aug_kv_set(&q, "k", s->u.k);
    aug_kv_set(&q, "n", (double)n);
    aug_kv_set(&q, "nnew", (double)s->d.nnew);
    aug_kv_set(&q, "nmod", (double)s->d.nmod);
    aug_kv_set(&q, "nadd", (double)s->d.nadd);
    aug_kv_set(&q, "nfix", (double)s->bc.nfix);
    aug_kv_set(&q, "nload", (double)s->bc.nload);
    aug_kv_set(&q, "pieces", (double)s->npieces);
    aug_kv_set(&q, "dropped_small", (double)s->nsmall);
    aug_kv_set(&q, "dropped_share", s->small_share);
    aug_kv_set(&q, "separated", (double)s->nseparated);
    aug_kv_set(&q, "flags", s->d.flags);
    if (aug_write_kv(w, "sTAt", s->step, &q, e)) return e->code;
    aug_kv_init(&q, "cut");
    aug_kv_set(&q, "time_ms", ms);
    return aug_write_kv(w, "tIMe", s->step, &q, e);
}
