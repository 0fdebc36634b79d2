/* augcut public header, grouped by layer: stream, mesh, assembly/factor,
   updates; the solver, cut, refinement, modal and stats layers add theirs. */
#ifndef AUGCUT_H
#define AUGCUT_H
#include "aug_stream.h"
#include "aug_mesh.h"
#include "aug_fem.h"
#include "aug_update.h"
#endif
