/* AMPS step 1 (paper 001 table 1): the new columns V_dt = L^-1 P H_dt of
   eq. 3.24 (V = L^-1 H of eq. 3.22, P the fill-reducing permutation), each solved
   only over the elimination-tree path of its nonzero (its closure, paper 000 thm 3). */
#include <stdlib.h>
#include <string.h>
#include "aug_solve.h"
#include "aug_par.h"

void aug_memo_init(aug_memo *M) { memset(M, 0, sizeof *M); }

void aug_memo_free(aug_memo *M)
{
    free(M->vp);
    free(M->vt);
    aug_map_free(M->vx, (size_t)M->vcap * (sizeof *M->vx + sizeof *M->vi)); /* and vi */
    free(M->col);
    free(M->cpos);
    aug_map_free(M->G, (size_t)M->mcap * (size_t)M->mcap * sizeof *M->G);
    int uc = M->use_cholmod, all = M->all;
    memset(M, 0, sizeof *M);
    M->use_cholmod = uc, M->all = all;
}

static int grow_cols(aug_memo *M, int64_t need)
{
    if (need <= M->mcap) return 0;
    int64_t nc = aug_sq_cap(M->mcap, need);
    int64_t *vp = aug_realloc(M->vp, (size_t)(nc + 1) * sizeof *vp);
    if (!vp) return -1;
    M->vp = vp;
    if (M->mcap == 0) vp[0] = 0;
    int64_t *vt = aug_realloc(M->vt, (size_t)nc * sizeof *vt);
    if (!vt) return -1;
    M->vt = vt;
    int32_t *col = aug_realloc(M->col, (size_t)nc * sizeof *col);
    if (!col) return -1;
    M->col = col;
    double *G = aug_sq_grow(M->G, M->mcap, nc, M->m);
    if (!G) return -1;
    M->G = G;
    M->mcap = nc;
    return 0;
}

static int grow_vals(aug_memo *M, int64_t need, int64_t n)
{
    if (need <= M->vcap) return 0;
    /* reserved for about 64 paths of full length from the start: pages are
       touched only as columns arrive, while a doubling at a million entries
       copied 12 MB and faulted in 24 MB in one step (35 ms, brick N=16) */
    int64_t r0 = 64 * n < (1 << 24) ? 64 * n : (1 << 24);
    int64_t nc = M->vcap ? M->vcap : (r0 > 4096 ? r0 : 4096);
    while (nc < need) nc *= 2;
    /* one mapping: vx, then vi (moved up to its new place) */
    size_t used = (size_t)(M->m ? M->vp[M->m] : 0), w = sizeof *M->vx + sizeof *M->vi;
    double *vx = aug_map_grow(M->vx, (size_t)M->vcap * w, (size_t)nc * w);
    if (!vx) return -1;
    int32_t *vi = (int32_t *)(vx + nc);
    memmove(vi, vx + M->vcap, used * sizeof *vi);
    M->vi = vi;
    M->vx = vx;
    M->vcap = nc;
    return 0;
}

/* out[t] = (L^-1 e_p)(path[t]) over the etree path of p (paper 000 thms 1, 3):
   x_p = 1, x_r -= L(r,c) x_c for c on the path; x (zero on entry) is zero again */
static void path_solve(const aug_base *b, const int32_t *path, int64_t len, double *x, double *out)
{
    const int *Lp = b->Lp, *Li = b->Li, *Lnz = b->Lnz;
    const double *Lx = b->Lx;
    x[path[0]] = 1.0;
    for (int64_t t = 0; t < len; t++) {
        int32_t j = path[t];
        double xj = x[j];
        out[t] = xj;
        x[j] = 0;
        if (xj == 0) continue;
        for (int q = Lp[j] + 1; q < Lp[j] + Lnz[j]; q++) x[Li[q]] -= Lx[q] * xj;
    }
}

/* the same column by CHOLMOD: cholmod_solve2(CHOLMOD_L) with Bset = {p} solves
   L x = e_p on its reach Xset only ([CHOLMOD]); out[t] = x(path[t]) */
static int cholmod_column(const aug_base *b, int32_t p, const int32_t *path, int64_t len,
                          double *out, cholmod_dense **X, cholmod_sparse **Xset,
                          cholmod_dense **Y, cholmod_dense **Ew, cholmod_common *cm)
{
    cholmod_dense *B = cholmod_zeros((size_t)b->n, 1, CHOLMOD_REAL, cm);
    cholmod_sparse *Bset = cholmod_allocate_sparse((size_t)b->n, 1, 1, 1, 1, 0, CHOLMOD_PATTERN, cm);
    if (!B || !Bset) goto fail;
    ((double *)B->x)[p] = 1.0;
    ((int *)Bset->p)[0] = 0, ((int *)Bset->p)[1] = 1, ((int *)Bset->i)[0] = p;
    if (!cholmod_solve2(CHOLMOD_L, b->L, B, Bset, X, Xset, Y, Ew, cm)) goto fail;
    const double *x = (*X)->x;
    for (int64_t t = 0; t < len; t++) out[t] = x[path[t]];
    cholmod_free_dense(&B, cm);
    cholmod_free_sparse(&Bset, cm);
    return 0;
fail:
    if (B) cholmod_free_dense(&B, cm);
    if (Bset) cholmod_free_sparse(&Bset, cm);
    return -1;
}

/* a memo column for position p of S: a base DOF not yet in it whose column
   of Ebar is nonzero, as S2's active positions (or every base DOF, M->all).
   The others change only
   the load (dF): S2 and the field reach them by one forward solve of their
   loads a step (amps_solve.c, lo_times), not by columns of V and G, which
   would cost their paths and their |S| products in G on every later step. */
static int wants(const aug_memo *M, const aug_cum *c, int64_t p)
{
    return c->S[p] < c->nb && M->cpos[p] < 0 && (M->all || aug_cum_coupled(c, p));
}

/* a group of columns on the pool: thread t < 2 solves the group's columns
   cut[t] .. cut[t+1]-1 through the supernodes (its own workspace) */
typedef struct reach_job {
    const aug_base *b;
    const int32_t *gp;
    int32_t *const *gpath;
    const int64_t *glen;
    double *const *gout;
    int cut[3], rc[2];
} reach_job;

static void reach_worker(void *arg, int t)
{
    reach_job *j = arg;
    if (t > 1) return;
    int lo = j->cut[t], hi = j->cut[t + 1];
    j->rc[t] = hi > lo ? aug_ldl_paths_solve_super(j->b, hi - lo, j->gp + lo, j->gpath + lo, j->glen + lo,
                                                   j->gout + lo)
                       : 0;
}

/* the group's columns solved at once, or, on a pool and with 8 or more, as
   two halves of about equal path length side by side (paper 001 sec. 3.6:
   the columns are independent; each half reads the top of L once) */
static int solve_group(const aug_base *b, struct aug_par *par, int ng, const int32_t *gp, int32_t *const *gpath,
                       const int64_t *glen, double *const *gout)
{
    if (!par || ng < 8) return aug_ldl_paths_solve_super(b, ng, gp, gpath, glen, gout);
    int64_t tot = 0, acc = 0;
    for (int q = 0; q < ng; q++) tot += glen[q];
    int h = 0;
    while (h < ng - 1 && 2 * (acc + glen[h]) <= tot) acc += glen[h++];
    if (h == 0) h = 1;
    reach_job j = {b, gp, gpath, glen, gout, {0, h, ng}, {0, 0}};
    aug_par_run(par, reach_worker, &j);
    return j.rc[0] || j.rc[1] ? -1 : 0;
}

/* V(:, new) = L^-1 P H_dt (paper 001 eqs. 3.23-3.24, table 1 step 1): a column for
   each base DOF of S not yet in the memo that wants one, over its etree path (aug_ldl_path), by
   path_solve, cholmod_column (use_cholmod), or 32 at a time through the supernodes
   (aug_ldl_paths_solve_super) when the base has Ls; vt marks each path's dense tail */
int aug_memo_reach(aug_memo *M, const aug_base *b, const aug_cum *c, struct aug_par *par,
                   cholmod_common *cm, aug_err *e)
{
    M->reach_new = 0;
    M->m_new = 0;
    if (M->pcap < c->pcap) {
        int32_t *cp = aug_realloc(M->cpos, (size_t)c->pcap * sizeof *cp);
        if (!cp) goto nomem;
        for (int64_t i = M->pcap; i < c->pcap; i++) cp[i] = -1;
        M->cpos = cp;
        M->pcap = c->pcap;
    }
    int64_t need = M->m;
    for (int64_t p = 0; p < c->ns; p++) need += wants(M, c, p);
    if (need == M->m) return 0;
    if (grow_cols(M, need)) goto nomem;
    int32_t *path = aug_malloc((size_t)b->n * sizeof *path);
    double *x = aug_calloc((size_t)b->n, sizeof *x);
    cholmod_dense *X = NULL, *Y = NULL, *Ew = NULL;
    cholmod_sparse *Xset = NULL;
    if (!path || !x) {
        free(path), free(x);
        goto nomem;
    }
    int rc = 0;
    /* with a supernodal factor the new columns go in groups through
       aug_ldl_paths_solve_super, their paths stored first. Each group reads
       the top supernodes of L (every path ends there) once: groups of 128
       instead of 32 took the brain's 8-node steps (36-87 new columns) from
       29-36 to 25-31 ms of reach, same runs alternated; the group's work
       array is |union of its paths| x 128 doubles */
    enum { GROUP = 128 };
    int32_t gp[GROUP];
    int32_t *gpath[GROUP];
    int64_t glen[GROUP], goff[GROUP];
    double *gout[GROUP];
    int ng = 0, grouped = b->Ls && !M->use_cholmod;
    for (int64_t p = 0; p <= c->ns && !rc; p++) {
        int last = p == c->ns;
        if (!last && !wants(M, c, p)) continue;
        if (grouped && ng > 0 && (last || ng == GROUP)) {
            for (int q = 0; q < ng; q++) gpath[q] = M->vi + goff[q], gout[q] = M->vx + goff[q];
            if (solve_group(b, par, ng, gp, gpath, glen, gout))
                rc = aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (V)");
            ng = 0;
        }
        if (last || rc) break;
        int32_t j = b->pinv[c->S[p]];
        int64_t at = M->vp[M->m], len = aug_ldl_path(b, j, path);
        if (grow_vals(M, at + len, b->n)) {
            rc = aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (V)");
            break;
        }
        memcpy(M->vi + at, path, (size_t)len * sizeof *path);
        if (grouped) {
            /* offsets, not pointers: vi/vx may move while the group fills */
            gp[ng] = j, glen[ng] = len, goff[ng] = at;
            ng++;
        } else if (M->use_cholmod) {
            if (cholmod_column(b, j, path, len, M->vx + at, &X, &Xset, &Y, &Ew, cm))
                rc = aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "cholmod_solve2 failed");
        } else {
            path_solve(b, path, len, x, M->vx + at);
        }
        int64_t tl = len - 1;
        while (tl > 0 && path[tl - 1] == path[tl] - 1) tl--;
        M->vt[M->m] = at + tl;
        M->col[M->m] = (int32_t)p;
        M->cpos[p] = (int32_t)M->m;
        M->vp[++M->m] = at + len;
        M->reach_new += len;
        M->m_new++;
    }
    if (X) cholmod_free_dense(&X, cm);
    if (Y) cholmod_free_dense(&Y, cm);
    if (Ew) cholmod_free_dense(&Ew, cm);
    if (Xset) cholmod_free_sparse(&Xset, cm);
    free(path);
    free(x);
    return rc;
nomem:
    return aug_err_set(e, AUG_ENOMEM, -1, "UPDT", "out of memory (V)");
}
