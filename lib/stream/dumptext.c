/* Text building blocks of stats --dump shared by every record codec: the
   record header line, escaped names, %.17g floats, arrays and row tables. */
#include <string.h>
#include "aug_stream.h"

#define PER_I 10 /* integers per line of a 1-D array */
#define PER_F 4  /* floats per line of a 1-D array */

/* "#N TYPE step=S flags=F len=L" */
void aug_txt_header(FILE *o, const aug_rec *rec)
{
    fprintf(o, "#%ld %s step=%d flags=%u len=%llu\n", rec->index, rec->type, (int)rec->step,
            (unsigned)rec->flags, (unsigned long long)rec->len);
}

/* bytes as a C-like string: printable ASCII as is, \" \\ and \xNN otherwise */
void aug_txt_esc(FILE *o, const char *s, size_t n, int quote)
{
    if (quote) fputc('"', o);
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '"' || c == '\\') fprintf(o, "\\%c", c);
        else if (c > ' ' && c < 127) fputc(c, o);
        else if (c == ' ' && quote) fputc(c, o);
        else fprintf(o, "\\x%02x", c);
    }
    if (quote) fputc('"', o);
}

/* "  label "escaped"" */
void aug_txt_name(FILE *o, const char *label, const char *s, size_t cap)
{
    fprintf(o, "  %s ", label);
    aug_txt_esc(o, s, strnlen(s, cap), 1);
    fputc('\n', o);
}

void aug_txt_f(FILE *o, double v) { fprintf(o, "%.17g", v); }

/* 1-D arrays read from the cursor: "  label[n]" then "    i: v v v" */
void aug_txt_i32s(FILE *o, const char *label, aug_cur *c, uint64_t n)
{
    fprintf(o, "  %s[%llu]\n", label, (unsigned long long)n);
    for (uint64_t i = 0; i < n; i++) {
        if (i % PER_I == 0) fprintf(o, "    %llu:", (unsigned long long)i);
        fprintf(o, " %d", (int)aug_cur_i32(c));
        if (i % PER_I == PER_I - 1 || i == n - 1) fputc('\n', o);
    }
}

void aug_txt_i64s(FILE *o, const char *label, aug_cur *c, uint64_t n)
{
    fprintf(o, "  %s[%llu]\n", label, (unsigned long long)n);
    for (uint64_t i = 0; i < n; i++) {
        if (i % PER_I == 0) fprintf(o, "    %llu:", (unsigned long long)i);
        fprintf(o, " %lld", (long long)aug_cur_i64(c));
        if (i % PER_I == PER_I - 1 || i == n - 1) fputc('\n', o);
    }
}

void aug_txt_f64s(FILE *o, const char *label, aug_cur *c, uint64_t n)
{
    fprintf(o, "  %s[%llu]\n", label, (unsigned long long)n);
    for (uint64_t i = 0; i < n; i++) {
        if (i % PER_F == 0) fprintf(o, "    %llu:", (unsigned long long)i);
        fputc(' ', o);
        aug_txt_f(o, aug_cur_f64(c));
        if (i % PER_F == PER_F - 1 || i == n - 1) fputc('\n', o);
    }
}

/* 2-D arrays, one row per line: "  label[rows x cols]" then "    r: v v v" */
void aug_txt_rows_i32(FILE *o, const char *label, aug_cur *c, uint64_t rows, int cols)
{
    fprintf(o, "  %s[%llu x %d]\n", label, (unsigned long long)rows, cols);
    for (uint64_t r = 0; r < rows; r++) {
        fprintf(o, "    %llu:", (unsigned long long)r);
        for (int j = 0; j < cols; j++) fprintf(o, " %d", (int)aug_cur_i32(c));
        fputc('\n', o);
    }
}

void aug_txt_rows_f64(FILE *o, const char *label, aug_cur *c, uint64_t rows, int cols)
{
    fprintf(o, "  %s[%llu x %d]\n", label, (unsigned long long)rows, cols);
    for (uint64_t r = 0; r < rows; r++) {
        fprintf(o, "    %llu:", (unsigned long long)r);
        for (int j = 0; j < cols; j++) {
            fputc(' ', o);
            aug_txt_f(o, aug_cur_f64(c));
        }
        fputc('\n', o);
    }
}

/* the payload as hex, 16 bytes a line (reserved and unknown records) */
void aug_txt_hex(FILE *o, const aug_rec *rec)
{
    fprintf(o, "  bytes[%llu]\n", (unsigned long long)rec->len);
    for (uint64_t i = 0; i < rec->len; i++) {
        if (i % 16 == 0) fprintf(o, "    %llu:", (unsigned long long)i);
        fprintf(o, " %02x", rec->data[i]);
        if (i % 16 == 15 || i == rec->len - 1) fputc('\n', o);
    }
}

/* a cursor over an in-memory array, to print decoded structs with the same helpers */
aug_cur aug_cur_mem(const void *p, uint64_t bytes)
{
    aug_cur c = {p, bytes, 0, 1};
    return c;
}

/* dst = src with control bytes (< 0x20, 0x7f) as \xNN, truncated to cap */
const char *aug_txt_clean(char *dst, size_t cap, const char *src)
{
    size_t k = 0;
    for (const unsigned char *p = (const unsigned char *)src; *p && k + 5 < cap; p++) {
        if (*p < 0x20 || *p == 0x7f) k += (size_t)snprintf(dst + k, 5, "\\x%02x", *p);
        else dst[k++] = (char)*p;
    }
    if (cap) dst[k < cap ? k : cap - 1] = 0;
    return dst;
}
