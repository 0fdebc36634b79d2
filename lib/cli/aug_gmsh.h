/* Reading gmsh .msh files (v2.2 and v4.1, ASCII and binary) through the gmsh C
   API. meshload and cut link this (with -lgmsh). */
#ifndef AUG_GMSH_H
#define AUG_GMSH_H

#include "../aug_scene.h"

/* Fill t with the tet4 or hex8 mesh of the file (one element type per mesh:
   tetrahedra and hexahedra together are refused), or its tri3 mesh when it
   has no volume elements, and every physical group (a physical surface of
   quadrilaterals or triangles is a node set like any other). gmsh runs in a
   child process (stdout and stderr on /dev/null, its messages kept for e) that sends t back
   through a pipe: a crash of gmsh is the error "gmsh failed to read the file
   (signal N)", and nothing of a reply cut short is used. What gmsh returns is
   checked first: element types of the mesh's dimension (mixed orders in one
   entity too), node and element tags gmsh saw twice, the element count of the
   file's $Elements headers against the elements gmsh kept, array sizes.
   Returns 0, or an error code with e filled (unreadable file, not a .msh
   file, gmsh's own error or crash, unsupported element types, no elements). */
int aug_gmsh_read(const char *path, aug_tagged *t, aug_err *e);
void aug_gmsh_free(aug_tagged *t);

/* The dimension (-1: a type gmsh does not know), node count (0 then) and
   name ("?") of gmsh element type `type`; nnodes and name may be NULL. Needs
   gmsh initialised (the child of aug_gmsh_read). */
void aug_gmsh_type(int type, int *dim, int *nnodes, char name[AUG_NAME]);
/* qsort comparator of size_t (gmsh's tags) */
int aug_cmp_size(const void *a, const void *b);

/* An MSH 2 file's physical groups as its elements give them (the first tag
   of each; 0: none), where gmsh's, attached to elementary entities,
   differ: t's groups get the file's element and node tags (msh2_groups.c;
   in gmsh's child, gmsh initialised). 0 also for a file that is not MSH 2,
   or an error code (memory). */
int aug_msh2_groups(const char *path, aug_tagged *t, aug_err *e);

/* Unnamed groups of t named from the file's $PhysicalNames where gmsh
   dropped the name (a second group of one dimension and name:
   phys_names.c; in gmsh's child). 0 (a file it cannot read: gmsh's names
   stand). */
int aug_physical_names(const char *path, aug_tagged *t, aug_err *e);

/* The child's reply (tagged_pipe.c): code 0 and t, or an error code and e's
   message. send returns 0 or -1 (write failed). recv returns 0 with t filled
   (free it with aug_gmsh_free), the child's error code with e filled, or -1
   when the reply is cut short or malformed (t empty). */
int aug_tagged_send(int fd, int code, const aug_tagged *t, const aug_err *e);
int aug_tagged_recv(int fd, aug_tagged *t, aug_err *e);

/* s += the triangles of a gmsh surface mesh (a .msh file of triangles and no
   volume elements; surface_gmsh.c): cut --surface. Also linked by cut. */
struct aug_soup;
int aug_surface_gmsh(const char *path, struct aug_soup *s, aug_err *e);

#endif
