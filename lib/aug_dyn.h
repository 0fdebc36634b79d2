/* augcut dynamics parameters: the implicit integrator of M u'' + D u' + K u = f
   with Rayleigh damping D = alpha M + beta K (thesis 003 sec. 3.4.1; paper 004
   eq. 1), the effective matrix A = c_M M + c_K K it factors, and its record
   DYNP (formats/stream.md 6.6). */
#ifndef AUG_DYN_H
#define AUG_DYN_H

#include "aug_stream.h"

enum { AUG_INT_EULER = 0, AUG_INT_NEWMARK = 1 };

/* One time step h of either integrator in increment form, du = u1 - u0:
     A du = h M v0 + gamma h^2 (f - K u0)
   backward Euler:   A = M + h D + h^2 K,          gamma = 1,   v1 = du / h
   Newmark (beta 1/4, gamma 1/2, the trapezoidal rule):
                     A = M + (h/2) D + (h^2/4) K,  gamma = 1/2, v1 = 2 du / h - v0
   so A = c_M M + c_K K with c_M = 1 + a_D h alpha, c_K = a_D h beta + a_K h^2,
   (a_D, a_K) = (1, 1) for Euler and (1/2, 1/4) for Newmark. */
typedef struct aug_dynp {
    int integrator;      /* AUG_INT_* */
    int mass;            /* KMAT kind of M: 1 consistent, 2 row-sum lumped */
    double h, alpha, beta;
    double cM, cK;       /* A = cM M + cK K */
} aug_dynp;

/* Fill cM and cK from the others; -1 when a value is out of range (h in
   (0, 1e6], alpha and beta >= 0 and finite, integrator and mass known). */
int aug_dynp_set(aug_dynp *d, int integrator, int mass, double h, double alpha, double beta);
/* gamma of the right-hand side above */
double aug_dynp_gamma(const aug_dynp *d);
/* v1 from du and v0 (length n) */
void aug_dynp_velocity(const aug_dynp *d, const double *du, const double *v0, double *v1,
                       int64_t n);
const char *aug_integrator_name(int integrator);

/* DYNP codec (lib/fem/dynp_rec.c): i32 integrator, i32 mass, f64 h, alpha, beta,
   cM, cK; the read checks ranges and that cM, cK are those of the rest. */
int aug_write_dynp(aug_writer *w, const aug_dynp *d, aug_err *e);
int aug_read_dynp(const aug_rec *rec, aug_dynp *d, aug_err *e);

#endif
