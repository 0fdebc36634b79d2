/* aug_tagged over a pipe: the private framing between meshload's gmsh child and its parent. */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "aug_gmsh.h"

/* The reply, in the byte order and sizes of the one binary on both ends:
     u32 magic "AGT1", i32 code
     code != 0:  u32 len, len bytes of message (< 256)
     code == 0:  i32 etype
                 size_t nnode, node_tags[nnode], double xyz[3 nnode]
                 size_t nelem, elem_tags[nelem], conn_tags[nv nelem]
                 i32 ngroup, then per group: i32 dim, i32 tag, char name[AUG_NAME],
                     size_t nnode, node_tags[nnode], size_t nelem, elem_tags[nelem]
     u32 magic "END1", then the end of the pipe. */
#define MAGIC_BEGIN 0x31544741u /* "AGT1" */
#define MAGIC_END 0x31444e45u   /* "END1" */

/* all n bytes of p written (out) or read; -1 on an error or the end of the pipe */
static int xfer(int fd, void *p, size_t n, int out)
{
    char *c = p;
    while (n > 0) {
        ssize_t k = out ? write(fd, c, n) : read(fd, c, n);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) return -1;
        c += k;
        n -= (size_t)k;
    }
    return 0;
}

static int put(int fd, const void *p, size_t n) { return xfer(fd, (void *)p, n, 1); }
static int get(int fd, void *p, size_t n) { return xfer(fd, p, n, 0); }

/* a count, then count*width items */
static int put_array(int fd, size_t count, const void *v, size_t width)
{
    return put(fd, &count, sizeof count) || (count && put(fd, v, count * width)) ? -1 : 0;
}

static int put_i32(int fd, int32_t v)
{
    return put(fd, &v, sizeof v);
}

int aug_tagged_send(int fd, int code, const aug_tagged *t, const aug_err *e)
{
    uint32_t magic = MAGIC_BEGIN, end = MAGIC_END;
    if (put(fd, &magic, sizeof magic) || put_i32(fd, code)) return -1;
    if (code) {
        uint32_t len = (uint32_t)strnlen(e->msg, sizeof e->msg - 1);
        if (put(fd, &len, sizeof len) || put(fd, e->msg, len)) return -1;
        return put(fd, &end, sizeof end);
    }
    size_t nv = (size_t)aug_etype_nv(t->etype);
    if (put_i32(fd, t->etype) || put_array(fd, t->nnode, t->node_tags, sizeof(size_t)) ||
        (t->nnode && put(fd, t->xyz, 3 * t->nnode * sizeof(double))) ||
        put_array(fd, t->nelem, t->elem_tags, sizeof(size_t)) ||
        (t->nelem && put(fd, t->conn_tags, nv * t->nelem * sizeof(size_t))) || put_i32(fd, t->ngroup))
        return -1;
    for (int i = 0; i < t->ngroup; i++) {
        const aug_tagged_group *g = &t->groups[i];
        if (put_i32(fd, g->dim) || put_i32(fd, g->tag) || put(fd, g->name, AUG_NAME) ||
            put_array(fd, g->nnode, g->node_tags, sizeof(size_t)) ||
            put_array(fd, g->nelem, g->elem_tags, sizeof(size_t)))
            return -1;
    }
    return put(fd, &end, sizeof end);
}

/* *v = groups of width bytes (count of them, count*groups items read) */
static int get_items(int fd, size_t count, size_t groups, size_t width, void **v)
{
    *v = NULL;
    if (count == 0) return 0;
    if (count > SIZE_MAX / groups / width) return -1;
    if (!(*v = malloc(count * groups * width))) return -1;
    return get(fd, *v, count * groups * width);
}

static int get_array(int fd, size_t *count, void **v)
{
    *v = NULL;
    return get(fd, count, sizeof *count) || get_items(fd, *count, 1, sizeof(size_t), v) ? -1 : 0;
}

static int get_i32(int fd, int *v)
{
    int32_t x;
    if (get(fd, &x, sizeof x)) return -1;
    *v = x;
    return 0;
}

static int get_mesh(int fd, aug_tagged *t)
{
    void *p;
    if (get_i32(fd, &t->etype) || !aug_etype_nv(t->etype)) return -1;
    int rc = get_array(fd, &t->nnode, &p);
    t->node_tags = p;
    if (rc || get_items(fd, t->nnode, 3, sizeof(double), &p)) return -1;
    t->xyz = p;
    rc = get_array(fd, &t->nelem, &p);
    t->elem_tags = p;
    if (rc || get_items(fd, t->nelem, (size_t)aug_etype_nv(t->etype), sizeof(size_t), &p)) return -1;
    t->conn_tags = p;
    int ngroup;
    if (get_i32(fd, &ngroup) || ngroup < 0) return -1;
    if (!(t->groups = calloc((size_t)ngroup + 1, sizeof *t->groups))) return -1;
    for (; t->ngroup < ngroup; t->ngroup++) {
        aug_tagged_group *g = &t->groups[t->ngroup];
        if (get_i32(fd, &g->dim) || get_i32(fd, &g->tag) || get(fd, g->name, AUG_NAME)) return -1;
        g->name[AUG_NAME - 1] = 0;
        rc = get_array(fd, &g->nnode, &p);
        g->node_tags = p;
        if (rc) return -1;
        rc = get_array(fd, &g->nelem, &p);
        g->elem_tags = p;
        if (rc) return -1;
    }
    return 0;
}

int aug_tagged_recv(int fd, aug_tagged *t, aug_err *e)
{
    uint32_t magic, end = 0, len;
    int code;
    char extra;
    memset(t, 0, sizeof *t);
    aug_err_clear(e);
    if (get(fd, &magic, sizeof magic) || magic != MAGIC_BEGIN || get_i32(fd, &code) || code < 0)
        return -1;
    if (code) {
        if (get(fd, &len, sizeof len) || len >= sizeof e->msg || get(fd, e->msg, len)) return -1;
        e->msg[len] = 0;
        e->code = code;
    } else if (get_mesh(fd, t)) {
        aug_gmsh_free(t);
        return -1;
    }
    if (get(fd, &end, sizeof end) || end != MAGIC_END || read(fd, &extra, 1) != 0) {
        aug_gmsh_free(t);
        return -1;
    }
    return code;
}
