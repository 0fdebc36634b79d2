/* gmsh .msh files into aug_tagged through the gmsh C API, with gmsh kept off stdout. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <gmshc.h>
#include "aug_gmsh.h"

void aug_gmsh_free(aug_tagged *t)
{
    gmshFree(t->node_tags);
    gmshFree(t->xyz);
    gmshFree(t->elem_tags);
    gmshFree(t->conn_tags);
    for (int i = 0; i < t->ngroup; i++) {
        gmshFree(t->groups[i].node_tags);
        gmshFree(t->groups[i].elem_tags);
    }
    free(t->groups);
    memset(t, 0, sizeof *t);
}

/* the file exists, is readable, begins with $MeshFormat (so that gmsh never
   takes it for a .geo script) and ends with a $End... line: gmsh silently
   accepts a file cut short inside a section */
static int check_file(const char *path, aug_err *e)
{
    FILE *f = fopen(path, "rb");
    if (!f) return aug_err_set(e, AUG_EIO, -1, "", "%s", strerror(errno));
    char head[12] = {0}, tail[257] = {0};
    size_t n = fread(head, 1, 11, f), m = 0;
    if (!ferror(f) && fseek(f, 0, SEEK_END) == 0) {
        long size = ftell(f);
        if (size >= 0 && fseek(f, size > 256 ? size - 256 : 0, SEEK_SET) == 0)
            m = fread(tail, 1, 256, f);
    }
    int rd = ferror(f) ? errno : 0;
    fclose(f);
    if (rd) return aug_err_set(e, AUG_EIO, -1, "", "%s", strerror(rd));
    if (n == 11 && memcmp(head, "$NOD", 4) == 0)
        return aug_err_set(e, AUG_EDATA, -1, "", "MSH version 1 is not supported (convert: gmsh FILE -0 -format msh41)");
    if (n < 11 || memcmp(head, "$MeshFormat", 11) != 0)
        return aug_err_set(e, AUG_EDATA, -1, "", "not a gmsh .msh file (it does not begin with $MeshFormat)");
    while (m > 0 && memchr(" \t\r\n", tail[m - 1], 4)) tail[--m] = 0;
    char *last = tail + m;
    while (last > tail && last[-1] != '\n') last--;
    if (strncmp(last, "$End", 4) != 0)
        return aug_err_set(e, AUG_EDATA, -1, "", "truncated: the file does not end with a $End... line");
    return 0;
}

static int gmsh_error(aug_err *e, const char *what)
{
    char *msg = NULL;
    int ierr;
    gmshLoggerGetLastError(&msg, &ierr);
    aug_err_set(e, AUG_EDATA, -1, "", "gmsh could not %s%s%s", what, msg && msg[0] ? ": " : "",
                msg ? msg : "");
    gmshFree(msg);
    return e->code;
}

/* the element type of the mesh: tet4 if there are volume elements, else tri3 */
static int mesh_type(int *etype, aug_err *e)
{
    int *types = NULL, ierr, top = -1, rc = 0;
    size_t n = 0;
    gmshModelMeshGetElementTypes(&types, &n, -1, -1, &ierr);
    if (ierr) return gmsh_error(e, "list the element types");
    int dims[64];
    for (size_t i = 0; i < n && i < 64; i++) {
        char *name = NULL;
        double *lc = NULL;
        size_t nlc;
        int order, nnodes, nprim;
        gmshModelMeshGetElementProperties(types[i], &name, &dims[i], &order, &nnodes, &lc, &nlc,
                                          &nprim, &ierr);
        gmshFree(name);
        gmshFree(lc);
        if (ierr) dims[i] = -1;
        if (dims[i] > top) top = dims[i];
    }
    *etype = top == 3 ? 4 : 2;
    if (top < 2) rc = aug_err_set(e, AUG_EDATA, -1, "", "the mesh has no tetrahedra or triangles");
    for (size_t i = 0; i < n && i < 64 && !rc; i++)
        if (dims[i] == top && types[i] != *etype) {
            char *name = NULL;
            double *lc = NULL;
            size_t nlc;
            int d, order, nnodes, nprim;
            gmshModelMeshGetElementProperties(types[i], &name, &d, &order, &nnodes, &lc, &nlc,
                                              &nprim, &ierr);
            rc = aug_err_set(e, AUG_EDATA, -1, "",
                             "element type %d (%s) is not supported: a %d-D mesh must be all %s",
                             types[i], name ? name : "?", top, top == 3 ? "tet4" : "tri3");
            gmshFree(name);
            gmshFree(lc);
        }
    gmshFree(types);
    return rc;
}

/* the physical group (dim, tag): name, node tags, and its elements of type etype */
static int read_group(int dim, int tag, int etype, int topdim, aug_tagged_group *g, aug_err *e)
{
    int ierr;
    char *name = NULL;
    g->dim = dim;
    g->tag = tag;
    gmshModelGetPhysicalName(dim, tag, &name, &ierr);
    if (ierr) return gmsh_error(e, "read a physical name");
    size_t len = strlen(name);
    if (len >= AUG_NAME) {
        aug_err_set(e, AUG_EDATA, -1, "", "physical group %d (dimension %d) has a name of %zu bytes (at most %d)",
                    tag, dim, len, AUG_NAME - 1);
        gmshFree(name);
        return e->code;
    }
    memcpy(g->name, name, len + 1);
    gmshFree(name);
    double *xyz = NULL;
    size_t nxyz;
    gmshModelMeshGetNodesForPhysicalGroup(dim, tag, &g->node_tags, &g->nnode, &xyz, &nxyz, &ierr);
    gmshFree(xyz);
    if (ierr) return gmsh_error(e, "read the nodes of a physical group");
    if (dim != topdim) return 0;
    int *ent = NULL;
    size_t nent = 0;
    gmshModelGetEntitiesForPhysicalGroup(dim, tag, &ent, &nent, &ierr);
    if (ierr) return gmsh_error(e, "read the entities of a physical group");
    for (size_t i = 0; i < nent; i++) {
        size_t *et = NULL, *ct = NULL, net, nct;
        gmshModelMeshGetElementsByType(etype, &et, &net, &ct, &nct, ent[i], 0, 1, &ierr);
        gmshFree(ct);
        if (ierr) {
            gmshFree(et);
            gmshFree(ent);
            return gmsh_error(e, "read the elements of a physical group");
        }
        size_t *all = gmshMalloc((g->nelem + net + 1) * sizeof *all);
        if (!all) {
            gmshFree(et);
            gmshFree(ent);
            return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        }
        if (g->nelem) memcpy(all, g->elem_tags, g->nelem * sizeof *all);
        if (net) memcpy(all + g->nelem, et, net * sizeof *all);
        gmshFree(g->elem_tags);
        gmshFree(et);
        g->elem_tags = all;
        g->nelem += net;
    }
    gmshFree(ent);
    return 0;
}

static int read_model(const char *path, aug_tagged *t, aug_err *e)
{
    int ierr, rc;
    gmshOpen(path, &ierr);
    if (ierr) return gmsh_error(e, "read it");
    if ((rc = mesh_type(&t->etype, e))) return rc;
    double *pc = NULL;
    size_t ncoord, npc;
    gmshModelMeshGetNodes(&t->node_tags, &t->nnode, &t->xyz, &ncoord, &pc, &npc, -1, -1, 0, 0, &ierr);
    gmshFree(pc);
    if (ierr || ncoord != 3 * t->nnode) return gmsh_error(e, "read the nodes");
    size_t nconn;
    gmshModelMeshGetElementsByType(t->etype, &t->elem_tags, &t->nelem, &t->conn_tags, &nconn, -1, 0,
                                   1, &ierr);
    if (ierr || nconn != t->nelem * (t->etype == 4 ? 4 : 3)) return gmsh_error(e, "read the elements");
    int *dt = NULL;
    size_t ndt;
    gmshModelGetPhysicalGroups(&dt, &ndt, -1, &ierr);
    if (ierr) return gmsh_error(e, "read the physical groups");
    t->groups = calloc(ndt / 2 + 1, sizeof *t->groups);
    if (!t->groups) {
        gmshFree(dt);
        return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    }
    int topdim = t->etype == 4 ? 3 : 2;
    for (size_t i = 0; i + 1 < ndt; i += 2) {
        rc = read_group(dt[i], dt[i + 1], t->etype, topdim, &t->groups[t->ngroup++], e);
        if (rc) break;
    }
    gmshFree(dt);
    return rc;
}

int aug_gmsh_read(const char *path, aug_tagged *t, aug_err *e)
{
    memset(t, 0, sizeof *t);
    aug_err_clear(e);
    int rc = check_file(path, e);
    if (rc) return rc;
    /* gmsh writes messages to stdout: point it at /dev/null while gmsh runs */
    fflush(stdout);
    int saved = dup(1), null = open("/dev/null", O_WRONLY);
    if (saved < 0 || null < 0 || dup2(null, 1) < 0) {
        if (saved >= 0) close(saved);
        if (null >= 0) close(null);
        return aug_err_set(e, AUG_EIO, -1, "", "cannot redirect gmsh's output: %s", strerror(errno));
    }
    close(null);
    int ierr;
    gmshInitialize(0, NULL, 0, &ierr);
    if (ierr) {
        rc = aug_err_set(e, AUG_EIO, -1, "", "gmsh failed to initialise");
    } else {
        gmshOptionSetNumber("General.Terminal", 0, &ierr);
        gmshLoggerStart(&ierr);
        rc = read_model(path, t, e);
        gmshLoggerStop(&ierr);
        gmshFinalize(&ierr);
    }
    fflush(stdout);
    dup2(saved, 1);
    close(saved);
    if (rc) aug_gmsh_free(t);
    return rc;
}
