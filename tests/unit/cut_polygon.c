/* Bounded planar cuts (cut --polygon): only nodes inside the polygon are
   duplicated, and at every step K_t from scratch == K_0 padded minus the
   accumulated updates (AMPS eq. 3.1), volume kept, faces conforming. */
#include "t.h"
#include "cut_check.h"

static cholmod_common cm;

/* the 4x4x8 brick (1 x 1 x 2), plane x = 0.5, polygon y in [0.25, 0.75],
   z in [0.5, 1.5]: 3 x 5 grid nodes inside */
static void brick_window(void)
{
    aug_mesh m;
    aug_err e;
    cc_brick(&m, 4, 4, 8, 1, 1, 2, NULL, 0);
    cc_track T;
    if (cc_init(&T, &m, &cm)) {
        T_CHECK(0, "%s", T.why);
        return;
    }
    aug_cutter C;
    aug_cutter_init(&C, &m, T.nn0, T.map0, T.nfree0, &e);
    C.policy = AUG_DETACH_ERROR;
    aug_plane_cut pc;
    double n[3] = {1, 0, 0};
    double poly[] = {0.5, 0.25, 0.5, 0.5, 0.75, 0.5, 0.5, 0.75, 1.5, 0.5, 0.25, 1.5};
    T_CHECK(aug_plane_plan(&pc, &m, &C.adj, n, 0.5, NULL, &e) == 0, "%s", e.msg);
    T_CHECK(aug_plane_restrict(&pc, &m, poly, 4, &e) == 0, "%s", e.msg);
    T_CHECK(pc.ncut == 15, "%lld cut nodes inside, want 15", (long long)pc.ncut);
    double v0 = cc_total_measure(&m, NULL);
    cc_faces f0 = cc_count_faces(&m);
    int64_t nn0 = m.nn;
    int step = 0;
    while (pc.next < pc.ncut && !t_cur_failed) {
        aug_cut_step S;
        aug_cut_step_init(&S, ++step);
        if (aug_plane_step(&pc, &C.ed, 2, &S.seg, &S.nseg, &e) || aug_cutter_apply(&C, &S, &e) ||
            aug_cutter_update(&C, &S, &e)) {
            T_CHECK(0, "step %d: %s", step, e.msg);
            aug_cut_step_free(&S);
            break;
        }
        for (int64_t i = 0; i < S.d.nnew; i++) {
            const double *x = m.x + (int64_t)S.d.parent[i] * 3;
            T_CHECK(fabs(x[0] - 0.5) < 1e-12 && x[1] > 0.24 && x[1] < 0.76 && x[2] > 0.49 && x[2] < 1.51,
                    "step %d: node %d at (%g,%g,%g) outside the polygon duplicated", step,
                    S.d.parent[i], x[0], x[1], x[2]);
        }
        if (cc_apply(&T, &S.u) || cc_check(&T, &m, &cm, step)) T_CHECK(0, "%s", T.why);
        double vmin;
        T_CHECK(fabs(cc_total_measure(&m, &vmin) - v0) < 1e-12 * v0 && vmin > 0, "step %d: volume", step);
        cc_faces ft = cc_count_faces(&m);
        T_CHECK(ft.more == 0 && ft.two <= f0.two && ft.one >= f0.one, "step %d: faces", step);
        aug_cut_step_free(&S);
    }
    T_CHECK(m.nn - nn0 == 15, "%lld nodes duplicated, want 15", (long long)(m.nn - nn0));
    /* inner faces of the window (both sides duplicated) are open: the cut
       surface of 2 x 4 squares, 2 triangles each, is boundary twice */
    cc_faces ft = cc_count_faces(&m);
    T_CHECK(ft.one - f0.one >= 2 * 16, "%lld new boundary faces, want >= 32",
            (long long)(ft.one - f0.one));
    aug_plane_free(&pc);
    aug_cutter_free(&C);
    cc_free(&T);
    aug_mesh_free(&m);
}

/* a polygon that holds no cut node, and a 2-D mesh, are refused */
static void refusals(void)
{
    aug_mesh m;
    aug_err e;
    cc_brick(&m, 3, 3, 6, 1, 1, 2, NULL, 0);
    aug_adj adj;
    aug_adj_build(&adj, &m);
    aug_plane_cut pc;
    double n[3] = {1, 0, 0}, far[] = {0.5, 5, 5, 0.5, 6, 5, 0.5, 6, 6};
    T_CHECK(aug_plane_plan(&pc, &m, &adj, n, 0.5, NULL, &e) == 0, "%s", e.msg);
    T_CHECK(aug_plane_restrict(&pc, &m, far, 3, &e) == AUG_EDATA, "empty polygon accepted");
    T_CHECK(aug_plane_restrict(&pc, &m, far, 2, &e) == AUG_EUSAGE, "two-point polygon accepted");
    aug_plane_free(&pc);
    aug_adj_free(&adj);
    aug_mesh_free(&m);
}

int main(void)
{
    cholmod_start(&cm);
    cm.print = 0;
    cm.error_handler = NULL;
    T_RUN(brick_window);
    T_RUN(refusals);
    cholmod_finish(&cm);
    T_EXIT();
}
