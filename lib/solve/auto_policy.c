/* The cost model of solve-aug --method auto: per step AMPS on the current
   base, a synchronous re-factorization of K_t that becomes the new base, or
   AMPS while a background re-factorization runs, from the measured times. */
#include <string.h>
#include "aug_solve.h"

void aug_auto_init(aug_auto *a, int bg_allowed)
{
    memset(a, 0, sizeof *a);
    a->bg_allowed = bg_allowed;
    a->c_flop = AUG_AUTO_CFLOP_PRIOR;
    a->probe_every = AUG_AUTO_PROBE;
}

static int pick(aug_auto *a, int choice, int reason)
{
    a->reason = reason;
    return a->choice = choice;
}

/* The S2 flops of the next AMPS step (paper 001 eqs. 3.8, 3.21: S2 grows by
   the positions of each step's update and is LU-factored densely, so its
   flops grow with the cube of its order): on a fresh base the LU of the
   step's own s positions; on a base, the last step's flops scaled by the
   growth of a full LU from order na to na + s, at least the elimination of
   the s new columns alone. */
static double predict_flops(const aug_auto *a, int64_t s)
{
    if (a->on_base == 0) return aug_s2_flops(0, s, 0);
    int64_t n1 = a->na + s;
    double full0 = aug_s2_flops(0, a->na, 0), w = aug_s2_flops(a->na, n1, a->na);
    if (full0 > 0 && a->w_last * aug_s2_flops(0, n1, 0) / full0 > w)
        w = a->w_last * aug_s2_flops(0, n1, 0) / full0;
    return w;
}

/* The time of the next AMPS step: a_last + c (w_next - w_last) on a base,
   a_last no higher than the steady steps' trend at that step once it has
   three points (one slow step, a page fault or a busy core, does not
   carry into the prediction: on sphere3's 8-node cut a 98 ms step among
   50 ms ones predicted 206 ms, and re-factoring looked cheap),
   with c the ms per S2 flop fitted on the last base where S2 grew (a prior
   until then, and within AUG_AUTO_CFLOP_MIN .. MAX), a_first + c (w_next - w_first) on a
   fresh base (the first steps of the bases before: their state is built
   from scratch, as this one's will be), 0 when no AMPS step was measured */
static double predict_ms(const aug_auto *a)
{
    if (a->on_base == 0) {
        if (!(a->a_first > 0)) return 0;
        double v = a->a_first + a->c_flop * (a->w_next - a->w_first);
        return v > 0 ? v : 0;
    }
    double grow = a->c_flop * (a->w_next - a->w_last), last = a->a_last;
    if (a->ls[0] >= 3) {
        double tr = a->trend0 + a->g * (a->on_base - 1 - AUG_AUTO_WARM);
        if (tr > 0 && tr < last) last = tr;
    }
    return last + (grow > 0 ? grow : 0);
}

/* The choice for the next step (paper 001 sec. 3.5: an AMPS step costs more
   as S2 and the memo grow with the update since the base; paper 000 sec.
   3.6: a re-factorization resets that growth, in the foreground or in a
   thread). With T the time of a re-factorization step (measured, else the
   prior), est the predicted time of the next AMPS step (predict_ms, from
   the S2 flops predict_flops), a_ref the first AMPS step on the base after
   its first AUG_AUTO_WARM (the warm-up), E = sum_j g (j - WARM) the time the
   growth has cost (g the least-squares slope of the steady steps' times)
   and R = T + the warm-up's excess over a_ref (measured on the bases
   before), the cost of a new base:
     - a background job running: AMPS;
     - a fresh base: re-factor again when est >= T (the first AMPS step on a
       new base would cost more than a re-factorization: the 2-D refined cut
       in long steps, re-factored every step; while est < 2 T, after
       AUG_AUTO_PROBE such steps in a row one AMPS step is measured, the
       interval doubling with each such probe), else AMPS (its first step
       measures the base);
     - est >= T: re-factor now (the step's S2 is predicted too dear before
       it is measured);
     - the warm-up: AMPS;
     - with a free core, E >= R / 4: AMPS, and a background job starts (it
       takes about T, the growth goes on meanwhile);
     - E >= R (the steps a new base would have saved outweigh it: for a_j
       growing linearly the optimum of the cycle cost (R + sum a_j) / j):
       re-factor now, unless the stream's length is known (left steps to
       come, this one included) and the left - 1 steps after this one,
       each cheaper by about g j on a new base (j steady steps on this
       one), save less than the re-factorization costs over this step's
       AMPS, R - est: then AMPS to the end (HORIZON; an online rule cannot
       see the end, and without it a re-factorization a few steps before
       it is paid and not recovered: sphere3's 8-node cut of bench/organs.sh
       re-factored at step 14 of 16);
     - else AMPS.
   With a free core and a known length a background job starts only if the
   steps left would outlast it (left - 1 AMPS steps take longer than T). */
int aug_auto_decide(aug_auto *a, int bg_running, int64_t s_step, int64_t left)
{
    double T = a->t_factor > 0 ? a->t_factor : a->t_prior, R = T + a->t_warm;
    a->want_bg = 0;
    a->est_factor = T;
    a->w_next = predict_flops(a, s_step);
    a->est_amps = predict_ms(a);
    if (bg_running) return pick(a, AUG_AUTO_AMPS, AUG_AUTO_BG_RUNNING);
    if (a->on_base == 0) {
        int dear = T > 0 && a->est_amps >= T;
        if (dear && (a->est_amps >= 2 * T || a->nsync_run < a->probe_every)) {
            a->nsync_run++;
            return pick(a, AUG_AUTO_REFACTOR, AUG_AUTO_FIRST_DEARER);
        }
        /* a probe doubles the interval to the next one; a first step
           predicted cheaper than T resets it */
        a->probe_every = dear && a->probe_every < 1024 ? 2 * a->probe_every : AUG_AUTO_PROBE;
        a->nsync_run = 0;
        return pick(a, AUG_AUTO_AMPS, AUG_AUTO_FIRST);
    }
    if (T > 0 && a->est_amps >= T) return pick(a, AUG_AUTO_REFACTOR, AUG_AUTO_STEP);
    if (a->on_base < AUG_AUTO_WARM) return pick(a, AUG_AUTO_AMPS, AUG_AUTO_FIRST);
    a->est_factor = R;
    if (a->bg_allowed && R > 0 && a->excess >= 0.25 * R) {
        if (left > 0 && !((double)(left - 1) * a->est_amps > T)) return pick(a, AUG_AUTO_AMPS, AUG_AUTO_HORIZON);
        a->want_bg = 1;
        return pick(a, AUG_AUTO_AMPS, AUG_AUTO_BG_START);
    }
    if (R > 0 && a->excess >= R) {
        double j = a->on_base - AUG_AUTO_WARM;
        if (left > 0 && !((double)(left - 1) * a->g * j >= R - a->est_amps))
            return pick(a, AUG_AUTO_AMPS, AUG_AUTO_HORIZON);
        return pick(a, AUG_AUTO_REFACTOR, AUG_AUTO_AMORTIZED);
    }
    return pick(a, AUG_AUTO_AMPS, AUG_AUTO_CHEAPER);
}

/* a running mean (the first value as it is) */
static double mean2(double old, double v) { return old > 0 ? 0.5 * (old + v) : v; }

/* the measured time ms of the step just taken with a->choice (refactor: the
   step that made the new base, AMPS: a step on the base, with the flops w
   of its S2 and S2's order na after it) */
void aug_auto_observe(aug_auto *a, double ms, double w, int64_t na)
{
    if (a->choice == AUG_AUTO_REFACTOR) {
        a->t_factor = mean2(a->t_factor, ms);
        aug_auto_rebased(a);
        return;
    }
    if (a->on_base == 0) {
        a->a1 = ms, a->w1 = w;
        a->a_first = mean2(a->a_first, ms);
        a->w_first = a->w_first > 0 ? 0.5 * (a->w_first + w) : w;
    } else if (w > 2 * a->w1 && w > a->w1) {
        /* S2 grew: the ms per flop from the first step on, within what a
           core's dense LU can take (the growth of the memo and the reach
           counts in it too) */
        double c = (ms - a->a1) / (w - a->w1);
        a->c_flop = c < AUG_AUTO_CFLOP_MIN ? AUG_AUTO_CFLOP_MIN : c > AUG_AUTO_CFLOP_MAX ? AUG_AUTO_CFLOP_MAX : c;
    }
    a->a_last = ms, a->w_last = w, a->na = na;
    if (a->on_base < AUG_AUTO_WARM) {
        a->warm_sum += ms;
    } else {
        /* E from the least-squares trend a_j = a_ref + g (j - WARM) of the
           steady steps (their noise cancels; a sum of a_j - min a_j would
           grow with it): sum_j g (j - WARM) */
        double j = a->on_base - AUG_AUTO_WARM;
        if (j == 0) a->a_ref = ms, a->t_warm = mean2(a->t_warm, a->warm_sum - AUG_AUTO_WARM * ms);
        a->ls[0] += 1, a->ls[1] += j, a->ls[2] += ms, a->ls[3] += j * j, a->ls[4] += j * ms;
        double den = a->ls[0] * a->ls[3] - a->ls[1] * a->ls[1];
        double g = a->ls[0] >= 3 && den > 0 ? (a->ls[0] * a->ls[4] - a->ls[1] * a->ls[2]) / den : 0;
        a->excess = g > 0 ? g * a->ls[1] : 0;
        a->g = g > 0 ? g : 0;
        a->trend0 = (a->ls[2] - a->g * a->ls[1]) / a->ls[0]; /* the intercept with that slope */
    }
    a->on_base++;
}

/* a new base (re-factored in the foreground or swapped in from the
   background): the growth starts again */
void aug_auto_rebased(aug_auto *a)
{
    a->nbase++;
    a->on_base = 0;
    a->na = 0;
    a->excess = a->warm_sum = a->g = a->trend0 = 0;
    a->a_ref = a->a_last = a->w_last = a->a1 = a->w1 = 0;
    memset(a->ls, 0, sizeof a->ls);
}
