/* augcut public header, grouped by layer: stream, mesh, assembly/factor,
   updates; the solver, cut, refinement, modal and stats layers add theirs. */
#ifndef AUGCUT_H
#define AUGCUT_H
#include "aug_stream.h"
#include "aug_mesh.h"
#include "aug_scene.h"
#include "aug_fem.h"
#include "aug_update.h"
#include "aug_solve.h"
#include "aug_cut.h"
#include "aug_refine.h"
#include "aug_modal.h"
#include "aug_stats.h"
#endif
