/* augcut scene layer: a mesh as a mesh file tags it (gmsh node and element
   tags, physical groups) turned into struct aug_mesh, and the scene options
   (fixed nodes, loads, output set) that meshload adds to it. */
#ifndef AUG_SCENE_H
#define AUG_SCENE_H

#include "aug_mesh.h"

/* One physical group as the file gives it. */
typedef struct aug_tagged_group {
    int dim, tag;              /* gmsh dimension and physical tag */
    char name[AUG_NAME];       /* physical name ("" when unnamed) */
    size_t nnode;              /* tags of the nodes of its elements (any order, repeats allowed) */
    size_t *node_tags;
    size_t nelem;              /* tags of its elements of the mesh's type (used when dim is the */
    size_t *elem_tags;         /* mesh's dimension: the group is then a material) */
} aug_tagged_group;

/* A tet4 or tri3 mesh with file tags (gmsh's, unique and positive). */
typedef struct aug_tagged {
    int etype;                 /* AUG_TET4 or AUG_TRI3 */
    size_t nnode;
    size_t *node_tags;
    double *xyz;               /* 3 coordinates per node */
    size_t nelem;
    size_t *elem_tags;
    size_t *conn_tags;         /* nv node tags per element */
    int ngroup;
    aug_tagged_group *groups;
} aug_tagged;

/* Defaults of every material: E = 1, nu = 0.3, rho = 1, t = 1. */
#define AUG_DEFAULT_E 1.0
#define AUG_DEFAULT_NU 0.3
#define AUG_DEFAULT_RHO 1.0
#define AUG_DEFAULT_T 1.0

/* Name given to an unnamed physical group: "physical_DIM_TAG". */
void aug_group_name(const aug_tagged_group *g, char name[AUG_NAME]);

/* m = the mesh of t, renumbered compactly: the nodes used by the elements in
   ascending tag order, the elements in ascending tag order. dim = 3 for tet4;
   for tri3 dim = 2 and every node must have the same z (to 1e-9 of the
   mesh's extent). Materials: one per physical group of the mesh's dimension
   (ascending tag; id = tag, name = physical name), then "default" (id 0) for
   the elements in none, all with the default properties; an element in two
   such groups is an error. Sets: one per physical group of any dimension
   (ascending dimension, then tag; groups sharing a name are merged), nodes
   restricted to the kept ones, then "boundary" (aug_mesh_boundary_nodes)
   unless a group has that name. An element of measure <= 0 is an error
   naming its index and tag, unless reorient is set and the measure is
   negative: then its last two nodes are swapped. Degenerate elements
   (|measure| <= 64 eps l^dim, l its longest edge) are always an error. */
int aug_import(const aug_tagged *t, int reorient, aug_mesh *m, aug_err *e);

/* Node predicates: set mark[i] = 1 for the nodes selected (marks of other
   nodes are left alone); return how many nodes the predicate selects. A 2-D
   mesh has z = 0 here. */
/* lo <= x <= hi componentwise (z ignored in 2-D) */
int64_t aug_nodes_in_box(const aug_mesh *m, const double lo[3], const double hi[3],
                         unsigned char *mark);
/* |n.x - d| <= tol |n| */
int64_t aug_nodes_on_plane(const aug_mesh *m, const double n[3], double d, double tol,
                           unsigned char *mark);
/* argmin_i |x_i - p| (ties: the lowest index); -1 for an empty mesh */
int64_t aug_nearest_node(const aug_mesh *m, const double p[3]);
/* diagonal of the bounding box */
double aug_mesh_extent(const aug_mesh *m);

/* FIXD := u_c(i) = 0 for every component c of every node i with mark[i] set. */
int aug_mesh_fix_marked(aug_mesh *m, const unsigned char *mark, aug_err *e);
/* f[i*dim + c] += F[c] / n for the n nodes i of nodes[] (a total force F split
   equally among the nodes). */
void aug_load_spread(const aug_mesh *m, const int32_t *nodes, int64_t n, const double F[3],
                     double *f);
/* LOAD := the nonzero entries of the dense nodal force vector f[nn*dim]. */
int aug_mesh_set_load(aug_mesh *m, const double *f, aug_err *e);
/* oUTs := kind (AUG_OUT_*), name, nodes (copied; none for AUG_OUT_ALL). */
int aug_mesh_set_output(aug_mesh *m, int kind, const char *name, const int32_t *nodes,
                        int64_t n, aug_err *e);

#endif
