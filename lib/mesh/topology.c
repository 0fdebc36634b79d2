/* Element types and their facets (faces of 3-D elements, edges of 2-D ones). */
#include <string.h>
#include "aug_mesh.h"

static const int tri_facets[3][4] = {{1, 2}, {0, 2}, {0, 1}};
static const int tet_facets[4][4] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
/* gmsh hexahedron: bottom 0 1 2 3 counter-clockwise seen from above, top 4 5 6 7
   above them; each face outward by the right-hand rule */
static const int hex_facets[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                     {1, 2, 6, 5}, {2, 3, 7, 6}, {0, 4, 7, 3}};

int aug_etype_nv(int etype)
{
    return etype == AUG_TRI3 || etype == AUG_MEM3 ? 3 : etype == AUG_TET4 ? 4 : etype == AUG_HEX8 ? 8 : 0;
}

int aug_etype_dim(int etype)
{
    return etype == AUG_TRI3 ? 2 : etype == AUG_TET4 || etype == AUG_HEX8 || etype == AUG_MEM3 ? 3 : 0;
}

const char *aug_etype_name(int etype)
{
    return etype == AUG_TRI3   ? "tri3"
           : etype == AUG_TET4 ? "tet4"
           : etype == AUG_HEX8 ? "hex8"
           : etype == AUG_MEM3 ? "mem3"
                               : "?";
}

int aug_etype_nfacet(int etype)
{
    return etype == AUG_HEX8 ? 6 : aug_etype_nv(etype);
}

int aug_etype_facet_nv(int etype)
{
    return etype == AUG_HEX8 ? 4 : aug_etype_nv(etype) - 1;
}

const int *aug_etype_facet(int etype, int f)
{
    if (etype == AUG_HEX8) return hex_facets[f];
    return etype == AUG_TET4 ? tet_facets[f] : tri_facets[f];
}

/* a facet of a all of whose nodes are in b (conforming meshes share whole facets) */
int aug_shared_facet(int etype, const int32_t *a, const int32_t *b, int32_t *f)
{
    int nv = aug_etype_nv(etype), fv = aug_etype_facet_nv(etype), nf = aug_etype_nfacet(etype);
    unsigned in = 0;
    int common = 0;
    for (int i = 0; i < nv; i++)
        for (int j = 0; j < nv; j++)
            if (a[i] == b[j]) {
                in |= 1u << i;
                common++;
                break;
            }
    if (common < fv) return 0;
    for (int q = 0; q < nf; q++) {
        const int *l = aug_etype_facet(etype, q);
        int all = 1;
        for (int k = 0; k < fv && all; k++) all = (in >> l[k]) & 1;
        if (!all) continue;
        for (int k = 0; k < fv; k++) f[k] = a[l[k]];
        return fv;
    }
    return 0;
}
