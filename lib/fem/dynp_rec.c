/* Dynamics codec: DYNP, the integrator, time step, Rayleigh factors and mass
   kind of a dynamic stream, and the effective-matrix coefficients they give
   (formats/stream.md 6.6; thesis 003 sec. 3.4.1). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "aug_dyn.h"

const char *aug_integrator_name(int integrator)
{
    return integrator == AUG_INT_EULER ? "euler" : integrator == AUG_INT_NEWMARK ? "newmark" : "unknown";
}

/* coefficients of A = cM M + cK K (aug_dyn.h) */
int aug_dynp_set(aug_dynp *d, int integrator, int mass, double h, double alpha, double beta)
{
    memset(d, 0, sizeof *d);
    d->integrator = integrator, d->mass = mass, d->h = h, d->alpha = alpha, d->beta = beta;
    if ((integrator != AUG_INT_EULER && integrator != AUG_INT_NEWMARK) || (mass != 1 && mass != 2) ||
        !(h > 0 && h <= 1e6) || !(alpha >= 0 && alpha < HUGE_VAL) || !(beta >= 0 && beta < HUGE_VAL))
        return -1;
    double aD = integrator == AUG_INT_EULER ? 1.0 : 0.5, aK = integrator == AUG_INT_EULER ? 1.0 : 0.25;
    d->cM = 1 + aD * h * alpha;
    d->cK = aD * h * beta + aK * h * h;
    return isfinite(d->cM) && isfinite(d->cK) ? 0 : -1;
}

double aug_dynp_gamma(const aug_dynp *d) { return d->integrator == AUG_INT_EULER ? 1.0 : 0.5; }

void aug_dynp_velocity(const aug_dynp *d, const double *du, const double *v0, double *v1, int64_t n)
{
    if (d->integrator == AUG_INT_EULER)
        for (int64_t i = 0; i < n; i++) v1[i] = du[i] / d->h;
    else
        for (int64_t i = 0; i < n; i++) v1[i] = 2 * du[i] / d->h - v0[i];
}

int aug_write_dynp(aug_writer *w, const aug_dynp *d, aug_err *e)
{
    aug_buf b;
    aug_buf_init(&b);
    aug_buf_i32(&b, d->integrator);
    aug_buf_i32(&b, d->mass);
    aug_buf_f64(&b, d->h);
    aug_buf_f64(&b, d->alpha);
    aug_buf_f64(&b, d->beta);
    aug_buf_f64(&b, d->cM);
    aug_buf_f64(&b, d->cK);
    return aug_buf_write(w, "DYNP", AUG_NOSTEP, &b, e);
}

int aug_read_dynp(const aug_rec *rec, aug_dynp *d, aug_err *e)
{
    aug_err_clear(e);
    aug_cur c;
    aug_cur_init(&c, rec);
    int32_t in = aug_cur_i32(&c), ms = aug_cur_i32(&c);
    double h = aug_cur_f64(&c), al = aug_cur_f64(&c), be = aug_cur_f64(&c);
    double cM = aug_cur_f64(&c), cK = aug_cur_f64(&c);
    if (!c.ok || c.pos != c.len)
        return aug_err_set(e, AUG_EPAYLOAD, rec->index, rec->type, "payload is not 48 bytes");
    if (aug_dynp_set(d, in, ms, h, al, be))
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                           "integrator %d, mass %d, h %g, alpha %g, beta %g out of range", (int)in,
                           (int)ms, h, al, be);
    if (!(fabs(cM - d->cM) <= 1e-14 * d->cM && fabs(cK - d->cK) <= 1e-14 * d->cK))
        return aug_err_set(e, AUG_EDATA, rec->index, rec->type,
                           "cM %.17g, cK %.17g are not the integrator's (%.17g, %.17g)", cM, cK,
                           d->cM, d->cK);
    return 0;
}

static int dynp_check(const aug_rec *rec, aug_err *e)
{
    aug_dynp d;
    return aug_read_dynp(rec, &d, e);
}

static int dynp_dump(FILE *o, struct aug_mesh *m, const aug_rec *rec, aug_err *e)
{
    (void)m;
    aug_dynp d;
    if (aug_read_dynp(rec, &d, e)) return e->code;
    aug_txt_header(o, rec);
    fprintf(o, "  integrator %d (%s)\n  mass %d (%s)\n  h ", d.integrator,
            aug_integrator_name(d.integrator), d.mass, d.mass == 1 ? "consistent" : "lumped");
    aug_txt_f(o, d.h);
    fprintf(o, "\n  alpha ");
    aug_txt_f(o, d.alpha);
    fprintf(o, "\n  beta ");
    aug_txt_f(o, d.beta);
    fprintf(o, "\n  cM ");
    aug_txt_f(o, d.cM);
    fprintf(o, "\n  cK ");
    aug_txt_f(o, d.cK);
    fprintf(o, "\n");
    return 0;
}

const aug_codec aug_codec_dynp = {"lib/fem/dynp_rec.c", dynp_check, dynp_dump};
