/* Unit tests of aug_import (tagged mesh -> aug_mesh) and the scene options (lib/mesh/scene.c). */
#include <string.h>
#include "aug_scene.h"
#include "t.h"

/* a unit cube split into 12 tets around its centre: corners tags 10*(i+1),
   centre tag 5, one unused node (tag 1000); element tags 100 - 7 k */
typedef struct cube {
    size_t ntag[10];
    double xyz[30];
    size_t etag[12], conn[48];
    aug_tagged t;
} cube;

static double det3(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], v[3], w[3];
    for (int i = 0; i < 3; i++) u[i] = b[i] - a[i], v[i] = c[i] - a[i], w[i] = d[i] - a[i];
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
}

static void make_cube(cube *c)
{
    memset(c, 0, sizeof *c);
    for (int i = 0; i < 8; i++) {
        c->ntag[i] = 10 * (size_t)(i + 1);
        c->xyz[3 * i] = i & 1, c->xyz[3 * i + 1] = (i >> 1) & 1, c->xyz[3 * i + 2] = (i >> 2) & 1;
    }
    c->ntag[8] = 5;
    c->xyz[24] = c->xyz[25] = c->xyz[26] = 0.5;
    c->ntag[9] = 1000;
    c->xyz[27] = NAN; /* unused, so harmless */
    static const int face[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                   {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
    int k = 0;
    for (int f = 0; f < 6; f++)
        for (int h = 0; h < 2; h++) {
            int a = face[f][0], b = face[f][1 + h], d = face[f][2 + h];
            if (det3(c->xyz + 3 * a, c->xyz + 3 * b, c->xyz + 3 * d, c->xyz + 24) < 0) {
                int s = b;
                b = d;
                d = s;
            }
            c->etag[k] = 100 - 7 * (size_t)k;
            c->conn[4 * k] = c->ntag[a], c->conn[4 * k + 1] = c->ntag[b];
            c->conn[4 * k + 2] = c->ntag[d], c->conn[4 * k + 3] = 5;
            k++;
        }
    c->t.etype = AUG_TET4;
    c->t.nnode = 10, c->t.node_tags = c->ntag, c->t.xyz = c->xyz;
    c->t.nelem = 12, c->t.elem_tags = c->etag, c->t.conn_tags = c->conn;
}

/* index of a tag among the used tags sorted ascending */
static int rank_of(const cube *c, size_t tag)
{
    int r = 0;
    for (int i = 0; i < 9; i++) r += c->ntag[i] < tag;
    return r;
}

static void t_renumber(void)
{
    cube c;
    make_cube(&c);
    aug_mesh m;
    aug_err e;
    int rc = aug_import(&c.t, 0, &m, &e);
    T_CHECK(rc == 0, "import: %s", e.msg);
    if (rc) return;
    T_CHECK(m.dim == 3 && m.nv == 4 && m.nn == 9 && m.ne == 12, "sizes %lld %lld", (long long)m.nn,
            (long long)m.ne);
    for (int i = 0; i < 9; i++) { /* node i is the (i)-th smallest used tag */
        int r = rank_of(&c, c.ntag[i]);
        for (int d = 0; d < 3; d++) T_CHECK(m.x[3 * r + d] == c.xyz[3 * i + d], "node %d coordinate", i);
    }
    for (int k = 0; k < 12; k++) { /* element k has the k-th smallest element tag: 100 - 7 (11 - k) */
        int src = 11 - k;
        T_CHECK(c.etag[src] == (size_t)(100 - 7 * (11 - k)), "tag order");
        for (int j = 0; j < 4; j++)
            T_CHECK(m.conn[4 * k + j] == rank_of(&c, c.conn[4 * src + j]), "element %d node %d", k, j);
        T_CHECK(aug_elem_measure(&m, k) > 0, "element %d measure", k);
    }
    T_CHECK(m.nmat == 1 && !strcmp(m.mats[0].name, "default") && m.mats[0].id == 0 &&
                m.mats[0].E == AUG_DEFAULT_E && m.mats[0].nu == AUG_DEFAULT_NU,
            "default material");
    const aug_set *b = aug_mesh_set(&m, "boundary");
    T_CHECK(b && b->n == 8, "boundary: the 8 corners, not the centre");
    for (int64_t i = 0; b && i < b->n; i++)
        T_CHECK(b->nodes[i] != rank_of(&c, 5), "centre on the boundary");
    aug_mesh_free(&m);
}

static void t_groups(void)
{
    cube c;
    make_cube(&c);
    size_t ea[] = {100, 93, 2000}, eb[] = {86, 79}, na[] = {10, 20, 1000, 20}, nb[] = {80}, nc[] = {30};
    aug_tagged_group g[4];
    memset(g, 0, sizeof g);
    g[0] = (aug_tagged_group){3, 9, "hard", 4, na, 3, ea};
    g[1] = (aug_tagged_group){3, 2, "soft", 1, nb, 2, eb};
    g[2] = (aug_tagged_group){0, 4, "", 1, nc, 0, NULL};
    g[3] = (aug_tagged_group){2, 1, "soft", 1, nc, 0, NULL}; /* same name: merged into the set */
    c.t.ngroup = 4, c.t.groups = g;
    aug_mesh m;
    aug_err e;
    int rc = aug_import(&c.t, 0, &m, &e);
    T_CHECK(rc == 0, "import: %s", e.msg);
    if (rc) return;
    T_CHECK(m.nmat == 3, "materials %d", m.nmat);
    T_CHECK(m.mats[0].id == 2 && !strcmp(m.mats[0].name, "soft"), "first material by tag");
    T_CHECK(m.mats[1].id == 9 && !strcmp(m.mats[1].name, "hard"), "second material");
    T_CHECK(m.mats[2].id == 0 && !strcmp(m.mats[2].name, "default"), "default last");
    for (int k = 0; k < 12; k++) { /* element k has tag 100 - 7 (11 - k) */
        size_t tag = 100 - 7 * (size_t)(11 - k);
        int want = (tag == 100 || tag == 93) ? 1 : (tag == 86 || tag == 79) ? 0 : 2;
        T_CHECK(m.mat[k] == want, "element %d (tag %zu) material %d, want %d", k, tag, m.mat[k], want);
    }
    T_CHECK(m.nset == 4, "sets %d", m.nset);
    T_CHECK(!strcmp(m.sets[0].name, "physical_0_4") && m.sets[0].n == 1 &&
                m.sets[0].nodes[0] == rank_of(&c, 30),
            "unnamed point group first (lowest dimension)");
    T_CHECK(!strcmp(m.sets[1].name, "soft") && m.sets[1].n == 2, "soft merged over dimensions 2 and 3");
    T_CHECK(!strcmp(m.sets[2].name, "hard") && m.sets[2].n == 2 && m.sets[2].nodes[0] == rank_of(&c, 10) &&
                m.sets[2].nodes[1] == rank_of(&c, 20),
            "hard: unused node dropped, repeats merged");
    T_CHECK(!strcmp(m.sets[3].name, "boundary"), "boundary last");
    aug_mesh_free(&m);

    size_t both[] = {100};
    g[1].elem_tags = both, g[1].nelem = 1;
    rc = aug_import(&c.t, 0, &m, &e);
    T_CHECK(rc == AUG_EDATA && strstr(e.msg, "element 11 (gmsh tag 100) is in two physical groups"),
            "two groups: %d %s", rc, e.msg);
}

static void t_inverted(void)
{
    cube c;
    make_cube(&c);
    size_t s = c.conn[4 * 3 + 1]; /* element with tag 79 = element 8 */
    c.conn[4 * 3 + 1] = c.conn[4 * 3 + 2];
    c.conn[4 * 3 + 2] = s;
    aug_mesh m;
    aug_err e;
    int rc = aug_import(&c.t, 0, &m, &e);
    T_CHECK(rc == AUG_EDATA && strstr(e.msg, "element 8 (gmsh tag 79) is inverted (volume -0.0833333)"),
            "inverted: %s", e.msg);
    rc = aug_import(&c.t, 1, &m, &e);
    T_CHECK(rc == 0, "reorient: %s", e.msg);
    for (int k = 0; !rc && k < 12; k++) T_CHECK(aug_elem_measure(&m, k) > 0, "element %d after reorient", k);
    if (!rc) aug_mesh_free(&m);
    c.xyz[24] = 0, c.xyz[25] = 0.5, c.xyz[26] = 0.5; /* centre onto the face x = 0 */
    rc = aug_import(&c.t, 1, &m, &e);
    T_CHECK(rc == AUG_EDATA && strstr(e.msg, "is degenerate (volume"), "degenerate: %s", e.msg);
}

static void t_bad_input(void)
{
    cube c;
    aug_mesh m;
    aug_err e;
    make_cube(&c);
    c.xyz[25] = INFINITY;
    int rc = aug_import(&c.t, 0, &m, &e);
    T_CHECK(rc == AUG_EDATA && strstr(e.msg, "node 0 (gmsh tag 5) has a non-finite coordinate"), "%s", e.msg);
    make_cube(&c);
    c.conn[5] = 77;
    rc = aug_import(&c.t, 0, &m, &e);
    T_CHECK(rc == AUG_EDATA && strstr(e.msg, "refers to node tag 77"), "%s", e.msg);
    make_cube(&c);
    c.ntag[3] = 10;
    rc = aug_import(&c.t, 0, &m, &e);
    T_CHECK(rc == AUG_EDATA && strstr(e.msg, "node tag 10 appears twice"), "%s", e.msg);
    make_cube(&c);
    c.etag[3] = c.etag[4];
    rc = aug_import(&c.t, 0, &m, &e);
    T_CHECK(rc == AUG_EDATA && strstr(e.msg, "appears twice"), "%s", e.msg);
    make_cube(&c);
    c.t.nelem = 0;
    rc = aug_import(&c.t, 0, &m, &e);
    T_CHECK(rc == AUG_EDATA && strstr(e.msg, "no elements"), "%s", e.msg);
}

/* a 2 x 1 rectangle in the plane z = z0 as 4 triangles around its centre */
static void t_plane(void)
{
    size_t nt[] = {1, 2, 3, 4, 5}, et[] = {1, 2, 3, 4};
    double xyz[] = {0, 0, 0.5, 2, 0, 0.5, 2, 1, 0.5, 0, 1, 0.5, 1, 0.5, 0.5};
    size_t conn[] = {1, 2, 5, 2, 3, 5, 3, 4, 5, 4, 1, 5};
    aug_tagged t = {AUG_TRI3, 5, nt, xyz, 4, et, conn, 0, NULL};
    aug_mesh m;
    aug_err e;
    int rc = aug_import(&t, 0, &m, &e);
    T_CHECK(rc == 0, "import: %s", e.msg);
    if (rc) return;
    T_CHECK(m.dim == 2 && m.nv == 3 && m.nn == 5 && m.ne == 4, "2-D sizes");
    double area = 0;
    for (int k = 0; k < 4; k++) area += aug_elem_measure(&m, k);
    T_CHECK(fabs(area - 2) < 1e-15, "area %g", area);
    T_CHECK(m.x[2] == 2 && m.x[3] == 0, "(x, y) kept, z dropped");
    const aug_set *b = aug_mesh_set(&m, "boundary");
    T_CHECK(b && b->n == 4, "boundary of the rectangle");
    aug_mesh_free(&m);
    xyz[14] = 0.6;
    rc = aug_import(&t, 0, &m, &e);
    T_CHECK(rc == AUG_EDATA && strstr(e.msg, "not plane"), "non-plane: %s", e.msg);
    xyz[14] = 0.5;
    conn[1] = 5, conn[2] = 2; /* clockwise */
    rc = aug_import(&t, 0, &m, &e);
    T_CHECK(rc == AUG_EDATA && strstr(e.msg, "element 0 (gmsh tag 1) is inverted (area -0.5)"), "cw: %s", e.msg);
}

/* every allocation failure is reported as such and leaves nothing behind (ASan checks leaks) */
static void t_malloc_failure(void)
{
    cube c;
    make_cube(&c);
    size_t ea[] = {100, 93}, na[] = {10, 20};
    aug_tagged_group g = {3, 9, "hard", 2, na, 2, ea};
    c.t.ngroup = 1, c.t.groups = &g;
    aug_mesh m;
    aug_err e;
    int n, rc = -1;
    for (n = 0; n < 200 && rc; n++) {
        aug_fail_after(n);
        rc = aug_import(&c.t, 0, &m, &e);
        aug_fail_after(-1);
        T_CHECK(rc == 0 || rc == AUG_ENOMEM, "failure %d gave %d (%s)", n, rc, e.msg);
        T_CHECK(rc == 0 || (m.x == NULL && m.sets == NULL && m.nset == 0), "failure %d left a mesh", n);
    }
    T_CHECK(rc == 0 && n > 5, "import never succeeded, or needed too few allocations (%d)", n);
    if (!rc) aug_mesh_free(&m);
}

static void t_scene(void)
{
    cube c;
    make_cube(&c);
    aug_mesh m;
    aug_err e;
    if (aug_import(&c.t, 0, &m, &e)) {
        T_CHECK(0, "import: %s", e.msg);
        return;
    }
    unsigned char mark[9] = {0};
    double lo[3] = {-1, -1, -0.1}, hi[3] = {2, 2, 0.1};
    T_CHECK(aug_nodes_in_box(&m, lo, hi, mark) == 4, "box z = 0");
    double n[3] = {0, 0, 2};
    T_CHECK(aug_nodes_on_plane(&m, n, 2, 1e-12, mark) == 4, "plane z = 1 (normal not unit)");
    int64_t marked = 0;
    for (int i = 0; i < 9; i++) marked += mark[i];
    T_CHECK(marked == 8, "both predicates mark the 8 corners");
    double p[3] = {0.45, 0.55, 0.5};
    T_CHECK(aug_nearest_node(&m, p) == rank_of(&c, 5), "nearest: the centre");
    T_CHECK(fabs(aug_mesh_extent(&m) - sqrt(3)) < 1e-15, "extent");
    memset(mark, 0, sizeof mark);
    mark[2] = mark[7] = 1;
    T_CHECK(aug_mesh_fix_marked(&m, mark, &e) == 0 && m.nfix == 6, "fix");
    T_CHECK(m.fix_dof[0] == 6 && m.fix_dof[5] == 23 && m.fix_val[3] == 0, "fix dofs");
    double f[27] = {0}, F[3] = {3, -6, 0.5};
    const aug_set *b = aug_mesh_set(&m, "boundary");
    aug_load_spread(&m, b->nodes, b->n, F, f);
    double s[3] = {0, 0, 0};
    for (int i = 0; i < 9; i++)
        for (int d = 0; d < 3; d++) s[d] += f[3 * i + d];
    T_CHECK(fabs(s[0] - 3) < 1e-14 && fabs(s[1] + 6) < 1e-14 && fabs(s[2] - 0.5) < 1e-14, "total force");
    T_CHECK(aug_mesh_set_load(&m, f, &e) == 0 && m.nload == 24, "load entries %lld", (long long)m.nload);
    T_CHECK(aug_mesh_set_output(&m, AUG_OUT_SET, "boundary", b->nodes, b->n, &e) == 0 && m.nout == 8 &&
                m.out_nodes[7] == b->nodes[7] && !strcmp(m.out_name, "boundary"),
            "output set");
    T_CHECK(aug_mesh_set_output(&m, AUG_OUT_ALL, "all", b->nodes, b->n, &e) == 0 && m.nout == 0,
            "output all has no list");
    aug_mesh_free(&m);
}

/* the imported mesh survives the stream: write, read back, compare */
static void t_roundtrip(void)
{
    cube c;
    make_cube(&c);
    aug_mesh m, r;
    aug_err e;
    if (aug_import(&c.t, 0, &m, &e)) {
        T_CHECK(0, "import: %s", e.msg);
        return;
    }
    unsigned char mark[9] = {1, 0, 0, 1, 0, 0, 0, 0, 1};
    double f[27] = {0};
    f[4] = 2.5;
    aug_mesh_fix_marked(&m, mark, &e);
    aug_mesh_set_load(&m, f, &e);
    aug_mesh_set_output(&m, AUG_OUT_ALL, "all", NULL, 0, &e);
    FILE *fp = tmpfile();
    aug_writer *w = aug_writer_open(fp, "test", &e);
    int rc = !w || aug_mesh_write(w, &m, &e) || aug_writer_close(w, &e);
    aug_writer_free(w);
    T_CHECK(!rc, "write: %s", e.msg);
    rewind(fp);
    aug_reader *rd = aug_reader_open(fp, "tmp", &e);
    aug_mesh_init(&r);
    aug_rec rec;
    memset(&rec, 0, sizeof rec);
    while (rd && (rc = aug_read(rd, &rec, &e)) == 1)
        if (aug_mesh_is_record(rec.type) && aug_mesh_absorb(&r, &rec, &e)) break;
    T_CHECK(rd && rc == 0, "read back: %s", e.msg);
    T_CHECK(r.nn == m.nn && r.ne == m.ne && !memcmp(r.x, m.x, 27 * sizeof(double)) &&
                !memcmp(r.conn, m.conn, 48 * sizeof(int32_t)) && r.nset == m.nset && r.nfix == 9 &&
                r.nload == 1 && r.load_val[0] == 2.5 && r.out_kind == AUG_OUT_ALL,
            "records differ");
    aug_rec_free(&rec);
    aug_reader_free(rd);
    fclose(fp);
    aug_mesh_free(&r);
    aug_mesh_free(&m);
}

int main(void)
{
    T_RUN(t_renumber);
    T_RUN(t_groups);
    T_RUN(t_inverted);
    T_RUN(t_bad_input);
    T_RUN(t_plane);
    T_RUN(t_malloc_failure);
    T_RUN(t_scene);
    T_RUN(t_roundtrip);
    T_EXIT();
}
