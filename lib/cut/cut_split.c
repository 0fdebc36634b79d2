/* Split mode surgery on tri3 meshes (thesis ch. 3.1.2, fig. 3.4): a node on an
   edge splits both triangles sharing it (conforming), a node inside a triangle
   splits it in three. */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

/* constrained components of node q (copies and split nodes inherit their parent's) */
static int nfixed(const aug_edit *ed, int32_t q)
{
    while (q >= ed->nn0) q = ed->parent[q - ed->nn0];
    int n = 0;
    for (int c = 0; c < ed->m->dim; c++) n += aug_mesh_fixed(ed->m, q * ed->m->dim + c, NULL);
    return n;
}

/* new node r = (1-s) a + s b splits edge ab: each triangle (a, b, c) on it becomes
   (a, r, c) and (r, b, c), conforming (thesis 003 sec. 3.1.2); r's parent is the
   end with fewer constrained components (the nearer on ties); a cut edge ab
   becomes ar and rb */
int32_t aug_split_edge(aug_edit *ed, aug_edgemap *cut, int32_t a, int32_t b, double s,
                       aug_err *e)
{
    aug_err_clear(e);
    const double *xa = aug_edit_x(ed, a), *xb = aug_edit_x(ed, b);
    double x[3];
    for (int c = 0; c < ed->m->dim; c++) x[c] = (1 - s) * xa[c] + s * xb[c]; /* tri3, mem3 */
    /* the new node inherits the constraints of the less constrained end (nearer on ties) */
    int fa = nfixed(ed, a), fb = nfixed(ed, b);
    int32_t parent = fa < fb ? a : (fb < fa ? b : (s <= 0.5 ? a : b));
    int32_t tris[8];
    int nt = 0;
    const aug_adj *adj = ed->adj;
    for (int32_t i = 0; i < adj->cnt[a] && nt < 8; i++) {
        int32_t t = adj->list[a][i];
        const int32_t *c = aug_edit_conn(ed, t);
        if (c[0] == b || c[1] == b || c[2] == b) tris[nt++] = t;
    }
    if (nt == 0)
        return aug_err_set(e, AUG_EUSAGE, -1, "MDLT", "nodes %d and %d share no edge", (int)a, (int)b);
    int32_t r = aug_edit_node(ed, x, parent);
    if (r < 0) goto nomem;
    for (int i = 0; i < nt; i++) {
        int32_t c1[3], c2[3];
        memcpy(c1, aug_edit_conn(ed, tris[i]), sizeof c1);
        memcpy(c2, c1, sizeof c2);
        for (int k = 0; k < 3; k++) {
            if (c1[k] == b) c1[k] = r; /* (a, r, c) */
            if (c2[k] == a) c2[k] = r; /* (r, b, c) */
        }
        int32_t mat = aug_edit_mat(ed, tris[i]);
        if (aug_edit_set(ed, tris[i], c1) || aug_edit_elem(ed, c2, mat) < 0) goto nomem;
    }
    if (cut && aug_edgemap_get(cut, a, b)) {
        aug_edgemap_del(cut, a, b);
        if (!aug_edgemap_put(cut, a, r) || !aug_edgemap_put(cut, r, b)) goto nomem;
    }
    return r;
nomem:
    aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
    return -1;
}

/* new node r = sum_k l_k c_k (barycentric l) splits t into (c0, c1, r),
   (c1, c2, r), (c2, c0, r): a cut ending inside a triangle (thesis 003 sec. 3.1.2,
   fig. 3.4); r's parent is the corner with fewest constrained components, then
   the largest l_k */
int32_t aug_split_tri(aug_edit *ed, int64_t t, const double l[3], aug_err *e)
{
    aug_err_clear(e);
    int32_t c[3];
    memcpy(c, aug_edit_conn(ed, t), sizeof c);
    double x[2] = {0, 0};
    for (int k = 0; k < 3; k++) {
        const double *p = aug_edit_x(ed, c[k]);
        x[0] += l[k] * p[0];
        x[1] += l[k] * p[1];
    }
    int best = 0;
    for (int k = 1; k < 3; k++) {
        int fk = nfixed(ed, c[k]), fb = nfixed(ed, c[best]);
        if (fk < fb || (fk == fb && l[k] > l[best])) best = k;
    }
    int32_t r = aug_edit_node(ed, x, c[best]);
    if (r < 0) goto nomem;
    int32_t mat = aug_edit_mat(ed, t);
    int32_t t0[3] = {c[0], c[1], r}, t1[3] = {c[1], c[2], r}, t2[3] = {c[2], c[0], r};
    if (aug_edit_set(ed, t, t0) || aug_edit_elem(ed, t1, mat) < 0 || aug_edit_elem(ed, t2, mat) < 0)
        goto nomem;
    return r;
nomem:
    aug_err_set(e, AUG_ENOMEM, -1, "MDLT", "out of memory");
    return -1;
}
