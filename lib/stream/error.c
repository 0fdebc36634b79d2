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
    char raw[sizeof e->msg];
    vsnprintf(raw, sizeof raw, fmt, ap);
    va_end(ap);
    /* names from records may hold control bytes: \xNN, so that a message stays
       one line and sends nothing to a terminal */
    size_t k = 0;
    for (const unsigned char *p = (const unsigned char *)raw; *p && k + 5 < sizeof e->msg; p++) {
        if (*p < 0x20 || *p == 0x7f) k += (size_t)snprintf(e->msg + k, 5, "\\x%02x", *p);
        else e->msg[k++] = (char)*p;
    }
    e->msg[k] = 0;
    return code;
}
