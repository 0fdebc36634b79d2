/* libFuzzer target: the whole input side of stats in-process: the summary of
   every record (aug_summary_add), printed; of a whole stream also its
   per-step CSV and the VTK file of its mesh and field, as stats --csv and
   stats --vtk make them. */
#include <stdlib.h>
#include <string.h>
#include "fuzz_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_in in;
    aug_err e;
    if (fuzz_open(&in, data, size, &e)) return 0;
    /* the --step of --vtk from the stream's length: the last step or step 1 */
    int32_t limit = size % 2 ? 1 : INT32_MAX;
    aug_summary *s = aug_summary_new(in.r, limit, &e);
    int rc = 0;
    while (s && (rc = aug_read(in.r, &in.rec, &e)) > 0)
        if (aug_summary_add(s, &in.rec, &e)) {
            rc = -1;
            break;
        }
    if (s) {
        /* as stats: records that disagree at the end are an error, no CSV */
        if (aug_summary_end(s, rc == 0 ? &in.rec : NULL, &e)) rc = -1;
        FILE *null = fuzz_devnull();
        aug_summary_print(null, s, "fuzz", &e);
        if (rc == 0) aug_steptab_csv(null, aug_summary_steps(s), &e);
        /* as stats --vtk: the field only when it is of the step shown */
        int32_t last = aug_summary_last_step(s), want = limit == INT32_MAX ? last : limit, step;
        const aug_mesh *m = aug_summary_mesh(s);
        double *u = NULL;
        unsigned char *mask = NULL;
        if (rc == 0 && m && want <= last && !aug_summary_field(s, &step, &u, &mask, &e)) {
            int mine = u && step == want;
            aug_vtk_write(null, m, mine ? u : NULL, mine ? mask : NULL, &e);
        }
        free(u);
        free(mask);
        aug_summary_free(s);
    }
    fuzz_close(&in);
    return 0;
}
