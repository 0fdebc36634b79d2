/* Error reports: codes, the record they concern, a message; never printed here. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "aug_stream.h"

void aug_err_clear(aug_err *e)
{
    if (!e) return;
    e->code = AUG_OK;
    e->record = -1;
    e->type[0] = 0;
    e->msg[0] = 0;
    e->output = 0;
}

int aug_err_set(aug_err *e, int code, long record, const char *type, const char *fmt, ...)
{
    if (!e) return code;
    e->code = code;
    e->record = record;
    e->output = 0;
    snprintf(e->type, sizeof e->type, "%s", type ? type : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->msg, sizeof e->msg, fmt, ap);
    va_end(ap);
    return code;
}
