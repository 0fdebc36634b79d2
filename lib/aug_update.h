/* augcut update layer: one cut step as a mesh delta (MDLT) and a principal
   submatrix update (UPDT), AMPS paper eq. 3.1 (formats/stream.md). */
#ifndef AUG_UPDATE_H
#define AUG_UPDATE_H

#include "aug_dyn.h"
#include "aug_mesh.h"

/* Mesh change of one step: new nodes are appended (their index is nn + i at the
   time of the step), changed elements get a new connectivity, new elements are
   appended (refinement/splitting). */
typedef struct aug_mdelta {
    int32_t step;
    int64_t nnew;
    int32_t *parent;     /* nnew: node each new node was copied or split from */
    double *x;           /* nnew*dim coordinates */
    int64_t nmod;
    int32_t *elem;       /* nmod element indices, increasing */
    int32_t *conn;       /* nmod*nv new connectivity */
    int64_t nadd;
    int32_t *conn_add;   /* nadd*nv */
    int32_t *mat_add;    /* nadd material indices */
    int32_t flags;       /* AUG_STEP_* */
} aug_mdelta;

enum {
    AUG_STEP_DETACHED = 1,   /* this step detaches a piece without Dirichlet support */
    AUG_STEP_PINNED = 2,     /* ... which was pinned by added constraints */
    AUG_STEP_DROPPED = 4     /* ... which was dropped (its DOFs constrained to 0) */
};

/* Principal submatrix update of one step, relative to the previous step's
   matrix K_{t-1} (order n_{t-1}):
     K_t = [K_{t-1} 0; 0 I_k] - Hbar (E + [0 0; 0 I_k]) Hbar'
   Hbar = [H 0; 0 I_k]: H holds m increasing indices into 0..n_{t-1}-1, the new
   DOFs are n_{t-1}..n_{t-1}+k-1. E is (m+k)x(m+k) symmetric, column-major.
   df = f_t - [f_{t-1}; 0] restricted to Hbar (loads changed on H and loads on
   the new DOFs). */
/* the largest m + k a writer produces (formats/stream.md 7.2: E is dense,
   16384^2 doubles = 2 GiB) */
#define AUG_UPDT_MAX_ORDER 16384

typedef struct aug_update {
    int32_t step;
    int32_t m, k;
    int32_t *H;
    double *E;
    double *df;
    /* dynamic streams (formats/stream.md 7.8, UPKM): E is the update of the
       effective matrix A (aug_dyn.h), and EK, EM those of K and M on the same
       Hbar in the same form (new-new blocks -K_t, -M_t); NULL in statics */
    double *EK, *EM;
    /* in memory only (solver.c, keep_blocks): keep[i] = 1 when the update
       keeps the block of H[i] that K_t replaces by a unit row; NULL: none */
    unsigned char *keep;
} aug_update;

/* Constraints and loads changed by one step (BDLT, formats/stream.md 7.7). */
typedef struct aug_bdelta {
    int32_t step;
    int64_t nfix;
    int32_t *fix_dof;    /* strictly increasing after aug_bdelta_finish */
    double *fix_val;
    int64_t nload;
    int32_t *load_dof;   /* strictly increasing; the new total force on that dof */
    double *load_val;
    int64_t capfix, capload;
} aug_bdelta;

void aug_bdelta_init(aug_bdelta *b);
void aug_bdelta_free(aug_bdelta *b);
int aug_bdelta_empty(const aug_bdelta *b);
/* Cut geometry of one step (pATH, formats/stream.md 7.6): nseg segments, each
   two end points of dim coordinates. */
typedef struct aug_pathrec {
    int32_t step;
    int dim;
    int64_t nseg;
    double *seg;         /* nseg*2*dim */
} aug_pathrec;

void aug_mdelta_init(aug_mdelta *d);
void aug_mdelta_free(aug_mdelta *d);
/* d := d followed by d2 (made on the mesh after d, adding no elements) as one
   MDLT; old (connectivity before d of the re-wired elements) extended with
   old2 (before d2). ne0: element count before d. 0 or -1 (memory). */
int aug_mdelta_merge(aug_mdelta *d, int32_t **old, int nv, int dim, int64_t ne0, const aug_mdelta *d2,
                     const int32_t *old2);
void aug_update_init(aug_update *u);
void aug_update_free(aug_update *u);

/* Step-family codecs (lib/mesh/step_rec.c): MDLT needs the mesh's dimension
   and element size; every read checks the payload (counts, orders, finite
   values) and fills the struct, which is freed by its _free also on error. */
int aug_write_mdelta(aug_writer *w, int dim, int nv, const aug_mdelta *d, aug_err *e);
int aug_read_mdelta(const aug_rec *rec, int dim, int nv, aug_mdelta *d, aug_err *e);
/* aug_write_update writes the step's UPKM first when u->EK is set. */
int aug_write_update(aug_writer *w, const aug_update *u, aug_err *e);
int aug_read_update(const aug_rec *rec, aug_update *u, aug_err *e);
/* UPKM: i32 m, i32 k, f64 EK[s*s], f64 EM[s*s] (s = m + k, symmetric, finite);
   read into a struct whose m, k, step are set and EK, EM filled (H, E, df NULL).
   aug_update_attach_km moves them into the UPDT u of the same step, after
   checking that step, m and k agree (else AUG_EDATA naming both records) and
   that u's E is cM EM + cK EK off the diagonal (formats 7.8; the diagonal of
   a constrained index differs: identity rows in all three). */
int aug_read_updkm(const aug_rec *rec, aug_update *km, aug_err *e);
int aug_update_attach_km(aug_update *u, aug_update *km, long km_index, const aug_rec *updt, double cM,
                         double cK, aug_err *e);
int aug_write_bdelta(aug_writer *w, const aug_bdelta *b, aug_err *e);
int aug_read_bdelta(const aug_rec *rec, aug_bdelta *b, aug_err *e);
int aug_write_path(aug_writer *w, const aug_pathrec *p, aug_err *e);
int aug_read_path(const aug_rec *rec, aug_pathrec *p, aug_err *e);
void aug_pathrec_free(aug_pathrec *p);

/* Apply a mesh delta to m (nodes appended, elements re-wired and appended, new
   nodes inherit their parent's constraints and set memberships). */
int aug_mesh_apply(aug_mesh *m, const aug_mdelta *d, aug_err *e);

/* Cut-matrix numbering (formats/stream.md 7.2) of a mesh whose first nn0 nodes
   are the original ones, numbered by map0 (aug_dofmap) with nfree0 free DOFs:
   index(node, c) = map0[node*dim+c] for node < nn0 (-1 if constrained), else
   nfree0 + (node - nn0)*dim + c. */
int64_t aug_cut_index(const aug_mesh *m, int64_t nn0, const int32_t *map0, int64_t nfree0,
                      int64_t node, int c);
/* The UPDT of mesh delta d applied to mesh `before` (eq. 3.1; lib/cut/update_build.c):
   H = the old matrix indices whose row of K or whose load changes (among the DOFs
   of changed elements), k = dim * d->nnew, E = -(K_t - [K_{t-1} 0; 0 0]) on Hbar
   (new-new block: -K_t), df = f_t - [f_{t-1}; 0] on Hbar; K_t, f_t as assembled
   from scratch by aug_assemble_cut / aug_load_cut (aug_cut.h). With a BDLT of the
   same step: aug_update_build_bc. */
int aug_update_build(const aug_mesh *before, const aug_mdelta *d, int64_t nn0,
                     const int32_t *map0, int64_t nfree0, aug_update *u, aug_err *e);

#endif
