/* The scene a stream describes, replayed record by record: the mesh records,
   the DOF numbering of the original mesh (checked against DOFM), every MDLT and
   BDLT applied in turn, and the output set (formats/stream.md 5, 6.1, 7.1, 7.7). */
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

void aug_replay_init(aug_replay *r)
{
    memset(r, 0, sizeof *r);
    aug_mesh_init(&r->mesh);
    r->step_limit = INT32_MAX;
    r->sys_n = -1;
}

void aug_replay_free(aug_replay *r)
{
    aug_mesh_free(&r->mesh);
    free(r->map0);
    free(r->out_dof);
    free(r->mdlt_parent);
    free(r->chg);
    memset(r, 0, sizeof *r);
}

static int has_mesh(const aug_mesh *m) { return (m->have & AUG_HAVE_NODE) != 0; }

/* --output: all, surface, a node set of the original mesh or node:ID[,ID...]
   (0-based node indices, formats/stream.md 1), replacing oUTs;
   new nodes then inherit set membership from their parents */
static int resolve_output(aug_replay *r, aug_err *e)
{
    aug_mesh *m = &r->mesh;
    const char *want = r->output;
    if (!want || !has_mesh(m)) return 0;
    if (!strcmp(want, "all")) {
        m->out_kind = AUG_OUT_ALL;
        m->nout = 0;
        return 0;
    }
    int32_t *nodes = aug_malloc((size_t)m->nn * sizeof *nodes + 4);
    int64_t n = 0;
    if (!nodes) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    if (!strcmp(want, "surface")) {
        unsigned char *mark = aug_malloc((size_t)m->nn + 1);
        if (!mark || aug_mesh_boundary_nodes(m, mark) < 0) {
            free(mark);
            free(nodes);
            return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        }
        for (int64_t i = 0; i < m->nn; i++)
            if (mark[i]) nodes[n++] = (int32_t)i;
        free(mark);
        m->out_kind = AUG_OUT_SURFACE;
    } else if (!strncmp(want, "node:", 5)) {
        /* node:ID[,ID...]: 0-based node indices of the stream's mesh, each once */
        const char *p = want + 5;
        for (;;) {
            char *end;
            long long id = strtoll(p, &end, 10);
            if (end == p || id < 0 || id >= m->nn || (*end && *end != ',')) {
                free(nodes);
                return aug_err_set(e, AUG_EDATA, -1, "",
                                   "--output %s: bad node id at '%.20s' (0 .. %lld)", want, p,
                                   (long long)m->nn - 1);
            }
            int dup = 0;
            for (int64_t k = 0; k < n; k++) dup |= nodes[k] == (int32_t)id;
            if (!dup) nodes[n++] = (int32_t)id;
            if (!*end) break;
            p = end + 1;
        }
        /* ascending, as fELD's indexed nodes must be (formats/stream.md 7.3) */
        qsort(nodes, (size_t)n, sizeof *nodes, aug_cmp_i32);
        m->out_kind = AUG_OUT_SET;
        snprintf(m->out_name, sizeof m->out_name, "node");
    } else {
        const aug_set *s = aug_mesh_set(m, want);
        if (!s) {
            free(nodes);
            return aug_err_set(e, AUG_EDATA, -1, "", "--output %s: no such node set in the stream", want);
        }
        memcpy(nodes, s->nodes, (size_t)s->n * sizeof *nodes);
        n = s->n;
        m->out_kind = AUG_OUT_SET;
        snprintf(m->out_name, sizeof m->out_name, "%s", want);
    }
    free(m->out_nodes);
    m->out_nodes = nodes;
    m->nout = n;
    return 0;
}

int aug_replay_start(aug_replay *r, aug_err *e)
{
    aug_err_clear(e);
    if (r->started) return 0;
    aug_mesh *m = &r->mesh;
    if (has_mesh(m)) {
        if (aug_mesh_validate(m, e)) return e->code;
        r->nn0 = m->nn;
        r->dim = m->dim;
        r->map0 = aug_malloc((size_t)(m->nn * m->dim) * sizeof *r->map0 + 1);
        if (!r->map0) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        r->nfree0 = aug_dofmap(m, r->map0);
    }
    r->started = 1;
    return resolve_output(r, e);
}

/* formats/stream.md 6.1-6.4: KMAT, FVEC and FACT are over DOFM's free
   DOFs. cut and refine pass them on byte for byte without reading them, so
   (check_sys) each is checked here by its codec and its order against
   DOFM's (the first one read before a DOFM when it comes): a damaged or
   misfit matrix is refused by the tool it passed through, not written on
   as whole. solve-aug and modal read them through aug_sys0, which checks
   the same; stats sets it too, for its summary. */
static int sys_order(aug_replay *r, int64_t n, long index, const char *type, aug_err *e)
{
    if (!r->have_dofm) {
        if (r->sys_n < 0) r->sys_n = n, r->sys_index = index, memcpy(r->sys_type, type, 4);
        return 0;
    }
    if (n == r->nfree0) return 0;
    return aug_err_set(e, AUG_EDATA, index, type, "order %lld, but DOFM has %lld free DOFs", (long long)n,
                       (long long)r->nfree0);
}

static int check_sys(aug_replay *r, const aug_rec *rec, aug_err *e)
{
    int fact = !memcmp(rec->type, "FACT", 4);
    if (!fact && memcmp(rec->type, "KMAT", 4) && memcmp(rec->type, "FVEC", 4)) return 0;
    if (aug_check_payload(rec, e)) return e->code;
    aug_cur c; /* n: after which and stype (KMAT), kind and 0 (FVEC), first (FACT) */
    aug_cur_init(&c, rec);
    if (!fact) aug_cur_i32(&c), aug_cur_i32(&c);
    return sys_order(r, aug_cur_i64(&c), rec->index, rec->type, e);
}

/* DOFM: the numbering of the mesh's constraints, or, without a mesh, the numbering */
static int add_dofm(aug_replay *r, const aug_rec *rec, aug_err *e)
{
    int dim;
    int64_t ndof, nfree;
    int32_t *map;
    if (aug_read_dofmap(rec, &dim, &ndof, &nfree, &map, e)) return e->code;
    if (!has_mesh(&r->mesh)) {
        free(r->map0);
        r->map0 = map;
        r->dim = dim;
        r->nfree0 = nfree;
        r->have_dofm = 1;
        r->kt_n = nfree;
        return r->sys_n >= 0 ? sys_order(r, r->sys_n, r->sys_index, r->sys_type, e) : 0;
    }
    int same = dim == r->dim && ndof == r->nn0 * r->dim && nfree == r->nfree0 &&
               !memcmp(map, r->map0, (size_t)ndof * sizeof *map);
    free(map);
    if (!same)
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                           "DOF numbering does not match the mesh's constraints");
    r->have_dofm = 1;
    r->kt_n = r->nfree0;
    return r->sys_n >= 0 ? sys_order(r, r->sys_n, r->sys_index, r->sys_type, e) : 0;
}

/* chg += the elements d re-wired (d->elem) and added (ne0 .. ne0 + nadd - 1) */
static int note_changes(aug_replay *r, const aug_mdelta *d, int64_t ne0)
{
    int64_t need = r->nchg + d->nmod + d->nadd;
    if (need > r->chgcap) {
        int64_t cap = need > 2 * r->chgcap ? need : 2 * r->chgcap;
        int32_t *c = aug_realloc(r->chg, (size_t)cap * sizeof *c);
        if (!c) return -1;
        r->chg = c;
        r->chgcap = cap;
    }
    if (d->nmod > 0) /* (a deformation-only step: no element, d->elem NULL) */
        memcpy(r->chg + r->nchg, d->elem, (size_t)d->nmod * sizeof *d->elem);
    r->nchg += d->nmod;
    for (int64_t i = 0; i < d->nadd; i++) r->chg[r->nchg++] = (int32_t)(ne0 + i);
    return 0;
}

static int add_mdlt(aug_replay *r, const aug_rec *rec, aug_err *e)
{
    aug_mesh *m = &r->mesh;
    if ((m->have & (AUG_HAVE_NODE | AUG_HAVE_ELEM)) != (AUG_HAVE_NODE | AUG_HAVE_ELEM))
        return aug_err_set(e, AUG_EORDER, rec->index, rec->type, "mesh delta before NODE and ELEM");
    aug_mdelta d;
    int rc = aug_read_mdelta(rec, m->dim, m->nv, &d, e);
    if (!rc) {
        r->nmdlt++;
        r->mdlt_flags = d.flags, r->mdlt_nmod = d.nmod, r->mdlt_nadd = d.nadd; /* (step, nnew: steps_agree) */
        if (rec->step <= r->step_limit) {
            int64_t ne0 = m->ne;
            rc = aug_mesh_apply(m, &d, e);
            if (rc) e->record = rec->index, memcpy(e->type, "MDLT", 5);
            else r->applied++;
            if (!rc && r->track && note_changes(r, &d, ne0))
                rc = aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
        }
        free(r->mdlt_parent);
        r->mdlt_parent = d.parent; /* kept: the nodes the new ones were copied from */
        d.parent = NULL;
    }
    aug_mdelta_free(&d);
    return rc;
}

static int add_bdlt(aug_replay *r, const aug_rec *rec, aug_err *e)
{
    aug_bdelta b;
    int rc = aug_read_bdelta(rec, &b, e);
    if (!rc && rec->step <= r->step_limit && has_mesh(&r->mesh)) {
        rc = aug_mesh_apply_bc(&r->mesh, &b, e);
        if (rc) e->record = rec->index, memcpy(e->type, "BDLT", 5);
    }
    aug_bdelta_free(&b);
    return rc;
}

/* pLAN (formats/stream.md 4.4): the steps the stream brings after it, which
   must all come later than every step before it; the latest one holds */
static int add_plan(aug_replay *r, const aug_rec *rec, aug_err *e)
{
    int32_t a, b;
    if (aug_read_plan(rec, &a, &b, e)) return e->code;
    if (a <= r->last_step)
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                           "plans steps %d to %d, but step %d came before it", (int)a, (int)b, (int)r->last_step);
    r->plan_first = a, r->plan_last = b, r->plan_index = rec->index;
    return 0;
}

/* a per-step record's step against the latest pLAN: within first..last */
static int plan_agrees(const aug_replay *r, const aug_rec *rec, aug_err *e)
{
    if (r->plan_last <= 0 || (rec->step >= r->plan_first && rec->step <= r->plan_last)) return 0;
    return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                       "step %d, but pLAN (record %ld) plans steps %d to %d after it", (int)rec->step,
                       r->plan_index, (int)r->plan_first, (int)r->plan_last);
}

/* an UPDT with new DOFs whose step ended without an MDLT (7.2: k = dim
   nnew; an MDLT after it is refused as out of order) */
static int orphan_k(const aug_replay *r, aug_err *e)
{
    return aug_err_set(e, AUG_EDATA, r->k_orphan_index, "UPDT", "step %d: k = %d new DOFs, but the step has no MDLT",
                       (int)r->k_orphan_step, (int)r->k_orphan);
}

int aug_replay_end(const aug_replay *r, aug_err *e)
{
    aug_err_clear(e);
    /* formats/stream.md 6.1: KMAT, FVEC and FACT are over DOFM's free DOFs;
       the numbering the mesh's constraints imply is none (solve-aug and
       modal solved on it, exit 0) */
    if (!r->have_dofm && (r->sys_n >= 0 || r->have_kmat))
        return aug_err_set(e, AUG_EDATA, r->sys_n >= 0 ? r->sys_index : r->kmat_index,
                           r->sys_n >= 0 ? r->sys_type : "KMAT", "no DOFM gives the free DOFs it is over");
    /* formats/stream.md 7.1: the last step's deltas need their UPDT too
       (a stream with UPDTs whose last one was dropped ends one step short) */
    if ((r->updt_step > 0 || r->have_kmat) && r->delta_lo > 0)
        return aug_err_set(e, AUG_EDATA, r->delta_index, r->delta_type,
                           "step %d's mesh or boundary delta has no UPDT (the stream ends)", (int)r->delta_lo);
    if (r->k_orphan_step > 0) return orphan_k(r, e);
    if (r->plan_last <= 0 || r->last_step == r->plan_last) return 0;
    return aug_err_set(e, AUG_EDATA, r->plan_index, "pLAN", "plans steps to %d, but the stream ends at step %d",
                       (int)r->plan_last, (int)r->last_step);
}

/* formats/stream.md 7.1: a step's MDLT and BDLT come before its UPDT, each
   step has one UPDT, and UPDTs come in increasing steps; a step's deltas
   with no UPDT before a later step's UPDT, an UPDT repeated or one before its
   deltas are records that disagree (each valid alone: the sweep's streams
   with step 2's UPDT doubled, step 1's removed, step 1's put before its
   MDLT were solved as if whole). Streams without UPDT (a mesh cut without a
   factor) are not concerned. */
static int steps_agree(aug_replay *r, const aug_rec *rec, aug_err *e)
{
    /* cut steps are 1, 2, ...: step 0 is the state before the first cut,
       and 0 is "none" below (a stream renumbered to step 0 lost its
       checks: an UPDT dropped or doubled was solved as if whole) */
    int delta = !memcmp(rec->type, "MDLT", 4) || !memcmp(rec->type, "BDLT", 4);
    if ((delta || !memcmp(rec->type, "UPDT", 4) || !memcmp(rec->type, "UPKM", 4)) && rec->step < 1)
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "step %d: a cut step's record (steps are 1, 2, ...)",
                           (int)rec->step);
    if (r->k_orphan_step > 0 && rec->step > r->k_orphan_step) return orphan_k(r, e);
    if (!memcmp(rec->type, "UPDT", 4)) {
        if (r->kt_n > 0) {
            /* formats/stream.md 7.2: H indexes K_{t-1}, of order DOFM's free
               DOFs plus the k of every UPDT before (H ascending: its last
               entry decides; the codec checked the record alone). solve-aug's
               cut matrix refused one past it, refine and stats passed it on. */
            aug_cur c;
            aug_cur_init(&c, rec);
            int32_t m = aug_cur_i32(&c), k = aug_cur_i32(&c), hmax = -1;
            if (m > 0) aug_cur_i32v(&c, NULL, (uint64_t)m - 1), hmax = aug_cur_i32(&c);
            if (c.ok && hmax >= r->kt_n)
                return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                                   "step %d: H[%d] = %d is not below the order %lld of the matrix before the step",
                                   (int)rec->step, (int)m - 1, (int)hmax, (long long)r->kt_n);
            /* 7.2: the new DOFs are those of the step's new nodes (k = 0
               in an UPDT of 60 new nodes was solved, their field read past
               the matrix) */
            int64_t want = r->mdlt_step == rec->step ? r->mesh.dim * r->mdlt_nnew : 0;
            if (c.ok && r->mesh.dim > 0 && k > 0 && r->mdlt_step != rec->step)
                r->k_orphan_step = rec->step, r->k_orphan = k, r->k_orphan_index = rec->index;
            else if (c.ok && r->mesh.dim > 0 && k != want)
                return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                                   "step %d: k = %d new DOFs, but the step's MDLT adds %lld nodes (k = %lld)",
                                   (int)rec->step, (int)k, (long long)(want / r->mesh.dim), (long long)want);
            if (c.ok) r->kt_n += k;
        }
        if (r->updt_step > 0 && rec->step <= r->updt_step)
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "step %d, but the UPDT of step %d came before it",
                               (int)rec->step, (int)r->updt_step);
        if (r->delta_lo > 0 && r->delta_lo < rec->step)
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                               "step %d, but step %d's mesh or boundary delta (record %ld) has no UPDT",
                               (int)rec->step, (int)r->delta_lo, r->delta_index);
        r->updt_step = rec->step, r->delta_lo = 0;
    } else if (delta) {
        if (!memcmp(rec->type, "MDLT", 4)) {
            aug_cur c;
            aug_cur_init(&c, rec);
            int64_t nnew = aug_cur_i64(&c);
            if (c.ok) r->mdlt_step = rec->step, r->mdlt_nnew = nnew;
        }
        if (r->updt_step > 0 && rec->step <= r->updt_step)
            return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "step %d after the UPDT of step %d",
                               (int)rec->step, (int)r->updt_step);
        if (!r->delta_lo) r->delta_lo = rec->step, r->delta_index = rec->index, memcpy(r->delta_type, rec->type, 4);
    }
    return 0;
}

int aug_replay_steps(aug_replay *r, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    const aug_rectype *rt = aug_rectype_find(rec->type);
    if (rt && rt->perstep && plan_agrees(r, rec, e)) return e->code;
    if (rt && rt->perstep && rec->step > r->last_step) r->last_step = rec->step;
    return steps_agree(r, rec, e);
}

int aug_replay_add(aug_replay *r, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    if (aug_mesh_is_record(rec->type)) return aug_mesh_absorb(&r->mesh, rec, e);
    const aug_rectype *rt = aug_rectype_find(rec->type);
    if (rt && rt->phase >= 2 && rt->phase <= 3 && aug_replay_start(r, e)) return e->code;
    if (aug_replay_steps(r, rec, e)) return e->code;
    if (r->check_sys && check_sys(r, rec, e)) return e->code;
    if (!memcmp(rec->type, "KMAT", 4) && !r->have_kmat) r->have_kmat = 1, r->kmat_index = rec->index;
    if (!memcmp(rec->type, "pLAN", 4)) return add_plan(r, rec, e);
    if (!memcmp(rec->type, "DOFM", 4)) return add_dofm(r, rec, e);
    if (!memcmp(rec->type, "MDLT", 4)) return add_mdlt(r, rec, e);
    if (!memcmp(rec->type, "BDLT", 4)) return add_bdlt(r, rec, e);
    if (!memcmp(rec->type, "DYNP", 4)) {
        if (aug_read_dynp(rec, &r->dyn, e)) return e->code;
        r->dynamic = 1;
    }
    return 0;
}

int64_t aug_replay_index(const aug_replay *r, int64_t node, int c)
{
    if (node < r->nn0) return r->map0[node * r->dim + c];
    return r->nfree0 + (node - r->nn0) * r->dim + c;
}

int aug_replay_all(const aug_replay *r)
{
    return r->mesh.out_kind == AUG_OUT_ALL || !has_mesh(&r->mesh);
}

int aug_replay_out_dofs(aug_replay *r, const int32_t **dofs, int64_t *n, aug_err *e)
{
    aug_err_clear(e);
    *dofs = NULL;
    *n = 0;
    if (aug_replay_all(r)) return 0;
    const aug_mesh *m = &r->mesh;
    free(r->out_dof);
    r->out_dof = aug_malloc((size_t)(m->nout * r->dim + 1) * sizeof *r->out_dof);
    if (!r->out_dof) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    int64_t k = 0;
    for (int64_t i = 0; i < m->nout; i++)
        for (int c = 0; c < r->dim; c++) {
            int64_t id = aug_replay_index(r, m->out_nodes[i], c);
            if (id >= 0) r->out_dof[k++] = (int32_t)id;
        }
    qsort(r->out_dof, (size_t)k, sizeof *r->out_dof, aug_cmp_i32);
    *dofs = r->out_dof;
    *n = k;
    return 0;
}

/* the state of d over every node, or the output set's nodes (indexed) */
int aug_replay_write_frame(aug_writer *w, const aug_replay *r, int32_t step, int32_t frame,
                           double time, const double *u, const double *v, aug_err *e)
{
    aug_err_clear(e);
    const aug_mesh *m = &r->mesh;
    int all = aug_replay_all(r), dim = r->dim;
    int64_t cnt = all ? m->nn : m->nout;
    aug_frame f = {frame, time, dim, cnt, NULL, (double *)u, (double *)v};
    if (all) return aug_write_frame(w, step, &f, e);
    double *uo = aug_malloc((size_t)(2 * cnt * dim + 1) * sizeof *uo), *vo = uo + cnt * dim;
    if (!uo) return aug_err_set(e, AUG_ENOMEM, aug_writer_count(w), "fRAM", "out of memory");
    for (int64_t i = 0; i < cnt; i++)
        for (int c = 0; c < dim; c++) {
            uo[i * dim + c] = u[(int64_t)m->out_nodes[i] * dim + c];
            vo[i * dim + c] = v[(int64_t)m->out_nodes[i] * dim + c];
        }
    static int32_t none[1] = {0};
    f.nodes = m->out_nodes ? m->out_nodes : none;
    f.u = uo, f.v = vo;
    int rc = aug_write_frame(w, step, &f, e);
    free(uo);
    return rc;
}

/* u(node, c) = the prescribed value of a constrained DOF (FIXD, inherited or
   added by BDLT: also an identity row of K_t, whose x holds it only to
   rounding), else x[index(node, c)]; over every node, or the output set's
   nodes (indexed) */
int aug_replay_write_field(aug_writer *w, const aug_replay *r, int32_t step, const double *x,
                           aug_err *e)
{
    aug_err_clear(e);
    const aug_mesh *m = &r->mesh;
    int all = aug_replay_all(r), dim = r->dim;
    int64_t cnt = all ? m->nn : m->nout;
    double *u = aug_malloc((size_t)(cnt * dim + 1) * sizeof *u);
    if (!u) return aug_err_set(e, AUG_ENOMEM, aug_writer_count(w), "fELD", "out of memory");
    for (int64_t i = 0; i < cnt; i++) {
        int64_t node = all ? i : m->out_nodes[i];
        for (int c = 0; c < dim; c++) {
            int64_t id = aug_replay_index(r, node, c);
            int64_t k = aug_find_i32(m->fix_dof, m->nfix, (int32_t)(node * dim + c));
            u[i * dim + c] = k >= 0 ? m->fix_val[k] : id >= 0 ? x[id] : 0.0;
        }
    }
    static const int32_t none[1] = {0};
    const int32_t *nodes = all ? NULL : m->out_nodes ? m->out_nodes : none;
    int rc = aug_write_field(w, step, 0, dim, cnt, nodes, u, e);
    free(u);
    return rc;
}
