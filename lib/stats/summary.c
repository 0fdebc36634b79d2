/* Stream summary: counts, pipeline, mesh, quality, matrices and per-step figures. */
#include <cholmod.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_stats.h"

#define MAXTYPES 64 /* distinct record types listed; more are folded into "other" */
#define MAXMAT 16   /* KMAT / FVEC / cOND records listed */
#define MAXDOM 64   /* MODE domains listed; more are counted only */

typedef struct tcount {
    char type[8];
    long count;
    uint64_t raw, wire;
} tcount;

/* mesh figures at one moment (initial, final) */
typedef struct snap {
    int valid;
    int64_t nn, ne;
    double lo[3], hi[3];
    aug_qstats q;
    int64_t *per_mat;  /* elements per material */
    int64_t *set_size; /* nodes per named set */
    int64_t fix_nodes, fix_nonzero, nfix, nload, nout;
    double force[3];   /* sum of the loads per component */
} snap;

struct aug_summary {
    char producer[256];
    uint32_t minor;
    int32_t limit;
    int complete;
    long nrec;
    uint64_t raw, wire;
    tcount tc[MAXTYPES + 1];
    int ntc;
    char **prov;
    int nprov;
    aug_replay rp;             /* the scene, mesh deltas of steps <= limit applied */
    snap init, fin;
    int have_dofm;
    int64_t ndof, nfree;
    int nkmat, nfvec, ncond;
    struct { int32_t which, stype; int64_t n, nnz; } kmat[MAXMAT];
    struct { int32_t kind; int64_t n; double norm; } fvec[MAXMAT];
    aug_kv cond[MAXMAT];
    int have_fact;
    int64_t fact_n, fact_nnz;
    int32_t fact_ord;
    int32_t last_step;
    long nsteps;
    long nmdlt, flag_count[3];
    int64_t nnew, nmod, nadd;
    long nupdt;
    int64_t m_max, k_sum, mk_max;
    double *m_all;             /* m of every UPDT, for the median */
    long npath;
    int64_t nseg;
    long nfeld;
    int32_t f_step;            /* the kept displacement field (step <= limit) */
    int f_dim, f_indexed;
    long f_index;        /* the fELD's record */
    int64_t f_count;
    int32_t *f_node;
    double *f_u, f_max;
    long nqual;
    int32_t qual_step;
    aug_kv qual;
    long nmode;
    int nmdom;                 /* MODE per domain, increasing domain */
    struct { int32_t domain, r, kind, step, frame; long n; } mdom[MAXDOM];
    aug_steptab tab;
};

aug_summary *aug_summary_new(const aug_reader *r, int32_t step_limit, aug_err *e)
{
    aug_err_clear(e);
    aug_summary *s = aug_calloc(1, sizeof *s);
    if (!s) {
        aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        return NULL;
    }
    snprintf(s->producer, sizeof s->producer, "%s", aug_reader_producer(r));
    uint32_t flags;
    uint64_t len, wl;
    aug_reader_head(r, &s->minor, &flags, &len, &wl);
    s->limit = step_limit;
    s->last_step = -1;
    s->f_step = -1;
    s->qual_step = -1;
    aug_replay_init(&s->rp);
    s->rp.step_limit = step_limit;
    s->rp.check_sys = 1; /* KMAT, FVEC, FACT: their codecs and orders (formats 6.1) */
    aug_steptab_init(&s->tab);
    memcpy(s->tc[0].type, "HEAD", 5);
    s->tc[0].count = 1;
    s->tc[0].raw = len;
    s->tc[0].wire = wl;
    s->ntc = 1;
    s->nrec = 1;
    s->raw = len;
    s->wire = 8 + wl;
    return s;
}

static void snap_free(snap *p)
{
    free(p->per_mat);
    free(p->set_size);
}

void aug_summary_free(aug_summary *s)
{
    if (!s) return;
    for (int i = 0; i < s->nprov; i++) free(s->prov[i]);
    free(s->prov);
    aug_replay_free(&s->rp);
    snap_free(&s->init);
    snap_free(&s->fin);
    free(s->m_all);
    free(s->f_node);
    free(s->f_u);
    aug_steptab_free(&s->tab);
    free(s);
}

static void count(aug_summary *s, const aug_rec *rec)
{
    int i = 0;
    while (i < s->ntc && memcmp(s->tc[i].type, rec->type, 4) != 0) i++;
    if (i == s->ntc) {
        if (s->ntc == MAXTYPES) i = MAXTYPES, memcpy(s->tc[i].type, "other", 6);
        else memcpy(s->tc[s->ntc++].type, rec->type, 5);
    }
    s->tc[i].count++;
    s->tc[i].raw += rec->len;
    s->tc[i].wire += rec->wirelen;
    s->nrec++;
    s->raw += rec->len;
    s->wire += rec->wirelen;
}

/* figures of the current mesh (nothing when it has no elements yet) */
static int take_snap(aug_summary *s, snap *p)
{
    const aug_mesh *m = &s->rp.mesh;
    snap_free(p);
    memset(p, 0, sizeof *p);
    if ((m->have & (AUG_HAVE_NODE | AUG_HAVE_ELEM | AUG_HAVE_MATL)) !=
        (AUG_HAVE_NODE | AUG_HAVE_ELEM | AUG_HAVE_MATL))
        return 0;
    p->per_mat = aug_calloc((size_t)m->nmat, sizeof *p->per_mat);
    p->set_size = aug_calloc((size_t)m->nset, sizeof *p->set_size);
    unsigned char *fixed = aug_calloc((size_t)m->nn, 1);
    if (!p->per_mat || !p->set_size || !fixed) {
        free(fixed);
        return -1;
    }
    for (int i = 0; i < m->nset; i++) p->set_size[i] = m->sets[i].n;
    for (int64_t i = 0; i < m->nfix; i++) {
        int64_t node = m->fix_dof[i] / m->dim;
        p->fix_nodes += !fixed[node];
        fixed[node] = 1;
        p->fix_nonzero += m->fix_val[i] != 0;
    }
    free(fixed);
    p->nfix = m->nfix;
    p->nload = m->nload;
    for (int64_t i = 0; i < m->nload; i++) p->force[m->load_dof[i] % m->dim] += m->load_val[i];
    p->nout = m->nout;
    p->valid = 1;
    p->nn = m->nn;
    p->ne = m->ne;
    for (int d = 0; d < 3; d++) p->lo[d] = INFINITY, p->hi[d] = -INFINITY;
    for (int64_t i = 0; i < m->nn; i++)
        for (int d = 0; d < m->dim; d++) {
            p->lo[d] = fmin(p->lo[d], m->x[i * m->dim + d]);
            p->hi[d] = fmax(p->hi[d], m->x[i * m->dim + d]);
        }
    for (int64_t i = 0; i < m->ne; i++) p->per_mat[m->mat[i]]++;
    aug_mesh_qstats(m, &p->q);
    return 0;
}

static int add_prov(aug_summary *s, const aug_rec *rec, aug_err *e)
{
    char **q = aug_realloc(s->prov, (size_t)(s->nprov + 1) * sizeof *q);
    if (!q) return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    s->prov = q;
    if (aug_read_prov(rec, &s->prov[s->nprov], e)) return e->code;
    s->nprov++;
    return 0;
}

static int add_mdlt(aug_summary *s, const aug_rec *rec, aug_err *e)
{
    aug_mesh *m = &s->rp.mesh;
    if ((m->have & (AUG_HAVE_NODE | AUG_HAVE_ELEM)) != (AUG_HAVE_NODE | AUG_HAVE_ELEM))
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "mesh delta before NODE and ELEM");
    if (!s->init.valid && take_snap(s, &s->init))
        return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    long before = s->rp.nmdlt;
    int rc = aug_replay_add(&s->rp, rec, e);
    if (s->rp.nmdlt > before) {
        s->nmdlt++;
        s->nnew += s->rp.mdlt_nnew;
        s->nmod += s->rp.mdlt_nmod;
        s->nadd += s->rp.mdlt_nadd;
        for (int b = 0; b < 3; b++) s->flag_count[b] += (s->rp.mdlt_flags >> b) & 1;
    }
    return rc;
}

static int add_updt(aug_summary *s, const aug_rec *rec, aug_err *e)
{
    aug_update u;
    if (aug_replay_add(&s->rp, rec, e)) return e->code; /* its step's order (formats 7.1) */
    int rc = aug_read_update(rec, &u, e);
    if (!rc) {
        double *q = aug_realloc(s->m_all, (size_t)(s->nupdt + 1) * sizeof *q);
        if (!q) rc = aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
        else {
            s->m_all = q;
            q[s->nupdt++] = u.m;
            if (u.m > s->m_max) s->m_max = u.m;
            s->k_sum += u.k;
            if (u.m + u.k > s->mk_max) s->mk_max = u.m + u.k;
        }
    }
    aug_update_free(&u);
    return rc;
}

/* 7.10: an rEAC's DOFs are DOFs of the mesh of its step, of its dimension
   (stats, --csv and --vtk took a DOF 10^7 of a 684-DOF mesh) */
static int reac_fits(const aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    if (!(m->have & AUG_HAVE_NODE)) return 0;
    aug_reaction q;
    memset(&q, 0, sizeof q);
    int rc = aug_read_reaction(rec, &q, e);
    if (!rc && q.dim != m->dim)
        rc = aug_err_set(e, AUG_EDATA, rec->index, rec->type, "step %d: reactions of dimension %d on a %d-D mesh",
                         (int)rec->step, q.dim, m->dim);
    else if (!rc && q.n > 0 && q.dof[q.n - 1] >= m->nn * m->dim)
        rc = aug_err_set(e, AUG_EDATA, rec->index, rec->type, "step %d: DOF %d is not one of the %lld of its mesh",
                         (int)rec->step, (int)q.dof[q.n - 1], (long long)(m->nn * m->dim));
    aug_reaction_free(&q);
    return rc;
}

/* a displacement fELD (record index, of step) of dimension dim, count
   values (at node[], or nodes 0..count-1 when node is NULL) on the mesh m:
   that of its step when read (stats and --csv took a node 10^6 of a
   600-node mesh, --vtk refused it naming no record), the summary's when its
   field is filled in (aug_summary_field: nodes are only added) */
static int feld_fits(const aug_mesh *m, long index, int32_t step, int dim, int64_t count, const int32_t *node,
                     aug_err *e)
{
    if (dim != m->dim)
        return aug_err_set(e, AUG_EDATA, index, "fELD", "step %d: field of dimension %d on a %d-D mesh", (int)step,
                           dim, m->dim);
    if (!node && count > m->nn)
        return aug_err_set(e, AUG_EDATA, index, "fELD", "step %d: %lld values for the %lld nodes of its mesh",
                           (int)step, (long long)count, (long long)m->nn);
    for (int64_t i = 0; node && i < count; i++)
        if (node[i] < 0 || node[i] >= m->nn)
            return aug_err_set(e, AUG_EDATA, index, "fELD", "step %d: node %d is not one of the %lld of its mesh",
                               (int)step, (int)node[i], (long long)m->nn);
    return 0;
}

/* fELD: validated; the last displacement field of a step <= limit is kept */
static int add_feld(aug_summary *s, const aug_rec *rec, aug_err *e)
{
    int32_t kind, *node;
    int dim;
    int64_t count;
    double *u;
    if (aug_read_field(rec, &kind, &dim, &count, &node, &u, e)) return e->code;
    s->nfeld++;
    if (kind != 0 || rec->step > s->limit) {
        free(node);
        free(u);
        return 0;
    }
    /* 7.3: nodes of the mesh of its step (applied: its MDLT came before) */
    int rc = (s->rp.mesh.have & AUG_HAVE_NODE) ? feld_fits(&s->rp.mesh, rec->index, rec->step, dim, count, node, e) : 0;
    if (rc) {
        free(node);
        free(u);
        return rc;
    }
    free(s->f_node);
    free(s->f_u);
    s->f_node = node;
    s->f_u = u;
    s->f_step = rec->step;
    s->f_dim = dim;
    s->f_indexed = node != NULL;
    s->f_index = rec->index;
    s->f_count = count;
    s->f_max = 0;
    for (int64_t i = 0; i < count; i++) {
        double n2 = 0;
        for (int d = 0; d < dim; d++) n2 += u[i * dim + d] * u[i * dim + d];
        s->f_max = fmax(s->f_max, sqrt(n2));
    }
    return 0;
}

static int add_matrix(aug_summary *s, const aug_rec *rec, aug_err *e)
{
    /* (KMAT, FVEC and FACT: checked by the replay, check_sys) */
    const char *t = rec->type;
    if (memcmp(t, "KMAT", 4) && memcmp(t, "FVEC", 4) && memcmp(t, "FACT", 4) && aug_check_payload(rec, e))
        return e->code;
    if (!memcmp(t, "DOFM", 4)) {
        int dim;
        int32_t *map;
        if (aug_read_dofmap(rec, &dim, &s->ndof, &s->nfree, &map, e)) return e->code;
        free(map);
        s->have_dofm = 1;
    } else if (!memcmp(t, "KMAT", 4)) {
        int32_t which, stype;
        int64_t n, nnz;
        aug_kmat_info(rec, &which, &stype, &n, &nnz);
        if (s->nkmat < MAXMAT) {
            s->kmat[s->nkmat].which = which, s->kmat[s->nkmat].stype = stype;
            s->kmat[s->nkmat].n = n, s->kmat[s->nkmat].nnz = nnz;
        }
        s->nkmat++;
    } else if (!memcmp(t, "FVEC", 4)) {
        int32_t kind;
        int64_t n;
        double *v, ss = 0;
        if (aug_read_vector(rec, &kind, &n, &v, e)) return e->code;
        for (int64_t i = 0; i < n; i++) ss += v[i] * v[i];
        free(v);
        if (s->nfvec < MAXMAT) s->fvec[s->nfvec].kind = kind, s->fvec[s->nfvec].n = n,
                               s->fvec[s->nfvec].norm = sqrt(ss);
        s->nfvec++;
    } else if (!memcmp(t, "FACT", 4)) {
        aug_fact_info(rec, &s->fact_n, &s->fact_nnz, &s->fact_ord);
        s->have_fact = 1;
    } else { /* cOND */
        aug_kv kv;
        if (aug_read_kv(rec, &kv, e)) return e->code;
        if (s->ncond < MAXMAT) s->cond[s->ncond] = kv;
        s->ncond++;
    }
    return 0;
}

static int add_path(aug_summary *s, const aug_rec *rec, aug_err *e)
{
    aug_pathrec p;
    int rc = aug_read_path(rec, &p, e);
    s->npath++;
    if (!rc) s->nseg += p.nseg;
    aug_pathrec_free(&p);
    return rc;
}

static int is(const aug_rec *rec, const char *t) { return memcmp(rec->type, t, 4) == 0; }

/* MODE (formats 7.5): per domain the count and the last record's rank */
static int add_mode(aug_summary *s, const aug_rec *rec, aug_err *e)
{
    if (aug_check_payload(rec, e)) return e->code;
    s->nmode++;
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t dom = aug_cur_i32(&c), frame = aug_cur_i32(&c);
    aug_cur_i32(&c);
    int32_t kind = aug_cur_i32(&c);
    aug_cur_i64(&c);
    int32_t r = aug_cur_i32(&c);
    int i = 0;
    while (i < s->nmdom && s->mdom[i].domain < dom) i++;
    if (i == s->nmdom || s->mdom[i].domain != dom) {
        if (s->nmdom == MAXDOM) return 0;
        memmove(s->mdom + i + 1, s->mdom + i, (size_t)(s->nmdom - i) * sizeof s->mdom[0]);
        s->nmdom++;
        s->mdom[i].domain = dom, s->mdom[i].n = 0;
    }
    s->mdom[i].n++;
    s->mdom[i].r = r, s->mdom[i].kind = kind, s->mdom[i].step = rec->step, s->mdom[i].frame = frame;
    return 0;
}

int aug_summary_add(aug_summary *s, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    count(s, rec);
    const aug_rectype *rt = aug_rectype_find(rec->type);
    if (rt && rt->perstep && rec->step >= 0) {
        if (rec->step != s->last_step) s->nsteps++;
        if (rec->step > s->last_step) s->last_step = rec->step;
    }
    int rc = 0;
    /* every per-step record's step against the pLAN (MDLT, UPDT and BDLT
       through aug_replay_add below); stats took a pLAN that planned steps
       the stream does not hold, as solve-aug and cut do not */
    if (rt && rt->perstep && rec->step >= 0 && !is(rec, "MDLT") && !is(rec, "UPDT") && !is(rec, "BDLT") &&
        aug_replay_steps(&s->rp, rec, e))
        return e->code;
    if (is(rec, "pROv")) {
        rc = add_prov(s, rec, e);
    } else if (is(rec, "pLAN")) {
        rc = aug_replay_add(&s->rp, rec, e);
    } else if (aug_mesh_is_record(rec->type)) {
        rc = aug_replay_add(&s->rp, rec, e);
    } else if (is(rec, "DOFM") || is(rec, "KMAT") || is(rec, "FVEC") || is(rec, "FACT") ||
               is(rec, "cOND")) {
        rc = aug_replay_add(&s->rp, rec, e);
        if (!rc) rc = add_matrix(s, rec, e);
    } else if (is(rec, "MDLT")) {
        rc = add_mdlt(s, rec, e);
    } else if (is(rec, "UPDT")) {
        rc = add_updt(s, rec, e);
    } else if (is(rec, "BDLT")) {
        rc = aug_replay_add(&s->rp, rec, e); /* applied after its MDLT */
    } else if (is(rec, "fELD")) {
        rc = add_feld(s, rec, e);
    } else if (is(rec, "pATH")) {
        rc = add_path(s, rec, e);
    } else if (is(rec, "sTAt") || is(rec, "tIMe")) {
        rc = aug_steptab_add(&s->tab, rec, e);
    } else if (is(rec, "rEAC")) {
        rc = rec->step <= s->limit ? reac_fits(&s->rp.mesh, rec, e) : 0;
        if (!rc) rc = rec->step <= s->limit ? aug_steptab_add(&s->tab, rec, e) : aug_check_payload(rec, e);
    } else if (is(rec, "qUAl")) {
        rc = aug_read_kv(rec, &s->qual, e);
        s->nqual++;
        s->qual_step = rec->step;
    } else if (is(rec, "MODE")) {
        rc = add_mode(s, rec, e);
    }
    return rc;
}

int aug_summary_end(aug_summary *s, const aug_rec *tail, aug_err *e)
{
    aug_err_clear(e);
    if (!tail) return 0;
    count(s, tail);
    s->complete = 1;
    return aug_replay_end(&s->rp, e);
}

const aug_steptab *aug_summary_steps(const aug_summary *s) { return &s->tab; }
int32_t aug_summary_last_step(const aug_summary *s) { return s->last_step; }

const aug_mesh *aug_summary_mesh(const aug_summary *s)
{
    int need = AUG_HAVE_NODE | AUG_HAVE_ELEM | AUG_HAVE_MATL;
    return (s->rp.mesh.have & need) == need ? &s->rp.mesh : NULL;
}

int aug_summary_field(const aug_summary *s, int32_t *step, double **u, unsigned char **mask,
                      aug_err *e)
{
    aug_err_clear(e);
    *step = s->f_step;
    *u = NULL;
    *mask = NULL;
    const aug_mesh *m = aug_summary_mesh(s);
    if (s->f_step < 0 || !m) return 0;
    if (feld_fits(m, s->f_index, s->f_step, s->f_dim, s->f_count, s->f_indexed ? s->f_node : NULL, e))
        return e->code;
    double *x = aug_calloc((size_t)m->nn * m->dim, sizeof *x);
    unsigned char *k = aug_calloc((size_t)m->nn, 1);
    if (!x || !k) {
        free(x);
        free(k);
        return aug_err_set(e, AUG_ENOMEM, -1, "fELD", "out of memory");
    }
    for (int64_t i = 0; i < s->f_count; i++) {
        int64_t node = s->f_indexed ? s->f_node[i] : i;
        memcpy(x + node * m->dim, s->f_u + i * m->dim, (size_t)m->dim * sizeof *x);
        k[node] = 1;
    }
    *u = x;
    *mask = k;
    return 0;
}

static void print_hist(FILE *o, const char *what, const double *edges, const int64_t *h)
{
    int64_t mx = 0;
    for (int i = 0; i < AUG_QHIST; i++) mx = h[i] > mx ? h[i] : mx;
    fprintf(o, "  %s histogram\n", what);
    for (int i = 0; i < AUG_QHIST; i++) {
        char lab[48];
        if (isinf(edges[i + 1])) snprintf(lab, sizeof lab, ">= %g", edges[i]);
        else snprintf(lab, sizeof lab, "[%g, %g)", edges[i], edges[i + 1]);
        int bar = mx ? (int)((40 * h[i] + mx - 1) / mx) : 0;
        fprintf(o, "    %-12s %10lld%s", lab, (long long)h[i], bar ? " " : "");
        for (int b = 0; b < bar; b++) fputc('#', o);
        fputc('\n', o);
    }
}

static void print_quality(FILE *o, const aug_summary *s, const snap *p, const char *which)
{
    const aug_mesh *m = &s->rp.mesh;
    int tet = m->nv == 4, hex = m->nv == 8;
    const char *ang = tet ? "min dihedral" : hex ? "min edge angle" : "min angle";
    fprintf(o, "quality (%s mesh: %lld elements)\n", which, (long long)p->q.ne);
    fprintf(o, "  total %-10s %.10g\n", m->nv != 3 ? "volume" : "area", p->q.measure);
    fprintf(o, "  aspect ratio     min %.6g  mean %.6g  max %.6g  (%s)\n", p->q.asp_min,
            p->q.asp_mean, p->q.asp_max, tet ? "R/(3r), 1 for the regular tet" : "longest/shortest edge");
    fprintf(o, "  %-16s min %.6g  mean %.6g  max %.6g  (degrees)\n", ang, p->q.ang_min,
            p->q.ang_mean, p->q.ang_max);
    if (hex)
        fprintf(o, "  scaled Jacobian  min %.6g  mean %.6g  (least over the corners, 1 for a cube)\n",
                p->q.sj_min, p->q.sj_mean);
    fprintf(o, "  edge ratio max   %.6g\n", p->q.edge_ratio_max);
    if (p->q.nbad) fprintf(o, "  degenerate       %lld elements (no finite quality)\n", (long long)p->q.nbad);
    print_hist(o, "aspect ratio", aug_qhist_aspect, p->q.asp_hist);
    print_hist(o, ang, aug_qhist_angle, p->q.ang_hist);
    if (hex) print_hist(o, "scaled Jacobian", aug_qhist_sjac, p->q.sj_hist);
}

/* each tool writes its pROv first and passes the upstream ones after it, so
   the pipeline runs from the last pROv record to the first */
static void print_prov(FILE *o, const aug_summary *s)
{
    fprintf(o, "  pipeline         %d pROv records, first tool first\n", s->nprov);
    for (int i = s->nprov - 1; i >= 0; i--) {
        const char *t = s->prov[i], *nl = strchr(t, '\n');
        fprintf(o, "    %d. ", s->nprov - i);
        for (const char *c = nl ? nl + 1 : t; *c; c++)
            fputc(*c == '\n' ? ' ' : (unsigned char)*c < ' ' ? '?' : *c, o);
        if (nl) fprintf(o, "   [%.*s]", (int)(nl - t), t);
        fputc('\n', o);
    }
}

static void print_mesh(FILE *o, const aug_summary *s)
{
    const aug_mesh *m = &s->rp.mesh;
    const snap *p = &s->init;
    fprintf(o, "mesh\n");
    fprintf(o, "  dimension        %d (%s)\n", m->dim, aug_etype_name(m->etype));
    fprintf(o, "  nodes            %lld\n", (long long)p->nn);
    fprintf(o, "  elements         %lld\n", (long long)p->ne);
    static const char ax[] = "xyz";
    fprintf(o, "  bounding box    ");
    for (int d = 0; d < m->dim; d++) fprintf(o, " %c [%.6g, %.6g]", ax[d], p->lo[d], p->hi[d]);
    fputc('\n', o);
    fprintf(o, "materials (%d)\n", m->nmat);
    fprintf(o, "  %3s %6s  %-20s %12s %8s %10s %8s %10s\n", "#", "id", "name", "E", "nu", "rho", "t",
            "elements");
    for (int i = 0; i < m->nmat; i++) {
        const aug_material *a = &m->mats[i];
        char nm[4 * AUG_NAME + 1];
        fprintf(o, "  %3d %6d  %-20s %12.6g %8.4g %10.6g %8.4g %10lld\n", i, (int)a->id,
                aug_txt_clean(nm, sizeof nm, a->name),
                a->E, a->nu, a->rho, a->t, (long long)p->per_mat[i]);
    }
}

static void print_scene(FILE *o, const aug_summary *s)
{
    const aug_mesh *m = &s->rp.mesh;
    const snap *p = &s->init;
    fprintf(o, "sets (%d)\n", m->nset);
    char nm[4 * AUG_NAME + 1];
    for (int i = 0; i < m->nset; i++)
        fprintf(o, "  %-24s %10lld nodes\n", aug_txt_clean(nm, sizeof nm, m->sets[i].name),
                (long long)p->set_size[i]);
    if (m->have & AUG_HAVE_FIXD)
        fprintf(o, "constraints        %lld DOFs on %lld nodes (%lld prescribed non-zero)\n",
                (long long)p->nfix, (long long)p->fix_nodes, (long long)p->fix_nonzero);
    if (m->have & AUG_HAVE_LOAD) {
        fprintf(o, "loads              %lld DOFs, total force (", (long long)p->nload);
        for (int d = 0; d < m->dim; d++) fprintf(o, "%s%.6g", d ? ", " : "", p->force[d]);
        fprintf(o, ")\n");
    }
    if (m->have & AUG_HAVE_OUTS) {
        static const char *kinds[] = {"all", "surface", "set"};
        fprintf(o, "output set         %s", kinds[m->out_kind]);
        char nm[4 * AUG_NAME + 1];
        if (m->out_kind == AUG_OUT_SET) fprintf(o, " '%s'", aug_txt_clean(nm, sizeof nm, m->out_name));
        if (m->out_kind == AUG_OUT_ALL && p->nout == 0) fprintf(o, " (all nodes)\n");
        else fprintf(o, " (%lld nodes)\n", (long long)p->nout);
    }
}

static void print_matrices(FILE *o, const aug_summary *s)
{
    if (!s->have_dofm && !s->nkmat && !s->nfvec && !s->have_fact && !s->ncond) return;
    static const char *which[] = {"stiffness K", "consistent mass M", "lumped mass"};
    fprintf(o, "matrices\n");
    if (s->have_dofm)
        fprintf(o, "  DOFM  %lld DOFs, %lld free, %lld constrained\n", (long long)s->ndof,
                (long long)s->nfree, (long long)(s->ndof - s->nfree));
    for (int i = 0; i < s->nkmat && i < MAXMAT; i++)
        fprintf(o, "  KMAT  %s: n %lld, nnz %lld (%s)\n",
                s->kmat[i].which >= 0 && s->kmat[i].which <= 2 ? which[s->kmat[i].which] : "unknown",
                (long long)s->kmat[i].n, (long long)s->kmat[i].nnz,
                s->kmat[i].stype == 1 ? "upper triangle" : "stype other than 1");
    for (int i = 0; i < s->nfvec && i < MAXMAT; i++)
        fprintf(o, "  FVEC  kind %d: n %lld, 2-norm %.6g\n", (int)s->fvec[i].kind,
                (long long)s->fvec[i].n, s->fvec[i].norm);
    if (s->have_fact)
        fprintf(o, "  FACT  LDL': n %lld, nnz(L+D) %lld, ordering %s (%d)\n", (long long)s->fact_n,
                (long long)s->fact_nnz, aug_ordering_name(s->fact_ord), (int)s->fact_ord);
    for (int i = 0; i < s->ncond && i < MAXMAT; i++) {
        fprintf(o, "  cOND  %s:", s->cond[i].tag);
        for (int k = 0; k < s->cond[i].n; k++)
            fprintf(o, " %s %.6g", s->cond[i].key[k], s->cond[i].val[k]);
        fputc('\n', o);
    }
}

/* a frame row (dynamic streams): its sTAt or tIMe has the key frame */
static int is_frame_row(const aug_steprow *r)
{
    int f;
    aug_steprow_get(r, "frame", &f);
    return f || strncmp(r->method, "dynamics", 16) == 0;
}

/* Dynamic streams (formats/stream.md 7.9): per method the frames, their
   relres, the median time of a frame's solve, of a step's work (its rows
   without frame), and frames per second = 1000 / (frame median + step median
   * steps / frames); then the frames' time span and energy range. */

/* v as %.4g, or "-" when it is NaN (no such value in the records) */
static void g4(char buf[32], double v)
{
    if (!isnan(v)) snprintf(buf, 32, "%.4g", v);
    else snprintf(buf, 32, "-");
}

static int print_frames(FILE *o, const aug_summary *s)
{
    const aug_steptab *t = &s->tab;
    size_t nfr = 0;
    for (size_t i = 0; i < t->n; i++) nfr += strncmp(t->row[i].method, "dynamics", 16) == 0 && t->row[i].has_stat;
    if (!nfr) return 0;
    double *rr = aug_malloc(t->n * sizeof *rr), *tf = aug_malloc(t->n * sizeof *tf), *ts = aug_malloc(t->n * sizeof *ts);
    if (!rr || !tf || !ts) {
        free(rr), free(tf), free(ts);
        return -1;
    }
    fprintf(o, "frames (fRAM; sTAt, tIMe with key frame)\n");
    fprintf(o, "  %-12s %7s %13s %13s %9s %14s %14s %10s\n", "method", "frames", "relres_median",
            "relres_max", "failures", "frame_ms_med", "step_ms_med", "frames/s");
    for (size_t i = 0; i < t->n; i++) {
        const char *mth = t->row[i].method;
        size_t j = 0;
        if (!strncmp(mth, "dynamics", 16)) continue;
        while (j < i && strncmp(t->row[j].method, mth, 16) != 0) j++;
        if (j < i) continue;
        size_t nf = 0, nr = 0, nt = 0, ns = 0, fail = 0;
        double rmax = NAN; /* fmax skips it: NaN while no relres is a number */
        for (j = i; j < t->n; j++) {
            const aug_steprow *r = &t->row[j];
            int f, fr = is_frame_row(r);
            double v;
            if (strncmp(r->method, mth, 16) != 0) continue;
            if (fr && r->has_stat) {
                nf++;
                if ((v = aug_steprow_get(r, "relres", &f), f)) rr[nr++] = v, rmax = fmax(rmax, v);
                if ((v = aug_steprow_get(r, "converged", &f), f) && v == 0) fail++;
            }
            if (r->has_time && (v = aug_steprow_get(r, "time_ms", &f), f)) {
                if (fr) tf[nt++] = v;
                else if (r->step > 0) ts[ns++] = v;
            }
        }
        if (!nf) continue;
        double fm = aug_median(tf, nt), sm = ns ? aug_median(ts, ns) : 0;
        double per = fm + sm * (double)ns / (double)nf;
        /* "-" where the records hold no such value (no timed step: a
           stream without cut steps, or read with --no-times) */
        char c[5][32];
        g4(c[0], aug_median(rr, nr)), g4(c[1], rmax), g4(c[2], fm), g4(c[3], ns ? sm : NAN), g4(c[4], 1000.0 / per);
        fprintf(o, "  %-12s %7zu %13s %13s %9zu %14s %14s %10s\n", mth, nf, c[0], c[1], fail, c[2], c[3], c[4]);
    }
    double t0 = NAN, t1 = NAN, emin = INFINITY, emax = -INFINITY, e0 = NAN, e1 = NAN;
    for (size_t i = 0; i < t->n; i++) {
        const aug_steprow *r = &t->row[i];
        int f, g;
        if (strncmp(r->method, "dynamics", 16) || !r->has_stat) continue;
        double tm = aug_steprow_get(r, "time", &f), en = aug_steprow_get(r, "energy", &g);
        if (f) t1 = tm, t0 = isnan(t0) ? tm : t0;
        if (g) e1 = en, e0 = isnan(e0) ? en : e0, emin = fmin(emin, en), emax = fmax(emax, en);
    }
    fprintf(o, "  time             %.6g .. %.6g (%zu frames)\n", t0, t1, nfr);
    fprintf(o, "  energy           first %.6g, last %.6g, min %.6g, max %.6g\n", e0, e1, emin, emax);
    free(rr), free(tf), free(ts);
    return 0;
}

/* modal (formats/stream.md 7.4, tag modal): its frames, how many had a
   domain reduced, the median frame time against the FE frame of --check, the
   largest L2 error and interface gap, the switch events, the system sizes */
static int print_modal(FILE *o, const aug_summary *s)
{
    const aug_steptab *t = &s->tab;
    size_t nf = 0, nred = 0, nt = 0, ne = 0;
    double l2 = -INFINITY, gap = -INFINITY, smax = -INFINITY, smin = INFINITY, ev = 0;
    double *tm = aug_malloc((t->n + 1) * sizeof *tm), *fe = aug_malloc((t->n + 1) * sizeof *fe);
    if (!tm || !fe) return free(tm), free(fe), -1;
    for (size_t i = 0; i < t->n; i++) {
        const aug_steprow *r = &t->row[i];
        int f;
        double v;
        if (strncmp(r->method, "modal", 16)) continue;
        if (r->has_stat) {
            nf++;
            if ((v = aug_steprow_get(r, "reduced", &f), f) && v > 0) nred++;
            if ((v = aug_steprow_get(r, "l2_err", &f), f)) l2 = fmax(l2, v);
            if ((v = aug_steprow_get(r, "gap", &f), f)) gap = fmax(gap, v);
            if ((v = aug_steprow_get(r, "events", &f), f)) ev += v;
            if ((v = aug_steprow_get(r, "n_sys", &f), f)) smax = fmax(smax, v), smin = fmin(smin, v);
        }
        if (r->has_time) {
            if ((v = aug_steprow_get(r, "time_ms", &f), f)) tm[nt++] = v;
            if ((v = aug_steprow_get(r, "fe_ms", &f), f)) fe[ne++] = v;
        }
    }
    if (nf) {
        fprintf(o, "modal (sTAt, tIMe tag modal)\n");
        fprintf(o, "  frames           %zu, %zu with a domain reduced, %.0f switch events\n", nf, nred, ev);
        fprintf(o, "  system size      %.0f .. %.0f unknowns\n", smin, smax);
        double hm = aug_median(tm, nt), fm = aug_median(fe, ne);
        fprintf(o, "  frame_ms median  %.4g", hm);
        if (ne) fprintf(o, " (full FE %.4g: %.3gx)", fm, fm / hm);
        fputc('\n', o);
        fprintf(o, "  gap max          %.3g\n", gap);
        if (l2 > -INFINITY) fprintf(o, "  l2_err max       %.3g (against full FE, --check)\n", l2);
    }
    free(tm), free(fe);
    return 0;
}

/* per method, in order of first appearance (rows of steps, not of frames) */
static int print_methods(FILE *o, const aug_summary *s)
{
    const aug_steptab *t = &s->tab;
    if (!t->n) return 0;
    double *rr = aug_malloc(t->n * sizeof *rr), *tm = aug_malloc(t->n * sizeof *tm);
    if (!rr || !tm) {
        free(rr);
        free(tm);
        return -1;
    }
    fprintf(o, "methods (sTAt, tIMe)\n");
    fprintf(o, "  %-12s %6s %13s %13s %9s %14s %12s\n", "method", "steps", "relres_median",
            "relres_max", "failures", "time_ms_median", "rate_Hz");
    for (size_t i = 0; i < t->n; i++) {
        size_t j = 0;
        while (j < i && strncmp(t->row[j].method, t->row[i].method, 16) != 0) j++;
        if (j < i || !strncmp(t->row[i].method, "dynamics", 16)) continue; /* printed, or frames */
        size_t nst = 0, nrow = 0, nr = 0, nt = 0, fail = 0; /* nrow: steps with either record (refine writes tIMe only) */
        double rmax = NAN; /* fmax skips it: NaN while no relres is a number */
        for (j = i; j < t->n; j++) {
            const aug_steprow *r = &t->row[j];
            if (strncmp(r->method, t->row[i].method, 16) != 0 || is_frame_row(r)) continue;
            int f;
            double v;
            nrow += r->has_stat || r->has_time;
            if (r->has_stat) {
                nst++;
                v = aug_steprow_get(r, "relres", &f);
                if (f) rr[nr++] = v, rmax = fmax(rmax, v);
                v = aug_steprow_get(r, "converged", &f);
                if (f && v == 0) fail++;
            }
            if (r->has_time && (v = aug_steprow_get(r, "time_ms", &f), f)) tm[nt++] = v;
        }
        if (!nst && !nt) continue; /* frame rows only (modal, lma): their own tables */
        char c[4][32]; /* "-" where the records have no such value */
        double tmed = aug_median(tm, nt);
        g4(c[0], aug_median(rr, nr)), g4(c[1], rmax), g4(c[2], tmed), g4(c[3], 1000.0 / tmed);
        fprintf(o, "  %-12s %6zu %13s %13s %9zu %14s %12s\n", t->row[i].method, nrow, c[0], c[1],
                fail, c[2], c[3]);
    }
    free(rr);
    free(tm);
    return 0;
}

static void print_steps(FILE *o, const aug_summary *s)
{
    if (s->last_step < 0) return;
    fprintf(o, "steps\n");
    fprintf(o, "  steps            %ld (last step %d)\n", s->nsteps, (int)s->last_step);
    if (s->nmdlt) {
        fprintf(o, "  mesh deltas      %ld: %lld new nodes, %lld re-wired and %lld added elements\n",
                s->nmdlt, (long long)s->nnew, (long long)s->nmod, (long long)s->nadd);
        fprintf(o, "  step flags       detached %ld, pinned %ld, dropped %ld\n", s->flag_count[0],
                s->flag_count[1], s->flag_count[2]);
    }
    if (s->fin.valid)
        fprintf(o, "  final mesh       %lld nodes, %lld elements (after %ld mesh deltas)\n",
                (long long)s->fin.nn, (long long)s->fin.ne, s->rp.applied);
    if (s->nupdt) {
        double *m = aug_malloc((size_t)s->nupdt * sizeof *m);
        double med = NAN;
        if (m) {
            memcpy(m, s->m_all, (size_t)s->nupdt * sizeof *m);
            med = aug_median(m, (size_t)s->nupdt);
            free(m);
        }
        fprintf(o, "  updates          %ld UPDT: m median %.6g, max %lld; k total %lld; max m+k %lld\n",
                s->nupdt, med, (long long)s->m_max, (long long)s->k_sum, (long long)s->mk_max);
    }
    if (s->npath) fprintf(o, "  cut paths        %ld pATH, %lld segments\n", s->npath, (long long)s->nseg);
    if (s->nfeld) {
        fprintf(o, "  fields           %ld fELD", s->nfeld);
        if (s->f_step >= 0)
            fprintf(o, "; last displacement at step %d: %lld nodes%s, max |u| %.6g", (int)s->f_step,
                    (long long)s->f_count, s->f_indexed ? " (indexed)" : "", s->f_max);
        fputc('\n', o);
    }
    if (s->nqual) {
        fprintf(o, "  refine quality   %ld qUAl; last (step %d, %s):", s->nqual, (int)s->qual_step,
                s->qual.tag);
        for (int k = 0; k < s->qual.n; k++) fprintf(o, " %s %.6g", s->qual.key[k], s->qual.val[k]);
        fputc('\n', o);
    }
    if (s->nmode) fprintf(o, "  modes            %ld MODE records\n", s->nmode);
    for (int i = 0; i < s->nmdom; i++)
        fprintf(o, "    domain %-9d %ld MODE, last rank %d (%s, step %d, frame %d)\n",
                (int)s->mdom[i].domain, s->mdom[i].n, (int)s->mdom[i].r,
                s->mdom[i].kind == 0 ? "snapshot basis" : "LMA modes", (int)s->mdom[i].step,
                (int)s->mdom[i].frame);
}

int aug_summary_print(FILE *o, aug_summary *s, const char *name, aug_err *e)
{
    aug_err_clear(e);
    if (!s->init.valid && take_snap(s, &s->init)) goto nomem;
    if (s->rp.applied && take_snap(s, &s->fin)) goto nomem;
    fprintf(o, "stream %s%s\n", name, s->complete ? "" : " (INCOMPLETE: reading stopped at an error)");
    fprintf(o, "  producer         %s (format %d.%u)\n", s->producer, AUG_VERSION_MAJOR,
            (unsigned)s->minor);
    print_prov(o, s);
    fprintf(o, "records (%ld; %llu payload bytes, %llu bytes on the wire with the signature)\n",
            s->nrec, (unsigned long long)s->raw, (unsigned long long)s->wire);
    fprintf(o, "  %-6s %10s %16s %16s\n", "type", "count", "raw_bytes", "wire_bytes");
    for (int i = 0; i <= MAXTYPES; i++) {
        const tcount *c = &s->tc[i];
        if (i < s->ntc || (i == MAXTYPES && c->count))
            fprintf(o, "  %-6s %10ld %16llu %16llu\n", c->type, c->count,
                    (unsigned long long)c->raw, (unsigned long long)c->wire);
    }
    if (s->init.valid) {
        print_mesh(o, s);
        print_scene(o, s);
        print_quality(o, s, &s->init, s->rp.applied ? "initial" : "whole");
    } else if (s->rp.mesh.have) {
        fprintf(o, "mesh               incomplete (NODE, MATL and ELEM needed)\n");
    }
    print_matrices(o, s);
    print_steps(o, s);
    aug_reactab_print(o, &s->tab.react);
    if (print_methods(o, s) || print_frames(o, s) || print_modal(o, s)) goto nomem;
    if (s->fin.valid) print_quality(o, s, &s->fin, "final");
    if (ferror(o)) return aug_err_set(e, AUG_EIO, -1, "", "write failed");
    return 0;
nomem:
    return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
}
