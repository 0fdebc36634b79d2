/* STL triangle surfaces (binary and ASCII) into a triangle soup. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"

static float f32(const unsigned char *p)
{
    float v;
    memcpy(&v, p, 4); /* STL is little-endian, as the machines we build for */
    return v;
}

/* binary STL: 80-byte header, uint32 count, 50 bytes per triangle (normal,
   three vertices as float32, uint16 attribute); exactly that size */
static int read_binary(const unsigned char *d, size_t n, aug_soup *s, const char *path, aug_err *e)
{
    uint32_t nt = (uint32_t)d[80] | (uint32_t)d[81] << 8 | (uint32_t)d[82] << 16 | (uint32_t)d[83] << 24;
    for (uint32_t i = 0; i < nt; i++) {
        const unsigned char *r = d + 84 + 50 * (size_t)i + 12;
        double v[9];
        for (int k = 0; k < 9; k++) v[k] = f32(r + 4 * k);
        if (aug_soup_add(s, v, v + 3, v + 6) < 0) return aug_err_set(e, AUG_ENOMEM, -1, "", "%s: out of memory", path);
    }
    (void)n;
    return 0;
}

/* ASCII STL: "vertex x y z" lines, three per facet */
static int read_ascii(char *d, aug_soup *s, const char *path, aug_err *e)
{
    double v[9];
    int nv = 0, line = 1;
    for (char *p = d; *p; p++) {
        if (*p == '\n') line++;
        if (strncmp(p, "vertex", 6) || (p > d && p[-1] != ' ' && p[-1] != '\t' && p[-1] != '\n')) continue;
        char *q = p + 6;
        for (int k = 0; k < 3; k++) {
            char *end;
            v[3 * nv + k] = strtod(q, &end);
            if (end == q) return aug_err_set(e, AUG_EUSAGE, -1, "", "%s:%d: a vertex needs three numbers", path, line);
            q = end;
        }
        p = q - 1;
        if (++nv == 3) {
            nv = 0;
            if (aug_soup_add(s, v, v + 3, v + 6) < 0) return aug_err_set(e, AUG_ENOMEM, -1, "", "%s: out of memory", path);
        }
    }
    if (nv) return aug_err_set(e, AUG_EUSAGE, -1, "", "%s: %d vertices left over (three a facet)", path, nv);
    return 0;
}

int aug_stl_read(const char *path, aug_soup *s, aug_err *e)
{
    aug_err_clear(e);
    FILE *f = fopen(path, "rb");
    if (!f) return aug_err_set(e, AUG_EIO, -1, "", "%s: %s", path, strerror(errno));
    size_t cap = 1 << 16, n = 0, r;
    unsigned char *d = aug_malloc(cap + 1);
    while (d && (r = fread(d + n, 1, cap - n, f)) > 0) {
        n += r;
        if (n == cap) {
            unsigned char *q = aug_realloc(d, 2 * cap + 1);
            if (!q) {
                free(d);
                d = NULL;
                break;
            }
            d = q;
            cap *= 2;
        }
    }
    int bad = ferror(f);
    fclose(f);
    if (!d) return aug_err_set(e, AUG_ENOMEM, -1, "", "%s: out of memory", path);
    if (bad) {
        free(d);
        return aug_err_set(e, AUG_EIO, -1, "", "%s: read error", path);
    }
    d[n] = 0;
    int rc;
    uint32_t nt = n >= 84 ? ((uint32_t)d[80] | (uint32_t)d[81] << 8 | (uint32_t)d[82] << 16 | (uint32_t)d[83] << 24) : 0;
    if (n >= 84 && n == 84 + 50 * (size_t)nt)
        rc = read_binary(d, n, s, path, e);
    else if (n >= 5 && !memcmp(d, "solid", 5) && !memchr(d, 0, n))
        rc = read_ascii((char *)d, s, path, e);
    else
        rc = aug_err_set(e, AUG_EUSAGE, -1, "", "%s: not an STL file (neither 84 + 50 n bytes nor text "
                         "beginning with 'solid')", path);
    free(d);
    if (!rc && s->n == 0) rc = aug_err_set(e, AUG_EUSAGE, -1, "", "%s: no triangle of positive area", path);
    return rc;
}
