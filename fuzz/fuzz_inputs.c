/* libFuzzer target: cut's non-stream inputs (man/cut.1): the path file of
   --path, the blade file of --blade, the STL surface of --surface. The first
   byte picks the reader, the rest is the file. What a reader accepts must be
   finite and usable: the curves evaluate to finite points with arc lengths
   increasing, the blade sweeps finite triangles, the surface's triangles are
   finite and their progressive order keys lie in [0, 1]. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#include "fuzz_util.h"

static void finite_or_fail(const char *what, const double *v, int64_t n)
{
    for (int64_t k = 0; k < n; k++)
        if (!isfinite(v[k])) fuzz_fail("%s: accepted, but value %lld is %g", what, (long long)k, v[k]);
}

/* an accepted path: finite points along every curve, arc lengths increasing */
static void path_input(FILE *f)
{
    aug_path p;
    aug_err e;
    if (aug_path_parse(f, "fuzz.path", &p, &e)) return;
    if (p.n < 1 || !isfinite(p.total) || p.total < 0) fuzz_fail("path: %d curves, length %g", p.n, p.total);
    for (int i = 0; i < p.n; i++) {
        if (i && !(p.s0[i] >= p.s0[i - 1])) fuzz_fail("path: curve %d starts at arc length %g before %g", i, p.s0[i], p.s0[i - 1]);
        for (int k = 0; k <= 4; k++) {
            double len = p.tab[(size_t)i * (AUG_PATH_NS + 1) + AUG_PATH_NS]; /* curve i's length */
            double xy[2], t = aug_path_param(&p, i, 0.25 * k * len);
            if (!(t >= -1e-12 && t <= 1 + 1e-12)) fuzz_fail("path: curve %d: parameter %g outside [0, 1]", i, t);
            aug_curve_eval(&p.c[i], t, xy);
            finite_or_fail("path point", xy, 2);
        }
    }
    aug_path_free(&p);
}

/* an accepted blade: finite keys and controls, a finite swept surface */
static void blade_input(FILE *f)
{
    aug_blade b;
    aug_err e;
    if (aug_blade_parse(f, "fuzz.blade", &b, &e)) return;
    if (b.nkey < 2) fuzz_fail("blade: accepted with %d key positions", b.nkey);
    finite_or_fail("blade key", b.key, 6 * (int64_t)b.nkey);
    for (int i = 0; i + 1 < b.nkey; i++) {
        if (b.nctrl[i] < 0 || b.nctrl[i] > AUG_BLADE_MAXCTRL) fuzz_fail("blade: interval %d has %d controls", i, b.nctrl[i]);
        finite_or_fail("blade control", b.ctrl + (int64_t)i * AUG_BLADE_MAXCTRL * 6, 6 * (int64_t)b.nctrl[i]);
    }
    aug_soup s = {0};
    if (aug_blade_sweep(&b, 0, 1, &s) >= 0) finite_or_fail("blade sweep", s.t, 9 * s.n);
    aug_soup_free(&s);
    aug_blade_free(&b);
}

/* an accepted STL: finite triangles, order keys in [0, 1]; the reader takes a
   path, so the bytes go to an anonymous memory file (/proc/self/fd/N) */
static void stl_input(const uint8_t *data, size_t size)
{
    int fd = memfd_create("fuzz.stl", 0);
    if (fd < 0) return;
    if (write(fd, data, size) != (ssize_t)size) {
        close(fd);
        return;
    }
    char path[64];
    snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    aug_soup s = {0};
    aug_err e;
    if (!aug_stl_read(path, &s, &e)) {
        finite_or_fail("stl triangle", s.t, 9 * s.n);
        double *key = malloc((size_t)(s.n + 1) * sizeof *key);
        if (key && !aug_soup_order(&s, NULL, key, &e))
            for (int64_t k = 0; k < s.n; k++)
                if (!(key[k] >= 0 && key[k] <= 1)) fuzz_fail("stl: order key %lld is %g", (long long)k, key[k]);
        free(key);
    }
    aug_soup_free(&s);
    close(fd);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    int which = data[0] % 3;
    if (which == 2) {
        stl_input(data + 1, size - 1);
        return 0;
    }
    static char blank[] = "\n"; /* an empty file: fmemopen needs a byte of buffer */
    FILE *f = size > 1 ? fmemopen((void *)(data + 1), size - 1, "r") : fmemopen(blank, 1, "r");
    if (!f) return 0;
    if (which == 0) path_input(f);
    else blade_input(f);
    fclose(f);
    return 0;
}
