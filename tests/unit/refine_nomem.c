/* Failure injection (CSparse style): the n-th allocation fails, for every n until
   a whole refine step succeeds; each run must end with AUG_ENOMEM reported or
   success, never another error, a crash or (under ASan) a leak; a run that
   succeeds gives the same folded step as a run without failures. */
#include <string.h>
#include "aug_cut.h"
#include "refine_gen.h"
#include "t.h"

/* one refiner + one refine step (with its UPDT) on a 10 x 10 square */
static int attempt(long n, aug_mdelta *keep, int *code)
{
    aug_mesh C;
    gen_square(&C, 10);
    gen_poly g = {0};
    double P[4][2] = {{0.12, 0.4}, {0.4, 0.75}, {0.6, 0.25}, {0.88, 0.55}};
    poly_cubic(&g, P, 60);
    aug_mdelta d;
    double *seg;
    int64_t nseg;
    int grc = gen_cut(&C, &g, 1, &d, &seg, &nseg);
    free(g.p);
    if (grc) {
        aug_mesh_free(&C);
        *code = -100;
        return -1;
    }
    aug_refiner R;
    aug_err e;
    aug_mdelta out;
    aug_update u;
    aug_refine_q q;
    aug_mdelta_init(&out);
    aug_update_init(&u);
    aug_fail_after(n);
    int rc = aug_refiner_init(&R, &C, NULL, &e);
    if (!rc) {
        rc = aug_refine_step(&R, &d, NULL, seg, nseg, &out, NULL, &u, &q, &e);
        aug_refiner_free(&R);
    }
    aug_fail_after(-1);
    *code = rc ? e.code : 0;
    if (!rc && keep) *keep = out;
    else aug_mdelta_free(&out);
    aug_update_free(&u);
    aug_mdelta_free(&d);
    free(seg);
    aug_mesh_free(&C);
    return rc;
}

static void every_allocation(void)
{
    aug_mdelta ref;
    int code;
    T_CHECK(attempt(-1, &ref, &code) == 0, "the step fails without injection (%d)", code);
    long n;
    int ok = 0;
    for (n = 0; n < 100000 && !t_cur_failed; n++) {
        aug_mdelta got;
        int rc = attempt(n, &got, &code);
        if (rc == 0) {
            T_CHECK(got.nnew == ref.nnew && got.nmod == ref.nmod && got.nadd == ref.nadd &&
                        !memcmp(got.conn_add, ref.conn_add, (size_t)got.nadd * 3 * sizeof(int32_t)),
                    "the step after %ld allocations differs", n);
            aug_mdelta_free(&got);
            ok = 1;
            break;
        }
        T_CHECK(code == AUG_ENOMEM, "allocation %ld failing gave error %d, not AUG_ENOMEM", n, code);
    }
    T_CHECK(ok, "never succeeded");
    printf("# %ld allocations injected\n", n);
    aug_mdelta_free(&ref);
}

int main(void)
{
    T_RUN(every_allocation);
    T_EXIT();
}
