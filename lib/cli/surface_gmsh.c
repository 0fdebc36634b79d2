/* A gmsh surface mesh (triangles, no volume elements) as a cut surface,
   read through the gmsh C API (aug_gmsh_read). */
#include <stdlib.h>
#include <string.h>
#include "aug_gmsh.h"
#include "../aug_cut.h"

typedef struct tagidx {
    size_t tag, i;
} tagidx;

static int cmp_tag(const void *a, const void *b)
{
    size_t x = ((const tagidx *)a)->tag, y = ((const tagidx *)b)->tag;
    return (x > y) - (x < y);
}

int aug_surface_gmsh(const char *path, aug_soup *s, aug_err *e)
{
    aug_tagged t;
    memset(&t, 0, sizeof t);
    int rc = aug_gmsh_read(path, &t, e);
    if (rc) { /* its messages do not name the file (meshload adds it too) */
        char msg[sizeof e->msg];
        memcpy(msg, e->msg, sizeof msg);
        return aug_err_set(e, rc, -1, "", "%s: %s", path, msg);
    }
    if (t.etype != AUG_TRI3) {
        aug_gmsh_free(&t);
        return aug_err_set(e, AUG_EUSAGE, -1, "", "%s: a volume mesh, not a triangle surface", path);
    }
    tagidx *ix = aug_malloc(t.nnode * sizeof *ix + 1);
    if (!ix) {
        aug_gmsh_free(&t);
        return aug_err_set(e, AUG_ENOMEM, -1, "", "%s: out of memory", path);
    }
    for (size_t i = 0; i < t.nnode; i++) ix[i].tag = t.node_tags[i], ix[i].i = i;
    qsort(ix, t.nnode, sizeof *ix, cmp_tag);
    rc = 0;
    for (size_t el = 0; el < t.nelem && !rc; el++) {
        const double *p[3];
        for (int k = 0; k < 3; k++) {
            tagidx key = {t.conn_tags[3 * el + k], 0}, *f = bsearch(&key, ix, t.nnode, sizeof *ix, cmp_tag);
            if (!f) {
                rc = aug_err_set(e, AUG_EDATA, -1, "", "%s: triangle %zu uses node %zu, which the file lacks",
                                 path, t.elem_tags[el], key.tag);
                break;
            }
            p[k] = t.xyz + 3 * f->i;
            if (!aug_soup_point_ok(p[k])) {
                rc = aug_err_set(e, AUG_EDATA, -1, "", "%s: node %zu is beyond 1e30", path, key.tag);
                break;
            }
        }
        if (!rc && aug_soup_add(s, p[0], p[1], p[2]) < 0) rc = aug_err_set(e, AUG_ENOMEM, -1, "", "%s: out of memory", path);
    }
    free(ix);
    aug_gmsh_free(&t);
    if (!rc && s->n == 0) rc = aug_err_set(e, AUG_EUSAGE, -1, "", "%s: no triangle of positive area", path);
    return rc;
}
