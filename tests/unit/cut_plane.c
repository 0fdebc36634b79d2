/* Planar cuts on tet and hex meshes: at every step of random cut sequences, K_t from
   scratch == K_0 padded minus the accumulated updates (AMPS eq. 3.1), loads,
   volume, no degenerate element, face conformity, detached pieces. */
#include "t.h"
#include "cut_check.h"

static cholmod_common cm;

typedef struct faces3 {
    int64_t n;
    int32_t *f;          /* original faces between + and - elements (4 nodes each, padded with -1) */
} faces3;

/* independent classification: faces shared by elements on both sides of n.x = d */
static faces3 plane_faces(const aug_mesh *m, const double *n, double d)
{
    int nv = m->nv, dim = m->dim, nfc = cc_nfacets(m);
    double len = 0;
    for (int k = 0; k < dim; k++) len += n[k] * n[k];
    len = sqrt(len);
    unsigned char *side = malloc((size_t)m->ne);
    for (int64_t e = 0; e < m->ne; e++) {
        double s = 0;
        for (int a = 0; a < nv; a++)
            for (int k = 0; k < dim; k++) s += m->x[m->conn[e * nv + a] * dim + k] / nv * n[k] / len;
        side[e] = s > d / len;
    }
    int64_t nf = m->ne * nfc;
    int32_t *F = malloc((size_t)nf * 5 * sizeof *F);
    for (int64_t e = 0; e < m->ne; e++)
        for (int f = 0; f < nfc; f++) {
            int32_t *q = F + (e * nfc + f) * 5;
            cc_facet(m, e, f, q);
            q[4] = side[e];
        }
    qsort(F, (size_t)nf, 5 * sizeof *F, cmp_face4);
    faces3 r = {0, malloc((size_t)nf * 4 * sizeof(int32_t))};
    for (int64_t i = 0; i + 1 < nf; i++)
        if (cmp_face4(F + i * 5, F + (i + 1) * 5) == 0 && F[i * 5 + 4] != F[(i + 1) * 5 + 4]) {
            memcpy(r.f + r.n * 4, F + i * 5, 4 * sizeof(int32_t));
            r.n++;
        }
    free(F);
    free(side);
    return r;
}

typedef struct run_opt {
    int nplanes, policy, constrain_step, maxsteps, fixed_adv, check_eig;
    double pull;
    const double *n, *d;    /* given planes (NULL: random) */
    unsigned long seed;
} run_opt;

typedef struct run_res {
    int steps, detached_step, error_step, flags;
    double last_min_eig;
    uint32_t hash;
} run_res;

static uint32_t fnv(uint32_t h, const void *p, size_t n)
{
    const unsigned char *c = p;
    for (size_t i = 0; i < n; i++) h = (h ^ c[i]) * 16777619u;
    return h;
}

/* run planar cuts with every invariant checked; 0 ok, -1 with t_why filled */
static int run_planes(aug_mesh *m, const run_opt *o, run_res *res)
{
    aug_err e;
    cc_track T;
    aug_cutter C;
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, o->seed);
    memset(res, 0, sizeof *res);
    res->hash = 2166136261u;
    int rc = -1;
    if (cc_init(&T, m, &cm)) {
        T_CHECK(0, "%s", T.why);
        goto out0;
    }
    aug_cutter_init(&C, m, T.nn0, T.map0, T.nfree0, &e);
    C.policy = o->policy;
    C.pull = o->pull;
    int step = 0;
    cc_faces f0 = cc_count_faces(m);
    unsigned char *dup = calloc((size_t)m->nn, 1);
    for (int pl = 0; pl < o->nplanes; pl++) {
        double n[3], d, p[3], adv[3];
        aug_plane_cut pc;
        int tries = 0;
        do {
            if (o->n) {
                memcpy(n, o->n + 3 * pl, sizeof n);
                d = o->d[pl];
            } else {
                double s = 0;
                for (int k = 0; k < 3; k++) {
                    n[k] = gsl_rng_uniform(r) - 0.5;
                    s += n[k] * n[k];
                }
                for (int k = 0; k < 3; k++) n[k] /= sqrt(s);
                p[0] = 0.2 + 0.6 * gsl_rng_uniform(r);
                p[1] = 0.2 + 0.6 * gsl_rng_uniform(r);
                p[2] = 0.4 + 1.2 * gsl_rng_uniform(r);
                d = n[0] * p[0] + n[1] * p[1] + n[2] * p[2];
            }
            for (int k = 0; k < 3; k++) adv[k] = gsl_rng_uniform(r) - 0.5;
        } while (aug_plane_plan(&pc, m, &C.adj, n, d, o->fixed_adv || gsl_rng_uniform(r) < 0.5 ? NULL : adv, &e) &&
                 ++tries < 20);
        if (tries == 20) {
            T_CHECK(0, "no plane cuts the mesh: %s", e.msg);
            goto out;
        }
        faces3 cf = plane_faces(m, n, d);
        T_CHECK(cf.n == pc.nface, "plane %d: %lld cut faces, the planner found %lld", pl,
                (long long)cf.n, (long long)pc.nface);
        while (pc.next < pc.ncut && step < o->maxsteps) {
            aug_cut_step S;
            aug_cut_step_init(&S, ++step);
            int64_t count = 1 + (int64_t)gsl_rng_uniform_int(r, 3);
            if (aug_plane_step(&pc, &C.ed, count, &S.seg, &S.nseg, &e) ||
                aug_cutter_apply(&C, &S, &e)) {
                T_CHECK(0, "step %d: %s", step, e.msg);
                aug_cut_step_free(&S);
                break;
            }
            for (int64_t i = 0; i < S.d.nnew; i++)
                if (S.d.parent[i] < T.nn0) dup[S.d.parent[i]] = 1;
            if (step == o->constrain_step) {
                double lo[3] = {-1, -1, 1.9}, hi[3] = {2, 0.5, 2.1};
                T_CHECK(aug_cut_constrain_box(m, lo, hi, NULL, &S.bc, &e) == 0, "%s", e.msg);
            }
            int urc = aug_cutter_update(&C, &S, &e);
            if (urc == AUG_ESINGULAR) {
                /* only --detached error reports a piece; pin and drop must support it */
                T_CHECK(o->policy == AUG_DETACH_ERROR, "step %d: a piece left without support under pin/drop: %s",
                        step, e.msg);
                /* independent check: the mesh after the step is singular */
                cc_track U;
                memset(&U, 0, sizeof U);
                U.n = aug_cut_order(m, T.nn0, T.nfree0);
                U.cap = U.n;
                U.K = calloc((size_t)(U.n * U.n), sizeof *U.K);
                cholmod_sparse *A = aug_assemble_cut(m, T.nn0, T.map0, T.nfree0, &cm, &e);
                cc_dense(A, U.K, U.n);
                cholmod_free_sparse(&A, &cm);
                res->last_min_eig = cc_min_eig_ratio(&U);
                free(U.K);
                res->error_step = step;
                aug_cut_step_free(&S);
                free(cf.f);
                aug_plane_free(&pc);
                rc = 0;
                goto out;
            }
            if (urc) {
                T_CHECK(0, "step %d: %s", step, e.msg);
                aug_cut_step_free(&S);
                break;
            }
            if (S.d.flags & AUG_STEP_DETACHED && !res->detached_step) res->detached_step = step;
            res->flags |= S.d.flags;
            res->hash = fnv(res->hash, S.u.H, (size_t)S.u.m * 4);
            res->hash = fnv(res->hash, S.u.E, (size_t)(S.u.m + S.u.k) * (S.u.m + S.u.k) * 8);
            res->hash = fnv(res->hash, S.u.df, (size_t)(S.u.m + S.u.k) * 8);
            T_CHECK(S.u.k == 3 * S.d.nnew, "step %d: k = %d for %lld new nodes", step, S.u.k,
                    (long long)S.d.nnew);
            if (cc_apply(&T, &S.u) || cc_check(&T, m, &cm, step)) {
                T_CHECK(0, "%s", T.why);
                aug_cut_step_free(&S);
                free(cf.f);
                aug_plane_free(&pc);
                goto out;
            }
            if (o->check_eig) {
                res->last_min_eig = cc_min_eig_ratio(&T);
                T_CHECK(res->last_min_eig > 1e-13, "step %d: K_t singular (%g) without a report",
                        step, res->last_min_eig);
            }
            cc_faces ft = cc_count_faces(m);
            T_CHECK(ft.more == 0, "step %d: %lld faces in 3 or more elements", step, (long long)ft.more);
            if (o->nplanes == 1) {
                int64_t opened = 0;
                for (int64_t i = 0; i < cf.n; i++)
                    opened += dup[cf.f[i * 4]] || dup[cf.f[i * 4 + 1]] || dup[cf.f[i * 4 + 2]] ||
                              (cf.f[i * 4 + 3] >= 0 && dup[cf.f[i * 4 + 3]]);
                T_CHECK(ft.two == f0.two - opened && ft.one == f0.one + 2 * opened,
                        "step %d: %lld shared and %lld boundary faces, want %lld and %lld", step,
                        (long long)ft.two, (long long)ft.one, (long long)(f0.two - opened),
                        (long long)(f0.one + 2 * opened));
            }
            aug_cut_step_free(&S);
            if (t_cur_failed) break;
        }
        free(cf.f);
        aug_plane_free(&pc);
        if (t_cur_failed) break;
    }
    res->steps = step;
    rc = t_cur_failed ? -1 : 0;
out:
    free(dup);
    aug_cutter_free(&C);
out0:
    cc_free(&T);
    gsl_rng_free(r);
    return rc;
}

/* a brick of tets (cc_brick) or hexes (cc_hexbrick) */
typedef void (*brick_fn)(aug_mesh *m, int nx, int ny, int nz, double lx, double ly, double lz, gsl_rng *r,
                         double fixval);

static void random_planes(brick_fn brick)
{
    for (unsigned long seed = 1; seed <= 4 && !t_cur_failed; seed++) {
        gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
        gsl_rng_set(r, seed);
        aug_mesh m;
        brick(&m, 3, 3, 6, 1, 1, 2, r, seed % 3 == 0 ? 0.01 : 0.0);
        run_opt o = {1, seed % 2 ? AUG_DETACH_PIN : AUG_DETACH_DROP, seed % 2 ? 0 : 3, 40, 0, 0,
                     seed % 2 ? 0.1 : 0.0, NULL, NULL, seed};
        run_res res;
        run_planes(&m, &o, &res);
        T_CHECK(res.steps > 3, "seed %lu: only %d steps", seed, res.steps);
        aug_mesh_free(&m);
        gsl_rng_free(r);
    }
}

static void brick_random(void) { random_planes(cc_brick); }
static void hex_random(void) { random_planes(cc_hexbrick); }

/* two and three planes one after another: cross cuts and re-cuts */
static void cross_planes(brick_fn brick)
{
    for (unsigned long seed = 11; seed <= 12 && !t_cur_failed; seed++) {
        aug_mesh m;
        brick(&m, 3, 3, 6, 1, 1, 2, NULL, 0);
        run_opt o = {(int)(seed - 9), AUG_DETACH_PIN, 0, 60, 0, 0, 0.05, NULL, NULL, seed};
        run_res res;
        run_planes(&m, &o, &res);
        aug_mesh_free(&m);
    }
}

static void brick_cross(void) { cross_planes(cc_brick); }
static void hex_cross(void) { cross_planes(cc_hexbrick); }

/* the papers' experiment on the 4x4x8 brick: plane x = 0.5, default advance
   (the hex brick: the plane runs along the faces x = 0.5 of its cells) */
static void paper_plane(brick_fn brick)
{
    aug_mesh m;
    aug_err e;
    brick(&m, 4, 4, 8, 1, 1, 2, NULL, 0);
    aug_adj adj;
    aug_adj_build(&adj, &m);
    aug_plane_cut pc;
    double n[3] = {1, 0, 0};
    T_CHECK(aug_plane_plan(&pc, &m, &adj, n, 0.5, NULL, &e) == 0, "%s", e.msg);
    /* cut nodes: the 5 x 9 grid nodes on x = 0.5, ordered away from the fixed face z = 0 */
    T_CHECK(pc.ncut == 45, "%lld cut nodes, want 45", (long long)pc.ncut);
    T_CHECK(fabs(pc.adv[2] - 1) < 1e-12, "advance (%g,%g,%g), want +z", pc.adv[0], pc.adv[1], pc.adv[2]);
    for (int64_t i = 0; i < pc.ncut; i++) {
        const double *x = m.x + pc.nodes[i] * 3;
        T_CHECK(fabs(x[0] - 0.5) < 1e-15, "cut node %d at x = %g", pc.nodes[i], x[0]);
        if (i > 0) {
            const double *y = m.x + pc.nodes[i - 1] * 3;
            T_CHECK(y[2] < x[2] || (y[2] == x[2] && pc.nodes[i - 1] < pc.nodes[i]),
                    "cut nodes out of order at %lld", (long long)i);
        }
    }
    aug_plane_free(&pc);
    aug_adj_free(&adj);
    run_opt o = {1, AUG_DETACH_ERROR, 0, 16, 1, 0, 0.0, n, (double[]){0.5}, 7};
    run_res res;
    run_planes(&m, &o, &res);
    T_CHECK(res.steps == 16 && res.error_step == 0 && res.detached_step == 0,
            "%d steps (error at %d, detached at %d)", res.steps, res.error_step, res.detached_step);
    aug_mesh_free(&m);
}

static void brick_paper(void) { paper_plane(cc_brick); }
static void hex_paper(void) { paper_plane(cc_hexbrick); }

/* a beam cut across: the tip comes off; error reports the step where K_t
   becomes singular, which an eigenvalue computation confirms */
static void detach_beam(brick_fn brick)
{
    double n[3] = {0, 0, 1}, d = 1.47;
    for (int run = 0; run < 6 && !t_cur_failed; run++) {
        int policy = run < 4 ? AUG_DETACH_ERROR : run - 3;
        aug_mesh m;
        brick(&m, 2, 2, 10, 0.4, 0.4, 2.0, NULL, 0);
        run_opt o = {1, policy, 0, 100, 1, policy == AUG_DETACH_ERROR, 0.0, n, &d,
                     (unsigned long)run + 3};
        run_res res;
        run_planes(&m, &o, &res);
        if (policy == AUG_DETACH_ERROR) {
            T_CHECK(res.error_step > 0, "no detached piece reported");
            T_CHECK(res.last_min_eig < 1e-13, "reported at step %d but K_t is regular (%g)",
                    res.error_step, res.last_min_eig);
        } else {
            T_CHECK(res.detached_step > 0, "policy %d: no detached step", policy);
            T_CHECK(res.flags & (policy == AUG_DETACH_PIN ? AUG_STEP_PINNED : AUG_STEP_DROPPED),
                    "flags %d", res.flags);
        }
        aug_mesh_free(&m);
    }
    /* the same with eigenvalues checked after pinning and dropping */
    for (int policy = 1; policy < 3 && !t_cur_failed; policy++) {
        aug_mesh m;
        brick(&m, 2, 2, 10, 0.4, 0.4, 2.0, NULL, 0);
        run_opt o = {1, policy, 0, 100, 1, 1, 0.0, n, &d, 3};
        run_res res;
        run_planes(&m, &o, &res);
        aug_mesh_free(&m);
    }
}

static void beam_detach(void) { detach_beam(cc_brick); }
static void hex_beam_detach(void) { detach_beam(cc_hexbrick); }

static void determinism(void)
{
    run_res a, b;
    for (int k = 0; k < 2; k++) {
        aug_mesh m;
        gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
        gsl_rng_set(r, 5);
        cc_brick(&m, 3, 3, 6, 1, 1, 2, r, 0.01);
        run_opt o = {2, AUG_DETACH_PIN, 4, 30, 0, 0, 0.1, NULL, NULL, 5};
        run_planes(&m, &o, k ? &b : &a);
        aug_mesh_free(&m);
        gsl_rng_free(r);
    }
    T_CHECK(a.steps == b.steps && a.hash == b.hash, "two runs differ (%d/%d steps)", a.steps, b.steps);
}

/* aug_update_build on a copy of the mesh before the step gives the same bytes */
static void build_api(void)
{
    aug_mesh m, before;
    aug_err e;
    cc_brick(&m, 3, 3, 6, 1, 1, 2, NULL, 0);
    int32_t *map0 = malloc((size_t)(m.nn * 3) * sizeof *map0);
    int64_t nfree0 = aug_dofmap(&m, map0), nn0 = m.nn;
    aug_cutter C;
    aug_cutter_init(&C, &m, nn0, map0, nfree0, &e);
    C.pull = 0.2;
    aug_plane_cut pc;
    double n[3] = {0.3, 1, 0.1};
    aug_plane_plan(&pc, &m, &C.adj, n, 0.6, NULL, &e);
    for (int step = 1; step <= 6 && !t_cur_failed; step++) {
        cc_mesh_copy(&before, &m);
        aug_cut_step S;
        aug_cut_step_init(&S, step);
        aug_plane_step(&pc, &C.ed, 2, &S.seg, &S.nseg, &e);
        aug_cutter_apply(&C, &S, &e);
        T_CHECK(aug_cutter_update(&C, &S, &e) == 0, "%s", e.msg);
        aug_update u;
        T_CHECK(aug_update_build_bc(&before, &S.d, &S.bc, nn0, map0, nfree0, NULL, &u, &e) == 0, "%s", e.msg);
        int s = u.m + u.k;
        T_CHECK(u.m == S.u.m && u.k == S.u.k && !memcmp(u.H, S.u.H, (size_t)u.m * 4) &&
                    !memcmp(u.E, S.u.E, (size_t)s * s * 8) && !memcmp(u.df, S.u.df, (size_t)s * 8),
                "step %d: aug_update_build_bc differs", step);
        T_CHECK(S.bc.nload > 0, "step %d: no pull loads", step);
        aug_update_free(&u);
        aug_cut_step_free(&S);
        aug_mesh_free(&before);
    }
    aug_plane_free(&pc);
    aug_cutter_free(&C);
    free(map0);
    aug_mesh_free(&m);
}

/* every allocation failing in turn: AUG_ENOMEM, never a crash or a leak */
static void alloc_failures(void)
{
    int done = 0;
    for (long k = 0; k < 100000 && !done; k++) {
        aug_mesh m;
        aug_err e;
        cc_brick(&m, 2, 2, 3, 1, 1, 1, NULL, 0);
        int32_t *map0 = malloc((size_t)(m.nn * 3) * sizeof *map0);
        int64_t nfree0 = aug_dofmap(&m, map0);
        aug_fail_after(k);
        aug_cutter C;
        int rc = aug_cutter_init(&C, &m, m.nn, map0, nfree0, &e);
        if (rc == 0) {
            C.pull = 0.1;
            aug_plane_cut pc;
            double n[3] = {1, 0, 0};
            rc = aug_plane_plan(&pc, &m, &C.adj, n, 0.5, NULL, &e);
            for (int step = 1; rc == 0 && step <= 3; step++) {
                aug_cut_step S;
                aug_cut_step_init(&S, step);
                rc = aug_plane_step(&pc, &C.ed, 2, &S.seg, &S.nseg, &e);
                if (!rc) rc = aug_cutter_apply(&C, &S, &e);
                if (!rc) {
                    aug_bdelta_fix(&S.bc, 0, 0.0);
                    rc = aug_cutter_update(&C, &S, &e);
                }
                aug_cut_step_free(&S);
            }
            aug_plane_free(&pc);
            aug_cutter_free(&C);
        }
        aug_fail_after(-1);
        T_CHECK(rc == 0 || rc == AUG_ENOMEM, "failure after %ld allocations: code %d (%s)", k, rc, e.msg);
        if (rc == 0) done = 1;
        free(map0);
        aug_mesh_free(&m);
    }
    T_CHECK(done, "never succeeded");
}

/* BDLT round trip through a real stream; malformed payloads are refused */
static void bdelta_records(void)
{
    aug_err e;
    aug_bdelta b, r;
    aug_bdelta_init(&b);
    b.step = 4;
    aug_bdelta_fix(&b, 7, 0.5);
    aug_bdelta_fix(&b, 3, 0.0);
    aug_bdelta_fix(&b, 7, 0.25); /* the last value given wins */
    aug_bdelta_load(&b, 11, -2.0);
    T_CHECK(aug_bdelta_finish(&b) == 0 && b.nfix == 2 && b.fix_dof[0] == 3 && b.fix_val[1] == 0.25,
            "finish: %lld constraints", (long long)b.nfix);
    FILE *f = tmpfile();
    aug_writer *w = aug_writer_open(f, "test", &e);
    T_CHECK(w && aug_write_bdelta(w, &b, &e) == 0 && aug_writer_close(w, &e) == 0, "write: %s", e.msg);
    aug_writer_free(w);
    rewind(f);
    aug_reader *rd = aug_reader_open(f, "tmp", &e);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    T_CHECK(rd && aug_read(rd, &rec, &e) == 1 && !memcmp(rec.type, "BDLT", 4), "read: %s", e.msg);
    T_CHECK(aug_read_bdelta(&rec, &r, &e) == 0, "decode: %s", e.msg);
    T_CHECK(r.step == 4 && r.nfix == 2 && r.fix_dof[1] == 7 && r.fix_val[1] == 0.25 && r.nload == 1 &&
                r.load_dof[0] == 11 && r.load_val[0] == -2.0, "round trip differs");
    aug_bdelta_free(&r);
    /* dofs not increasing; counts beyond the payload */
    int32_t bad1[] = {2, 0, 5, 0, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    int64_t bad2[] = {1000, 0};
    aug_rec q = rec;
    q.data = (unsigned char *)bad1;
    q.len = 8 + 2 * 4 + 2 * 8 + 8;
    T_CHECK(aug_read_bdelta(&q, &r, &e) != 0, "non-increasing dofs accepted");
    aug_bdelta_free(&r);
    q.data = (unsigned char *)bad2;
    q.len = sizeof bad2;
    T_CHECK(aug_read_bdelta(&q, &r, &e) == AUG_EPAYLOAD, "absurd count accepted");
    aug_bdelta_free(&r);
    aug_rec_free(&rec);
    aug_reader_free(rd);
    fclose(f);
    aug_bdelta_free(&b);
}

int main(void)
{
    aug_cholmod_start(&cm);
    T_RUN(brick_random);
    T_RUN(brick_cross);
    T_RUN(brick_paper);
    T_RUN(beam_detach);
    T_RUN(hex_random);
    T_RUN(hex_cross);
    T_RUN(hex_paper);
    T_RUN(hex_beam_detach);
    T_RUN(determinism);
    T_RUN(build_api);
    T_RUN(alloc_failures);
    T_RUN(bdelta_records);
    cholmod_finish(&cm);
    T_EXIT();
}
