/* AMPS steps 3 and 5: the Schur complement S2 = I - Gbar Ebar of eq. 3.21 on the
   active positions, LU-factored with LAPACK (paper 001 sec. 3.2, 3.4). */
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

void aug_schur_init(aug_schur *s) { memset(s, 0, sizeof *s); }

void aug_schur_free(aug_schur *s)
{
    free(s->A);
    free(s->act);
    free(s->S2);
    free(s->ipiv);
    free(s->Ga);
    free(s->sr);
    memset(s, 0, sizeof *s);
}

/* positions whose Ebar column became nonzero join A (in activation order);
   a position with Ebar(:,p) = 0 has S2(:,p) = e_p and decouples (sec. 3.4) */
static int activate(aug_schur *s, const aug_cum *c)
{
    if (s->pcap < c->cap) {
        unsigned char *a = aug_realloc(s->act, (size_t)c->cap);
        if (!a) return -1;
        memset(a + s->pcap, 0, (size_t)(c->cap - s->pcap));
        s->act = a;
        s->pcap = c->cap;
    }
    for (int64_t p = 0; p < c->ns; p++) {
        if (s->act[p]) continue;
        const double *Ep = c->E + p * c->cap;
        int64_t i = 0;
        while (i < c->ns && Ep[i] == 0) i++;
        if (i == c->ns) continue;
        if (s->na == s->acap) {
            int64_t nc = s->acap ? 2 * s->acap : 64;
            int32_t *A = aug_realloc(s->A, (size_t)nc * sizeof *A);
            if (!A) return -1;
            s->A = A;
            s->acap = nc;
        }
        s->A[s->na++] = (int32_t)p;
        s->act[p] = 1;
    }
    return 0;
}

int aug_schur_factor(aug_schur *s, const aug_memo *M, const aug_cum *c, double rcond_min,
                     aug_err *e)
{
    s->singular = 0;
    s->rcond = 1;
    s->detsign = 1;
    if (activate(s, c)) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (S2)");
    int64_t na = s->na;
    if (na == 0) return 0;
    if (s->scap < na) {
        free(s->S2), free(s->Ga), free(s->ipiv);
        s->S2 = aug_malloc((size_t)na * (size_t)na * sizeof *s->S2);
        s->Ga = aug_malloc((size_t)na * (size_t)na * sizeof *s->Ga);
        s->ipiv = aug_malloc((size_t)na * sizeof *s->ipiv);
        free(s->sr);
        s->sr = aug_malloc((size_t)na * 2 * sizeof *s->sr);
        s->scap = s->S2 && s->Ga && s->ipiv && s->sr ? na : 0;
        if (!s->scap) return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (S2 %lld)", (long long)na);
    }
    /* Gbar_AA = blkdiag(H'K^-1H, I) restricted to A */
    double *Ga = s->Ga, *S2 = s->S2;
    for (int64_t bq = 0; bq < na; bq++) {
        int32_t pb = s->A[bq];
        int ob = c->S[pb] < c->nb;
        const double *Gb = ob ? M->G + (int64_t)M->cpos[pb] * M->mcap : NULL;
        for (int64_t aq = 0; aq < na; aq++) {
            int32_t pa = s->A[aq];
            int oa = c->S[pa] < c->nb;
            Ga[aq + bq * na] = oa && ob ? Gb[M->cpos[pa]] : (!oa && !ob && pa == pb);
        }
    }
    /* S2 = I - Gbar_AA Ebar_AA, Ebar taken column by column over its nonzeros */
    s->nnzE = 0;
    for (int64_t bq = 0; bq < na; bq++) {
        double *S2b = S2 + bq * na;
        for (int64_t i = 0; i < na; i++) S2b[i] = 0;
        S2b[bq] = 1;
        const double *Eb = c->E + (int64_t)s->A[bq] * c->cap;
        for (int64_t cq = 0; cq < na; cq++) {
            double ecb = Eb[s->A[cq]];
            if (ecb == 0) continue;
            s->nnzE++;
            const double *Gc = Ga + cq * na;
            for (int64_t i = 0; i < na; i++) S2b[i] -= Gc[i] * ecb;
        }
    }
    double anorm = 0;
    for (int64_t bq = 0; bq < na; bq++) {
        double cs = 0;
        for (int64_t i = 0; i < na; i++) cs += fabs(S2[i + bq * na]);
        if (cs > anorm) anorm = cs;
    }
    lapack_int info = LAPACKE_dgetrf(LAPACK_COL_MAJOR, (lapack_int)na, (lapack_int)na, S2,
                                     (lapack_int)na, s->ipiv);
    if (info < 0) return aug_err_set(e, AUG_EUSAGE, -1, "UPDT", "dgetrf: argument %d", (int)-info);
    if (info > 0) {
        s->singular = 1;
        s->rcond = 0;
        return 0;
    }
    double rc = 0;
    LAPACKE_dgecon(LAPACK_COL_MAJOR, '1', (lapack_int)na, S2, (lapack_int)na, anorm, &rc);
    s->rcond = rc;
    int sign = 1;
    for (int64_t i = 0; i < na; i++) {
        if (S2[i + i * na] < 0) sign = -sign;
        if (s->ipiv[i] != i + 1) sign = -sign;
    }
    s->detsign = sign;
    /* det S2 = det Gbar det M (M: Schur complement of K_t on A, SPD iff K_t is) */
    if (rc < rcond_min || sign < 0) s->singular = 1;
    return 0;
}

/* x := S2^-1 x with the LU factors */
void aug_schur_solve(const aug_schur *s, double *x)
{
    int64_t na = s->na;
    if (na == 0) return;
    LAPACKE_dgetrs(LAPACK_COL_MAJOR, 'N', (lapack_int)na, 1, s->S2, (lapack_int)na, s->ipiv, x,
                   (lapack_int)na);
}
