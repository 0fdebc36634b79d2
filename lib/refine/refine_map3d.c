/* A 3-D cut step carried over to the refined mesh: the cut's new nodes appended in
   its order, its re-wired and added tets mapped onto the work tets that still
   coincide with the cut's (tets an earlier step bisected cannot be re-cut: refine's
   look-ahead, aug_refiner_plan, keeps the tets a later step re-cuts whole). */
#include <stdlib.h>
#include <string.h>
#include "aug_refine.h"

/* 3-D: the cut's new nodes appended (parents mapped to work nodes) and its re-wired
   and added tets written onto the work tets they coincide with (their original
   measure carried); AUG_EDATA when the cut changes a tet refine bisected before */
int aug_refine_map3d(aug_refiner *r, const aug_mdelta *d, const int32_t *oldc, int64_t nnc,
                     int64_t nec, aug_refine_q *q, aug_err *e)
{
    aug_work *W = &r->work;
    const aug_mesh *C = &r->cut;
    (void)oldc;
    for (int64_t i = 0; i < d->nmod; i++)
        if (r->cel[d->elem[i]] < 0)
            return aug_err_set(e, AUG_EDATA, -1, "MDLT",
                               "step %d: the cut changes tetrahedron %d, which refine bisected at an "
                               "earlier step (re-cutting refined tetrahedra is not supported)",
                               (int)d->step, (int)d->elem[i]);
    for (int64_t i = 0; i < d->nnew; i++) {
        int32_t c = (int32_t)(nnc + i), par = r->cnode[d->parent[i]];
        if (par < 0)
            return aug_err_set(e, AUG_EDATA, -1, "MDLT", "step %d: bad parent of new node %lld",
                               (int)d->step, (long long)i);
        int32_t wn = aug_work_node(W, C->x + 3 * (int64_t)c, par);
        if (wn < 0) return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
        r->cnode[c] = wn;
    }
    for (int64_t i = 0; i < d->nmod + d->nadd; i++) {
        int32_t t = i < d->nmod ? d->elem[i] : (int32_t)(nec + i - d->nmod);
        int32_t conn[4];
        for (int j = 0; j < 4; j++) conn[j] = r->cnode[C->conn[4 * (int64_t)t + j]];
        int rc;
        if (i < d->nmod) {
            if ((rc = aug_work_set(W, r->cel[t], conn)))
                return aug_err_set(e, rc, -1, "MDLT", "step %d: %s", (int)d->step,
                                   rc == AUG_ENOMEM ? "out of memory" : "bad tetrahedron");
            W->area0[r->cel[t]] = r->carea0[t];
        } else {
            int64_t w = aug_work_add(W, conn, C->mat[t], r->carea0[t]);
            if (w < 0) return aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
            W->own[w] = t;
            r->cel[t] = (int32_t)w;
        }
    }
    q->intersected = d->nmod;
    q->region = d->nmod;
    return 0;
}
