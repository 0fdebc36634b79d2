/* augcut scene layer: a mesh as a mesh file tags it (gmsh node and element
   tags, physical groups) turned into struct aug_mesh, and the scene options
   (materials, fixed nodes, loads, output set) that meshload adds to it. */
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

/* A tet4, hex8 or tri3 mesh with file tags (gmsh's, unique and positive). */
typedef struct aug_tagged {
    int etype;                 /* AUG_TET4, AUG_HEX8 or AUG_TRI3 */
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
   mesh's extent); t->etype = AUG_MEM3 (a gmsh triangle mesh read as a
   membrane, meshload --membrane) keeps x, y, z (dim 3), its materials are
   the physical surfaces and its area |(p1-p0) x (p2-p0)| / 2 is never
   negative (a triangle's normal is its node order's). Materials: one per physical group of the mesh's dimension
   (ascending tag; id = tag, name = physical name), then "default" (id 0) for
   the elements in none, all with the default properties; an element in two
   such groups is an error. Sets: one per physical group of any dimension
   (ascending dimension, then tag; groups sharing a name are merged), nodes
   restricted to the kept ones, then "boundary" (aug_mesh_boundary_nodes)
   unless a group has that name. An element of measure <= 0 is an error
   naming its index and tag, unless reorient is set and the measure is
   negative: then its last two nodes are swapped. Degenerate elements
   (|measure| <= 64 eps l^2 (triangles) or l^3, l its longest edge) are always an error.
   hex8 (dim 3): a scaled Jacobian (aug_hex_scaled_jacobian) <= 64 eps at a
   corner is an error naming the element, its tag and the corner, unless
   reorient is set and the mirrored hex (bottom and top faces exchanged,
   0123 4567 -> 4567 0123) is valid at every corner. */
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

/* ---- Scene options (lib/mesh/scene_spec.c, scene_apply.c) ----
   The values of meshload's --fix, --material, --default-material, --load,
   --gravity and --output, parsed, then applied to an imported mesh. Each problem found is
   one message to a sink, in the order found, and the search goes on, so that
   a caller can report them all (GMT's rule); the library never prints. */
typedef struct aug_sink {
    void (*report)(void *ctx, const char *msg); /* NULL: problems only counted */
    void *ctx;
    int n;                     /* problems reported */
} aug_sink;
/* One problem: n += 1 and the formatted message to report. */
void aug_sink_report(aug_sink *k, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Material properties as given: v[i] when has[i]. */
enum { AUG_PROP_E, AUG_PROP_NU, AUG_PROP_RHO, AUG_PROP_T, AUG_NPROP };
typedef struct aug_props {
    int has[AUG_NPROP];
    double v[AUG_NPROP];
} aug_props;

enum { AUG_FIX_GROUP, AUG_FIX_BOX, AUG_FIX_PLANE };
typedef struct aug_fix_spec {  /* --fix GROUP | box:x0,y0,z0,x1,y1,z1 | plane:nx,ny,nz,d[,tol] */
    int kind;                  /* AUG_FIX_* */
    const char *arg;           /* the option's value (messages) */
    char group[AUG_NAME];
    double v[6];               /* box: lo[3], hi[3]; plane: n[3], d, tol */
    int ntol;                  /* plane: 1 when tol was given */
} aug_fix_spec;
typedef struct aug_load_spec { /* --load GROUP:fx,fy,fz | point:x,y,z:fx,fy,fz */
    int point;                 /* 1: on the node nearest p; 0: on the set group */
    const char *arg;
    char group[AUG_NAME];
    double p[3], F[3];         /* fz = 0 when given two numbers */
    int nF, np;                /* the count of numbers given for F and p (2 or 3) */
} aug_load_spec;
typedef struct aug_mat_spec {  /* --material GROUP:E=..,nu=..,rho=..,t=.. */
    const char *arg;
    char group[AUG_NAME];
    aug_props p;
} aug_mat_spec;
typedef struct aug_scene_spec {
    int nfix, nload, nmat;     /* the accepted values, in the order given */
    int cap;                   /* room in each array */
    aug_fix_spec *fix;
    aug_load_spec *load;
    aug_mat_spec *mat;
    aug_props def;             /* --default-material */
    const char *defarg;
    int gravity;               /* --gravity given (and well formed): its count of numbers, 2 or 3 */
    double g[3];               /* its acceleration, gz = 0 when given two numbers */
    const char *garg;
    const char *output;        /* all (also NULL), surface or a set name */
} aug_scene_spec;
/* The texts given to a spec are the caller's (argv's): kept, not copied. */
void aug_scene_spec_init(aug_scene_spec *s);
void aug_scene_spec_free(aug_scene_spec *s);
/* s += the value text of option opt: "--fix", "--material",
   "--default-material", "--load" or "--gravity" (gx,gy[,gz], finite). A value
   refused for its own text (bad syntax, a number out of range, E > 0,
   -1 < nu < 0.5, rho >= 0, t > 0, a key given twice) is left out, each of its problems reported to k as "OPT TEXT:
   what" (--default-material keeps its well-formed keys). Returns 0, also for
   a refused value; AUG_ENOMEM; AUG_EUSAGE for another opt. */
int aug_scene_spec_add(aug_scene_spec *s, const char *opt, const char *text, aug_sink *k,
                       aug_err *e);
/* m += the options of s, in this order (the problems, reported to k, in it too):
   materials: each property p of material a := --material a's p, else
   --default-material's p, else a's own (the defaults above); a --material not
   naming a material of m and t= on a 3-D mesh are problems.
   FIXD := u = 0 at every node of the --fix sets, boxes and planes (tol
   defaults to 1e-6 aug_mesh_extent); an unknown or empty set and a box or
   plane selecting no node are problems.
   LOAD := the sum of the --load forces: a set's total F split equally among
   its nodes (aug_load_spread), a point's F on the node nearest it; an
   unknown or empty set is a problem, and so is fz != 0 on a 2-D mesh (which
   ignores fz). GRAV := --gravity g, the body force rho g of each element's
   material (formats/stream.md 5.8, assembled per element: aug_elem_body); with g != 0 a
   material of rho = 0 that some element uses is a problem naming it, and so
   is gz != 0 on a 2-D mesh.
   oUTs := output: all; surface (aug_mesh_boundary_nodes); or a set (unknown
   or empty: a problem, and oUTs left out).
   A problem stops nothing: an unknown set selects no node, t= is unused in
   3-D. Returns 0 (problems or not), or AUG_ENOMEM. */
int aug_scene_spec_apply(const aug_scene_spec *s, aug_mesh *m, aug_sink *k, aug_err *e);

#endif
