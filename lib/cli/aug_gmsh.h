/* Reading gmsh .msh files (v2.2 and v4.1, ASCII and binary) through the gmsh C
   API. Only meshload links this (with -lgmsh). */
#ifndef AUG_GMSH_H
#define AUG_GMSH_H

#include "../aug_scene.h"

/* Fill t with the tet4 mesh of the file, or its tri3 mesh when it has no
   volume elements, and every physical group. gmsh prints nothing: stdout is
   redirected to /dev/null while it runs and its messages are kept for e.
   Returns 0, or an error code with e filled (unreadable file, not a .msh
   file, gmsh's own error, unsupported element types, no elements). */
int aug_gmsh_read(const char *path, aug_tagged *t, aug_err *e);
void aug_gmsh_free(aug_tagged *t);

#endif
