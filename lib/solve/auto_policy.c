/* The cost model of solve-aug --method auto: per step AMPS on the current
   base, a synchronous re-factorization of K_t that becomes the new base, or
   AMPS while a background re-factorization runs, from the measured times. */
#include <string.h>
#include "aug_solve.h"

void aug_auto_init(aug_auto *a, int bg_allowed)
{
    memset(a, 0, sizeof *a);
    a->bg_allowed = bg_allowed;
}

static int pick(aug_auto *a, int choice, int reason)
{
    a->reason = reason;
    return a->choice = choice;
}

/* The choice for the next step (paper 001 sec. 3.5: an AMPS step costs more
   as S2 and the memo grow with the update since the base; paper 000 sec.
   3.6: a re-factorization resets that growth, in the foreground or in a
   thread). On a base, the first AUG_AUTO_WARM AMPS steps build its state
   (warm-up); with a_j the measured times of the later steps, a_ref = min
   a_j, E = sum_j (a_j - a_ref) the time the growth has cost, T the time of a
   re-factorization step (measured, else the prior) and R = T + the warm-up's
   excess over a_ref (measured on the bases before), the cost of a new base:
     - warm-up: AMPS, unless on the last base measured even the cheapest
       steady step cost T or more (re-factor every step, the 2-D refined
       cut; after AUG_AUTO_PROBE such steps one base is measured again);
     - a background job running: AMPS;
     - the next AMPS step, predicted a_last + max(0, slope), costs >= T:
       re-factor now (AUG_AUTO_STEP);
     - with a free core, E >= R / 4: AMPS, and a background job starts (it
       takes about T, the growth goes on meanwhile);
     - E >= R (the steps a new base would have saved outweigh it: for a_j
       growing linearly the optimum of the cycle cost (R + sum a_j) / j):
       re-factor now;
     - else AMPS. */
int aug_auto_decide(aug_auto *a, int bg_running)
{
    double T = a->t_factor > 0 ? a->t_factor : a->t_prior, R = T + a->t_warm;
    a->want_bg = 0;
    a->est_factor = R;
    if (a->on_base < AUG_AUTO_WARM) {
        a->est_amps = a->a_warm;
        if (!bg_running && a->a_min_prev > 0 && T > 0 && a->a_min_prev >= T && a->nsync_run < AUG_AUTO_PROBE) {
            a->nsync_run++;
            a->est_factor = T;
            return pick(a, AUG_AUTO_REFACTOR, AUG_AUTO_FIRST_DEARER);
        }
        a->nsync_run = 0;
        return pick(a, AUG_AUTO_AMPS, AUG_AUTO_FIRST);
    }
    int k = a->on_base - AUG_AUTO_WARM; /* steady steps measured */
    double slope = k >= 2 ? (a->a_last - a->a_ref) / (k - 1) : 0;
    a->est_amps = k ? a->a_last + (slope > 0 ? slope : 0) : a->a_warm;
    if (bg_running) return pick(a, AUG_AUTO_AMPS, AUG_AUTO_BG_RUNNING);
    if (k && T > 0 && a->est_amps >= T) {
        a->est_factor = T;
        return pick(a, AUG_AUTO_REFACTOR, AUG_AUTO_STEP);
    }
    if (a->bg_allowed && R > 0 && a->excess >= 0.25 * R) {
        a->want_bg = 1;
        return pick(a, AUG_AUTO_AMPS, AUG_AUTO_BG_START);
    }
    if (R > 0 && a->excess >= R) return pick(a, AUG_AUTO_REFACTOR, AUG_AUTO_AMORTIZED);
    return pick(a, AUG_AUTO_AMPS, AUG_AUTO_CHEAPER);
}

/* a running mean (the first value as it is) */
static double mean2(double old, double v) { return old > 0 ? 0.5 * (old + v) : v; }

/* the measured time ms of the step just taken with a->choice (refactor: the
   step that made the new base, AMPS: a step on the base) */
void aug_auto_observe(aug_auto *a, double ms)
{
    if (a->choice == AUG_AUTO_REFACTOR) {
        a->t_factor = mean2(a->t_factor, ms);
        aug_auto_rebased(a);
        return;
    }
    if (a->on_base < AUG_AUTO_WARM) {
        a->warm_sum += ms;
        a->a_warm = mean2(a->a_warm, ms);
    } else {
        if (a->on_base == AUG_AUTO_WARM || ms < a->a_ref) a->a_ref = ms;
        if (a->on_base == AUG_AUTO_WARM) a->t_warm = mean2(a->t_warm, a->warm_sum - AUG_AUTO_WARM * ms);
        a->excess += ms - a->a_ref;
        a->a_last = ms;
    }
    a->on_base++;
}

/* a new base (re-factored in the foreground or swapped in from the
   background): the growth starts again */
void aug_auto_rebased(aug_auto *a)
{
    if (a->on_base > AUG_AUTO_WARM) a->a_min_prev = a->a_ref;
    a->on_base = 0;
    a->excess = a->warm_sum = 0;
    a->a_ref = a->a_last = 0;
}
