/* augcut mesh layer: the scene (nodes, elements, materials, sets, constraints,
   loads, output set) and its records NODE ELEM MATL nSEt FIXD LOAD oUTs. */
#ifndef AUG_MESH_H
#define AUG_MESH_H

#include "aug_stream.h"

/* Element types use gmsh's numbering. */
#define AUG_TRI3 2
#define AUG_TET4 4

#define AUG_NAME 64

typedef struct aug_material {
    int32_t id;               /* gmsh physical tag (or user id) */
    char name[AUG_NAME];
    double E, nu, rho, t;     /* Young's modulus, Poisson ratio, density, thickness (2-D) */
} aug_material;

typedef struct aug_set {
    char name[AUG_NAME];
    int64_t n;
    int32_t *nodes;           /* sorted, unique node indices */
} aug_set;

/* Output set kinds (oUTs record). */
enum { AUG_OUT_ALL = 0, AUG_OUT_SURFACE = 1, AUG_OUT_SET = 2 };

typedef struct aug_mesh {
    int dim;                  /* 2 (tri3, plane stress) or 3 (tet4) */
    int etype;                /* AUG_TRI3 or AUG_TET4 */
    int nv;                   /* nodes per element: 3 or 4 */
    int64_t nn;               /* nodes */
    double *x;                /* nn*dim coordinates */
    int64_t ne;               /* elements */
    int32_t *conn;            /* ne*nv node indices, 0-based */
    int32_t *mat;             /* ne material indices into mats[] */
    int nmat;
    aug_material *mats;
    int nset;
    aug_set *sets;
    int64_t nfix;             /* Dirichlet constraints: dof = node*dim + component */
    int32_t *fix_dof;
    double *fix_val;
    int64_t nload;            /* nodal forces */
    int32_t *load_dof;
    double *load_val;
    int out_kind;             /* AUG_OUT_* ; nout/out_nodes valid when AUG_OUT_SET/SURFACE */
    char out_name[AUG_NAME];
    int64_t nout;
    int32_t *out_nodes;
    int have;                 /* bit mask of records absorbed (AUG_HAVE_*) */
    double grav[3];           /* GRAV: body force rho * grav per unit volume (0: none) */
} aug_mesh;

enum { AUG_HAVE_NODE = 1, AUG_HAVE_ELEM = 2, AUG_HAVE_MATL = 4, AUG_HAVE_FIXD = 8,
       AUG_HAVE_LOAD = 16, AUG_HAVE_OUTS = 32, AUG_HAVE_GRAV = 64 };

void aug_mesh_init(aug_mesh *m);
void aug_mesh_free(aug_mesh *m);
/* Deep copy of m into t; -1 on allocation failure (t is then empty). */
int aug_mesh_copy(aug_mesh *t, const aug_mesh *m);

/* Is this one of the mesh record types? */
int aug_mesh_is_record(const char *type);
/* Absorb one mesh record into m (validating indices against what is known). */
int aug_mesh_absorb(aug_mesh *m, const aug_rec *rec, aug_err *e);
/* After all mesh records: cross-checks (element node indices < nn, material
   indices < nmat, constraint/load dofs < nn*dim, finite coordinates). */
int aug_mesh_validate(const aug_mesh *m, aug_err *e);
/* Write all mesh records of m in canonical order. */
int aug_mesh_write(aug_writer *w, const aug_mesh *m, aug_err *e);

/* Position of v in the strictly increasing a[0..n), -1 if absent. */
int64_t aug_find_i32(const int32_t *a, int64_t n, int32_t v);
/* qsort comparator of int32_t, increasing */
int aug_cmp_i32(const void *a, const void *b);

/* Find a named set; NULL if absent. */
const aug_set *aug_mesh_set(const aug_mesh *m, const char *name);

/* DOF numbering: map[node*dim+c] = free index (0..nfree-1, node order) or -1 if
   constrained. Returns nfree. */
int64_t aug_dofmap(const aug_mesh *m, int32_t *map);

/* Signed measure of element e: volume (tet4) or area (tri3, in the x-y plane). */
double aug_elem_measure(const aug_mesh *m, int64_t e);
/* Element quality: aspect ratio (longest edge / shortest altitude-free form:
   longest edge over shortest edge for tri3; for tet4 the normalised ratio
   circumradius/(3*inradius), 1 for the regular tet), minimum angle (tri3) or
   minimum dihedral angle (tet4) in degrees. */
typedef struct aug_quality {
    double measure;
    double aspect;
    double min_angle;
    double edge_ratio;        /* longest / shortest edge */
} aug_quality;
void aug_elem_quality(const aug_mesh *m, int64_t e, aug_quality *q);

/* Boundary nodes (nodes on faces/edges used by one element only): fills mark[nn]
   with 1 on the boundary. Returns the count or -1 on allocation failure. */
int64_t aug_mesh_boundary_nodes(const aug_mesh *m, unsigned char *mark);

#endif
