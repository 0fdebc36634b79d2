/* libFuzzer target: the stream reader (framing, order, inflation) and the mesh
   as the records build it: absorbed, changed by MDLT, validated. */
#include <string.h>
#include "fuzz_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    FILE *f;
    aug_err e;
    aug_reader *r = fuzz_open(data, size, &f);
    if (r) {
        aug_rec rec;
        memset(&rec, 0, sizeof rec);
        aug_mesh m;
        aug_mesh_init(&m);
        int validated = 0, valid = 0;
        while (aug_read(r, &rec, &e) == 1) {
            if (aug_mesh_is_record(rec.type)) {
                if (aug_mesh_absorb(&m, &rec, &e)) break;
            } else if (!memcmp(rec.type, "UPDT", 4)) {
                aug_update u;
                aug_read_update(&rec, &u, &e);
                aug_update_free(&u);
            } else if (!memcmp(rec.type, "MDLT", 4) && m.nv) {
                /* deltas apply to a validated mesh, as in the tools (aug_replay_start) */
                if (!validated) valid = !aug_mesh_validate(&m, &e), validated = 1;
                aug_mdelta d;
                if (aug_read_mdelta(&rec, m.dim, m.nv, &d, &e) == 0 && valid &&
                    aug_mesh_apply(&m, &d, &e))
                    valid = 0;
                aug_mdelta_free(&d);
            } else if (rec.type[1] >= 'A' && rec.type[1] <= 'Z' && rec.type[0] >= 'a' &&
                       (!memcmp(rec.type + 1, "OND", 3) || !memcmp(rec.type + 1, "TAt", 3) ||
                        !memcmp(rec.type + 1, "IMe", 3) || !memcmp(rec.type + 1, "UAl", 3))) {
                aug_kv kv;
                aug_read_kv(&rec, &kv, &e);
            }
        }
        if (m.nn && m.ne) aug_mesh_validate(&m, &e);
        aug_mesh_free(&m);
        fuzz_close(r, f, &rec);
    }
    return 0;
}
