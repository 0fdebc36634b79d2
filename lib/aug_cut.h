/* augcut cut layer: cut-matrix assembly, boundary-condition deltas (BDLT), the
   mesh edit of one cut step, node separation, planar and path cuts, detached
   pieces (formats/stream.md 7.1, 7.2, 7.6, 7.7). */
#ifndef AUG_CUT_H
#define AUG_CUT_H

#include <stdio.h>
#include "aug_fem.h"
#include "aug_update.h"

/* ---- The cut system assembled from scratch (formats/stream.md 7.2) ----
   Matrix order n_t = nfree0 + dim*(nn - nn0). Index of (node, c): aug_cut_index.
   An index whose DOF is constrained (FIXD, inherited or added by BDLT) is an
   identity row and column with load = its prescribed value; every other row is
   the stiffness over the free indices, load = nodal force - K[i, constrained] * value. */
int64_t aug_cut_order(const aug_mesh *m, int64_t nn0, int64_t nfree0);
/* K_t over all indices 0..n_t-1: upper triangle, sorted columns, stype 1. */
cholmod_sparse *aug_assemble_cut(const aug_mesh *m, int64_t nn0, const int32_t *map0,
                                 int64_t nfree0, cholmod_common *cm, aug_err *e);
/* f_t (length n_t). */
int aug_load_cut(const aug_mesh *m, int64_t nn0, const int32_t *map0, int64_t nfree0,
                 double *f, aug_err *e);
/* Constrained value of dof in m (sorted fix list): 1 and *v, or 0. */
int aug_mesh_fixed(const aug_mesh *m, int32_t dof, double *v);
/* Nodal force on dof (0 when none). */
double aug_mesh_load(const aug_mesh *m, int32_t dof);

/* ---- The scene of a stream, replayed (lib/cut/replay.c) ----
   Fed every record: absorbs the mesh records; at the first matrix or step
   record the original mesh is complete: it is validated, its numbering fixed
   (map0 = aug_dofmap, nfree0 free DOFs, nn0 nodes) and the output set
   resolved (--output overrides oUTs); a DOFM must equal that numbering (a
   stream without mesh records takes its numbering from DOFM); every MDLT and
   BDLT of a step <= step_limit is applied to the mesh (later ones are only
   checked). Index of (node, c) in the cut-matrix numbering (formats 7.2):
   aug_replay_index. */
typedef struct aug_replay {
    aug_mesh mesh;             /* now: the records, then every applied delta */
    int started, have_dofm, dim;
    int64_t nn0, nfree0;
    int32_t *map0;             /* nn0*dim: index in K0, or -1 (constrained) */
    int32_t last_step;         /* highest step of a per-step record so far (0: none) */
    int32_t updt_step;         /* step of the last UPDT (0: none) */
    int32_t delta_lo;          /* lowest step of an MDLT/BDLT since that UPDT (0: none) */
    long delta_index;          /* its record */
    char delta_type[5];        /* and its type */
    int have_kmat;             /* a KMAT passed: every step's deltas need an UPDT */
    long kmat_index;           /* ... the first one's record (it needs a DOFM, 6.1) */
    int64_t kt_n;              /* order of K_t after the UPDTs so far (0: no DOFM yet) */
    int32_t k_orphan_step, k_orphan; /* an UPDT with k > 0 before any MDLT of its step ... */
    long k_orphan_index;       /* ... its record (refused once its step is over) */
    int32_t plan_first, plan_last; /* the latest pLAN's steps (0: none read) */
    long plan_index;           /* ... and its record index */
    int32_t step_limit;        /* default INT32_MAX */
    const char *output;        /* all, surface, a set name, or NULL (the stream's oUTs) */
    long nmdlt, applied;       /* MDLT records read, applied */
    int32_t mdlt_step, mdlt_flags; /* the latest MDLT's step, flags (AUG_STEP_*) and counts
                                  (step and nnew set by the step checks, which every
                                  path runs: a step's UPDT has k = dim nnew) */
    int64_t mdlt_nnew, mdlt_nmod, mdlt_nadd;
    int32_t *mdlt_parent;      /* the latest MDLT's parent[mdlt_nnew] */
    int32_t *out_dof;          /* aug_replay_out_dofs' array */
    int dynamic;               /* a DYNP was read (formats/stream.md 6.6) into dyn */
    aug_dynp dyn;
    int check_sys;             /* 1: check KMAT, FVEC and FACT too (aug_replay_add; cut, refine, stats) */
    int64_t sys_n;             /* ... the order of the first of them, while no DOFM is read (-1: none) */
    long sys_index;            /* ... its record */
    char sys_type[5];          /* ... and type */
    int track;                 /* 1: note in chg the elements each applied MDLT re-wires or adds */
    int32_t *chg;              /* ... until its reader (aug_react_sync) empties it */
    int64_t nchg, chgcap;
} aug_replay;
void aug_replay_init(aug_replay *r);
void aug_replay_free(aug_replay *r);
int aug_replay_add(aug_replay *r, const aug_rec *rec, aug_err *e);
/* The per-step checks of aug_replay_add alone (a reader that stops replaying,
   refine after its first step): the step within the latest pLAN, each step's
   MDLT/BDLT before its one UPDT (formats/stream.md 7.1). */
int aug_replay_steps(aug_replay *r, const aug_rec *rec, aug_err *e);
/* At the stream's end: its last step is the latest pLAN's last (when there
   is one), and no step's delta is left without its UPDT (when there are UPDTs). */
int aug_replay_end(const aug_replay *r, aug_err *e);
/* Fix the original mesh now (called by add at the first matrix/step record). */
int aug_replay_start(aug_replay *r, aug_err *e);
int64_t aug_replay_index(const aug_replay *r, int64_t node, int c);
/* 1 when the field covers every node (output set all, or no mesh). */
int aug_replay_all(const aug_replay *r);
/* Increasing cut-matrix indices of the output set's free DOFs (none when all);
   the array belongs to r and lives until the next call. */
int aug_replay_out_dofs(aug_replay *r, const int32_t **dofs, int64_t *n, aug_err *e);
/* fELD (kind 0) of the solution x of step `step` on the output set. */
/* fRAM of nodal u, v (nn*dim) at frame, time: every node, or the output set */
int aug_replay_write_frame(aug_writer *w, const aug_replay *r, int32_t step, int32_t frame,
                           double time, const double *u, const double *v, aug_err *e);
int aug_replay_write_field(aug_writer *w, const aug_replay *r, int32_t step, const double *x,
                           aug_err *e);

/* ---- Reaction forces of the replayed steps (lib/cut/reaction_step.c) ----
   The elements touching a constrained DOF of the replay's mesh (aug_react_elements),
   followed step by step through the elements each MDLT re-wires or adds (the
   replay notes them once aug_react_init set its track flag) and rebuilt when a
   BDLT constrains a node that was there before; the cut-matrix DOFs the
   reactions read; the rEAC of a step or frame (aug_reaction_compute on the
   nodal field of the solution). */
typedef struct aug_react {
    aug_replay *rp;
    int synced;
    int64_t nn, ne, nfix_old;    /* the mesh at the last sync */
    unsigned char *cnode, *in;   /* per node: has a constrained DOF; per element: listed */
    int32_t *elems;              /* the elements touching a constrained DOF, increasing */
    int64_t nel, elcap;
    int32_t *dofs;               /* aug_react_out_dofs' array */
    int64_t dofcap;
    double *u;                   /* nodal displacement, valid at the nodes of elems */
    int64_t ucap;
    aug_reaction q;
} aug_react;
/* Dynamics of one frame for aug_react_write: the nodal velocity and
   acceleration (nn*dim, every DOF, constrained ones moving at their rate),
   Rayleigh alpha, beta, mass kind. */
typedef struct aug_react_frame {
    int32_t frame;
    double time;
    const double *v, *a;
    double alpha, beta;
    int lumped;
} aug_react_frame;
/* rp NULL: an unused s that aug_react_free accepts (rp is not tracked) */
void aug_react_init(aug_react *s, aug_replay *rp);
void aug_react_free(aug_react *s);
/* The element list made to match the replay's mesh now. */
int aug_react_sync(aug_react *s, aug_err *e);
/* *out (increasing matrix indices requested of a step, as from
   aug_replay_out_dofs; NULL: all, left so) := its union with the indices of
   every node of the elements touching a constrained DOF (s's array, valid
   until the next call): what a solve restricted to an output set must also
   solve for the reactions. Syncs first. */
int aug_react_out_dofs(aug_react *s, const int32_t **out, int64_t *nout, aug_err *e);
/* rEAC of `step` from the solution x of K_t (cut-matrix numbering; a DOF
   outside the matrix at its prescribed value, as in aug_replay_write_field);
   fr NULL in statics (frame 0, time 0); with fr (dynamics) x is the nodal
   displacement (nn*dim). Syncs first. */
int aug_react_write(aug_writer *w, aug_react *s, int32_t step, const double *x,
                    const aug_react_frame *fr, aug_err *e);

/* ---- BDLT: building one (aug_bdelta in aug_update.h) ---- */
/* Append a constraint / a load (duplicates: the last one wins at finish). 0 or -1 (memory). */
int aug_bdelta_fix(aug_bdelta *b, int32_t dof, double v);
int aug_bdelta_load(aug_bdelta *b, int32_t dof, double v);
/* Sort and de-duplicate both lists: 0 or -1 (memory). */
int aug_bdelta_finish(aug_bdelta *b);
/* Constrain / set loads in m (sorted insertion). */
int aug_mesh_apply_bc(aug_mesh *m, const aug_bdelta *b, aug_err *e);

/* ---- Update of one step (AMPS eq. 3.1) from the mesh after its MDLT ----
   after: the mesh with d applied (aug_mesh_apply) but bc not yet applied;
   nn_before, ne_before: counts before d; oldconn: the connectivity of d->elem
   before d (d->nmod * nv). bc may be NULL. Fills u (see aug_update_build).
   dyn non-NULL (a dynamic stream, DYNP): u->E is the update of the
   effective matrix A = cM M + cK K assembled from cM M_e + cK K_e, u->EK and
   u->EM those of K and M on the same Hbar (formats/stream.md 7.8), every one
   with identity rows where the step constrains; df is the static load's. */
int aug_update_build_after(const aug_mesh *after, int64_t nn_before, int64_t ne_before,
                           const int32_t *oldconn, const aug_mdelta *d, const aug_bdelta *bc,
                           int64_t nn0, const int32_t *map0, int64_t nfree0, const aug_dynp *dyn,
                           aug_update *u, aug_err *e);
/* As aug_update_build, with a BDLT of the same step (applied after d). */
int aug_update_build_bc(const aug_mesh *before, const aug_mdelta *d, const aug_bdelta *bc,
                        int64_t nn0, const int32_t *map0, int64_t nfree0, const aug_dynp *dyn,
                        aug_update *u, aug_err *e);

/* ---- Node -> element adjacency, kept current while a mesh is edited ---- */
typedef struct aug_adj {
    int64_t nn, capn;
    int32_t **list;      /* list[node][0..cnt-1] element indices (unordered) */
    int32_t *cnt, *cap;
} aug_adj;
int aug_adj_build(aug_adj *a, const aug_mesh *m);
void aug_adj_free(aug_adj *a);
int aug_adj_grow(aug_adj *a, int64_t nn);            /* nodes 0..nn-1 exist */
int aug_adj_add(aug_adj *a, int32_t node, int32_t elem);
void aug_adj_remove(aug_adj *a, int32_t node, int32_t elem);
/* The element across facet f (aug_etype_facet) of element el: the least
   other element holding all of the facet's nodes, or -1. */
int32_t aug_adj_across(const aug_mesh *m, const aug_adj *adj, int64_t el, int f);

/* ---- The mesh edit of one step: new nodes, re-wired and added elements ----
   Changes are kept on the side (new nodes and elements) or in place (re-wired
   elements, old connectivity saved); aug_edit_end turns them into an MDLT and
   restores the mesh arrays, leaving the adjacency as after the step, so that
   aug_mesh_apply(m, d) completes the step; aug_edit_begin then starts the next. */
typedef struct aug_edit {
    aug_mesh *m;
    aug_adj *adj;
    int64_t nn0, ne0;            /* counts when the edit began */
    int64_t nnew, capnew;
    double *xnew;                /* nnew*dim */
    int32_t *parent;
    int64_t nadd, capadd;
    int32_t *conn_add, *mat_add;
    int64_t nmod, capmod;
    int32_t *mod_elem, *mod_old; /* elements re-wired and their connectivity at begin */
    int32_t *slot;               /* per element: index in mod_elem or -1 (size capslot) */
    int64_t capslot;
} aug_edit;

int aug_edit_init(aug_edit *ed, aug_mesh *m, aug_adj *adj);
void aug_edit_free(aug_edit *ed);
void aug_edit_begin(aug_edit *ed);
int64_t aug_edit_nn(const aug_edit *ed);
int64_t aug_edit_ne(const aug_edit *ed);
const double *aug_edit_x(const aug_edit *ed, int64_t node);
const int32_t *aug_edit_conn(const aug_edit *ed, int64_t elem);
int32_t aug_edit_mat(const aug_edit *ed, int64_t elem);
/* New node at x with the given parent: its index, or -1 (memory). */
int32_t aug_edit_node(aug_edit *ed, const double *x, int32_t parent);
/* Replace the connectivity of an element: 0 or -1. */
int aug_edit_set(aug_edit *ed, int64_t elem, const int32_t *conn);
/* Append an element: its index or -1. */
int64_t aug_edit_elem(aug_edit *ed, const int32_t *conn, int32_t mat);
/* The step as an MDLT (d->elem: elements whose connectivity changed, increasing)
   and their old connectivity (*oldconn, malloc'd); restores the mesh arrays. */
int aug_edit_end(aug_edit *ed, int32_t step, aug_mdelta *d, int32_t **oldconn, aug_err *e);

/* ---- Node separation (node duplication, AMPS sec. 4.3.2) ----
   Is the face f (nf nodes) between elements a and b cut? */
typedef int (*aug_cutface_fn)(void *ctx, const aug_edit *ed, int32_t a, int32_t b,
                              const int32_t *f, int nf);
/* Which component keeps the node: the one holding the element of least rank
   (rank NULL: the element index). */
typedef int64_t (*aug_rank_fn)(void *ctx, int32_t elem);
/* Split the element star of node p into the components connected through
   uncut faces containing p; each component but the keeper gets a copy of p
   and is re-wired to it. *ncopies: copies made (0: the star is whole). */
int aug_separate_node(aug_edit *ed, int32_t p, aug_cutface_fn cut, aug_rank_fn rank,
                      void *ctx, int *ncopies, aug_err *e);

/* ---- Element face neighbours (faces shared by two elements) ---- */
typedef struct aug_facenbr {
    int nf;                      /* facets per element (aug_etype_nfacet) */
    int64_t ne, cap;
    int32_t *nbr;                /* ne*nf: element across facet f (aug_adj_across), -1 */
    int32_t *dirty;              /* elements the last update refreshed */
    int64_t ndirty;
    int32_t *mark, *lab, *queue; /* search workspace (cap each), marks by generation */
    int32_t gen;
} aug_facenbr;
int aug_facenbr_build(aug_facenbr *f, const aug_mesh *m, const aug_adj *adj);
/* After elements changed (re-wired or appended, listed in elems): refresh them and
   their former neighbours. */
int aug_facenbr_update(aug_facenbr *f, const aug_mesh *m, const aug_adj *adj,
                       const int32_t *elems, int64_t n);
void aug_facenbr_free(aug_facenbr *f);
/* Are the elements the last update refreshed still face-connected to one
   another? A search from one of them that visits at most budget elements:
   1 yes; 0 no, or the budget ran out. */
int aug_facenbr_local_connected(aug_facenbr *f, int64_t budget);

/* ---- Pieces without Dirichlet support (DESIGN: hard cases) ----
   Pieces are the face-connected components of the elements; a piece is rigid.
   The mesh is singular exactly when the rigid motions of the pieces, coupled
   through shared nodes and stopped by the constraints (those of m plus extra),
   leave a non-zero motion. The detached pieces are the pieces moving in it. */
typedef struct aug_pieces {
    int64_t np;                  /* face-connected pieces */
    int32_t *piece;              /* per element */
    int64_t nbad;                /* pieces moving in the null space */
    int32_t *bad;                /* their ids, by increasing first element */
    int32_t *first;              /* per piece: its least element */
    int64_t *size;               /* per piece: element count */
    int32_t *queue;              /* workspace, kept between calls */
    int64_t cap;                 /* elements piece[] and queue[] hold */
} aug_pieces;
/* Zero an aug_pieces before the first aug_detach_find; it can be reused. */
void aug_pieces_free(aug_pieces *p);
int aug_detach_find(const aug_mesh *m, const aug_adj *adj, const aug_facenbr *fn,
                    const aug_bdelta *extra, aug_pieces *out, aug_err *e);
/* The same when the elements are known to form one face-connected piece. */
int aug_detach_find_one(const aug_mesh *m, const aug_adj *adj, const aug_bdelta *extra,
                        aug_pieces *out, aug_err *e);
/* Constraints (value 0) into b that hold piece id still: pin = 3-2-1 (2-D: 2-1)
   rigid-body supports; drop = every DOF of the piece. */
/* Per node of m: 1 held by piece id alone, 3 by it and another piece (a
   sliver hinged on the body), 0 not by it (malloc'd, nn bytes; NULL: memory). */
unsigned char *aug_piece_marks(const aug_mesh *m, const aug_pieces *p, int32_t id);
int aug_detach_pin(const aug_mesh *m, const aug_pieces *p, int32_t id, const aug_bdelta *extra,
                   aug_bdelta *b, aug_err *e);
int aug_detach_drop(const aug_mesh *m, const aug_pieces *p, int32_t id, const aug_bdelta *extra,
                    aug_bdelta *b, aug_err *e);

/* ---- Planar cut (AMPS and the augmented-matrix paper, sec. 4.3.2) ---- */
typedef struct aug_plane_cut {
    int dim;
    double n[3], d, adv[3];      /* plane n.x = d, unit advance direction */
    int64_t ne;                  /* elements classified */
    unsigned char *side;         /* per element: 1 on the + side (n.centroid > d) */
    int64_t ncut, next;
    int32_t *nodes;              /* cut nodes in advance order; next = first not yet cut */
    int64_t nface;               /* faces between + and - elements at planning */
} aug_plane_cut;
/* Classify elements, collect and order the cut nodes. adv NULL: away from the
   fixed set (see man/cut.1). Fails (AUG_EDATA) when the plane misses the mesh. */
/* A random plane n.x = n[3] (GSL mt19937 with seed): normal uniform on the
   sphere (circle in 2-D), through a point in the middle half of the bounding box. */
void aug_plane_random(const aug_mesh *m, unsigned long seed, double n[4]);
int aug_plane_plan(aug_plane_cut *pc, const aug_mesh *m, const aug_adj *adj,
                   const double n[3], double d, const double *adv, aug_err *e);
/* Keep only the planned cut nodes whose projection onto the plane lies in the
   polygon poly[0..npoly) (3-D points, projected; the even-odd rule, its edges
   inclusive): a bounded cut (cut_polygon.c). Their order is kept. */
int aug_plane_restrict(aug_plane_cut *pc, const aug_mesh *m, const double *poly, int npoly,
                       aug_err *e);
/* Duplicate the next count cut nodes; appends to seg the edges (2*dim doubles
   each) of the faces this opens. */
int aug_plane_step(aug_plane_cut *pc, aug_edit *ed, int64_t count, double **seg,
                   int64_t *nseg, aug_err *e);
void aug_plane_free(aug_plane_cut *pc);

/* ---- Cut paths in 2-D (thesis ch. 3.1, 3.6) ---- */
enum { AUG_CURVE_LINE = 1, AUG_CURVE_CUBIC = 2, AUG_CURVE_RQUAD = 3, AUG_CURVE_BEZIER = 4 };
#define AUG_CURVE_MAXDEG 64      /* highest degree of a general Bezier curve */
typedef struct aug_curve {
    int kind;
    double p[4][2];              /* control points: line 2, cubic 4, rational quadratic 3 */
    double w;                    /* middle weight of the rational quadratic (end weights 1) */
    int newstroke;               /* 1: does not continue the previous curve */
    int line;                    /* line of the path file it came from */
    int deg;                     /* AUG_CURVE_BEZIER: degree n, 1..AUG_CURVE_MAXDEG */
    double *h;                   /* AUG_CURVE_BEZIER: n+1 homogeneous points (w x, w y, w),
                                    w = 1 for a polynomial curve; owned by the aug_path */
} aug_curve;
void aug_curve_eval(const aug_curve *c, double t, double xy[2]);
void aug_curve_deriv(const aug_curve *c, double t, double dxy[2]);
/* B(t) and its first three derivatives, any kind (de Casteljau on the
   homogeneous points, thesis 003 eqs. 3.4-3.6); d1, d2, d3 may be NULL. */
void aug_curve_jet(const aug_curve *c, double t, double b[2], double d1[2], double d2[2], double d3[2]);
/* The degree and the homogeneous control points (w x, w y, w) of any kind, at
   most AUG_CURVE_MAXDEG + 1 of them; the pointer is h or c->h. */
int aug_curve_homog(const aug_curve *c, double (*h)[3], const double **hp);
/* Parameters t in [t0, t1] where the curve meets the line through a and b,
   increasing; returns their count (<= max(3, degree), t has room for
   AUG_CURVE_MAXDEG), -1 when the curve lies on the line. */
int aug_curve_line_roots(const aug_curve *c, const double a[2], const double b[2], double t0,
                         double t1, double *t);
/* Roots in [t0, t1] of the Bernstein polynomial sum b_i beta_{n,i}(t)
   (thesis eq. 3.5), increasing, at most n; -1 when it vanishes. */
int aug_bernstein_roots(const double *b, int n, double t0, double t1, double *t);
/* Curvature kappa(t) = |B' x B''| / |B'|^3 (thesis eq. 3.8, with the cube
   that makes it the curvature); +inf where B' = 0. */
double aug_curve_kappa(const aug_curve *c, double t);
/* The t of maximal kappa on [t0, t1] (sampled bracket, then kappa' = 0);
   1 when it lies inside (not at an end, kappa above both ends), 0 else. */
int aug_curve_kappa_max(const aug_curve *c, double t0, double t1, double *tk);

typedef struct aug_path {
    int n;
    aug_curve *c;
    double *s0;                  /* arc length at the start of curve i */
    double total;
    double *tab;                 /* per curve: arc length at AUG_PATH_NS+1 equal parameter steps */
} aug_path;
#define AUG_PATH_NS 256
/* the largest ratio of a rational curve's weights (arc: w and 1/w; the
   sweep of 2026-12-08: at w = 4e5 an arc's second leg was not cut, at
   w = 1e-5 nothing was; 1e-4 and 1e4 cut both legs as the polyline) */
#define AUG_PATH_WRATIO 1e4
/* Parse a path file (format in man/cut.1); errors name the line. */
int aug_path_parse(FILE *f, const char *name, aug_path *p, aug_err *e);
void aug_path_free(aug_path *p);
/* Curve parameter at arc length s within curve i. */
double aug_path_param(const aug_path *p, int i, double s);

/* ---- Edge map (edgemap.c): unordered node pair -> two int32 slots, open
   addressing; a zeroed map is empty. As a set: put, get != NULL, del. ---- */
typedef struct aug_edgemap {
    uint64_t *key;      /* ((uint64)min << 32 | max) + 1; 0 empty, UINT64_MAX deleted */
    int32_t *val;       /* 2 per entry */
    size_t cap, n, used;
} aug_edgemap;
int aug_edgemap_init(aug_edgemap *h, size_t hint);
void aug_edgemap_free(aug_edgemap *h);
void aug_edgemap_clear(aug_edgemap *h);
/* The two slots of edge {a, b}, NULL when absent. */
int32_t *aug_edgemap_get(const aug_edgemap *h, int32_t a, int32_t b);
/* The slots of {a, b}, inserted as {-1, -1} when absent; NULL when out of memory. */
int32_t *aug_edgemap_put(aug_edgemap *h, int32_t a, int32_t b);
void aug_edgemap_del(aug_edgemap *h, int32_t a, int32_t b);
/* Add v to the first free slot of {a, b} (0), -1 memory, -2 both slots taken. */
int aug_edgemap_link(aug_edgemap *h, int32_t a, int32_t b, int32_t v);
/* Remove v from the slots of {a, b}; deletes the entry when both are free. */
void aug_edgemap_unlink(aug_edgemap *h, int32_t a, int32_t b, int32_t v);

/* Split mode surgery on tri3, mem3 and tet4 meshes: insert a node on edge (a, b) at parameter
   s (0 < s < 1) splitting every simplex that shares the edge, or (tri3) inside
   triangle t at barycentric l. Cut edges through the split edge follow it. */
int32_t aug_split_edge(aug_edit *ed, aug_edgemap *cut, int32_t a, int32_t b, double s,
                       aug_err *e);
int32_t aug_split_tri(aug_edit *ed, int64_t t, const double l[3], aug_err *e);

enum { AUG_PATH_SNAP = 0, AUG_PATH_SPLIT = 1 };
typedef struct aug_path_cut {
    const aug_path *path;
    int mode;
    double tol;                  /* snap tolerance, relative to the edge or altitude */
    int kappa;                   /* split mode: a vertex at the curvature maximum of each
                                    piece in an element (thesis eq. 3.8); 1 by init */
    double s;                    /* arc length realised so far */
    int32_t node;                /* walk state: current node, -1 outside the mesh */
    int curve;                   /* curve of the walk state */
    double t;
    aug_edgemap cut;             /* the cut edges (node pairs) realised so far */
    int32_t *twin;               /* copies of the state node made by the last step */
    int64_t ntwin;
} aug_path_cut;
int aug_path_cut_init(aug_path_cut *pc, const aug_path *path, int mode, double tol);
void aug_path_cut_free(aug_path_cut *pc);
/* Realise the path up to arc length s_to: walk, insert (split) or snap, then
   separate the cut edges; appends the realised segments to seg. */
int aug_path_step(aug_path_cut *pc, aug_edit *ed, double s_to, double **seg, int64_t *nseg,
                  aug_err *e);

/* ---- Boundary conditions a cut adds ----
   Constrain (value v[dim]) every DOF of the nodes in a named set or a box
   (lo, hi: dim values each) of the current mesh: b += each, also those m
   has with that value already. */
int aug_cut_constrain_set(const aug_mesh *m, const char *set, const double *v, aug_bdelta *b,
                          aug_err *e);
int aug_cut_constrain_box(const aug_mesh *m, const double *lo, const double *hi,
                          const double *v, aug_bdelta *b, aug_err *e);
/* cut's --constrain SET|box:LO,HI[=u,v[,w]][@S] (lib/cut/constrain_spec.c):
   u = v (0 when no values are given) on the nodes of a set or of the box
   lo <= x <= hi (LO, HI: 2 numbers each in 2-D, 3 in 3-D) at the run's cut
   step S (default 1). cut's --drag SET|box:LO,HI:dx,dy[,dz]: at every step
   k of N, u = (k / N) d on every DOF of the set's or box's nodes (a grasped
   region pulled along d; the papers' deformation experiments, paper 000
   figs. 5-6, AMPS figs. 4-5). */
typedef struct aug_constraint {
    char set[AUG_NAME];          /* the set, "" for a box */
    double lo[3], hi[3];
    int nbox;                    /* numbers the box was given: 4 or 6 */
    double v[3];                 /* the values; --drag: d */
    int nv;                      /* values given: 0 (all zero), 2 or 3 */
    long step;                   /* --constrain: >= 1 */
    int drag;                    /* 1: a --drag, at every step */
} aug_constraint;
/* c = the --constrain spec s: 0, or -1 when s is not one (c is then undefined). */
int aug_constraint_parse(const char *s, aug_constraint *c);
/* c = the --drag spec s (the target is what precedes the last ':'; d has 2
   or 3 finite numbers): 0, or -1 when s is not one. */
int aug_drag_parse(const char *s, aug_constraint *c);
/* b += the constraints c[i] of step k of nsteps on m, in order
   (aug_cut_constrain_set, _box): each --constrain of step k (c[i].step == k)
   and every --drag, with u = ((double)k / nsteps) d; of several on one DOF
   the last one wins, and one that m has already (same value) is left out. AUG_EUSAGE when one does
   not fit m's dimension (its values or its box), e.msg "--constrain: ..." or
   "--drag: ..." naming both; AUG_EDATA, e.msg naming the option, when its set
   is not in m or its box holds no node; otherwise their errors. */
int aug_constrain_step(const aug_constraint *c, int n, const aug_mesh *m, long k, long nsteps,
                       aug_bdelta *b, aug_err *e);
/* Pull forces (AMPS sec. 4.3.2): every copy made by d (a new node at its parent's
   place) gets F along the direction from its parent's element star to its own
   (dir non-NULL: along +-dir, the sign of that direction), the parent the
   opposite force. m: the mesh after d; adj current. */
int aug_cut_pull(const aug_mesh *m, const aug_adj *adj, const aug_mdelta *d, double F,
                 const double *dir, aug_bdelta *b, aug_err *e);

/* ---- One cut step: edit -> MDLT, BDLT, UPDT, pATH (bin/cut.c and the tests) ---- */
/* keep: write the step as it is, flagged AUG_STEP_DETACHED (K_t singular),
   for solvers to report */
/* auto (the default of cut(1)): drop a piece whose volume (2-D: area) is below
   AUG_DETACH_SHARE of the mesh's, as drop does; a larger one is an error */
enum { AUG_DETACH_ERROR = 0, AUG_DETACH_PIN = 1, AUG_DETACH_DROP = 2, AUG_DETACH_KEEP = 3,
       AUG_DETACH_AUTO = 4 };
#define AUG_DETACH_SHARE 1e-3
typedef struct aug_cutter {
    aug_mesh *m;                 /* the current mesh (updated by every step) */
    aug_adj adj;
    aug_facenbr fn;
    aug_edit ed;
    aug_pieces pieces;
    int64_t nn0, nfree0;         /* cut-matrix numbering (formats/stream.md 7.2) */
    const int32_t *map0;
    const aug_dynp *dyn;         /* a dynamic stream's DYNP (updates of A, K, M), or NULL */
    int policy;                  /* AUG_DETACH_* */
    int one_piece;               /* the last analysis found one face-connected piece */
    double pull;                 /* pull force per copy, 0: none */
    const double *pull_dir;      /* its direction up to sign (planar cut: the normal), or NULL */
} aug_cutter;
typedef struct aug_cut_step {
    int32_t step;
    aug_mdelta d;
    int32_t *oldconn;            /* d->elem's connectivity before the step */
    int64_t nn_before, ne_before;
    aug_bdelta bc;               /* constraints and loads of the step (may stay empty) */
    aug_update u;
    double *seg;                 /* pATH segments, 2*dim doubles each */
    int64_t nseg;
    int64_t npieces;             /* face-connected pieces after the step */
    int32_t bad_first;           /* first element of the first detached piece, -1 */
    int64_t bad_size;
    int64_t nsmall;              /* pieces auto dropped as below AUG_DETACH_SHARE */
    double small_share;          /* their volume share of the mesh, summed */
    int64_t nseparated;          /* nodes copied to separate dropped pieces (cut_step.c separate_piece) */
} aug_cut_step;
int aug_cutter_init(aug_cutter *c, aug_mesh *m, int64_t nn0, const int32_t *map0,
                    int64_t nfree0, aug_err *e);
void aug_cutter_free(aug_cutter *c);
/* Start a step: geometry then edits c->ed and appends to s->seg. */
void aug_cut_step_init(aug_cut_step *s, int32_t step);
void aug_cut_step_free(aug_cut_step *s);
/* End the geometry: MDLT from the edit, applied to the mesh. The caller may
   then add constraints to s->bc (they see the new nodes). */
int aug_cutter_apply(aug_cutter *c, aug_cut_step *s, aug_err *e);
/* Pull forces, detached pieces (policy), the UPDT; applies s->bc to the mesh.
   Under AUG_DETACH_ERROR a detached piece is AUG_ESINGULAR naming it. */
int aug_cutter_update(aug_cutter *c, aug_cut_step *s, aug_err *e);
/* The step's records: MDLT, BDLT (when not empty), UPDT, pATH; with stats also
   sTAt (tag cut: m, k, n the order of K_t, nnew, nmod, nadd, nfix, nload,
   pieces, dropped_small, dropped_share, flags) and tIMe (time_ms = ms). */
int aug_cut_step_write(aug_writer *w, const aug_mesh *m, const aug_cut_step *s, int stats,
                       int64_t n, double ms, aug_err *e);

/* ---- Swept blades and cut surfaces in 3-D (issue 13; lib/cut/sweep*.c, blade*.c) ----
   A blade is a segment a-b; its key positions (blade file lines "blade ax ay az
   bx by bz") are passed at equal intervals of the motion time tau in [0, 1]
   (key i at i / (nkey - 1)); between two keys the ends move straight, or along
   the Bezier curves whose inner control positions are the "curve" lines
   between them (one: quadratic, two: cubic, up to AUG_BLADE_MAXCTRL). The
   cut surface is the one the blade sweeps (man/cut.1). */
#define AUG_BLADE_MAXCTRL 8
#define AUG_BLADE_SUB 16         /* samples of tau per curved key interval */
typedef struct aug_blade {
    int nkey;
    double *key;                 /* nkey * 6: a, b of each key position */
    int *nctrl;                  /* per key interval (nkey - 1): control positions */
    double *ctrl;                /* per key interval: AUG_BLADE_MAXCTRL * 6 */
} aug_blade;
/* Parse a blade file (syntax in man/cut.1); errors name the file and line. */
int aug_blade_parse(FILE *f, const char *name, aug_blade *b, aug_err *e);
void aug_blade_free(aug_blade *b);
/* The blade at motion time tau: a = p, b = p + 3 (Bernstein form of the key
   interval's Bezier curve, thesis 003 eq. 3.4; degree 1 between plain keys). */
void aug_blade_at(const aug_blade *b, double tau, double p[6]);

/* A triangle soup: the cut surface so far. */
typedef struct aug_soup {
    int64_t n, cap;
    double *t;                   /* 9 per triangle */
} aug_soup;
void aug_soup_free(aug_soup *s);
/* Append triangle (p, q, r) unless its area is <= 1e-12 * the squared
   longest edge (a blade that does not move): 1 appended, 0 skipped, -1 memory. */
int aug_soup_add(aug_soup *s, const double *p, const double *q, const double *r);
/* a surface file's corner: finite and at most AUG_COORD_MAX in magnitude (the
   bound on mesh coordinates, formats 5.1) */
int aug_soup_point_ok(const double *p);
/* s += the surface the blade sweeps for tau in [t0, t1]: the quads between
   its positions at t0, t1, the key times between them and, on a curved
   interval, the times j / AUG_BLADE_SUB of the interval between them, each
   quad (a_i, b_i, b_j, a_j) as the triangles (a_i, b_i, b_j), (a_i, b_j, a_j). */
int aug_blade_sweep(const aug_blade *b, double t0, double t1, aug_soup *s);
/* A triangle surface file: binary or ASCII STL (sweep_stl.c); a gmsh .msh
   surface mesh through aug_surface_gmsh (lib/cli, needs -lgmsh). */
int aug_stl_read(const char *path, aug_soup *s, aug_err *e);
/* Sort s's triangles by their centroids' coordinate along dir (NULL: the
   axis of the widest extent of the centroids) and fill key[] (s->n) with that
   coordinate mapped to [0, 1]: the progressive order of a --surface cut. */
int aug_soup_order(aug_soup *s, const double *dir, double *key, aug_err *e);

/* Uniform hash grid of boxes (boxgrid.c): items with bounding boxes; a query
   lists each item whose box meets the query box once. */
typedef struct aug_boxgrid {
    double h, lo[3];             /* cell size, origin */
    size_t cap, used;            /* hash slots, filled */
    uint64_t *key;               /* cell id + 1, 0 empty */
    int32_t *head;               /* per slot: first entry */
    int64_t nent, capent;
    int32_t *item, *next;        /* entries: item, next entry of the cell (-1 end) */
    int64_t capmark;
    uint32_t *mark, gen;         /* per item: query generation */
} aug_boxgrid;
int aug_boxgrid_init(aug_boxgrid *g, double h, const double lo[3]);
void aug_boxgrid_free(aug_boxgrid *g);
int aug_boxgrid_add(aug_boxgrid *g, int32_t item, const double lo[3], const double hi[3]);
/* out (*n items, *cap room, grown) = the items whose box meets [lo, hi]. */
int aug_boxgrid_query(aug_boxgrid *g, const double lo[3], const double hi[3], int32_t **out,
                      int64_t *n, int64_t *cap);

/* Geometry (tri_geom.c). Segment p-q against triangle t (9 doubles): 1 when
   it crosses the triangle's plane strictly between its ends (signed
   distances of p and q of opposite signs, |.| > eps, Moller & Trumbore 1997
   in the barycentric form) at a point inside the closed triangle (to 1e-9
   of its size), *s its parameter on p-q; else 0. */
int aug_seg_tri(const double *p, const double *q, const double *t, double eps, double *s);
/* Distance of point p from triangle t (Ericson, Real-Time Collision
   Detection, 2005, sec. 5.1.5: the closest point by Voronoi regions). */
double aug_point_tri(const double *p, const double *t);

/* A 3-D cut along a swept or given surface (blade_cut.c). mode AUG_PATH_SNAP:
   the faces between two elements whose centroids the surface separates (the
   segment between them crosses it, aug_seg_tri) open by node duplication, no
   new elements (AMPS sec. 4.3.2 for a plane); any element type.
   AUG_PATH_SPLIT (tet4): every edge the surface crosses is split at the
   crossing (aug_split_edge, both ends farther than tol times the edge; a
   nearer end is snapped, i.e. taken as lying on the surface), then the faces
   whose nodes all lie on the surface open by node duplication. */
typedef struct aug_blade_cut {
    int mode;
    double tol;                  /* split: snap tolerance, relative to the edge */
    double eps, h, hon;          /* 1e-12 * mesh size; longest element edge; 1e-9 h */
    double lo[3], hi[3];         /* the mesh's box, widened by h */
    int64_t nsplit;              /* split: edges split so far */
    aug_soup soup;               /* the surface so far */
    aug_boxgrid tg, eg;          /* triangles of soup; elements (their boxes) */
    aug_edgemap pairs;           /* snap: cut element pairs */
    unsigned char *on;           /* split: node lies on the surface (capon nodes) */
    int64_t capon;
    int64_t nface;               /* faces cut so far */
    int oom;                     /* split: a face test ran out of memory (the
                                    aug_separate_node callback cannot say so) */
    int32_t *buf, *buf2;         /* query workspaces */
    int64_t nbuf, capbuf, nbuf2, capbuf2;
} aug_blade_cut;
/* What one cut step realises (sweep_steps.c): step k of n of a blade
   (blade = 1, b) its sweep for tau in [(k-1)/n, k/n] (aug_blade_sweep); of a
   surface (blade = 0, all, ordered by aug_cutsurf_surface along dir, NULL:
   the widest axis) the triangles of key in ((k-1)/n, k/n], from 0 at k = 1
   and every one left at k = n. The step's triangles: step. */
typedef struct aug_cutsurf {
    int blade;
    aug_blade b;
    aug_soup all, step;
    double *key;
    int64_t next;
} aug_cutsurf;
void aug_cutsurf_free(aug_cutsurf *s);
int aug_cutsurf_surface(aug_cutsurf *s, const double *dir, aug_err *e);
int aug_cutsurf_step(aug_cutsurf *s, long k, long n, aug_err *e);
/* 1 when the box of some triangle of the whole surface meets the mesh's, 0
   not, -2 when it has no triangle of positive area (a blade that does not
   move: aug_soup_add skips them), -1 memory. */
int aug_cutsurf_meets(const aug_cutsurf *s, const aug_mesh *m);

int aug_blade_cut_init(aug_blade_cut *bc, const aug_mesh *m, int mode, double tol, aug_err *e);
void aug_blade_cut_free(aug_blade_cut *bc);
/* One step: the triangles add[0..nadd) join the surface; the faces they cut
   open (appending their edges to seg); fn: the face neighbours of the mesh
   before the step (the cutter's). */
int aug_blade_cut_step(aug_blade_cut *bc, aug_edit *ed, const aug_facenbr *fn, const double *add,
                       int64_t nadd, double **seg, int64_t *nseg, aug_err *e);
/* ---- Paths projected onto a membrane along a view (lib/cut/path_project.c) ----
   Thesis 003 sec. 3.1.1: the sheet (mem3) seen through the orthographic view
   with orthonormal screen axes u, v (toward the viewer w = u x v) is a 2-D
   triangle mesh, its image; a path (screen coordinates (u.x, v.x)) is cut on
   the image by aug_path_step and each edit is replayed on the sheet, new
   nodes lifted back onto its triangles (the shape unchanged). A cut's lips
   are free edges, which a membrane alone cannot hold out of its plane: the
   cut scene needs a foundation (FNDN) or its K_t is singular. */
typedef struct aug_view {
    double u[3], v[3], w[3];
    int flip;                    /* the sheet faces away: the image's triangles reversed */
    aug_mesh img;                /* the image: tri3, x = (u.x, v.x) */
    aug_adj adj;
    aug_edit ed;
} aug_view;
/* The image of the mem3 mesh m; AUG_EDATA naming a triangle seen edge-on or
   facing the other way (a folded sheet). */
int aug_view_init(aug_view *vw, const aug_mesh *m, const double u[3], const double v[3], aug_err *e);
void aug_view_free(aug_view *vw);
/* view = (u, v) normalised; AUG_EUSAGE when zero, not finite or not orthogonal. */
int aug_view_axes(double view[6], aug_err *e);
/* aug_path_step on the image up to arc length s_to, replayed onto ed3 (the
   cutter's edit of the sheet); *seg (empty on entry) gets the step's
   segments as 3-D points. */
int aug_view_path_step(aug_view *vw, aug_path_cut *pc, aug_edit *ed3, int32_t step, double s_to,
                       double **seg, int64_t *nseg, aug_err *e);

#endif
