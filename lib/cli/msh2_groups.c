/* MSH 2 physical groups per element. An MSH 2 file gives every element its
   own physical tag (the first of its tags; 0: none), independently of its
   elementary entity; gmsh's API, which meshload reads the file through,
   attaches physical groups to entities, so an entity holding elements of
   several physical tags (or of a tag and 0) came back with every one of its
   elements in each of them: an element of physical tag 0 took the material
   of its neighbours in the entity without a word, and two materials in one
   entity (elementary tag 1, or 0 as TetWild writes) read as "an element in
   two physical groups". The file's $Elements section is read here and each
   physical group whose elements or nodes differ from the file's is given
   the file's. Runs in gmsh's child (gmsh_read.c), gmsh initialised. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "aug_gmsh.h"

typedef struct {
    size_t tag;
    int type, dim, phys;
    size_t off;          /* its node tags in nodes[off..off+nn) */
    int nn;
} msh2_elem;

typedef struct {
    msh2_elem *el;
    size_t nel, capel;
    size_t *nodes;
    size_t nnodes, capnodes;
    int props[128][2];   /* per MSH type: dim, node count (0: not yet asked) */
} msh2_file;

static int type_props(msh2_file *f, int type, int *dim, int *nn)
{
    if (type <= 0 || type >= 128) return -1;
    if (!f->props[type][1]) {
        int d, n;
        aug_gmsh_type(type, &d, &n, NULL);
        if (d < 0 || n <= 0) return -1;
        f->props[type][0] = d, f->props[type][1] = n;
    }
    *dim = f->props[type][0], *nn = f->props[type][1];
    return 0;
}

static int add_elem(msh2_file *f, size_t tag, int type, int phys, const size_t *nodes, int nn, int dim)
{
    if (f->nel == f->capel) {
        size_t c = f->capel ? 2 * f->capel : 1024;
        msh2_elem *p = realloc(f->el, c * sizeof *p);
        if (!p) return -1;
        f->el = p, f->capel = c;
    }
    if (f->nnodes + (size_t)nn > f->capnodes) {
        size_t c = f->capnodes ? 2 * f->capnodes : 4096;
        while (c < f->nnodes + (size_t)nn) c *= 2;
        size_t *p = realloc(f->nodes, c * sizeof *p);
        if (!p) return -1;
        f->nodes = p, f->capnodes = c;
    }
    f->el[f->nel++] = (msh2_elem){tag, type, dim, phys, f->nnodes, nn};
    memcpy(f->nodes + f->nnodes, nodes, (size_t)nn * sizeof *nodes);
    f->nnodes += (size_t)nn;
    return 0;
}

/* the $Elements section of an MSH 2 file (ASCII or binary); 1 when the file
   is not MSH 2, 0 read, -1 unreadable (gmsh read it: left to gmsh's view) */
static int read_elements(FILE *in, msh2_file *f)
{
    char line[256];
    double ver;
    int ft, ds;
    if (!fgets(line, sizeof line, in) || strncmp(line, "$MeshFormat", 11)) return -1;
    if (!fgets(line, sizeof line, in) || sscanf(line, "%lf %d %d", &ver, &ft, &ds) != 3) return -1;
    if (ver < 2 || ver >= 3) return 1;
    if (ft == 1) {
        int one;
        if (fread(&one, sizeof one, 1, in) != 1 || one != 1) return -1; /* another byte order */
    }
    while (fgets(line, sizeof line, in))
        if (!strncmp(line, "$Elements", 9)) break;
    if (feof(in) || !fgets(line, sizeof line, in)) return -1;
    unsigned long long count;
    if (sscanf(line, "%llu", &count) != 1) return -1;
    size_t nodes[64];
    if (ft == 0) {
        for (unsigned long long k = 0; k < count; k++) {
            unsigned long long tag;
            int type, ntags, dim, nn;
            if (fscanf(in, "%llu %d %d", &tag, &type, &ntags) != 3 || ntags < 0 || ntags > 64) return -1;
            if (type_props(f, type, &dim, &nn) || nn > 64) return -1;
            int phys = 0;
            for (int i = 0; i < ntags; i++) {
                long long v;
                if (fscanf(in, "%lld", &v) != 1) return -1;
                if (i == 0) phys = v > 0 && v < INT32_MAX ? (int)v : 0;
            }
            for (int i = 0; i < nn; i++) {
                unsigned long long v;
                if (fscanf(in, "%llu", &v) != 1) return -1;
                nodes[i] = (size_t)v;
            }
            if (add_elem(f, (size_t)tag, type, phys, nodes, nn, dim)) return -1;
        }
        return 0;
    }
    for (unsigned long long k = 0; k < count;) {
        int hdr[3], dim, nn;
        if (fread(hdr, sizeof(int), 3, in) != 3 || hdr[1] <= 0 || hdr[2] < 0 || hdr[2] > 64) return -1;
        if (type_props(f, hdr[0], &dim, &nn) || nn > 64) return -1;
        int rec[1 + 64 + 64];
        for (int j = 0; j < hdr[1] && k < count; j++, k++) {
            size_t w = (size_t)(1 + hdr[2] + nn);
            if (fread(rec, sizeof(int), w, in) != w) return -1;
            for (int i = 0; i < nn; i++) nodes[i] = (size_t)(unsigned)rec[1 + hdr[2] + i];
            int phys = hdr[2] > 0 && rec[1] > 0 ? rec[1] : 0;
            if (add_elem(f, (size_t)(unsigned)rec[0], hdr[0], phys, nodes, nn, dim)) return -1;
        }
    }
    return 0;
}

/* a[0..n) sorted, repeats removed; returns the new count */
static size_t sort_unique(size_t *a, size_t n)
{
    qsort(a, n, sizeof *a, aug_cmp_size);
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        if (!k || a[i] != a[k - 1]) a[k++] = a[i];
    return k;
}

/* do the n tags of a (any order, repeats) form the sorted unique set s[0..ns)? */
static int same_set(const size_t *a, size_t n, const size_t *s, size_t ns)
{
    size_t *c = malloc((n + 1) * sizeof *c);
    if (!c) return -1;
    if (n) memcpy(c, a, n * sizeof *c);
    size_t k = sort_unique(c, n);
    int same = k == ns && (k == 0 || !memcmp(c, s, k * sizeof *c));
    free(c);
    return same;
}

/* a malloc'd copy of a[0..n) (the child's reply takes it; gmsh's array it
   replaces is left: the child exits), NULL on memory */
static size_t *copy_tags(const size_t *a, size_t n)
{
    size_t *p = malloc((n + 1) * sizeof *p);
    if (p && n) memcpy(p, a, n * sizeof *p);
    return p;
}

static int msh_type_of(int etype)
{
    return etype == AUG_TET4 ? 4 : etype == AUG_HEX8 ? 5 : etype == AUG_TRI3 ? 2 : -1;
}

int aug_msh2_groups(const char *path, aug_tagged *t, aug_err *e)
{
    FILE *in = fopen(path, "rb");
    if (!in) return 0; /* gmsh read it; nothing to correct from here */
    msh2_file f;
    memset(&f, 0, sizeof f);
    int rc = read_elements(in, &f);
    fclose(in);
    if (rc) { /* not MSH 2, or not readable here: gmsh's groups stand */
        free(f.el), free(f.nodes);
        return 0;
    }
    int mtype = msh_type_of(t->etype);
    size_t *en = malloc((f.nel + 1) * sizeof *en), *nn = malloc((f.nnodes + 1) * sizeof *nn);
    if (!en || !nn) {
        free(f.el), free(f.nodes), free(en), free(nn);
        return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    }
    for (int gi = 0; gi < t->ngroup && !rc; gi++) {
        aug_tagged_group *g = &t->groups[gi];
        size_t ne = 0, nv = 0;
        for (size_t i = 0; i < f.nel; i++) {
            const msh2_elem *x = &f.el[i];
            if (x->dim != g->dim || x->phys != g->tag) continue;
            if (x->type == mtype) en[ne++] = x->tag;
            memcpy(nn + nv, f.nodes + x->off, (size_t)x->nn * sizeof *nn);
            nv += (size_t)x->nn;
        }
        ne = sort_unique(en, ne), nv = sort_unique(nn, nv);
        int se = g->elem_tags || g->nelem ? same_set(g->elem_tags, g->nelem, en, ne) : ne == 0;
        int sn = same_set(g->node_tags, g->nnode, nn, nv);
        if (se < 0 || sn < 0) {
            rc = aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
            break;
        }
        /* the elements only where gmsh listed them (the mesh's dimension) */
        int we = !se && g->dim == aug_etype_dim(t->etype), wn = !sn;
        size_t *pe = we ? copy_tags(en, ne) : NULL, *pn = wn ? copy_tags(nn, nv) : NULL;
        if ((we && !pe) || (wn && !pn)) {
            free(pe), free(pn);
            rc = aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
            break;
        }
        if (we) g->elem_tags = pe, g->nelem = ne;
        if (wn) g->node_tags = pn, g->nnode = nv;
    }
    free(f.el), free(f.nodes), free(en), free(nn);
    return rc;
}
