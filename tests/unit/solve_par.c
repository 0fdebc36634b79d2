/* The two-core supernodal solves (lib/solve/par_*.c) on a factored 3-D
   27-point grid matrix with three DOFs per node: the split is a partition
   of the supernodes whose bins share no ancestor-descendant pair, and
   Ls^-T x (the back-substitution of an AMPS step) on two and three threads
   equals cholmod_solve2 bitwise, Ls^-1 x and K^-1 b to 1e-14 (and are
   repeatable bitwise), with OpenBLAS at one thread or two; K x = b holds
   to rounding. */
#include <gsl/gsl_rng.h>
#include <string.h>
#include "t.h"
#include "aug_par.h"
#include "aug_fem.h"

extern void openblas_set_num_threads(int);

static cholmod_common cm;

enum { G = 16 }; /* G^3 nodes, 3 DOFs each */

/* K = Lap_w (x) M + 1e-3 I: Lap_w the Laplacian of the 27-point grid graph
   with random positive weights, M a fixed SPD 3x3 (upper part, stype 1) */
static cholmod_sparse *grid_matrix(gsl_rng *r)
{
    int64_t nn = (int64_t)G * G * G, n = 3 * nn;
    static const double M[3][3] = {{2, 0.5, 0.2}, {0.5, 1.5, 0.3}, {0.2, 0.3, 1}};
    cholmod_triplet *T = cholmod_allocate_triplet((size_t)n, (size_t)n, (size_t)(nn * 27 * 9), 1, CHOLMOD_REAL, &cm);
    int *Ti = T->i, *Tj = T->j;
    double *Tx = T->x, *deg = calloc((size_t)nn, sizeof *deg);
    size_t k = 0;
    for (int z = 0; z < G; z++)
        for (int y = 0; y < G; y++)
            for (int x = 0; x < G; x++) {
                int64_t u = ((int64_t)z * G + y) * G + x;
                for (int dz = -1; dz <= 1; dz++)
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            int X = x + dx, Y = y + dy, Z = z + dz;
                            if (X < 0 || Y < 0 || Z < 0 || X >= G || Y >= G || Z >= G) continue;
                            int64_t v = ((int64_t)Z * G + Y) * G + X;
                            if (v <= u) continue;
                            double w = 0.5 + gsl_rng_uniform(r);
                            deg[u] += w, deg[v] += w;
                            for (int a = 0; a < 3; a++)
                                for (int b = 0; b < 3; b++)
                                    Ti[k] = (int)(3 * u + a), Tj[k] = (int)(3 * v + b), Tx[k++] = -w * M[a][b];
                        }
            }
    for (int64_t u = 0; u < nn; u++)
        for (int a = 0; a < 3; a++)
            for (int b = a; b < 3; b++)
                Ti[k] = (int)(3 * u + a), Tj[k] = (int)(3 * u + b), Tx[k++] = deg[u] * M[a][b] + (a == b ? 1e-3 : 0);
    T->nnz = k;
    /* the lower couplings (v > u) are stored at (3u+a, 3v+b): upper, as stype 1 */
    cholmod_sparse *K = cholmod_triplet_to_sparse(T, 0, &cm);
    cholmod_free_triplet(&T, &cm);
    free(deg);
    return K;
}

typedef struct fixture {
    gsl_rng *r;
    cholmod_sparse *K;
    cholmod_factor *L; /* supernodal */
    aug_par_plan *pl;
    int64_t n;
} fixture;

static void fix_open(fixture *f)
{
    f->r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(f->r, 15);
    f->K = grid_matrix(f->r);
    cm.supernodal = CHOLMOD_SUPERNODAL;
    f->L = cholmod_analyze(f->K, &cm);
    cholmod_factorize(f->K, f->L, &cm);
    cm.supernodal = CHOLMOD_AUTO;
    f->n = (int64_t)f->K->nrow;
    T_CHECK(f->L->is_super && f->L->minor == f->L->n, "supernodal factor");
    f->pl = aug_par_plan_new(f->L);
    T_CHECK(f->pl != NULL, "no split of %d supernodes", (int)f->L->nsuper);
}

static void fix_close(fixture *f)
{
    aug_par_plan_free(f->pl);
    cholmod_free_factor(&f->L, &cm);
    cholmod_free_sparse(&f->K, &cm);
    gsl_rng_free(f->r);
}

static double *random_vec(gsl_rng *r, int64_t n)
{
    double *x = malloc((size_t)n * sizeof *x);
    for (int64_t i = 0; i < n; i++) x[i] = gsl_rng_uniform(r) - 0.5;
    return x;
}

/* cholmod_solve2 of sys on b: the serial reference */
static double *cholmod_ref(fixture *f, int sys, const double *b)
{
    cholmod_dense B = {0}, *X = NULL, *Y = NULL, *E = NULL;
    B.nrow = B.d = B.nzmax = (size_t)f->n, B.ncol = 1;
    B.x = (void *)b, B.xtype = CHOLMOD_REAL, B.dtype = CHOLMOD_DOUBLE;
    int ok = cholmod_solve2(sys, f->L, &B, NULL, &X, NULL, &Y, &E, &cm);
    T_CHECK(ok, "cholmod_solve2: status %d", cm.status);
    double *x = calloc((size_t)f->n, sizeof *x);
    if (ok) memcpy(x, X->x, (size_t)f->n * sizeof *x);
    cholmod_free_dense(&X, &cm), cholmod_free_dense(&Y, &cm), cholmod_free_dense(&E, &cm);
    return x;
}

static int64_t ndiff(const double *a, const double *b, int64_t n)
{
    int64_t d = 0;
    for (int64_t i = 0; i < n; i++) d += memcmp(a + i, b + i, sizeof *a) != 0;
    return d;
}

/* top, bin 0 and bin 1 partition the supernodes, each list ascending; the
   ancestors of a bin's supernode are in that bin or in top, those of a top
   one in top; so for the tasks; the weights add up and the split gains */
static void plan_is_a_split(void)
{
    fixture f = {0};
    fix_open(&f);
    if (!f.pl) return fix_close(&f);
    const cholmod_factor *L = f.L;
    int64_t ns = (int64_t)L->nsuper;
    const int *sup = L->super, *pi = L->pi, *rows = L->s;
    int *lab = malloc((size_t)ns * sizeof *lab), *sof = malloc((size_t)f.n * sizeof *sof);
    for (int64_t s = 0; s < ns; s++) lab[s] = -1;
    for (int64_t s = 0; s < ns; s++)
        for (int j = sup[s]; j < sup[s + 1]; j++) sof[j] = (int)s;
    const int32_t *lists[3] = {f.pl->bin[0], f.pl->bin[1], f.pl->top};
    int64_t lens[3] = {f.pl->nbin[0], f.pl->nbin[1], f.pl->ntop};
    double wsum = 0;
    for (int l = 0; l < 3; l++)
        for (int64_t k = 0; k < lens[l]; k++) {
            int32_t s = lists[l][k];
            T_CHECK(s >= 0 && s < ns && lab[s] < 0, "supernode %d listed twice", (int)s);
            T_CHECK(k == 0 || lists[l][k - 1] < s, "list %d not ascending", l);
            if (s >= 0 && s < ns) lab[s] = l;
        }
    for (int64_t s = 0; s < ns; s++) {
        T_CHECK(lab[s] >= 0, "supernode %d in no set", (int)s);
        int nscol = sup[s + 1] - sup[s], nsrow = pi[s + 1] - pi[s];
        wsum += (double)nsrow * nscol + (nsrow - nscol);
        for (int q = pi[s] + nscol; q < pi[s + 1]; q++) {
            int a = lab[sof[rows[q]]];
            T_CHECK(a == 2 || a == lab[s], "supernode %d (set %d) has an ancestor in set %d", (int)s, lab[s], a);
        }
    }
    /* the tasks: the supernodes below top, each once, ascending within a
       task, their ancestors in the same task or in top */
    int *task = malloc((size_t)ns * sizeof *task);
    for (int64_t s = 0; s < ns; s++) task[s] = -1;
    int64_t ntasked = 0;
    for (int k = 0; k < f.pl->ntask; k++)
        for (int64_t q = f.pl->task_p[k]; q < f.pl->task_p[k + 1]; q++) {
            int32_t s = f.pl->task_s[q];
            T_CHECK(s >= 0 && s < ns && task[s] < 0 && lab[s] != 2, "task %d: supernode %d", k, (int)s);
            T_CHECK(q == f.pl->task_p[k] || f.pl->task_s[q - 1] < s, "task %d not ascending", k);
            if (s >= 0 && s < ns) task[s] = k;
            ntasked++;
        }
    T_CHECK(ntasked == ns - f.pl->ntop, "%lld supernodes in tasks, %lld below top", (long long)ntasked,
            (long long)(ns - f.pl->ntop));
    for (int64_t s = 0; s < ns; s++) {
        if (task[s] < 0) continue;
        int nscol = sup[s + 1] - sup[s];
        for (int q = pi[s] + nscol; q < pi[s + 1]; q++) {
            int a = sof[rows[q]];
            T_CHECK(lab[a] == 2 || task[a] == task[s], "supernode %d (task %d): ancestor %d in task %d",
                    (int)s, task[s], a, task[a]);
        }
    }
    free(task);
    double w = f.pl->wtop + f.pl->wbin[0] + f.pl->wbin[1];
    T_CHECK(fabs(w - wsum) <= 1e-12 * wsum, "weights %g, supernodes %g", w, wsum);
    double cost = f.pl->wtop + fmax(f.pl->wbin[0], f.pl->wbin[1]);
    T_CHECK(cost <= 0.95 * wsum, "split cost %g of serial %g", cost, wsum);
    T_CHECK(f.pl->nbin[0] > 0 && f.pl->nbin[1] > 0, "an empty bin");
    printf("  split: %d supernodes, top %d (%.0f%%), %d tasks, bins %d / %d (%.0f%% / %.0f%%)\n", (int)ns,
           (int)f.pl->ntop, 100 * f.pl->wtop / wsum, (int)f.pl->ntask, (int)f.pl->nbin[0], (int)f.pl->nbin[1],
           100 * f.pl->wbin[0] / wsum, 100 * f.pl->wbin[1] / wsum);
    free(lab), free(sof);
    fix_close(&f);
}

/* max |a - b| / max |b| */
static double normdiff(const double *a, const double *b, int64_t n)
{
    double d = 0, m = 0;
    for (int64_t i = 0; i < n; i++) d = fmax(d, fabs(a[i] - b[i])), m = fmax(m, fabs(b[i]));
    return m > 0 ? d / m : d;
}

/* Ls^-T x: serial, 2 and 3 threads, 20 repetitions each, bitwise equal to
   cholmod_solve2's CHOLMOD_Lt; Ls^-1 x: serial bitwise CHOLMOD_L, on 2 and
   3 threads within 1e-14 of it (a top row's updates from the bins are added
   later, after a zero start) and bitwise the same on every repetition and
   thread count. The reference with one OpenBLAS thread (as --threads 1),
   the solves with OpenBLAS at nblas threads (--threads 2 sets 2; serial
   is then not bitwise CHOLMOD at 2 BLAS threads, so q = 0 is compared only
   when nblas is 1). */
static void solves_bitwise(int nblas)
{
    fixture f = {0};
    fix_open(&f);
    if (!f.pl) return fix_close(&f);
    aug_par *p2 = aug_par_new(2), *p3 = aug_par_new(3);
    T_CHECK(p2 && p3 && aug_par_nthreads(p2) == 2 && aug_par_nthreads(p3) == 3, "pools");
    T_CHECK(aug_par_new(1) == NULL, "a pool of one thread");
    double *b = random_vec(f.r, f.n), *x = malloc((size_t)f.n * sizeof *x);
    double *x2 = malloc((size_t)f.n * sizeof *x2);
    for (int sys = AUG_PAR_L; sys <= AUG_PAR_LT && p2 && p3; sys++) {
        openblas_set_num_threads(1); /* the reference: --threads 1 */
        double *ref = cholmod_ref(&f, sys == AUG_PAR_L ? CHOLMOD_L : CHOLMOD_Lt, b);
        openblas_set_num_threads(nblas);
        aug_par *ps[3] = {NULL, p2, p3};
        for (int q = 0; q < 3; q++)
            for (int rep = 0; rep < 20; rep++) {
                memcpy(x, b, (size_t)f.n * sizeof *x);
                T_CHECK(aug_par_super_solve(ps[q], f.pl, f.L, sys, x) == 0, "solve failed");
                int64_t d = ndiff(x, ref, f.n);
                if (q == 0 && nblas > 1) continue;
                if (sys == AUG_PAR_LT || q == 0) {
                    T_CHECK(d == 0, "sys %d, %d threads, rep %d: %lld of %lld entries differ from cholmod_solve2",
                            sys, q + 1, rep, (long long)d, (long long)f.n);
                    continue;
                }
                double nd = normdiff(x, ref, f.n);
                T_CHECK(nd <= 1e-14, "L, %d threads: %g from cholmod_solve2", q + 1, nd);
                if (q == 1 && rep == 0) memcpy(x2, x, (size_t)f.n * sizeof *x2);
                d = ndiff(x, x2, f.n);
                T_CHECK(d == 0, "L, %d threads, rep %d: %lld entries differ from the first", q + 1, rep, (long long)d);
            }
        free(ref);
    }
    openblas_set_num_threads(1);
    free(b), free(x), free(x2);
    aug_par_free(p2), aug_par_free(p3);
    fix_close(&f);
}
static void solves_bitwise_blas1(void) { solves_bitwise(1); }
static void solves_bitwise_blas2(void) { solves_bitwise(2); }

/* the fixture, a random right-hand side b, a base on a copy of its factor
   and a pool of two threads; 0, or -1 (checked, everything freed) */
static int base_open(fixture *f, double **b, aug_base **base, aug_par **p)
{
    fix_open(f);
    if (!f->pl) {
        fix_close(f);
        return -1;
    }
    aug_err e = {0};
    *b = random_vec(f->r, f->n);
    cholmod_factor *L0 = cholmod_copy_factor(f->L, &cm);
    *base = aug_base_new(L0, f->K, *b, -1, &cm, &e);
    *p = aug_par_new(2);
    if (*base) aug_base_split(*base);
    T_CHECK(*base && (*base)->Ls && (*base)->par_plan && *p, "base with Ls, split, pool: %s", e.msg);
    if (*base && (*base)->Ls && (*base)->par_plan && *p) return 0;
    aug_base_release(*base, &cm), aug_par_free(*p), free(*b);
    fix_close(f);
    return -1;
}

/* K^-1 b by aug_par_full_solve on a base: within 1e-14 of cholmod_solve2 CHOLMOD_A,
   and the residual of K x = b (computed with cholmod_sdmult, long double
   norms) at rounding; aug_par_ltsolve_all equals aug_ldl_ltsolve_all */
static void full_solve_and_base(void)
{
    fixture f = {0};
    double *b;
    aug_base *base;
    aug_par *p;
    if (base_open(&f, &b, &base, &p)) return;
    double *x = malloc((size_t)f.n * sizeof *x), *y = malloc((size_t)f.n * sizeof *y);
    T_CHECK(aug_par_full_solve(p, base, b, x) == 0, "full solve");
    T_CHECK(aug_par_full_solve(NULL, base, b, y) == 1, "no pool: not applicable");
    cholmod_dense B = {0}, *X = NULL, *Y = NULL, *E = NULL, R = {0};
    B.nrow = B.d = B.nzmax = (size_t)f.n, B.ncol = 1;
    B.x = b, B.xtype = CHOLMOD_REAL, B.dtype = CHOLMOD_DOUBLE;
    cholmod_solve2(CHOLMOD_A, base->Ls, &B, NULL, &X, NULL, &Y, &E, &cm);
    double nd = normdiff(x, X->x, f.n);
    T_CHECK(nd <= 1e-14, "full solve: %g from cholmod_solve2", nd);
    /* r = b - K x */
    double *r = malloc((size_t)f.n * sizeof *r);
    memcpy(r, b, (size_t)f.n * sizeof *r);
    R = B, R.x = r;
    cholmod_dense Xd = B;
    Xd.x = x;
    double mone[2] = {-1, 0}, one[2] = {1, 0};
    cholmod_sdmult(f.K, 0, mone, one, &Xd, &R, &cm);
    long double rn = 0, bn = 0;
    for (int64_t i = 0; i < f.n; i++) rn += (long double)r[i] * r[i], bn += (long double)b[i] * b[i];
    double rel = (double)sqrtl(rn / bn);
    T_CHECK(rel < 1e-12, "relres %g", rel);
    /* the AMPS wrapper: D^1/2 scaling, then Ls^-T */
    for (int64_t i = 0; i < f.n; i++) x[i] = y[i] = b[i];
    T_CHECK(aug_par_ltsolve_all(p, base, x) == 0, "ltsolve_all");
    T_CHECK(aug_ldl_ltsolve_all(base, y, &X, &Y, &E, &cm) == 0, "serial ltsolve_all");
    int64_t d = ndiff(x, y, f.n);
    T_CHECK(d == 0, "ltsolve_all: %lld entries differ", (long long)d);
    cholmod_free_dense(&X, &cm), cholmod_free_dense(&Y, &cm), cholmod_free_dense(&E, &cm);
    free(x), free(y), free(r), free(b);
    aug_par_free(p);
    aug_base_release(base, &cm);
    fix_close(&f);
}

/* The deferred back-substitution of AMPS's corrected field (amps_solve.c):
   L^-T y over an etree closure C (aug_ldl_ltsolve_closure_super), then the
   rest from y with x_C given (aug_ldl_closure_pre, aug_par_ltsolve_rest),
   equals one full L^-T y (aug_ldl_ltsolve_all) to 1e-13; with x_C the full
   solve's own values, the rest is the full solve's to 1e-13 too, and on
   two threads bitwise the serial rest. C: the closure of 40 random
   columns, of 1 column, and of none (the rest is then the whole solve,
   bitwise). pre counts each supernode's columns outside C. */
static void deferred_rest(void)
{
    fixture f = {0};
    double *b;
    aug_base *base;
    aug_par *p;
    if (base_open(&f, &b, &base, &p)) return;
    int64_t n = f.n;
    double *y = random_vec(f.r, n), *ref = malloc((size_t)n * sizeof *ref);
    double *x = malloc((size_t)n * sizeof *x), *x2 = malloc((size_t)n * sizeof *x2);
    double *tmp = malloc((size_t)n * sizeof *tmp);
    int32_t *start = malloc(40 * sizeof *start), *C = malloc((size_t)n * sizeof *C);
    int *pre = malloc((size_t)n * sizeof *pre);
    unsigned char *mark = calloc((size_t)n, 1);
    cholmod_dense *X = NULL, *Y = NULL, *E = NULL;
    memcpy(ref, y, (size_t)n * sizeof *ref);
    T_CHECK(aug_ldl_ltsolve_all(base, ref, &X, &Y, &E, &cm) == 0, "full L^-T");
    static const int nstart[3] = {40, 1, 0};
    for (int c = 0; c < 3; c++) {
        for (int k = 0; k < nstart[c]; k++) start[k] = (int32_t)gsl_rng_uniform_int(f.r, (unsigned long)n);
        int64_t nc = aug_ldl_closure(base, start, nstart[c], C, mark);
        T_CHECK(aug_ldl_closure_pre(base, C, nc, pre) == 0, "closure %d: not suffixes", c);
        int64_t outside = 0;
        for (int64_t s = 0; s < (int64_t)base->Ls->nsuper; s++) outside += pre[s];
        T_CHECK(outside == n - nc, "closure %d: %lld columns outside, %lld expected", c, (long long)outside,
                (long long)(n - nc));
        /* x_C by the closure solve, the rest deferred */
        for (int64_t t = 0; t < nc; t++) x[C[t]] = y[C[t]];
        aug_ldl_ltsolve_closure_super(base, C, nc, x, tmp);
        T_CHECK(aug_par_ltsolve_rest(NULL, base, pre, y, x) == 0, "rest");
        double nd = normdiff(x, ref, n);
        T_CHECK(nd <= 1e-13, "closure %d (%lld columns): %g from the full L^-T", c, (long long)nc, nd);
        if (nc == 0)
            T_CHECK(ndiff(x, ref, n) == 0, "empty closure: not the full solve bitwise");
        /* x_C from the full solve: the rest serially and on two threads */
        for (int64_t t = 0; t < nc; t++) x[C[t]] = x2[C[t]] = ref[C[t]];
        T_CHECK(aug_par_ltsolve_rest(NULL, base, pre, y, x) == 0 && aug_par_ltsolve_rest(p, base, pre, y, x2) == 0,
                "rest");
        nd = normdiff(x, ref, n);
        T_CHECK(nd <= 1e-13, "closure %d, x_C given: %g from the full L^-T", c, nd);
        int64_t d = ndiff(x, x2, n);
        T_CHECK(d == 0, "closure %d: two threads differ from one in %lld entries", c, (long long)d);
    }
    /* a set that is not an etree closure's suffix form is refused */
    const int *sup = base->Ls->super;
    if (base->Ls->nsuper > 0 && sup[1] - sup[0] > 1) {
        int32_t first = (int32_t)sup[0];
        T_CHECK(aug_ldl_closure_pre(base, &first, 1, pre) == -1, "a first column alone accepted as a suffix");
    }
    cholmod_free_dense(&X, &cm), cholmod_free_dense(&Y, &cm), cholmod_free_dense(&E, &cm);
    free(y), free(ref), free(x), free(x2), free(tmp), free(start), free(C), free(pre), free(mark), free(b);
    aug_par_free(p);
    aug_base_release(base, &cm);
    fix_close(&f);
}

/* the memo H'K^-1H (amps_memo.c) grown on the pool equals the serial one
   bit for bit, over two steps (60, then 90 more positions of S: passes of
   32 with a tail, the second step's new columns against the first's), and
   is H'K^-1H: its columns within 1e-12 of cholmod_solve2 CHOLMOD_A; with
   the columns of V also solved on the pool (amps_reach.c, two halves) G is
   the serial one to 1e-13 */
static void memo_pool_bitwise(void)
{
    fixture f = {0};
    double *b;
    aug_base *base;
    aug_par *p;
    if (base_open(&f, &b, &base, &p)) return;
    int64_t n = base->n;
    aug_err e = {0};
    aug_cum c;
    aug_memo M[3];
    T_CHECK(aug_cum_init(&c, n, &e) == 0, "cum");
    aug_memo_init(&M[0]), aug_memo_init(&M[1]), aug_memo_init(&M[2]);
    M[0].all = M[1].all = M[2].all = 1;
    unsigned char *used = calloc((size_t)n, 1);
    static const int32_t mstep[2] = {60, 90};
    for (int st = 0; st < 2; st++) {
        int32_t m = mstep[st];
        aug_update u = {st + 1, m, 0, malloc((size_t)m * sizeof(int32_t)), calloc((size_t)m * m, sizeof(double)),
                        calloc((size_t)m, sizeof(double)), NULL, NULL, NULL};
        for (int32_t i = 0; i < m; i++) {
            int32_t q;
            do q = (int32_t)gsl_rng_uniform_int(f.r, (unsigned long)n);
            while (used[q]);
            used[q] = 1, u.H[i] = q, u.E[i + (size_t)i * m] = 1e-3;
        }
        T_CHECK(aug_cum_apply(&c, &u, &e) == 0, "step %d: %s", st + 1, e.msg);
        free(u.H), free(u.E), free(u.df);
        for (int k = 0; k < 3; k++) {
            T_CHECK(aug_memo_reach(&M[k], base, &c, k == 2 ? p : NULL, &cm, &e) == 0, "reach: %s", e.msg);
            T_CHECK(aug_memo_grow(&M[k], base, k ? p : NULL, &e) == 0, "grow: %s", e.msg);
        }
        int64_t mm = M[0].m, d = 0;
        T_CHECK(mm == M[1].m && mm == (st ? 150 : 60), "step %d: %lld and %lld columns", st + 1, (long long)mm,
                (long long)M[1].m);
        for (int64_t j = 0; j < mm && mm == M[1].m; j++)
            d += ndiff(M[0].G + j * M[0].mcap, M[1].G + j * M[1].mcap, mm);
        T_CHECK(d == 0, "step %d: %lld of %lld entries differ with the pool", st + 1, (long long)d,
                (long long)(mm * mm));
        double gd = 0, gm = 0;
        for (int64_t j = 0; j < mm && mm == M[2].m; j++)
            for (int64_t i = 0; i < mm; i++) {
                double g0 = M[0].G[i + j * M[0].mcap], g2 = M[2].G[i + j * M[2].mcap];
                gd = fmax(gd, fabs(g0 - g2)), gm = fmax(gm, fabs(g0));
            }
        T_CHECK(mm == M[2].m && gd <= 1e-13 * gm, "step %d, V on the pool: G differs by %g of %g", st + 1, gd, gm);
    }
    /* G(:, j) = H' K^-1 e_{H_j} for a few j */
    cholmod_dense *B = cholmod_zeros((size_t)n, 1, CHOLMOD_REAL, &cm), *X = NULL;
    double worst = 0;
    for (int64_t j = 0; j < M[0].m; j += 37) {
        int32_t hj = c.S[M[0].col[j]];
        ((double *)B->x)[hj] = 1;
        X = cholmod_solve(CHOLMOD_A, f.L, B, &cm);
        ((double *)B->x)[hj] = 0;
        double mx = 0, dd = 0;
        for (int64_t i = 0; i < M[0].m; i++) {
            double ref = ((double *)X->x)[c.S[M[0].col[i]]];
            mx = fmax(mx, fabs(ref)), dd = fmax(dd, fabs(ref - M[0].G[i + j * M[0].mcap]));
        }
        worst = fmax(worst, dd / mx);
        cholmod_free_dense(&X, &cm);
    }
    T_CHECK(worst <= 1e-12, "G against H'K^-1H: %g", worst);
    cholmod_free_dense(&B, &cm);
    free(used);
    aug_memo_free(&M[0]), aug_memo_free(&M[1]), aug_memo_free(&M[2]);
    aug_cum_free(&c);
    aug_base_release(base, &cm), aug_par_free(p), free(b);
    fix_close(&f);
}

/* aug_base_new skips its etree check for a simplicial L made from a
   supernodal one (ldl_sparse.c): on CHOLMOD's relaxed supernodes of the
   grid, struct L(:,j) minus the parent lies in struct L(:,parent) for every
   column (paper 000 thm 3's premise), the parent is the smallest row below
   the diagonal, and a_b (solved with Ls) satisfies K a_b = b to rounding */
static void super_base_closed(void)
{
    fixture f = {0};
    double *b;
    aug_base *base;
    aug_par *p;
    if (base_open(&f, &b, &base, &p)) return;
    int64_t n = base->n, bad = 0, badp = 0;
    unsigned char *mark = calloc((size_t)n, 1);
    for (int64_t j = 0; j < n; j++) {
        int32_t par = base->parent[j];
        int lo = base->Lp[j] + 1, hi = base->Lp[j] + base->Lnz[j];
        int32_t mn = -1;
        for (int k = lo; k < hi; k++)
            if (mn < 0 || base->Li[k] < mn) mn = base->Li[k];
        badp += mn != par;
        if (par < 0) continue;
        for (int k = base->Lp[par] + 1; k < base->Lp[par] + base->Lnz[par]; k++) mark[base->Li[k]] = 1;
        for (int k = lo; k < hi; k++) bad += base->Li[k] != par && !mark[base->Li[k]];
        for (int k = base->Lp[par] + 1; k < base->Lp[par] + base->Lnz[par]; k++) mark[base->Li[k]] = 0;
    }
    T_CHECK(bad == 0, "%lld entries outside their parent's column", (long long)bad);
    T_CHECK(badp == 0, "%lld parents not the smallest row", (long long)badp);
    double *r = malloc((size_t)n * sizeof *r);
    T_CHECK(aug_sym_mult(f.K, base->a, r, &cm) == 0, "K a_b");
    long double rn = 0, bn = 0;
    for (int64_t i = 0; i < n; i++) rn += (long double)(b[i] - r[i]) * (b[i] - r[i]), bn += (long double)b[i] * b[i];
    T_CHECK((double)sqrtl(rn / bn) < 1e-12, "a_b: relres %g", (double)sqrtl(rn / bn));
    free(mark), free(r), free(b);
    aug_par_free(p);
    aug_base_release(base, &cm);
    fix_close(&f);
}

/* aug_closure_work of a supernodal symbolic factor (the supernode chains)
   against its simplicial copy: parent(j) the smallest row below the
   diagonal of column j, and the sum of Lnz over each column's path to the
   root, for every j (an O(n depth) walk, independent of the supernodes) */
static void closure_work_paths(void)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 7);
    cholmod_sparse *K = grid_matrix(r);
    cm.supernodal = CHOLMOD_SUPERNODAL;
    cholmod_factor *L = cholmod_analyze(K, &cm);
    cm.supernodal = CHOLMOD_AUTO;
    double w = aug_closure_work(L);
    cholmod_factorize(K, L, &cm);
    cholmod_factor *S = cholmod_copy_factor(L, &cm);
    cholmod_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, S, &cm);
    int64_t n = (int64_t)S->n;
    const int *Sp = S->p, *Si = S->i, *Snz = S->nz;
    int32_t *par = malloc((size_t)n * sizeof *par);
    for (int64_t j = 0; j < n; j++) {
        par[j] = -1;
        for (int k = Sp[j] + 1; k < Sp[j] + Snz[j]; k++)
            if (par[j] < 0 || Si[k] < par[j]) par[j] = Si[k];
    }
    long double tot = 0;
    for (int64_t j = 0; j < n; j++)
        for (int64_t k = j; k >= 0; k = par[k]) tot += Snz[k];
    T_CHECK(w > 0 && fabs(w - (double)(tot / n)) <= 1e-12 * w, "closure work %.17g, by paths %.17g",
            w, (double)(tot / n));
    T_CHECK(aug_closure_work(S) < 0, "a simplicial factor has no supernodal closure work");
    free(par);
    cholmod_free_factor(&S, &cm);
    cholmod_free_factor(&L, &cm);
    cholmod_free_sparse(&K, &cm);
    gsl_rng_free(r);
}

/* aug_analyze_steps returns the candidate (AMD or METIS alone) of least
   lnz + 4 closure work, and cm->lnz describes it; a forced ordering is kept */
static void ordering_by_step_cost(void)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 9);
    cholmod_sparse *K = grid_matrix(r);
    double cost[2], lnz[2];
    static const int cand[2] = {CHOLMOD_AMD, CHOLMOD_METIS};
    for (int c = 0; c < 2; c++) {
        aug_factor_options(&cm, c == 0 ? AUG_ORDER_AMD : AUG_ORDER_METIS, 0);
        cholmod_factor *L = cholmod_analyze(K, &cm);
        T_CHECK(L && L->ordering == cand[c], "candidate %d", c);
        lnz[c] = cm.lnz, cost[c] = cm.lnz + 4 * aug_closure_work(L);
        cholmod_free_factor(&L, &cm);
    }
    aug_err e;
    aug_factor_options(&cm, AUG_ORDER_AUTO, 0);
    cholmod_factor *L = aug_analyze_steps(K, AUG_ORDER_AUTO, &cm, &e);
    int b = cost[1] < cost[0];
    T_CHECK(L && L->ordering == cand[b], "chose %d, costs amd %g metis %g", L ? L->ordering : -1, cost[0], cost[1]);
    T_CHECK(cm.lnz == lnz[b], "cm.lnz %g, the chosen one's %g", cm.lnz, lnz[b]);
    T_CHECK(cm.nmethods == 0, "the options restored");
    cholmod_free_factor(&L, &cm);
    aug_factor_options(&cm, AUG_ORDER_AMD, 0);
    L = aug_analyze_steps(K, AUG_ORDER_AMD, &cm, &e);
    T_CHECK(L && L->ordering == CHOLMOD_AMD, "--ordering amd kept");
    cholmod_free_factor(&L, &cm);
    aug_factor_options(&cm, AUG_ORDER_AUTO, 0);
    cm.supernodal = CHOLMOD_AUTO;
    cholmod_free_sparse(&K, &cm);
    gsl_rng_free(r);
}

/* a simplicial factor or a one-supernode one has no split */
static void no_split_without_tree(void)
{
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    cholmod_sparse *K = grid_matrix(r);
    cm.supernodal = CHOLMOD_SIMPLICIAL;
    cholmod_factor *L = cholmod_analyze(K, &cm);
    cholmod_factorize(K, L, &cm);
    cm.supernodal = CHOLMOD_AUTO;
    T_CHECK(!L->is_super && aug_par_plan_new(L) == NULL, "a split of a simplicial factor");
    T_CHECK(aug_par_plan_new(NULL) == NULL, "a split of nothing");
    cholmod_free_factor(&L, &cm);
    cholmod_free_sparse(&K, &cm);
    gsl_rng_free(r);
}

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(plan_is_a_split);
    T_RUN(solves_bitwise_blas1);
    T_RUN(solves_bitwise_blas2);
    T_RUN(full_solve_and_base);
    T_RUN(deferred_rest);
    T_RUN(memo_pool_bitwise);
    T_RUN(super_base_closed);
    T_RUN(no_split_without_tree);
    T_RUN(closure_work_paths);
    T_RUN(ordering_by_step_cost);
    cholmod_finish(&cm);
    T_EXIT();
}
