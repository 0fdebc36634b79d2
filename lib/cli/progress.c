/* Progress line on stderr for long runs: "prog: step i/N, R Hz", rewritten in place. */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#include "aug_tool.h"

#define PROGRESS_AFTER 2.0   /* seconds before the line first shows */
#define PROGRESS_EVERY 0.25  /* seconds between redraws */

static struct {
    int started, tty, shown;
    double t0, last;
    long i0;
} pg;

static void clear_line(void)
{
    if (pg.shown) fputs("\r\033[K", stderr);
    pg.shown = 0;
}

/* rate = steps since the first call / seconds since it */
void aug_progress(const aug_tool *t, long i, long n)
{
    if (i < 0) {
        clear_line();
        return;
    }
    double now = aug_now();
    if (!pg.started) {
        pg.started = 1;
        pg.tty = isatty(2);
        pg.t0 = now;
        pg.i0 = i;
        if (pg.tty) atexit(clear_line);
        return;
    }
    if (!pg.tty) return;
    if (n > 0 && i >= n) {
        clear_line();
        return;
    }
    if (now - pg.t0 < PROGRESS_AFTER || (pg.shown && now - pg.last < PROGRESS_EVERY)) return;
    double hz = (double)(i - pg.i0) / (now - pg.t0);
    if (n > 0) fprintf(stderr, "\r\033[K%s: step %ld/%ld, %.3g Hz", t->prog, i, n, hz);
    else fprintf(stderr, "\r\033[K%s: step %ld, %.3g Hz", t->prog, i, hz);
    fflush(stderr);
    pg.shown = 1;
    pg.last = now;
}
