/* augcut refinement layer: conditional (constrained) Delaunay re-triangulation of
   the elements a cut step intersected and longest-edge bisection until every
   triangle meets the aspect-ratio bound (thesis 003, ch. 3.2-3.3, algorithm 1
   "ACDM"); 3-D conformal longest-edge bisection of tetrahedra; the refined step
   folded into one MDLT + UPDT (formats/stream.md 7.1, 7.2, 7.4). */
#ifndef AUG_REFINE_H
#define AUG_REFINE_H

#include "aug_cut.h"

/* ---- Local constrained Delaunay triangulation (cdt_local.c) ----
   A triangulated planar region (counter-clockwise triangles over its own vertex
   numbering; coincident vertices stay distinct, so slits are allowed). Edges
   with one triangle are the region's boundary; `fixed' edges are constraints.
   Triangles carry a tag (caller's data: material, origin) that insertion,
   recovery and flips pass on to the triangles they create. */
typedef struct aug_cdt {
    int32_t nv, capv;
    double *xy;          /* 2 per vertex */
    int32_t nt, capt;
    int32_t *tri;        /* 3 per triangle, -1 for a free slot */
    int32_t *tag;        /* per triangle */
    int32_t nfree;
    int32_t *freel;      /* free triangle slots */
    aug_edgemap edges;   /* edge -> its triangles */
    aug_edgemap fixed;   /* constrained edges (slot 0 = 1) */
    double eps;          /* relative tolerance of the geometric predicates */
    int64_t flips;       /* statistics */
} aug_cdt;
int aug_cdt_init(aug_cdt *c);
void aug_cdt_free(aug_cdt *c);
void aug_cdt_reset(aug_cdt *c);
int32_t aug_cdt_vertex(aug_cdt *c, double x, double y);          /* id or -1 (memory) */
/* Add a triangle (counter-clockwise); slot, or -1 (memory / non-manifold edge). */
int32_t aug_cdt_tri(aug_cdt *c, int32_t a, int32_t b, int32_t d, int32_t tag);
int aug_cdt_fix(aug_cdt *c, int32_t a, int32_t b);                /* mark fixed: 0 / -1 */
int aug_cdt_is_fixed(const aug_cdt *c, int32_t a, int32_t b);
/* Triangle across edge (a, b) from triangle t, -1 if none. */
int32_t aug_cdt_across(const aug_cdt *c, int32_t t, int32_t a, int32_t b);
/* Triangle whose closure holds (x, y): searched from hint (walk), else all;
   -1 when no triangle holds it. *at receives a vertex at the point or -1. */
int32_t aug_cdt_locate(const aug_cdt *c, double x, double y, int32_t hint, int32_t *at);
/* Bowyer-Watson insertion of vertex v (thesis 003 sec. 3.3.1; Bowyer 1981,
   Watson 1981) into the triangle t holding it: the cavity is every triangle
   whose circumcircle strictly holds v and that is reached from t without
   crossing a fixed edge; it is re-triangulated as the star of v. A vertex on
   an edge splits it (a fixed edge into two fixed halves). 0 or an AUG_E code. */
int aug_cdt_insert(aug_cdt *c, int32_t v, int32_t t);
/* Make a-b an edge and fix it (constraint recovery: remove the triangles the
   segment crosses and re-triangulate both sides Delaunay, Anglada 1997); a
   vertex on the segment splits it. AUG_EDATA when it crosses a fixed edge. */
int aug_cdt_recover(aug_cdt *c, int32_t a, int32_t b);
/* Lawson flips of non-fixed interior edges until the triangulation is
   constrained Delaunay (strict in-circle test: co-circular ties keep the
   current diagonal). Only edges whose triangles have equal tags flip. */
int aug_cdt_legalize(aug_cdt *c);
/* In-circle and orientation with the tolerance of c (> 0: inside / left). */
int aug_cdt_incircle(const aug_cdt *c, const double *a, const double *b, const double *d,
                     const double *p);
double aug_orient2d(const double *a, const double *b, const double *p);
/* 3-vectors of the membrane refiner (refine_mem3.c, refine_mem3_region.c):
   r = a - b, a . b, r = a x b */
static inline void aug_sub3(const double *a, const double *b, double *r)
{
    r[0] = a[0] - b[0], r[1] = a[1] - b[1], r[2] = a[2] - b[2];
}
static inline double aug_dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline void aug_cross3(const double *a, const double *b, double *r)
{
    r[0] = a[1] * b[2] - a[2] * b[1], r[1] = a[2] * b[0] - a[0] * b[2], r[2] = a[0] * b[1] - a[1] * b[0];
}
/* sign of the in-circle determinant of p against (a, b, d) counter-clockwise,
   0 within eps times its permanent (co-circular ties) */
int aug_incircle(const double *a, const double *b, const double *d, const double *p, double eps);

/* ---- Mutable triangle/tetrahedron mesh with edge adjacency (trimesh.c) ----
   The work copy of the refined mesh: geometry and connectivity only, edits in
   place, new nodes and elements appended; per element the area (volume) of the
   original element it descends from (for the area ratio) and a stamp of the
   step that last changed it. */
typedef struct aug_work {
    aug_mesh m;          /* dim, nv, nn, x, ne, conn, mat (no sets/constraints) */
    int64_t capn, cape;
    double *area0;       /* per element: measure of its original ancestor */
    int32_t *stamp;      /* per element: step that last wrote it, -1 never */
    int32_t *ver;        /* per element: writes so far (stale queue entries) */
    int32_t *own;        /* per element: caller's owner tag, copied to bisection children */
    aug_edgemap adj;     /* 2-D: edge -> its (at most 2) triangles */
    int32_t **nel;       /* 3-D: node -> its elements (unordered) */
    int32_t *ncnt, *ncap;
    aug_edgemap fixed;   /* 2-D: interior constrained edges (cut edges not separated) */
    int32_t step;        /* current step (stamps) */
    /* the current step's changes */
    int64_t nn_begin, ne_begin;
    int64_t nmod, capmod;
    int32_t *mod;        /* elements < ne_begin written this step (unique) */
    int32_t *mod_old;    /* their connectivity at aug_work_begin */
    int32_t *parent;     /* new nodes' parents (nn - nn_begin of them) */
    int64_t capparent;
    int32_t *cre;        /* per node, 4 slots: the nodes a refinement node was
                            made from (a midpoint: its edge's ends; a centroid:
                            the four corners; a copy: its original), -1 unused;
                            all -1 for the cut's own and the original nodes */
    int64_t max_new;     /* refinement stops adding nodes beyond this many per step
                            (0: the options' max_new, else 200000) */
    const int32_t *keep; /* 3-D, or NULL: per owner tag (< nkeep), the last step that
                            re-writes that owner; its tets are not bisected before it */
    int64_t nkeep;
} aug_work;
int aug_work_init(aug_work *w, const aug_mesh *m);   /* copies geometry; builds adjacency */
void aug_work_free(aug_work *w);
void aug_work_begin(aug_work *w, int32_t step);
int32_t aug_work_node(aug_work *w, const double *x, int32_t parent);  /* -1: memory */
/* node was made from c[0..n) (n <= 4; refiner.c fix_inserted: it is
   constrained where all of them are) */
void aug_work_creators(aug_work *w, int32_t node, const int32_t *c, int n);
int aug_work_set(aug_work *w, int64_t e, const int32_t *conn);       /* 0 / AUG_E* */
int64_t aug_work_add(aug_work *w, const int32_t *conn, int32_t mat, double area0); /* -1 */
/* 2-D: triangle across edge {a, b} from triangle t, -1 if none (boundary). */
int64_t aug_work_across(const aug_work *w, int64_t t, int32_t a, int32_t b);
int aug_work_edge_fixed(const aug_work *w, int32_t a, int32_t b);
/* The step's MDLT (relative to the state at aug_work_begin; parents as recorded)
   and, when oldconn != NULL, the old connectivity of d->elem (malloc'd). */
int aug_work_delta(const aug_work *w, int32_t step, int32_t flags, aug_mdelta *d,
                   int32_t **oldconn, aug_err *e);

/* ---- Refinement options and per-step figures ---- */
typedef struct aug_refine_opt {
    double max_aspect;   /* 2-D: longest / shortest edge bound (thesis: 3) */
    double area_ratio;   /* > 0: refine only elements with measure / original > this */
    double min_angle;    /* > 0: also refine triangles with a smaller angle (degrees) */
    double max_aspect3;  /* 3-D: bound on R / (3 r) (1 for the regular tet) */
    double min_dihedral; /* 3-D: also refine tets with a smaller dihedral angle (degrees) */
    int max_level3;      /* 3-D: bisection levels per step at most */
    int flip;            /* 2-D: Lawson flips after each bisection (Lepp-Delaunay) */
    int min_angle_given; /* mem3: min_angle applies only when given (refine --min-angle) */
    int64_t max_new;     /* new nodes per step at most (0: aug_refine_default_cap) */
} aug_refine_opt;
void aug_refine_opt_default(aug_refine_opt *o);

/* The default cap on a step's new nodes: 1000 + 100 per element of the region
   the step changed, at most AUG_UPDT_MAX_ORDER / (2 dim) nodes (half the
   orders a step's UPDT may have: a larger step is refused by update_build,
   after the whole refinement; plain bisection, --no-flip, grew a 2-D step by
   138k nodes so). */
static inline int64_t aug_refine_default_cap(int64_t region, int dim)
{
    int64_t c = 1000 + 100 * region, lim = AUG_UPDT_MAX_ORDER / (2 * dim);
    return c < lim ? c : lim;
}

/* Parent policy for new nodes of refinement: the end of the split edge with the
   fewest constraints (FIXD components, then sets and output membership, scored
   on its original ancestor), then the nearer end, then the lower index. */
typedef struct aug_parent_rule {
    const int32_t *score;    /* per node of the mesh before the step */
    int64_t nscore;
} aug_parent_rule;

typedef struct aug_bisect_stats {
    int64_t bisections, flips, skipped_corner, skipped_small, capped;
} aug_bisect_stats;
/* Is element e bad under o (2-D: aspect > max_aspect or an angle < min_angle,
   and measure / area0 > area_ratio)? */
int aug_bisect2d_bad(const aug_work *w, int64_t e, const aug_refine_opt *o);
/* 3-D: tet t above --max-aspect3 or below --min-dihedral (with area_ratio,
   only when also larger than area_ratio times its original volume) */
int aug_bisect3d_bad(const aug_work *w, int64_t t, const aug_refine_opt *o);
/* ACDM (thesis 003 algorithm 1) as longest-edge propagation-path bisection
   (Rivara 1997): every bad triangle among seeds (and every bad triangle the
   bisections create) is refined by bisecting the terminal edge of its LEPP,
   which splits both triangles of that edge, so no node hangs; with o->flip each
   new midpoint is followed by Lawson flips of the edges opposite to it. Stops
   when no bad triangle is left, except corners between two constrained edges
   that are too sharp for the bound and triangles at the size floor (counted). */
int aug_bisect2d(aug_work *w, const int64_t *seeds, int64_t nseed, const aug_refine_opt *o,
                 const aug_parent_rule *pr, aug_bisect_stats *st, aug_err *e);

/* 3-D conformal edge bisection: for each bad tet of seeds (aspect R/(3r) >
   max_aspect3 or min dihedral < min_dihedral) the first of its edges, longest
   first, whose bisection (splitting every tet around the edge) lowers the worst
   aspect around that edge is bisected; children are checked again, at most
   max_level3 levels. Tets no split improves are left (skipped_corner). */
int aug_bisect3d(aug_work *w, const int64_t *seeds, int64_t nseed, const aug_refine_opt *o,
                 const aug_parent_rule *pr, aug_bisect_stats *st, aug_err *e);

/* ---- The refine filter's state across steps (refiner.c) ----
   cut: the mesh as the upstream cut sees it (its MDLTs apply to it); base: the
   refined mesh as downstream sees it (the folded MDLTs apply to it); work: its
   editable copy; cnode: cut node -> base node. */
typedef struct aug_refiner {
    aug_mesh cut, base;
    aug_work work;
    aug_edgemap cadj;     /* 2-D: cut-view edge -> its triangles */
    double *carea0;       /* per cut-view element: measure of its original ancestor */
    int32_t *cel;         /* 3-D: cut-view element -> its unrefined work element, -1;
                             work.own: work element -> the cut-view element holding it */
    int64_t capce;
    int32_t *cnode;       /* cut-view node -> base node */
    int64_t capc;
    int32_t *own;         /* mem3: base element -> the cut-view element it still is, -1 */
    int64_t capown;
    int32_t *corig, *borig; /* mem3: cut-view / base element -> the original triangle it lies in */
    int64_t capcorig, capborig;
    int32_t *cre3;        /* mem3: per base node, 4 slots, as aug_work's cre (the
                             nodes refine made it from; -1 unused, all -1 for the
                             cut's own and the original nodes) */
    int64_t capcre3;      /* (slots) */
    int32_t *conn0;       /* mem3: the original triangles (ne0) */
    int64_t ne0;
    int64_t nn0, nfree0;  /* original nodes and free DOFs */
    int32_t *map0;        /* aug_dofmap of the original mesh */
    const aug_dynp *dyn;  /* a dynamic stream's DYNP (updates of A, K, M), or NULL */
    double route_tol;     /* > 0 (mem3's local refiners): a cut edge passes through the region's
                             inner fine nodes within route_tol of its length (refine_region2d.c) */
    aug_refine_opt opt;
    int32_t *last;        /* 3-D look-ahead: per cut-view element, the last step whose
                             MDLT changes it (aug_refiner_plan), -1 none */
    int64_t nlast;
} aug_refiner;
/* 3-D look-ahead over the whole cut stream, before its first step is refined:
   every MDLT's changed elements in step order (d), so that a tet a later step
   re-cuts is bisected only at the last step that changes it. */
int aug_refiner_plan(aug_refiner *r, const aug_mdelta *d, aug_err *e);

/* Per-step figures for qUAl (tag "refine"). */
typedef struct aug_refine_q {
    double aspect_mean, aspect_max, area_ratio, min_angle;     /* after refine */
    double aspect_mean0, aspect_max0, area_ratio0, min_angle0; /* the cut's own pieces */
    int64_t intersected, region, added, nodes, cut_added, cut_nodes, bad_left;
    int64_t bisections, flips, capped;
    int64_t written, written0;  /* elements the figures are over (after, the cut's own) */
    double t_cdt, t_bisect, t_update, t_total;                 /* ms */
} aug_refine_q;

/* From the whole original mesh (phase 1). */
int aug_refiner_init(aug_refiner *r, const aug_mesh *m, const aug_refine_opt *o, aug_err *e);
void aug_refiner_free(aug_refiner *r);
/* One cut step: d (and bc, may be NULL) as the cut wrote them, seg[nseg*2*dim]
   its pATH (may be NULL). Fills out (the folded MDLT relative to r->base),
   outbc (bc in the refined numbering; NULL if bc is NULL), q; then advances
   the state. When u is not NULL the matching UPDT is built (eq. 3.1). */
struct aug_bdelta;
int aug_refine_step(aug_refiner *r, const aug_mdelta *d, const struct aug_bdelta *bc,
                    const double *seg, int64_t nseg, aug_mdelta *out, struct aug_bdelta *outbc,
                    aug_update *u, aug_refine_q *q, aug_err *e);
/* The same for a membrane (mem3) sheet (lib/refine/refine_mem3.c): a step
   whose triangles refine has not changed before is replayed onto the refined
   mesh, one through refined triangles re-triangulated per original triangle
   in its plane (aug_refine_mem3_region); then longest-edge bisection and
   coplanar flips in each triangle's plane; seg (3-D) as for 2-D. */
/* a[0..need) available (new entries -1): 0 or -1 (memory) */
int aug_refine_grow_i32(int32_t **a, int64_t *cap, int64_t need);
/* mem3: node (a base node) was made from c[0..n) (n <= 4), in r->cre3; 0 or
   -1 (memory) */
int aug_refine_mem3_creators(aug_refiner *r, int32_t node, const int32_t *c, int n);
/* The constraints of the nodes refine made (refiner.c): out holds a step's
   translated constraints on the mesh base (before the step's new nodes,
   base->nn of them) grown to nn nodes; parent[j - pbase] is the parent of a
   node j >= base->nn, cre[4 j ..] its 4 creator slots (nodes from ncre on
   have none).
   A made node whose creators are all constrained in a component after the
   step is constrained there at their mean, and follows them when the step
   prescribes one of them anew. 0, or AUG_ENOMEM. */
int aug_refine_fix_made(const aug_mesh *base, int64_t nn, const int32_t *parent, int64_t pbase,
                        const int32_t *cre, int64_t ncre, aug_bdelta *out, aug_err *e);
int aug_refine_mem3_init(aug_refiner *r);
int aug_refine_step_mem3(aug_refiner *r, const aug_mdelta *d, const struct aug_bdelta *bc, const double *seg,
                         int64_t nseg, aug_mdelta *out, struct aug_bdelta *outbc, aug_update *u, aug_refine_q *q,
                         aug_err *e);
/* mem3, a cut step through refined triangles (lib/refine/refine_mem3_region.c):
   r->cut holds the step already (oldc: the old connectivity of d->elem; nnc,
   nec: the cut's counts before; r->corig of its pieces set), ed an edit of
   r->base. The step's new nodes get base nodes in the cut's order (r->cnode;
   a point near an earlier refinement node is realised at it); per original
   triangle touched, in its plane, its refined triangles and the step's pieces
   in it are re-triangulated by aug_refine_region2d and written back (borig);
   fine nodes left shared by two lips get copies. */
int aug_refine_mem3_region(aug_refiner *r, aug_edit *ed, const aug_mdelta *d, const int32_t *oldc, int64_t nnc,
                           int64_t nec, const double *seg, int64_t nseg, aug_refine_q *q, aug_err *e);
/* A step without MDLT: translate bc only (and build its UPDT when u != NULL). */
int aug_refine_bc_only(aug_refiner *r, int32_t step, const struct aug_bdelta *bc,
                       struct aug_bdelta *outbc, aug_update *u, aug_err *e);
/* qUAl and tIMe named values of q. */
void aug_refine_q_kv(const aug_refine_q *q, int dim, aug_kv *qual, aug_kv *time);
/* The n records of cut step `step` (in stream order) refined and written to w
   (lib/refine/refine_records.c). */
int aug_refine_records(aug_refiner *r, const aug_rec *recs, int n, int32_t step, aug_writer *w,
                       aug_err *e);

/* Internal steps of aug_refine_step (r->cut already holds the cut's step; nnc,
   nec: its counts before; oldc: the old connectivity of d->elem). 2-D: the
   changed region of the refined mesh re-triangulated conditional Delaunay with
   the step's nodes and cut edges, node copies mapped (refine_region2d.c);
   3-D: the step's changes carried over to unrefined tets (refine_map3d.c). */
int aug_refine_region2d(aug_refiner *r, const aug_mdelta *d, const int32_t *oldc, int64_t nnc,
                        int64_t nec, const double *seg, int64_t nseg, aug_refine_q *q, aug_err *e);
int aug_refine_map3d(aug_refiner *r, const aug_mdelta *d, const int32_t *oldc, int64_t nnc,
                     int64_t nec, aug_refine_q *q, aug_err *e);
/* Detach element e from the adjacency (recording it as changed) / give it a new
   connectivity without detaching (after aug_work_unlink). */
int aug_work_unlink(aug_work *w, int64_t e);
int aug_work_put(aug_work *w, int64_t e, const int32_t *conn);

#endif
