/* stats --dump: deterministic text of every record through its codec
   (aug_dump_rec, the record table in lib/stream/stream.c). */
#include <string.h>
#include "aug_stats.h"

void aug_dump_init(aug_dump *d, int no_times)
{
    memset(d, 0, sizeof *d);
    d->no_times = no_times;
    aug_mesh_init(&d->mesh);
}

void aug_dump_free(aug_dump *d) { aug_mesh_free(&d->mesh); }

/* decode (and so validate) first, then print: a bad record prints nothing */
int aug_dump_record(FILE *out, aug_dump *d, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    if (d->no_times && memcmp(rec->type, "tIMe", 4) == 0) return 0;
    if (aug_dump_rec(out, &d->mesh, rec, e)) return e->code;
    if (ferror(out)) return aug_err_set(e, AUG_EIO, rec->index, rec->type, "write failed");
    return 0;
}
