/* gmsh .msh files into aug_tagged through the gmsh C API, run in a child process
   so that a crash of gmsh is an error of the file, never one of meshload. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <gmshc.h>
#include "aug_gmsh.h"

void aug_gmsh_free(aug_tagged *t)
{
    free(t->node_tags);
    free(t->xyz);
    free(t->elem_tags);
    free(t->conn_tags);
    for (int i = 0; i < t->ngroup; i++) {
        free(t->groups[i].node_tags);
        free(t->groups[i].elem_tags);
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
    struct stat st;
    /* gmsh opens the file by name and seeks in it: a pipe (/dev/stdin of
       cat f.msh |) read as "truncated" */
    if (fstat(fileno(f), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) {
        fclose(f);
        return aug_err_set(e, AUG_EDATA, -1, "", "not a regular file (gmsh reads a file by its name, not a pipe)");
    }
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

static unsigned long long gmsh_cap(const char *path);
static const char *cap_note(const char *path, char note[96]);

/* "gmsh could not WHAT: gmsh's last error", or " (NONE)" after WHAT when gmsh
   gave no reason (none NULL: nothing) */
static int gmsh_error_or(aug_err *e, const char *what, const char *none)
{
    char *msg = NULL;
    int ierr;
    gmshLoggerGetLastError(&msg, &ierr);
    if (msg && msg[0]) aug_err_set(e, AUG_EDATA, -1, "", "gmsh could not %s: %s", what, msg);
    else aug_err_set(e, AUG_EDATA, -1, "", "gmsh could not %s%s%s%s", what, none ? " (" : "", none ? none : "",
                     none ? ")" : "");
    gmshFree(msg);
    return e->code;
}

static int gmsh_error(aug_err *e, const char *what) { return gmsh_error_or(e, what, NULL); }

/* the name and dimension of a gmsh element type (dim -1 when gmsh does not know it) */
void aug_gmsh_type(int type, int *dim, int *nnodes, char name[AUG_NAME])
{
    char *s = NULL;
    double *lc = NULL;
    size_t nlc;
    int order, nn, nprim, ierr;
    gmshModelMeshGetElementProperties(type, &s, dim, &order, &nn, &lc, &nlc, &nprim, &ierr);
    if (name) snprintf(name, AUG_NAME, "%s", !ierr && s ? s : "?");
    if (ierr) *dim = -1;
    if (nnodes) *nnodes = ierr ? 0 : nn;
    gmshFree(s);
    gmshFree(lc);
}

/* What gmsh logged while reading: a repeated node or element tag (gmsh keeps
   one of the definitions and goes on), and the element count of each $Elements
   header, summed into *declared (0 when gmsh logged none). */
static int check_log(size_t *declared, aug_err *e)
{
    char **log = NULL;
    size_t nlog = 0, tag;
    int ierr, rc = 0, pos;
    gmshLoggerGet(&log, &nlog, &ierr);
    *declared = 0;
    for (size_t i = 0; i < nlog; i++) {
        const char *s = strchr(log[i], ':');
        s = s ? s + 2 : log[i];
        pos = -1;
        if (!rc && sscanf(s, "Skipping duplicate node %zu", &tag) == 1)
            rc = aug_err_set(e, AUG_EDATA, -1, "", "node tag %zu appears twice (or as a tag of 2^32 or more, which gmsh "
                             "reads modulo 2^32)", tag);
        else if (!rc && sscanf(s, "Skipping duplicate element %zu", &tag) == 1)
            rc = aug_err_set(e, AUG_EDATA, -1, "", "element tag %zu appears twice (or as a tag of 2^32 or more, which "
                             "gmsh reads modulo 2^32)", tag);
        else if (!strncmp(log[i], "Info: ", 6) && sscanf(s, "%zu element%n", &tag, &pos) == 1 &&
                 pos > 0 && (!s[pos] || !strcmp(s + pos, "s")))
            *declared += tag;
        gmshFree(log[i]);
    }
    gmshFree(log);
    return rc;
}

/* the element type of the mesh: tet4 or hex8 (one of them) if there are
   volume elements, else tri3 */
static int mesh_type(int *etype, aug_err *e)
{
    int *types = NULL, ierr, top = -1, rc = 0, ntet = 0, nhex = 0;
    size_t n = 0;
    char name[AUG_NAME];
    gmshModelMeshGetElementTypes(&types, &n, -1, -1, &ierr);
    if (ierr) return gmsh_error(e, "list the element types");
    int dims[64];
    for (size_t i = 0; i < n && i < 64; i++) {
        aug_gmsh_type(types[i], &dims[i], NULL, name);
        if (dims[i] > top) top = dims[i];
    }
    for (size_t i = 0; i < n && i < 64; i++)
        if (dims[i] == 3) ntet += types[i] == AUG_TET4, nhex += types[i] == AUG_HEX8;
    *etype = top == 3 ? (nhex ? AUG_HEX8 : AUG_TET4) : AUG_TRI3;
    if (top < 2) rc = aug_err_set(e, AUG_EDATA, -1, "", "the mesh has no tetrahedra, hexahedra or triangles");
    for (size_t i = 0; i < n && i < 64 && !rc; i++)
        if (dims[i] == top && types[i] != *etype && !(top == 3 && types[i] == AUG_TET4)) {
            int d;
            aug_gmsh_type(types[i], &d, NULL, name);
            rc = aug_err_set(e, AUG_EDATA, -1, "",
                             "element type %d (%s) is not supported: a %d-D mesh must be all %s",
                             types[i], name, top, top == 3 ? "tet4 or all hex8" : "tri3");
        }
    if (!rc && ntet && nhex)
        rc = aug_err_set(e, AUG_EDATA, -1, "",
                         "the mesh mixes tetrahedra (tet4) and hexahedra (hex8): one element type per mesh");
    gmshFree(types);
    return rc;
}

/* The elements of type etype in the entities of dimension dim (tag -1: all of
   them, else the one entity (dim, tag)) and their node tags. Through
   gmshModelMeshGetElements, which copies element by element: gmsh 4.8's
   getElementsByType sizes its arrays by the type of an entity's first element
   and writes past them when a later one has more nodes. */
static int elements_of_type(int etype, int dim, int tag, size_t **et, size_t *net, size_t **ct,
                            size_t *nct, aug_err *e)
{
    int *types = NULL, ierr;
    size_t ntypes = 0, **etags = NULL, *etn = NULL, netn = 0, **ntags = NULL, *ntn = NULL, nntn = 0;
    gmshModelMeshGetElements(&types, &ntypes, &etags, &etn, &netn, &ntags, &ntn, &nntn, dim, tag, &ierr);
    *et = *ct = NULL;
    *net = *nct = 0;
    for (size_t i = 0; i < ntypes && i < netn && i < nntn; i++) {
        if (types[i] == etype && !*et) {
            *et = etags[i], *net = etn[i], *ct = ntags[i], *nct = ntn[i];
            continue;
        }
        gmshFree(etags[i]);
        gmshFree(ntags[i]);
    }
    gmshFree(types);
    gmshFree(etags);
    gmshFree(etn);
    gmshFree(ntags);
    gmshFree(ntn);
    if (ierr) return gmsh_error(e, "read the elements");
    return 0;
}

/* how many elements gmsh holds in the family (tetrahedra, triangles, ...) of
   type, in the entities it lists under type: one barycenter each */
static size_t family_count(int type)
{
    double *b = NULL;
    size_t nb = 0;
    int ierr;
    gmshModelMeshGetBarycenters(type, -1, 1, 1, &b, &nb, 0, 1, &ierr);
    gmshFree(b);
    return ierr ? 0 : nb / 3;
}

int aug_cmp_size(const void *a, const void *b)
{
    size_t x = *(const size_t *)a, y = *(const size_t *)b;
    return x < y ? -1 : x > y;
}

/* the tag of an element of dimension dim and type other than etype: tags
   from 1 up, skipping those of known[n], at most 2^18 lookups; 0 if none */
static size_t foreign_element(int etype, int dim, const size_t *known, size_t n, int *type)
{
    size_t *k = malloc((n ? n : 1) * sizeof *k), j = 0;
    if (!k) return 0;
    memcpy(k, known, n * sizeof *k);
    qsort(k, n, sizeof *k, aug_cmp_size);
    for (size_t tag = 1, tries = 0; tries < (1u << 18); tag++) {
        while (j < n && k[j] < tag) j++;
        if (j < n && k[j] == tag) continue;
        tries++;
        size_t *nodes = NULL, nn;
        int ierr, d;
        char name[AUG_NAME];
        gmshModelMeshGetElement(tag, type, &nodes, &nn, &ierr);
        gmshFree(nodes);
        if (ierr || *type == etype) continue;
        aug_gmsh_type(*type, &d, NULL, name);
        if (d == dim) {
            free(k);
            return tag;
        }
    }
    free(k);
    return 0;
}

/* Every element of the mesh's dimension is of type etype (nelem of them, tags
   et): gmsh lists an entity's types by its first element, so a quadratic
   tetrahedron among linear ones shows only in the count of the family. */
static int check_orders(int etype, const size_t *et, size_t nelem, aug_err *e)
{
    size_t all = family_count(etype);
    if (all <= nelem) return 0;
    int dim = aug_etype_dim(etype), type = 0;
    const char *want = aug_etype_name(etype);
    gmshLoggerStop(&(int){0});
    size_t tag = foreign_element(etype, dim, et, nelem, &type);
    if (tag) {
        char name[AUG_NAME];
        aug_gmsh_type(type, &dim, NULL, name);
        return aug_err_set(e, AUG_EDATA, -1, "",
                           "element type %d (%s) is not supported: a %d-D mesh must be all %s "
                           "(gmsh tag %zu, among %s elements)", type, name, dim, want, tag, want);
    }
    return aug_err_set(e, AUG_EDATA, -1, "",
                       "%zu element%s of a %s %s of another order than %s: a %d-D mesh must be all %s",
                       all - nelem, all - nelem > 1 ? "s" : "", dim == 3 ? "volume" : "surface",
                       all - nelem > 1 ? "are" : "is", want, dim, want);
}

/* the element count of the $Elements headers against the elements gmsh holds
   (of any type and dimension): gmsh keeps one of two elements with the same
   tag of an MSH 2 file and says nothing */
static int check_count(size_t declared, aug_err *e)
{
    int *types = NULL, ierr;
    size_t n = 0, held = 0;
    gmshModelMeshGetElementTypes(&types, &n, -1, -1, &ierr);
    if (ierr) return gmsh_error(e, "list the element types");
    for (size_t i = 0; i < n; i++) held += family_count(types[i]);
    gmshFree(types);
    if (declared > held)
        return aug_err_set(e, AUG_EDATA, -1, "",
                           "the file's $Elements headers declare %zu elements but gmsh holds %zu: a count past the "
                           "elements given, or an element tag that appears twice", declared, held);
    return 0;
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
    if (ierr || nxyz != 3 * g->nnode) return gmsh_error(e, "read the nodes of a physical group");
    if (dim != topdim) return 0;
    int *ent = NULL;
    size_t nent = 0;
    gmshModelGetEntitiesForPhysicalGroup(dim, tag, &ent, &nent, &ierr);
    if (ierr) return gmsh_error(e, "read the entities of a physical group");
    int rc = 0;
    for (size_t i = 0; i < nent && !rc; i++) {
        size_t *et = NULL, *ct = NULL, net, nct;
        if ((rc = elements_of_type(etype, dim, ent[i], &et, &net, &ct, &nct, e))) break;
        gmshFree(ct);
        if (nct != net * (size_t)aug_etype_nv(etype)) {
            gmshFree(et);
            rc = gmsh_error(e, "read the elements of a physical group");
            break;
        }
        size_t *all = realloc(g->elem_tags, (g->nelem + net + 1) * sizeof *all);
        if (!all) rc = aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        else if (net) memcpy(all + g->nelem, et, net * sizeof *all);
        gmshFree(et);
        if (all) g->elem_tags = all, g->nelem += net;
    }
    gmshFree(ent);
    return rc;
}

/* t := the mesh of the file; runs in the child (which exits after sending t,
   so nothing here is freed) */
static int read_model(const char *path, aug_tagged *t, aug_err *e)
{
    int ierr, rc;
    size_t declared;
    gmshOpen(path, &ierr);
    if (ierr) { /* no reason given: out of memory, as a rule */
        char note[96], why[160];
        snprintf(why, sizeof why, "out of memory%s: a count in the file past its data?", cap_note(path, note));
        return gmsh_error_or(e, "read it", why);
    }
    if ((rc = check_log(&declared, e)) || (rc = mesh_type(&t->etype, e))) return rc;
    double *pc = NULL;
    size_t ncoord, npc;
    gmshModelMeshGetNodes(&t->node_tags, &t->nnode, &t->xyz, &ncoord, &pc, &npc, -1, -1, 0, 0, &ierr);
    gmshFree(pc);
    if (ierr || ncoord != 3 * t->nnode) return gmsh_error(e, "read the nodes");
    int topdim = aug_etype_dim(t->etype);
    size_t nconn;
    if ((rc = elements_of_type(t->etype, topdim, -1, &t->elem_tags, &t->nelem, &t->conn_tags, &nconn, e)))
        return rc;
    if (nconn != t->nelem * (size_t)aug_etype_nv(t->etype)) return gmsh_error(e, "read the elements");
    if ((rc = check_orders(t->etype, t->elem_tags, t->nelem, e)) || (rc = check_count(declared, e)))
        return rc;
    int *dt = NULL;
    size_t ndt;
    gmshModelGetPhysicalGroups(&dt, &ndt, -1, &ierr);
    if (ierr) return gmsh_error(e, "read the physical groups");
    t->groups = calloc(ndt / 2 + 1, sizeof *t->groups);
    if (!t->groups) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    for (size_t i = 0; i + 1 < ndt && !rc; i += 2)
        rc = read_group(dt[i], dt[i + 1], t->etype, topdim, &t->groups[t->ngroup++], e);
    gmshFree(dt);
    /* an MSH 2 file's groups per element, not per entity (msh2_groups.c) */
    if (!rc) rc = aug_msh2_groups(path, t, e);
    if (!rc) rc = aug_physical_names(path, t, e);
    return rc;
}

/* The address space the gmsh child may take (bytes): 2 GiB plus 64 bytes
   per byte of the file (gmsh holds a mesh in a few times its text), or
   AUG_GMSH_MEM_MB MiB. A count in the file is believed by gmsh before the
   data behind it: one number changed in a 230-byte .msh (1,174,405,122
   elements) took the child past 12 GB of the shared machine before it
   failed; capped, it fails at once. */
static unsigned long long gmsh_cap(const char *path)
{
#if defined(__SANITIZE_ADDRESS__)
    /* ASan reserves terabytes of address space for its shadow: no cap of
       it can hold (tests/run.sh gives the ASan tools max_allocation_size_mb
       instead) */
    (void)path;
    return 0;
#endif
    const char *env = getenv("AUG_GMSH_MEM_MB");
    char *end;
    if (env && *env) {
        unsigned long long mb = strtoull(env, &end, 10);
        if (*end == 0 && mb > 0 && mb < (1ull << 40)) return mb << 20;
    }
    struct stat st;
    unsigned long long size = stat(path, &st) == 0 && st.st_size > 0 ? (unsigned long long)st.st_size : 0;
    return (2ull << 30) + (size < (1ull << 50) / 64 ? 64 * size : 1ull << 50);
}

/* note := " at the cap of N MiB (AUG_GMSH_MEM_MB)", or "" without a cap */
static const char *cap_note(const char *path, char note[96])
{
    unsigned long long cap = gmsh_cap(path);
    if (cap) snprintf(note, 96, " at the cap of %llu MiB (AUG_GMSH_MEM_MB)", cap >> 20);
    else note[0] = 0;
    return note;
}

/* The child: gmsh reads the file with its messages kept (stdout and stderr
   on /dev/null, no core file, its address space capped: gmsh_cap) and the
   reply goes to fd. Never returns. */
static void child(const char *path, int fd)
{
    aug_tagged t;
    aug_err e;
    int ierr, rc, null = open("/dev/null", O_WRONLY);
    struct rlimit nocore = {0, 0}, as;
    setrlimit(RLIMIT_CORE, &nocore);
    rlim_t cap = (rlim_t)gmsh_cap(path);
    if (cap > 0 && getrlimit(RLIMIT_AS, &as) == 0) {
        if (as.rlim_cur == RLIM_INFINITY || as.rlim_cur > cap) {
            as.rlim_cur = cap;
            setrlimit(RLIMIT_AS, &as);
        }
    }
    if (null < 0 || dup2(null, 1) < 0 || dup2(null, 2) < 0) _exit(3);
    close(null);
    memset(&t, 0, sizeof t);
    aug_err_clear(&e);
    gmshInitialize(0, NULL, 0, &ierr);
    if (ierr) {
        rc = aug_err_set(&e, AUG_EIO, -1, "", "gmsh failed to initialise");
    } else {
        gmshOptionSetNumber("General.Terminal", 0, &ierr);
        gmshLoggerStart(&ierr);
        rc = read_model(path, &t, &e);
    }
    _exit(aug_tagged_send(fd, rc, &t, &e) ? 4 : 0);
}

int aug_gmsh_read(const char *path, aug_tagged *t, aug_err *e)
{
    memset(t, 0, sizeof *t);
    aug_err_clear(e);
    int rc = check_file(path, e), fd[2], status;
    if (rc) return rc;
    fflush(stdout);
    fflush(stderr);
    pid_t pid;
    if (pipe(fd) < 0) return aug_err_set(e, AUG_EIO, -1, "", "cannot start gmsh: %s", strerror(errno));
    if ((pid = fork()) < 0) {
        rc = errno;
        close(fd[0]);
        close(fd[1]);
        return aug_err_set(e, AUG_EIO, -1, "", "cannot start gmsh: %s", strerror(rc));
    }
    if (pid == 0) {
        close(fd[0]);
        child(path, fd[1]);
    }
    close(fd[1]);
    rc = aug_tagged_recv(fd[0], t, e);
    close(fd[0]);
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) {
            status = -1;
            break;
        }
    if (status == 0 && rc >= 0) return rc;
    aug_gmsh_free(t);
    char note[96];
    cap_note(path, note);
    /* an abort (an uncaught bad_alloc) may be the cap; a SIGSEGV is gmsh's own */
    if (status != -1 && WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT)
        return aug_err_set(e, AUG_EDATA, -1, "", "gmsh failed to read the file (signal %d: out of memory%s? a count "
                           "in the file past its data?)", WTERMSIG(status), note);
    if (status != -1 && WIFSIGNALED(status))
        return aug_err_set(e, AUG_EDATA, -1, "", "gmsh failed to read the file (signal %d)", WTERMSIG(status));
    if (status != -1 && WIFEXITED(status) && WEXITSTATUS(status))
        return aug_err_set(e, AUG_EDATA, -1, "", "gmsh failed to read the file (exit status %d)", WEXITSTATUS(status));
    return aug_err_set(e, AUG_EIO, -1, "", "gmsh failed to read the file (its reply is incomplete)");
}
