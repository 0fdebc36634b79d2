/* augcut stats layer: mesh quality summaries, the deterministic text dump of
   every record, the per-step (step, method) table and its CSV, the stream
   summary, the VTK .vtu export and .pvd time series, and the Matrix Market
   export of K and M. These functions write text to a FILE the
   caller gives them; they never print anywhere else and never exit. */
#ifndef AUG_STATS_H
#define AUG_STATS_H

#include "aug_fem.h"
#include "aug_update.h"

/* Quality of a whole mesh (aug_elem_quality per element): totals, extremes and
   fixed-bin histograms. Non-finite qualities (degenerate elements after a cut)
   are counted in nbad and left out of the extremes and histograms. */
#define AUG_QHIST 8
extern const double aug_qhist_aspect[AUG_QHIST + 1]; /* bin edges, last = +inf */
extern const double aug_qhist_angle[AUG_QHIST + 1];  /* degrees */
extern const double aug_qhist_sjac[AUG_QHIST + 1];   /* scaled Jacobian (hex8) */
typedef struct aug_qstats {
    int64_t ne, nbad;
    double measure;                  /* total volume (tet4, hex8) or area (tri3) */
    double asp_min, asp_mean, asp_max;
    double ang_min, ang_mean, ang_max; /* min angle (tri3, hex8 corners) / min dihedral (tet4), degrees */
    double edge_ratio_max;
    int64_t asp_hist[AUG_QHIST];
    int64_t ang_hist[AUG_QHIST];
    double sj_min, sj_mean;          /* hex8: scaled Jacobian (NAN otherwise) */
    int64_t sj_hist[AUG_QHIST];
} aug_qstats;
void aug_mesh_qstats(const aug_mesh *m, aug_qstats *s);
/* Histogram bin of value v for edges[0..AUG_QHIST] (v below edges[0] goes to bin 0). */
int aug_qhist_bin(const double *edges, double v);

/* --dump: one header line per record "#N TYPE step=S flags=F len=L" (L the
   inflated payload length) and its fields decoded per formats/stream.md, floats
   as %.17g. The dump keeps the mesh it has read to decode later records. */
typedef struct aug_dump {
    int no_times;     /* leave out tIMe records */
    aug_mesh mesh;    /* mesh records absorbed so far (dimension, element size) */
} aug_dump;
void aug_dump_init(aug_dump *d, int no_times);
void aug_dump_free(aug_dump *d);
/* One record (TAIL included); payloads that do not match their layout fail. */
int aug_dump_record(FILE *out, aug_dump *d, const aug_rec *rec, aug_err *e);

/* Reaction resultants (lib/stats/reactab.c) from rEAC records: per step the
   last rEAC of that step (its last frame) as a row of columns, column 0 the
   total over every constrained DOF, then each set in the order it first
   appears; per column the largest magnitude |R| over every rEAC and its step
   and frame. */
typedef struct aug_reacrow {
    int32_t step, frame;
    double time;
    int64_t ndof;
    int ncol;                 /* columns known when the row was written */
    double *val;              /* ncol*dim; NAN for a set the record lacks */
} aug_reacrow;
typedef struct aug_reactab {
    int dim;
    long nrec;
    int ncol, colcap;
    char (*name)[AUG_NAME];   /* per column ("" for the total) */
    double *max;
    int32_t *max_step, *max_frame;
    aug_reacrow *row;
    size_t nrow, rowcap;
    aug_reaction q;           /* read buffer */
} aug_reactab;
void aug_reactab_init(aug_reactab *t);
void aug_reactab_free(aug_reactab *t);
int aug_reactab_add(aug_reactab *t, const aug_rec *rec, aug_err *e);
/* CSV columns (0 without rEAC): reaction_x, reaction_y[, reaction_z] for the
   total, then SET_x, SET_y[, SET_z] per set; the value of column k at a step
   (*found = 0: none). */
int aug_reactab_ncsv(const aug_reactab *t);
void aug_reactab_csv_name(const aug_reactab *t, int k, char *buf, size_t cap);
double aug_reactab_csv_value(const aug_reactab *t, int32_t step, int k, int *found);
/* The summary's lines: per column the last resultant and the largest |R|. */
void aug_reactab_print(FILE *o, const aug_reactab *t);

/* Per-step table: one row per (step, method) from sTAt and tIMe records with
   the same step and tag; rows in stream order; the reaction resultants of
   rEAC records by step (react). */
typedef struct aug_steprow {
    int32_t step;
    char method[16];
    int has_stat, has_time;
    aug_kv stat, time;
} aug_steprow;
typedef struct aug_steptab {
    aug_steprow *row;
    size_t n, cap;
    aug_reactab react;
} aug_steptab;
void aug_steptab_init(aug_steptab *t);
void aug_steptab_free(aug_steptab *t);
/* Add a sTAt, tIMe or rEAC record (other types are ignored). */
int aug_steptab_add(aug_steptab *t, const aug_rec *rec, aug_err *e);
/* Value of key in row r: sTAt first, then tIMe; NAN when absent (*found = 0). */
double aug_steprow_get(const aug_steprow *r, const char *key, int *found);
/* CSV: step,method,time_ms,relres,m,k then every other key of any row, sorted
   by name, then the reaction columns of the row's step; an empty cell where a
   row lacks the key. */
int aug_steptab_csv(FILE *out, const aug_steptab *t, aug_err *e);

/* the median of v[0..n) (reordered in place), NaN entries left out; NaN when
   none is left */
double aug_median(double *v, size_t n);

/* Stream summary: fed every record, keeps counts, the mesh (with the mesh
   deltas of steps <= step_limit applied), the last displacement field of a
   step <= step_limit, matrix and per-step figures. */
typedef struct aug_summary aug_summary;
aug_summary *aug_summary_new(const aug_reader *r, int32_t step_limit, aug_err *e);
void aug_summary_free(aug_summary *s);
int aug_summary_add(aug_summary *s, const aug_rec *rec, aug_err *e);
/* Mark the end: rec is the TAIL record (NULL when the stream broke off).
   A whole stream is checked as a whole (aug_replay_end: pLAN's last step,
   no step's delta without its UPDT): 0, or the error in e. */
int aug_summary_end(aug_summary *s, const aug_rec *tail, aug_err *e);
int aug_summary_print(FILE *out, aug_summary *s, const char *name, aug_err *e);
const aug_steptab *aug_summary_steps(const aug_summary *s);
/* Highest step number seen (-1 when the stream has no per-step record). */
int32_t aug_summary_last_step(const aug_summary *s);
/* Mesh after the mesh deltas of steps <= step_limit (NULL without a mesh). */
const aug_mesh *aug_summary_mesh(const aug_summary *s);
/* Last displacement field (fELD kind 0) with step <= step_limit: its step
   (-1 if none), and values scattered to nn*dim with mask[nn] = 1 on the nodes
   it lists. Returns AUG_OK or fills e; *u and *mask are NULL when there is none. */
int aug_summary_field(const aug_summary *s, int32_t *step, double **u, unsigned char **mask,
                      aug_err *e);

/* VTK XML UnstructuredGrid (ASCII) of m: points (z = 0 in 2-D), hexahedron
   (12, VTK's node order = gmsh's), tet (10) or triangle (5) cells, cell data
   material / material_id / aspect_ratio / min_angle (and scaled_jacobian
   for hex8), and when u is given point data displacement (3 components) and
   displacement_mask (mask, or all 1 when mask is NULL). */
int aug_vtk_write(FILE *out, const aug_mesh *m, const double *u, const unsigned char *mask,
                  aug_err *e);
/* As aug_vtk_write with a velocity array v too (NULL: none): a time frame. */
int aug_vtk_write_uv(FILE *out, const aug_mesh *m, const double *u, const double *v,
                     const unsigned char *mask, aug_err *e);
/* A MODE record's basis on m (the mesh of its step): field data sigma,
   domain, frame, kind; point data mode_0 .. mode_{r-1} (dim components, 0 off
   the domain) and in_domain (1 on its nodes). AUG_EDATA when its dim or
   nodes do not fit m. */
struct aug_moderec;
int aug_vtk_write_modes(FILE *out, const aug_mesh *m, const struct aug_moderec *r, aug_err *e);
/* path := the .vtu of step `step` of a summary read up to it (step limit >=
   step): its mesh and the displacement field of that very step, if any. File
   errors name the file (AUG_EIO, record -1); a file that failed is removed. */
int aug_vtk_step_file(const char *path, const aug_summary *s, int32_t step, aug_err *e);

/* Output files (lib/stats/outfile.c): aug_out_protect(fd) registers the
   input stream (a regular file; else nothing); aug_out_check refuses a path
   that is that file (AUG_EIO naming the path), aug_out_create checks and
   opens the path for writing (NULL and e set on failure). */
void aug_out_protect(int fd);
int aug_out_check(const char *path, aug_err *e);
FILE *aug_out_create(const char *path, aug_err *e);

/* ParaView time series of a cut sequence: DIR/NAME.pvd lists one
   DIR/NAME_SSSS.vtu (aug_vtk_write; SSSS the step number, at least four
   digits) per step: step 0 and every step that has a per-step record, each
   with the mesh of that step and the displacement field (fELD kind 0) of that
   very step if the stream has one; DataSet timestep = the step number. Feed
   every record to aug_pvd_add before aug_summary_add (summary made with step
   limit INT32_MAX) absorbs it: a step is written once a record of a later
   step arrives; aug_pvd_end writes the last step and the .pvd. */
typedef struct aug_pvd aug_pvd;
int aug_path_is_pvd(const char *path);  /* ends in ".pvd" */
aug_pvd *aug_pvd_new(const char *path, aug_err *e);
int aug_pvd_add(aug_pvd *p, const aug_summary *s, const aug_rec *rec, aug_err *e);
int aug_pvd_end(aug_pvd *p, const aug_summary *s, aug_err *e);
/* discard: remove every file written (a failed run leaves none behind). */
void aug_pvd_free(aug_pvd *p, int discard);

/* Matrix Market (coordinate real symmetric, lower triangle, %.17g) export of
   K (and M) at one step (lib/stats/mtx.c): feed every record to
   aug_mtx_add (keeps DOFM and the first KMAT of each kind), then
   aug_mtx_write with m the mesh of that step (aug_summary_mesh). Step 0:
   PREFIX_K.mtx = the KMAT of K0, PREFIX_M.mtx / PREFIX_ML.mtx = the
   consistent / lumped mass when present. Step t > 0: PREFIX_K.mtx = K_t in
   the cut-matrix numbering (formats/stream.md 7.2) assembled from scratch on
   m (aug_assemble_cut), equal to K0 with the updates of steps 1..t applied. */
typedef struct aug_mtx aug_mtx;
aug_mtx *aug_mtx_new(aug_err *e);
int aug_mtx_add(aug_mtx *x, const aug_rec *rec, aug_err *e);
int aug_mtx_write(aug_mtx *x, int32_t step, const aug_mesh *m, const char *prefix, aug_err *e);
/* discard: remove the files written. */
void aug_mtx_free(aug_mtx *x, int discard);

#endif
