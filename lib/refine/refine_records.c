/* One cut step's records through the refiner: its MDLT, BDLT, UPDT and pATH are
   read, the step refined (aug_refine_step, or aug_refine_bc_only for a
   constraint-only step), and the step written again in its order: the folded
   MDLT, the translated BDLT, the rebuilt UPDT, the other records as they were
   (a fELD or rEAC of the unrefined mesh is dropped; on a dynamic stream the
   rebuilt UPDT carries its UPKM), then qUAl and tIMe. */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_refine.h"

typedef struct group {
    int imd, ibc, iup;          /* positions of MDLT, BDLT, UPDT; -1 if absent */
    double *seg;                /* every pATH's segments, concatenated */
    int64_t nseg;
} group;

/* stage 1: find the step's records; a second MDLT/BDLT/UPDT, a step refined already */
static int collect(const aug_rec *recs, int n, int dim, group *g, aug_err *e)
{
    g->imd = g->ibc = g->iup = -1;
    for (int i = 0; i < n; i++) {
        const aug_rec *rec = &recs[i];
        int *slot = !memcmp(rec->type, "MDLT", 4) ? &g->imd : !memcmp(rec->type, "BDLT", 4) ? &g->ibc
                  : !memcmp(rec->type, "UPDT", 4) ? &g->iup : NULL;
        if (slot) {
            if (*slot >= 0)
                return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "a second %s in step %d",
                                   rec->type, (int)rec->step);
            *slot = i;
            if (slot == &g->iup) { /* a malformed UPDT is refused, never rebuilt */
                aug_update u;
                int rc = aug_read_update(rec, &u, e);
                aug_update_free(&u);
                if (rc) return rc;
            }
        } else if (!memcmp(rec->type, "pATH", 4)) {
            aug_pathrec p;
            if (aug_read_path(rec, &p, e)) {
                aug_pathrec_free(&p);
                return e->code;
            }
            if (p.dim != dim) {
                aug_pathrec_free(&p);
                return aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type,
                                   "dimension %d of a %d-D mesh", p.dim, dim);
            }
            double *q = aug_realloc(g->seg, (size_t)((g->nseg + p.nseg) * 2 * dim + 1) * sizeof *q);
            if (!q) {
                aug_pathrec_free(&p);
                return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
            }
            g->seg = q;
            memcpy(g->seg + g->nseg * 2 * dim, p.seg, (size_t)(p.nseg * 2 * dim) * sizeof *q);
            g->nseg += p.nseg;
            aug_pathrec_free(&p);
        } else if (!memcmp(rec->type, "qUAl", 4)) {
            aug_kv kv;
            if (aug_read_kv(rec, &kv, e)) return e->code;
            if (!strcmp(kv.tag, "refine"))
                return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                                   "step %d was refined already (refine the cut's own output)",
                                   (int)rec->step);
        }
    }
    return 0;
}

static int at(aug_err *e, const aug_rec *rec)
{
    if (e->record < 0) e->record = rec->index, memcpy(e->type, rec->type, 5);
    return e->code;
}

int aug_refine_records(aug_refiner *r, const aug_rec *recs, int n, int32_t step, aug_writer *w,
                       aug_err *e)
{
    aug_err_clear(e);
    int dim = r->cut.dim, nv = r->cut.nv, have_q = 0, rc = 0;
    group g = {-1, -1, -1, NULL, 0};
    aug_mdelta d, out;
    aug_bdelta bc, outbc;
    aug_update u;
    aug_refine_q q;
    aug_mdelta_init(&d);
    aug_mdelta_init(&out);
    aug_bdelta_init(&bc);
    aug_bdelta_init(&outbc);
    aug_update_init(&u);
    if ((rc = collect(recs, n, dim, &g, e))) goto done;
    if (g.ibc >= 0 && (rc = aug_read_bdelta(&recs[g.ibc], &bc, e))) goto done;
    /* stage 2: refine */
    if (g.imd >= 0) {
        const aug_rec *rec = &recs[g.imd];
        if ((rc = aug_read_mdelta(rec, dim, nv, &d, e))) goto done;
        if ((rc = r->base.etype == AUG_MEM3
                      ? aug_refine_step_mem3(r, &d, g.ibc >= 0 ? &bc : NULL, g.seg, g.nseg, &out, &outbc,
                                             g.iup >= 0 ? &u : NULL, &q, e)
                      : aug_refine_step(r, &d, g.ibc >= 0 ? &bc : NULL, g.seg, g.nseg, &out, &outbc,
                                        g.iup >= 0 ? &u : NULL, &q, e))) {
            rc = at(e, rec);
            goto done;
        }
        have_q = 1;
    } else if (g.ibc >= 0) {
        aug_mdelta d0; /* mem3: an empty MDLT, refined (nothing) with its bc */
        aug_mdelta_init(&d0);
        int32_t i0[1] = {0};
        double x0[3] = {0, 0, 0};
        d0.step = recs[g.ibc].step;
        d0.parent = d0.elem = d0.conn = d0.conn_add = d0.mat_add = i0;
        d0.x = x0;
        if ((rc = r->base.etype == AUG_MEM3
                      ? aug_refine_step_mem3(r, &d0, &bc, NULL, 0, &out, &outbc, g.iup >= 0 ? &u : NULL, &q, e)
                      : aug_refine_bc_only(r, recs[g.ibc].step, &bc, &outbc, g.iup >= 0 ? &u : NULL, e))) {
            rc = at(e, &recs[g.ibc]);
            goto done;
        }
    } else if (g.iup >= 0 && (r->cut.nn != r->base.nn || r->cut.ne != r->base.ne)) {
        rc = aug_err_set(e, AUG_EDATA, recs[g.iup].index, "UPDT",
                         "step %d: an update without MDLT or BDLT cannot be renumbered after refinement",
                         (int)recs[g.iup].step);
        goto done;
    }
    /* stage 3: write the step again */
    for (int i = 0; i < n && !rc; i++) {
        const aug_rec *rec = &recs[i];
        if (i == g.imd) rc = aug_write_mdelta(w, dim, nv, &out, e);
        else if (i == g.ibc) {
            outbc.step = rec->step;
            rc = aug_write_bdelta(w, &outbc, e);
        } else if (i == g.iup && (g.imd >= 0 || g.ibc >= 0)) {
            u.step = rec->step;
            rc = aug_write_update(w, &u, e);
        } else if (!memcmp(rec->type, "UPKM", 4) && g.iup >= 0 && (g.imd >= 0 || g.ibc >= 0))
            continue; /* the rebuilt UPDT writes its own (dynamic streams) */
        else if ((!memcmp(rec->type, "fELD", 4) || !memcmp(rec->type, "rEAC", 4)) && g.imd >= 0)
            continue; /* a field (its reactions) of the unrefined mesh */
        else rc = aug_write_rec(w, rec, e);
    }
    if (!rc && have_q) {
        aug_kv qual, tim;
        aug_refine_q_kv(&q, r->base.etype == AUG_MEM3 ? 2 : dim, &qual, &tim); /* mem3: triangles' angles */
        rc = aug_write_kv(w, "qUAl", step, &qual, e);
        if (!rc) rc = aug_write_kv(w, "tIMe", step, &tim, e);
    }
done:
    free(g.seg);
    aug_mdelta_free(&d);
    aug_mdelta_free(&out);
    aug_bdelta_free(&bc);
    aug_bdelta_free(&outbc);
    aug_update_free(&u);
    return rc;
}
