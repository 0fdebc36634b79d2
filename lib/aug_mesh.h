/* augcut mesh layer: the scene (nodes, elements, materials, sets, constraints,
   loads, output set) and its records NODE ELEM MATL nSEt FIXD LOAD oUTs. */
#ifndef AUG_MESH_H
#define AUG_MESH_H

#include "aug_stream.h"

/* Element types use gmsh's numbering. One type per mesh. */
#define AUG_TRI3 2
#define AUG_TET4 4
#define AUG_HEX8 5
/* The membrane triangle: a gmsh triangle (type 2) in 3-D, plane stress in its
   own plane, 3 DOFs per node (lib/fem/membrane.c). Not a gmsh number. */
#define AUG_MEM3 1002

/* The largest element (hex8): nodes, DOFs (nodes x dim) and element matrix
   entries; fixed element arrays are sized by these. */
#define AUG_MAX_NV 8
#define AUG_MAX_EDOF 24
#define AUG_MAX_EMAT (AUG_MAX_EDOF * AUG_MAX_EDOF)

#define AUG_NAME 64
/* |coordinate| bound (formats/stream.md 5.1): finite is not enough, an
   element's measure (l^3) overflows near 1e102; no scene is larger than
   the observable universe (1e27 m) */
#define AUG_COORD_MAX 1e30

typedef struct aug_material {
    int32_t id;               /* gmsh physical tag (or user id) */
    char name[AUG_NAME];
    double E, nu, rho, t;     /* Young's modulus, Poisson ratio, density, thickness (2-D) */
    double kf;                /* mem3: Winkler foundation modulus (FNDN; 0: none) */
} aug_material;

typedef struct aug_set {
    char name[AUG_NAME];
    int64_t n;
    int32_t *nodes;           /* sorted, unique node indices */
} aug_set;

/* Output set kinds (oUTs record). */
enum { AUG_OUT_ALL = 0, AUG_OUT_SURFACE = 1, AUG_OUT_SET = 2 };

typedef struct aug_mesh {
    int dim;                  /* 2 (tri3, plane stress) or 3 (tet4, hex8, mem3) */
    int etype;                /* AUG_TRI3, AUG_TET4, AUG_HEX8 or AUG_MEM3 */
    int nv;                   /* nodes per element: 3, 4 or 8 */
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
       AUG_HAVE_LOAD = 16, AUG_HAVE_OUTS = 32, AUG_HAVE_GRAV = 64, AUG_HAVE_FNDN = 128 };

void aug_mesh_init(aug_mesh *m);
void aug_mesh_free(aug_mesh *m);
/* Deep copy of m into t; -1 on allocation failure (t is then empty). */
int aug_mesh_copy(aug_mesh *t, const aug_mesh *m);

/* Is this one of the mesh record types? */
int aug_mesh_is_record(const char *type);
/* Absorb one mesh record into m (validating indices against what is known). */
int aug_mesh_absorb(aug_mesh *m, const aug_rec *rec, aug_err *e);
/* the first material with a foundation (kf != 0) on a mesh that is not mem3
   (formats 5.9: only a membrane takes one), or -1 */
int aug_mesh_fndn_misplaced(const aug_mesh *m);
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

/* ---- Element types and their facets (lib/mesh/topology.c) ----
   Facets are the faces of a 3-D element and the edges of a 2-D one: tri3 3
   edges and tet4 4 triangles (facet f: every local node but f, increasing);
   hex8 6 quadrilaterals in gmsh's node order (nodes 0-3 the bottom
   counter-clockwise seen from above, 4-7 above them), each facet's nodes in
   cyclic order, outward by the right-hand rule;
   mem3 (the membrane triangle in 3-D) has the facets of tri3: its 3 edges. */
int aug_etype_nv(int etype);          /* 3, 4, 8, 3 (mem3); 0 for an unknown type */
int aug_etype_dim(int etype);         /* 2, 3, 3, 3; 0 */
const char *aug_etype_name(int etype);/* "tri3", "tet4", "hex8", "mem3"; "?" */
int aug_etype_nfacet(int etype);      /* 3, 4, 6, 3 */
int aug_etype_facet_nv(int etype);    /* 2, 3, 4, 2 */
/* local nodes of facet f (aug_etype_facet_nv of them) */
const int *aug_etype_facet(int etype, int f);
/* Elements a and b (connectivities of nv nodes, type etype) share a whole
   facet of a: its nodes in a's facet order into f (room for 4), count
   returned; 0 when they share none. */
int aug_shared_facet(int etype, const int32_t *a, const int32_t *b, int32_t *f);

/* ---- The trilinear hexahedron (lib/mesh/hex8.c) ----
   Shape functions of hex8 element e at natural coordinates xi in [-1,1]^3:
   N[a] = (1 + xi xi_a)(1 + eta eta_a)(1 + zeta zeta_a) / 8, (xi_a, eta_a,
   zeta_a) the corners in gmsh order; g non-NULL: the physical gradients
   g[a*3+c] = dN_a/dx_c = (J^-T dN_a/dxi)_c with J = dx/dxi = sum_a x_a
   (dN_a/dxi)'. Returns det J (Hughes, The Finite Element Method, 2000,
   sec. 3.5-3.8; Zienkiewicz & Taylor vol. 1 ch. 6). */
double aug_hex_shape(const aug_mesh *m, int64_t e, const double xi[3], double N[8], double *g);
/* cof = the cofactors of the 3 x 3 a (cof[r][k] = (-1)^(r+k) times the
   minor of a[r][k]); returns det a, so that (a^-1)[k][r] = cof[r][k] / det */
double aug_cofactor3(const double a[3][3], double cof[3][3]);
/* The 2x2x2 Gauss-Legendre rule on [-1,1]^3: point q (0..7) at (+-1/sqrt 3)^3,
   weight 1 (Hughes sec. 3.8: exact for the volume and the Q1 mass). */
void aug_hex_gauss(int q, double xi[3]);

/* Signed measure of element e: volume (tet4, hex8) or area (tri3, in the x-y
   plane; mem3: |(p1-p0) x (p2-p0)| / 2, never negative, a membrane having no
   inside-out). */
double aug_elem_measure(const aug_mesh *m, int64_t e);
/* Scaled Jacobian of hex8 element e: the least over its 8 corners of
   det[e1, e2, e3] / (|e1| |e2| |e3|), e_k the edges from the corner to its
   three neighbours in right-handed order (1 for a cube, <= 0 at an inverted
   or degenerate corner; [Knupp 2000], the Verdict library's hex scaled
   Jacobian); *corner (may be NULL) the local node where it is least. */
double aug_hex_scaled_jacobian(const aug_mesh *m, int64_t e, int *corner);
/* Element quality: aspect ratio (longest edge / shortest altitude-free form:
   longest edge over shortest edge for tri3; for tet4 the normalised ratio
   circumradius/(3*inradius), 1 for the regular tet), minimum angle (tri3) or
   minimum dihedral angle (tet4) in degrees. */
/* hex8: aspect = edge_ratio, min_angle = the least angle between two edges
   at a corner (90 for a cube), sjac = aug_hex_scaled_jacobian (NAN for tri3
   and tet4). */
typedef struct aug_quality {
    double measure;
    double aspect;
    double min_angle;
    double edge_ratio;        /* longest / shortest edge */
    double sjac;              /* scaled Jacobian (hex8) */
} aug_quality;
void aug_elem_quality(const aug_mesh *m, int64_t e, aug_quality *q);

/* Boundary nodes (nodes on faces/edges used by one element only): fills mark[nn]
   with 1 on the boundary. Returns the count or -1 on allocation failure. */
int64_t aug_mesh_boundary_nodes(const aug_mesh *m, unsigned char *mark);

#endif
