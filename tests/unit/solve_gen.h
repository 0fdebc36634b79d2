/* Test generator for the solver tests: a structured tet grid with linear
   elasticity, node-duplication cuts, added constraints and load changes; the
   cut matrix K_t is assembled from scratch (dense) every step and the UPDT of
   the step is the exact difference K_{t-1} -> K_t (formats/stream.md 7.2). */
#ifndef SOLVE_GEN_H
#define SOLVE_GEN_H
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"

typedef struct gen {
    int nx, ny, nz;
    int64_t nn, nn0, ne;
    double *x;          /* nn*3 */
    int32_t *conn;      /* ne*4 */
    double Emod, nu;
    double *estiff;     /* ne*144 (element stiffness, fixed per element) */
    int64_t nfree0;
    int32_t *map0;      /* nn0*3 -> free index or -1 (fixed at z = 0) */
    int64_t n;          /* order of K_t */
    double *K, *f;      /* dense K_t (n x n), f_t */
    double *loads;      /* nodal loads over matrix indices (before lifting) */
    int32_t *cons;      /* cons[i] = 1: index i constrained (identity row) */
    double *cval;
    unsigned char *cut; /* per original node: already duplicated */
    int64_t ncap;
    double stiff_jump;  /* material factor for elements with centroid z > half (1: none) */
} gen;

static int64_t gen_index(const gen *g, int64_t node, int c)
{
    if (node < g->nn0) return g->map0[node * 3 + c];
    return g->nfree0 + (node - g->nn0) * 3 + c;
}

/* tet4 stiffness, column-major 12x12 */
static void gen_tet_stiffness(const double *X, double Emod, double nu, double *Ke)
{
    double J[9], Ji[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) J[r * 3 + c] = X[(c + 1) * 3 + r] - X[r];
    double det = J[0] * (J[4] * J[8] - J[5] * J[7]) - J[1] * (J[3] * J[8] - J[5] * J[6]) +
                 J[2] * (J[3] * J[7] - J[4] * J[6]);
    Ji[0] = (J[4] * J[8] - J[5] * J[7]) / det;
    Ji[1] = (J[2] * J[7] - J[1] * J[8]) / det;
    Ji[2] = (J[1] * J[5] - J[2] * J[4]) / det;
    Ji[3] = (J[5] * J[6] - J[3] * J[8]) / det;
    Ji[4] = (J[0] * J[8] - J[2] * J[6]) / det;
    Ji[5] = (J[2] * J[3] - J[0] * J[5]) / det;
    Ji[6] = (J[3] * J[7] - J[4] * J[6]) / det;
    Ji[7] = (J[1] * J[6] - J[0] * J[7]) / det;
    Ji[8] = (J[0] * J[4] - J[1] * J[3]) / det;
    /* grad N_a (rows of Ji' applied to reference gradients) */
    double dN[4][3], ref[4][3] = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 4; a++)
        for (int d = 0; d < 3; d++)
            dN[a][d] = ref[a][0] * Ji[0 * 3 + d] + ref[a][1] * Ji[1 * 3 + d] + ref[a][2] * Ji[2 * 3 + d];
    double vol = fabs(det) / 6, lam = Emod * nu / ((1 + nu) * (1 - 2 * nu)), mu = Emod / (2 * (1 + nu));
    double B[6][12];
    memset(B, 0, sizeof B);
    for (int a = 0; a < 4; a++) {
        B[0][a * 3] = dN[a][0], B[1][a * 3 + 1] = dN[a][1], B[2][a * 3 + 2] = dN[a][2];
        B[3][a * 3] = dN[a][1], B[3][a * 3 + 1] = dN[a][0];
        B[4][a * 3 + 1] = dN[a][2], B[4][a * 3 + 2] = dN[a][1];
        B[5][a * 3] = dN[a][2], B[5][a * 3 + 2] = dN[a][0];
    }
    double D[6][6];
    memset(D, 0, sizeof D);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) D[i][j] = lam;
        D[i][i] = lam + 2 * mu;
        D[i + 3][i + 3] = mu;
    }
    for (int i = 0; i < 12; i++)
        for (int j = 0; j < 12; j++) {
            double s = 0;
            for (int p = 0; p < 6; p++)
                for (int q = 0; q < 6; q++) s += B[p][i] * D[p][q] * B[q][j];
            Ke[i + 12 * j] = vol * s;
        }
}

static void gen_free(gen *g)
{
    free(g->x), free(g->conn), free(g->estiff), free(g->map0), free(g->K), free(g->f);
    free(g->loads), free(g->cons), free(g->cval), free(g->cut);
    memset(g, 0, sizeof *g);
}

static void gen_reserve(gen *g, int64_t n)
{
    if (n <= g->ncap) return;
    int64_t nc = n * 2;
    double *K = calloc((size_t)(nc * nc), sizeof *K);
    if (g->K)
        for (int64_t j = 0; j < g->n; j++) memcpy(K + j * nc, g->K + j * g->ncap, (size_t)g->n * sizeof *K);
    free(g->K);
    g->K = K;
    g->f = realloc(g->f, (size_t)nc * sizeof *g->f);
    g->loads = realloc(g->loads, (size_t)nc * sizeof *g->loads);
    g->cons = realloc(g->cons, (size_t)nc * sizeof *g->cons);
    g->cval = realloc(g->cval, (size_t)nc * sizeof *g->cval);
    for (int64_t i = g->ncap; i < nc; i++) g->loads[i] = 0, g->cons[i] = 0, g->cval[i] = 0;
    g->ncap = nc;
}

/* K_t, f_t from scratch: elasticity over the current mesh, then each added
   constraint j: row/column j = e_j, f_j = value, its coupling lifted into f */
static void gen_assemble(gen *g)
{
    int64_t n = g->n, ld = g->ncap;
    for (int64_t j = 0; j < n; j++) memset(g->K + j * ld, 0, (size_t)n * sizeof(double));
    for (int64_t el = 0; el < g->ne; el++) {
        int64_t id[12];
        for (int a = 0; a < 4; a++)
            for (int c = 0; c < 3; c++) id[a * 3 + c] = gen_index(g, g->conn[el * 4 + a], c);
        const double *Ke = g->estiff + el * 144;
        for (int j = 0; j < 12; j++) {
            if (id[j] < 0) continue;
            for (int i = 0; i < 12; i++)
                if (id[i] >= 0) g->K[id[i] + id[j] * ld] += Ke[i + 12 * j];
        }
    }
    for (int64_t i = 0; i < n; i++) g->f[i] = g->loads[i];
    for (int64_t j = 0; j < n; j++) {
        if (!g->cons[j]) continue;
        for (int64_t i = 0; i < n; i++)
            if (!g->cons[i]) g->f[i] -= g->K[i + j * ld] * g->cval[j];
    }
    for (int64_t j = 0; j < n; j++) {
        if (!g->cons[j]) continue;
        for (int64_t i = 0; i < n; i++) g->K[i + j * ld] = g->K[j + i * ld] = 0;
        g->K[j + j * ld] = 1;
        g->f[j] = g->cval[j];
    }
}

/* nx x ny x nz unit cells of size h, 6 tets per cell, fixed at z = 0 */
static void gen_init(gen *g, int nx, int ny, int nz, double stiff_jump, gsl_rng *rng)
{
    memset(g, 0, sizeof *g);
    g->nx = nx, g->ny = ny, g->nz = nz;
    g->Emod = 1.0, g->nu = 0.3, g->stiff_jump = stiff_jump;
    g->nn = g->nn0 = (int64_t)(nx + 1) * (ny + 1) * (nz + 1);
    g->x = malloc((size_t)g->nn * 3 * sizeof *g->x);
    for (int k = 0; k <= nz; k++)
        for (int j = 0; j <= ny; j++)
            for (int i = 0; i <= nx; i++) {
                int64_t v = ((int64_t)k * (ny + 1) + j) * (nx + 1) + i;
                g->x[v * 3] = i, g->x[v * 3 + 1] = j, g->x[v * 3 + 2] = k;
            }
    g->ne = (int64_t)nx * ny * nz * 6;
    g->conn = malloc((size_t)g->ne * 4 * sizeof *g->conn);
    static const int tets[6][4] = {{0, 1, 3, 7}, {0, 1, 7, 5}, {0, 5, 7, 4}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}};
    int64_t e = 0;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                int64_t c[8];
                for (int b = 0; b < 8; b++)
                    c[b] = ((int64_t)(k + (b >> 2 & 1)) * (ny + 1) + (j + (b >> 1 & 1))) * (nx + 1) + i + (b & 1);
                for (int t = 0; t < 6; t++, e++)
                    for (int a = 0; a < 4; a++) g->conn[e * 4 + a] = (int32_t)c[tets[t][a]];
            }
    g->estiff = malloc((size_t)g->ne * 144 * sizeof *g->estiff);
    for (e = 0; e < g->ne; e++) {
        double X[12], zc = 0;
        for (int a = 0; a < 4; a++) {
            memcpy(X + a * 3, g->x + (int64_t)g->conn[e * 4 + a] * 3, 3 * sizeof(double));
            zc += X[a * 3 + 2] / 4;
        }
        double Em = zc > nz / 2.0 ? g->Emod * stiff_jump : g->Emod;
        gen_tet_stiffness(X, Em, g->nu, g->estiff + e * 144);
    }
    g->map0 = malloc((size_t)g->nn0 * 3 * sizeof *g->map0);
    g->nfree0 = 0;
    for (int64_t v = 0; v < g->nn0; v++)
        for (int c = 0; c < 3; c++) g->map0[v * 3 + c] = g->x[v * 3 + 2] == 0 ? -1 : (int32_t)g->nfree0++;
    g->n = g->nfree0;
    gen_reserve(g, g->n + 64);
    for (int64_t i = 0; i < g->n; i++) g->loads[i] = 0;
    /* loads on the top face plus a little noise everywhere */
    for (int64_t v = 0; v < g->nn0; v++)
        for (int c = 0; c < 3; c++) {
            int64_t id = g->map0[v * 3 + c];
            if (id < 0) continue;
            g->loads[id] = 0.01 * (gsl_rng_uniform(rng) - 0.5);
            if (g->x[v * 3 + 2] == nz) g->loads[id] += c == 0 ? 0.1 : 0.02;
        }
    g->cut = calloc((size_t)g->nn0, 1);
    gen_assemble(g);
}

/* CHOLMOD copies of K_t (upper, stype 1) */
static cholmod_sparse *gen_sparse(const gen *g, cholmod_common *cm)
{
    int64_t n = g->n, nz = 0, ld = g->ncap;
    for (int64_t j = 0; j < n; j++)
        for (int64_t i = 0; i <= j; i++) nz += g->K[i + j * ld] != 0;
    cholmod_sparse *A = cholmod_allocate_sparse((size_t)n, (size_t)n, (size_t)nz, 1, 1, 1, CHOLMOD_REAL, cm);
    int *Ap = A->p, *Ai = A->i;
    double *Ax = A->x;
    nz = 0;
    for (int64_t j = 0; j < n; j++) {
        Ap[j] = (int)nz;
        for (int64_t i = 0; i <= j; i++)
            if (g->K[i + j * ld] != 0) Ai[nz] = (int)i, Ax[nz++] = g->K[i + j * ld];
    }
    Ap[n] = (int)nz;
    return A;
}

/* reference: fresh CHOLMOD solve of K_t (NULL if not positive definite) */
static double *gen_direct(const gen *g, cholmod_common *cm)
{
    cholmod_sparse *A = gen_sparse(g, cm);
    cholmod_factor *L = cholmod_analyze(A, cm);
    int ok = L && cholmod_factorize(A, L, cm) && L->minor == L->n;
    double *x = NULL;
    if (ok) {
        cholmod_dense *b = cholmod_zeros((size_t)g->n, 1, CHOLMOD_REAL, cm);
        memcpy(b->x, g->f, (size_t)g->n * sizeof(double));
        cholmod_dense *X = cholmod_solve(CHOLMOD_A, L, b, cm);
        x = malloc((size_t)g->n * sizeof *x);
        memcpy(x, X->x, (size_t)g->n * sizeof *x);
        cholmod_free_dense(&X, cm);
        cholmod_free_dense(&b, cm);
    }
    cholmod_free_factor(&L, cm);
    cholmod_free_sparse(&A, cm);
    return x;
}

/* r = f - K_t x with the dense K_t, column by column (contiguous) */
static inline void gen_residual(const gen *g, const double *x, double *r)
{
    memcpy(r, g->f, (size_t)g->n * sizeof *r);
    for (int64_t j = 0; j < g->n; j++) {
        const double *kj = g->K + j * g->ncap;
        for (int64_t i = 0; i < g->n; i++) r[i] -= kj[i] * x[j];
    }
}

/* the UPDT of the change (Kold, fold, nold) -> (g->K, g->f, g->n) */
static void gen_diff(const gen *g, const double *Kold, int64_t ldo, const double *fold, int64_t nold,
                     int32_t step, aug_update *u)
{
    int64_t ld = g->ncap, n = g->n, k = n - nold, m = 0;
    int32_t *H = malloc((size_t)(nold + 1) * sizeof *H);
    char *ch = calloc((size_t)(nold + 1), 1);
    /* rows that changed, read column by column (contiguous) */
    for (int64_t j = 0; j < n; j++) {
        const double *kt = g->K + j * ld, *ko = j < nold ? Kold + j * ldo : NULL;
        for (int64_t i = 0; i < nold; i++) ch[i] |= kt[i] != (ko ? ko[i] : 0);
    }
    for (int64_t i = 0; i < nold; i++)
        if (ch[i] || fold[i] != g->f[i]) H[m++] = (int32_t)i;
    free(ch);
    int64_t s = m + k;
    aug_update_init(u);
    u->step = step, u->m = (int32_t)m, u->k = (int32_t)k;
    u->H = H;
    u->E = calloc((size_t)(s * s + 1), sizeof *u->E);
    u->df = calloc((size_t)(s + 1), sizeof *u->df);
    for (int64_t b = 0; b < s; b++) {
        int64_t jb = b < m ? H[b] : nold + (b - m);
        for (int64_t a = 0; a < s; a++) {
            int64_t ia = a < m ? H[a] : nold + (a - m);
            double kbar = (a < m && b < m) ? Kold[ia + jb * ldo] : 0;
            u->E[a + b * s] = kbar - g->K[ia + jb * ld]; /* E_nn = -K_t[new,new] */
        }
        u->df[b] = g->f[jb] - (b < m ? fold[jb] : 0);
    }
}

/* save K_t, f_t, n before a change */
typedef struct gen_snap { double *K, *f; int64_t n, ld; } gen_snap;
static void gen_snapshot(const gen *g, gen_snap *s)
{
    s->n = g->n, s->ld = g->n ? g->n : 1;
    s->K = malloc((size_t)(s->ld * s->ld) * sizeof *s->K);
    s->f = malloc((size_t)s->ld * sizeof *s->f);
    for (int64_t j = 0; j < g->n; j++) memcpy(s->K + j * s->ld, g->K + j * g->ncap, (size_t)g->n * sizeof(double));
    memcpy(s->f, g->f, (size_t)g->n * sizeof(double));
}
static void gen_snap_free(gen_snap *s) { free(s->K), free(s->f); }

/* duplicate node p: elements on the x > xc side get a copy of p.
   orphan = 1: every element moves (leaves p without elements: singular). */
static int gen_cut_node(gen *g, int64_t p, double xc, int orphan)
{
    int64_t q = g->nn;
    int any_plus = 0, any_minus = 0;
    for (int64_t e = 0; e < g->ne; e++) {
        int has = 0;
        double cx = 0;
        for (int a = 0; a < 4; a++) {
            has |= g->conn[e * 4 + a] == p;
            cx += g->x[(int64_t)g->conn[e * 4 + a] * 3] / 4;
        }
        if (!has) continue;
        if (cx > xc) any_plus = 1; else any_minus = 1;
    }
    if (!orphan && !(any_plus && any_minus)) return 0;
    g->x = realloc(g->x, (size_t)(g->nn + 1) * 3 * sizeof *g->x);
    memcpy(g->x + q * 3, g->x + p * 3, 3 * sizeof(double));
    g->nn++;
    gen_reserve(g, g->n + 3);
    for (int c = 0; c < 3; c++) {
        int64_t ip = gen_index(g, p, c), iq = g->n + c;
        g->loads[iq] = 0;
        g->cons[iq] = ip >= 0 && g->cons[ip];
        g->cval[iq] = ip >= 0 ? g->cval[ip] : 0;
        if (ip < 0) g->cons[iq] = 1, g->cval[iq] = 0; /* parent fixed: identity row */
    }
    g->n += 3;
    for (int64_t e = 0; e < g->ne; e++) {
        double cx = 0;
        int at = -1;
        for (int a = 0; a < 4; a++) {
            if (g->conn[e * 4 + a] == p) at = a;
            cx += g->x[(int64_t)g->conn[e * 4 + a] * 3] / 4;
        }
        if (at >= 0 && (orphan || cx > xc)) g->conn[e * 4 + at] = (int32_t)q;
    }
    if (p < g->nn0) g->cut[p] = 1;
    return 1;
}
#endif
