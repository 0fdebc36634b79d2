/* STL triangle surfaces (binary and ASCII) into a triangle soup. */
#include <errno.h>
#include <math.h>
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
        for (int k = 0; k < 3; k++) /* as the text reader refuses them (NaN, inf were skipped) */
            if (!aug_soup_point_ok(v + 3 * k))
                return aug_err_set(e, AUG_EUSAGE, -1, "", "%s: triangle %u: vertex %d is not finite or beyond "
                                   "1e30", path, i + 1, k + 1);
        if (aug_soup_add(s, v, v + 3, v + 6) < 0) return aug_err_set(e, AUG_ENOMEM, -1, "", "%s: out of memory", path);
    }
    (void)n;
    return 0;
}

/* the next blank-separated word of *p (NULL at the end of the line), cut
   off with a NUL; *p moves past it */
static char *word(char **p)
{
    char *q = *p;
    while (*q == ' ' || *q == '\t' || *q == '\r') q++;
    if (!*q) return *p = q, NULL;
    char *w = q;
    while (*q && *q != ' ' && *q != '\t' && *q != '\r') q++;
    if (*q) *q++ = 0;
    *p = q;
    return w;
}

/* three finite numbers and nothing after them on the line */
static int three(char **p, double *v)
{
    for (int k = 0; k < 3; k++) {
        char *w = word(p), *end;
        if (!w) return -1;
        v[k] = strtod(w, &end);
        if (*end || !isfinite(v[k])) return -1;
    }
    return word(p) ? -1 : 0;
}

/* ASCII STL, line by line in its grammar: solid NAME, then per facet
   "facet normal nx ny nz", "outer loop", three "vertex x y z", "endloop",
   "endfacet", then "endsolid [NAME]" (more solids may follow). Any other
   line, text after the numbers, a missing end: an error naming the line. */
static int read_ascii(char *d, aug_soup *s, const char *path, aug_err *e)
{
    enum { TOP, SOLID, FACET, LOOP, ENDLOOP, ENDED } st = TOP;
    static const char *want[] = {"solid", "facet normal or endsolid", "outer loop", "vertex or endloop",
                                 "endfacet", "solid"};
    double v[9], nrm[3];
    int nv = 0, line = 0;
    for (char *p = d; *p;) {
        char *eol = strchr(p, '\n'), *next = eol ? eol + 1 : p + strlen(p);
        if (eol) *eol = 0;
        line++;
        char *q = p, *w = word(&q);
        p = next;
        if (!w) continue; /* a blank line */
        int ok = 0;
        if (!strcmp(w, "solid") && (st == TOP || st == ENDED)) {
            st = SOLID, ok = 1; /* the name: the rest of the line */
        } else if (!strcmp(w, "endsolid") && st == SOLID) {
            st = ENDED, ok = 1;
        } else if (!strcmp(w, "facet") && st == SOLID) {
            char *w2 = word(&q);
            ok = w2 && !strcmp(w2, "normal") && !three(&q, nrm);
            if (!ok)
                return aug_err_set(e, AUG_EUSAGE, -1, "", "%s:%d: want 'facet normal nx ny nz' (three finite "
                                   "numbers, nothing after)", path, line);
            st = FACET;
        } else if (!strcmp(w, "outer") && st == FACET) {
            char *w2 = word(&q);
            ok = w2 && !strcmp(w2, "loop") && !word(&q);
            st = LOOP, nv = 0;
        } else if (!strcmp(w, "vertex") && st == LOOP) {
            if (nv == 3 || three(&q, v + 3 * nv))
                return aug_err_set(e, AUG_EUSAGE, -1, "", nv == 3 ? "%s:%d: a fourth vertex in a facet"
                                   : "%s:%d: want 'vertex x y z' (three finite numbers, nothing after)", path, line);
            /* past 1e30 the area test overflowed: a triangle at 1e200 had "no area" */
            if (!aug_soup_point_ok(v + 3 * nv))
                return aug_err_set(e, AUG_EUSAGE, -1, "", "%s:%d: a vertex beyond 1e30", path, line);
            nv++, ok = 1;
        } else if (!strcmp(w, "endloop") && st == LOOP) {
            if (nv != 3) return aug_err_set(e, AUG_EUSAGE, -1, "", "%s:%d: a facet of %d vertices, want 3", path, line, nv);
            ok = !word(&q);
            st = ENDLOOP;
        } else if (!strcmp(w, "endfacet") && st == ENDLOOP) {
            ok = !word(&q);
            if (ok && aug_soup_add(s, v, v + 3, v + 6) < 0) return aug_err_set(e, AUG_ENOMEM, -1, "", "%s: out of memory", path);
            st = SOLID;
        }
        if (!ok) return aug_err_set(e, AUG_EUSAGE, -1, "", "%s:%d: '%s' where the STL grammar wants %s", path, line, w, want[st]);
    }
    if (st != ENDED) return aug_err_set(e, AUG_EUSAGE, -1, "", "%s:%d: the file ends before 'endsolid'", path, line);
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
