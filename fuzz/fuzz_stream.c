/* libFuzzer target: the stream reader and every record decoder of lib/. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include "augcut.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0) return 0;
    FILE *f = fmemopen((void *)data, size, "rb");
    if (!f) return 0;
    aug_err e;
    aug_reader *r = aug_reader_open(f, "fuzz", &e);
    if (r) {
        aug_rec rec;
        memset(&rec, 0, sizeof rec);
        aug_mesh m;
        aug_mesh_init(&m);
        while (aug_read(r, &rec, &e) == 1) {
            if (aug_mesh_is_record(rec.type)) {
                if (aug_mesh_absorb(&m, &rec, &e)) break;
            } else if (!memcmp(rec.type, "UPDT", 4)) {
                aug_update u;
                aug_read_update(&rec, &u, &e);
                aug_update_free(&u);
            } else if (!memcmp(rec.type, "MDLT", 4) && m.nv) {
                aug_mdelta d;
                if (aug_read_mdelta(&rec, m.dim, m.nv, &d, &e) == 0) aug_mesh_apply(&m, &d, &e);
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
        aug_rec_free(&rec);
        aug_reader_free(r);
    }
    fclose(f);
    return 0;
}
