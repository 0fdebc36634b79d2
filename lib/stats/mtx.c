/* Matrix Market export of K (and M) at one step of a stream: K0 from KMAT, K_t assembled in the cut numbering. */
#include <cholmod.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include "aug_cut.h"
#include "aug_stats.h"

struct aug_mtx {
    cholmod_common cm;
    cholmod_sparse *kmat[4]; /* the first KMAT of each kind (AUG_MAT_K, _M, _ML, _A) */
    int32_t *map0;           /* DOFM: the numbering of K0 */
    int dim;
    int64_t ndof, nfree;
    char *written[4];        /* files written, removed again on failure */
};

aug_mtx *aug_mtx_new(aug_err *e)
{
    aug_err_clear(e);
    aug_mtx *x = aug_calloc(1, sizeof *x);
    if (!x) {
        aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        return NULL;
    }
    aug_cholmod_start(&x->cm);
    return x;
}

void aug_mtx_free(aug_mtx *x, int discard)
{
    if (!x) return;
    for (int i = 0; i < 4; i++) {
        if (x->kmat[i]) cholmod_free_sparse(&x->kmat[i], &x->cm);
        if (discard && x->written[i]) remove(x->written[i]);
        free(x->written[i]);
    }
    free(x->map0);
    cholmod_finish(&x->cm);
    free(x);
}

/* keeps the DOFM and the first KMAT of each kind; other records pass */
int aug_mtx_add(aug_mtx *x, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    if (!memcmp(rec->type, "DOFM", 4) && !x->map0)
        return aug_read_dofmap(rec, &x->dim, &x->ndof, &x->nfree, &x->map0, e);
    if (memcmp(rec->type, "KMAT", 4) != 0) return 0;
    int which = -1;
    cholmod_sparse *A = aug_read_sparse(rec, &which, &x->cm, e);
    if (!A) return e->code;
    /* (aug_read_sparse refuses a kind outside 0..AUG_MAT_A) */
    if (which >= 0 && which <= AUG_MAT_A && !x->kmat[which]) x->kmat[which] = A;
    else cholmod_free_sparse(&A, &x->cm);
    return 0;
}

/* A (upper triangle by columns) in Matrix Market coordinate real symmetric:
   the lower triangle, entry (j+1, i+1, A_ij) for every stored A_ij, i <= j,
   column by column; values %.17g (exact). */
static int put_matrix(FILE *o, const cholmod_sparse *A, const char *what)
{
    const int *Ap = A->p, *Ai = A->i;
    const double *Ax = A->x;
    int64_t n = (int64_t)A->ncol;
    fprintf(o, "%%%%MatrixMarket matrix coordinate real symmetric\n%% augcut %s\n", what);
    fprintf(o, "%lld %lld %lld\n", (long long)n, (long long)n, (long long)Ap[n]);
    for (int64_t j = 0; j < n; j++)
        for (int p = Ap[j]; p < Ap[j + 1]; p++)
            fprintf(o, "%lld %d %.17g\n", (long long)j + 1, Ai[p] + 1, Ax[p]);
    return ferror(o);
}

static int write_file(aug_mtx *x, int slot, const char *prefix, const char *suffix,
                      const cholmod_sparse *A, const char *what, aug_err *e)
{
    size_t len = strlen(prefix) + strlen(suffix) + 1;
    char *name = aug_malloc(len);
    if (!name) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    snprintf(name, len, "%s%s", prefix, suffix);
    FILE *o = aug_out_create(name, e);
    if (!o) {
        free(name);
        return e->code;
    }
    x->written[slot] = name;
    int bad = put_matrix(o, A, what);
    if (fclose(o) != 0 || bad) return aug_err_set(e, AUG_EIO, -1, "", "%s: write failed", name);
    return 0;
}

/* Step 0: PREFIX_K.mtx = K0 as in the KMAT record (over the free DOFs of
   DOFM), PREFIX_M.mtx / PREFIX_ML.mtx = the consistent / lumped mass matrix
   when the stream has it, PREFIX_A.mtx = the integrator's matrix A of a
   dynamic stream (factor --dynamic, KMAT which 3). Step t > 0: PREFIX_K.mtx = K_t in the cut-matrix
   numbering (formats/stream.md 7.2), assembled from scratch on m, the mesh of
   step t (aug_assemble_cut: constrained indices are identity rows); by 7.2
   this is K0 with the updates of steps 1..t applied. M and A are written
   at step 0 only (a dynamic stream's UPKM updates are not applied). */
int aug_mtx_write(aug_mtx *x, int32_t step, const aug_mesh *m, const char *prefix, aug_err *e)
{
    aug_err_clear(e);
    char what[96];
    if (step == 0) {
        if (!x->kmat[AUG_MAT_K])
            return aug_err_set(e, AUG_EDATA, -1, "", "no stiffness matrix in the stream (KMAT which 0; run factor)");
        static const char *suffix[4] = {"_K.mtx", "_M.mtx", "_ML.mtx", "_A.mtx"};
        static const char *name[4] = {"K0", "M (consistent mass)", "M (lumped mass)",
                                      "A (the integrator's matrix of factor --dynamic)"};
        for (int i = 0; i < 4; i++) {
            if (!x->kmat[i]) continue;
            snprintf(what, sizeof what, "%s at step 0 over the free DOFs (DOFM order)", name[i]);
            if (write_file(x, i, prefix, suffix[i], x->kmat[i], what, e)) return e->code;
        }
        return 0;
    }
    if (!x->map0) return aug_err_set(e, AUG_EDATA, -1, "", "no DOFM in the stream (run factor)");
    if (!m) return aug_err_set(e, AUG_EDATA, -1, "", "no mesh in the stream (NODE, MATL and ELEM needed)");
    int64_t nn0 = x->ndof / x->dim;
    if (m->dim != x->dim || m->nn < nn0)
        return aug_err_set(e, AUG_EDATA, -1, "DOFM", "%lld DOFs in %d-D do not number the mesh's %lld nodes",
                           (long long)x->ndof, x->dim, (long long)m->nn);
    cholmod_sparse *K = aug_assemble_cut(m, nn0, x->map0, x->nfree, &x->cm, e);
    if (!K) return e->code;
    snprintf(what, sizeof what, "K_t at step %d in the cut-matrix numbering (stream.md 7.2)", (int)step);
    int rc = write_file(x, 0, prefix, "_K.mtx", K, what, e);
    cholmod_free_sparse(&K, &x->cm);
    return rc;
}
