/* libFuzzer target: the whole input side of cut and solve-aug in-process: every
   record through the scene replay (aug_replay_add) and the original system
   (aug_sys0_add), then each UPDT read, the solver made from the records
   (aug_sys0_solver: K0, f0, FACT and DOFM agree) and stepped by every method,
   its field written as solve-aug writes it. */
#include <string.h>
#include "fuzz_util.h"

/* one UPDT as solve-aug's step() takes it, minus the reports */
static int step(aug_replay *rp, aug_sys0 *sys, const aug_solver_opts *o, aug_writer *w,
                const aug_rec *rec, aug_err *e)
{
    aug_update u;
    int rc = aug_read_update(rec, &u, e);
    if (!rc && !sys->solver) rc = aug_sys0_solver(sys, rp->started ? rp->nfree0 : -1, o, rec, e);
    const int32_t *out;
    int64_t nout;
    if (!rc) rc = aug_replay_out_dofs(rp, &out, &nout, e);
    int flags = rp->nmdlt && rp->mdlt_step == u.step ? rp->mdlt_flags : 0;
    if (!rc) rc = aug_solver_step(sys->solver, &u, aug_replay_all(rp) ? NULL : out, nout, flags, e);
    if (!rc && !aug_solver_singular(sys->solver, o->order[0]) && (rp->mesh.have & AUG_HAVE_NODE))
        rc = aug_replay_write_field(w, rp, u.step, aug_solver_field(sys->solver, o->order[0]), e);
    aug_update_free(&u);
    return rc;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_in in;
    aug_err e;
    if (fuzz_open(&in, data, size, &e)) return 0;
    aug_replay rp;
    aug_replay_init(&rp);
    /* --output from the stream's length: the stream's own, surface, all or a set */
    static const char *const outs[] = {NULL, "surface", "all", "boundary", "fixed", "nosuch"};
    rp.output = outs[size % 6];
    aug_sys0 sys;
    aug_solver_opts o;
    aug_solver_opts_default(&o);
    /* every method but auto (which runs apart from amps); the dense cgm-*
       methods (static streams only) on every other input, small */
    o.nmeth = 0;
    for (int i = 0; i < AUG_M_COUNT; i++)
        if (i != AUG_M_AUTO && (size % 2 || i < AUG_M_CGM_COV)) o.order[o.nmeth++] = i;
    o.cgm.max_n = 200, o.cgm.ns_maxit = 30;
    o.maxit = 200;
    o.spare = 64;
    aug_writer *w = aug_writer_open(fuzz_devnull(), "fuzz", &e);
    if (w && !aug_sys0_init(&sys, &e)) {
        while (aug_read(in.r, &in.rec, &e) == 1) {
            if (aug_replay_add(&rp, &in.rec, &e) || aug_sys0_add(&sys, &in.rec, &e)) break;
            if (!memcmp(in.rec.type, "UPDT", 4) && step(&rp, &sys, &o, w, &in.rec, &e)) break;
        }
        aug_sys0_free(&sys);
    }
    aug_writer_free(w);
    aug_replay_free(&rp);
    fuzz_close(&in);
    return 0;
}
