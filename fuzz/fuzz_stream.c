/* libFuzzer target: the stream reader (framing, order, inflation) and the mesh
   as the records build it: absorbed, changed by MDLT, validated. */
#include <string.h>
#include "fuzz_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_in in;
    aug_err e;
    if (!fuzz_open(&in, data, size, &e)) {
        aug_mesh m;
        aug_mesh_init(&m);
        int validated = 0, valid = 0;
        while (aug_read(in.r, &in.rec, &e) == 1) {
            if (aug_mesh_is_record(in.rec.type)) {
                if (aug_mesh_absorb(&m, &in.rec, &e)) break;
            } else if (!memcmp(in.rec.type, "UPDT", 4)) {
                aug_update u;
                aug_read_update(&in.rec, &u, &e);
                aug_update_free(&u);
            } else if (!memcmp(in.rec.type, "MDLT", 4) && m.nv) {
                /* deltas apply to a validated mesh, as in the tools (aug_replay_start) */
                if (!validated) valid = !aug_mesh_validate(&m, &e), validated = 1;
                aug_mdelta d;
                if (aug_read_mdelta(&in.rec, m.dim, m.nv, &d, &e) == 0 && valid &&
                    aug_mesh_apply(&m, &d, &e))
                    valid = 0;
                aug_mdelta_free(&d);
            } else if (in.rec.type[1] >= 'A' && in.rec.type[1] <= 'Z' && in.rec.type[0] >= 'a' &&
                       (!memcmp(in.rec.type + 1, "OND", 3) || !memcmp(in.rec.type + 1, "TAt", 3) ||
                        !memcmp(in.rec.type + 1, "IMe", 3) || !memcmp(in.rec.type + 1, "UAl", 3))) {
                aug_kv kv;
                aug_read_kv(&in.rec, &kv, &e);
            }
        }
        if (m.nn && m.ne) aug_mesh_validate(&m, &e);
        aug_mesh_free(&m);
        fuzz_close(&in);
    }
    return 0;
}
