/* ParaView time series (.pvd collection of one .vtu per step) of a stream's cut
   sequence; of a dynamic stream, one .vtu per time frame (fRAM, formats/stream.md
   7.9) with displacement and velocity, timestep = the frame's time. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include "aug_stats.h"

struct aug_pvd {
    char *path;        /* DIR/NAME.pvd */
    size_t stem;       /* length of DIR/NAME */
    size_t base;       /* offset of NAME in path */
    int32_t cur;       /* the step whose records are being read */
    int32_t *step;     /* steps (frames) written, increasing */
    double *time;      /* their timesteps */
    char **file;       /* their .vtu paths */
    size_t n, cap;
    int wrote_pvd;
    int frames;        /* a dynamic stream: the datasets are the fRAM frames */
};

int aug_path_is_pvd(const char *path)
{
    size_t n = strlen(path);
    return n > 4 && !strcmp(path + n - 4, ".pvd");
}

/* path = DIR/NAME.pvd; the series starts at step 0 */
aug_pvd *aug_pvd_new(const char *path, aug_err *e)
{
    aug_err_clear(e);
    if (!aug_path_is_pvd(path)) {
        aug_err_set(e, AUG_EUSAGE, -1, "", "%s: not a .pvd file name", path);
        return NULL;
    }
    aug_pvd *p = aug_calloc(1, sizeof *p);
    if (p) p->path = aug_malloc(strlen(path) + 1);
    if (!p || !p->path) {
        free(p);
        aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        return NULL;
    }
    strcpy(p->path, path);
    p->stem = strlen(path) - 4;
    const char *slash = strrchr(path, '/');
    p->base = slash ? (size_t)(slash + 1 - path) : 0;
    return p;
}

void aug_pvd_free(aug_pvd *p, int discard)
{
    if (!p) return;
    for (size_t i = 0; i < p->n; i++) {
        if (discard) remove(p->file[i]);
        free(p->file[i]);
    }
    if (discard && p->wrote_pvd) remove(p->path);
    free(p->file);
    free(p->step);
    free(p->time);
    free(p->path);
    free(p);
}

/* DIR/NAME_SSSS.vtu (at least four digits) appended to the list */
static char *next_file(aug_pvd *p, int32_t step, aug_err *e)
{
    if (p->n == p->cap) {
        size_t cap = p->cap ? 2 * p->cap : 16;
        int32_t *s = aug_realloc(p->step, cap * sizeof *s);
        if (s) p->step = s;
        double *tm = s ? aug_realloc(p->time, cap * sizeof *tm) : NULL;
        if (tm) p->time = tm;
        char **f = tm ? aug_realloc(p->file, cap * sizeof *f) : NULL;
        if (!f) {
            aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
            return NULL;
        }
        p->file = f;
        p->cap = cap;
    }
    size_t len = p->stem + 20;
    char *name = aug_malloc(len);
    if (!name) {
        aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
        return NULL;
    }
    snprintf(name, len, "%.*s_%04d.vtu", (int)p->stem, p->path, (int)step);
    p->step[p->n] = step;
    p->time[p->n] = step;
    p->file[p->n++] = name;
    return name;
}

/* the .vtu of step p->cur */
static int write_step(aug_pvd *p, const aug_summary *s, aug_err *e)
{
    const char *name = next_file(p, p->cur, e);
    return name ? aug_vtk_step_file(name, s, p->cur, e) : e->code;
}

/* Series steps: 0 and every step of a per-step record; step t is complete
   when a record of a later step arrives (formats/stream.md 3.2: steps never
   decrease), so it is written before the summary absorbs that record. */
/* a frame's .vtu: the mesh of its step (the summary's), u and v at the
   frame's nodes (indexed frames: the others masked out) */
static int write_frame(aug_pvd *p, const aug_summary *s, const aug_rec *rec, aug_err *e)
{
    aug_frame f;
    const aug_mesh *m = aug_summary_mesh(s);
    if (!m) return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "a frame before the mesh");
    if (aug_read_frame(rec, &f, e)) {
        aug_frame_free(&f);
        return e->code;
    }
    int64_t nd = m->nn * m->dim;
    double *u = aug_calloc((size_t)(2 * nd + 1), sizeof *u), *v = u + nd;
    unsigned char *mask = aug_calloc((size_t)m->nn + 1, 1);
    int rc = 0;
    if (!u || !mask) rc = aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    for (int64_t q = 0; !rc && q < f.count; q++) {
        int64_t nd0 = f.nodes ? f.nodes[q] : q;
        if (nd0 >= m->nn || f.dim != m->dim) {
            rc = aug_err_set(e, AUG_EDATA, rec->index, rec->type, "frame %d: node %lld of a mesh of %lld",
                             (int)f.frame, (long long)nd0, (long long)m->nn);
            break;
        }
        mask[nd0] = 1;
        for (int c = 0; c < m->dim; c++)
            u[nd0 * m->dim + c] = f.u[q * m->dim + c], v[nd0 * m->dim + c] = f.v[q * m->dim + c];
    }
    const char *name = rc ? NULL : next_file(p, f.frame, e);
    if (!rc && !name) rc = e->code;
    if (!rc) {
        p->time[p->n - 1] = f.time;
        FILE *o = fopen(name, "w");
        if (!o) rc = aug_err_set(e, AUG_EIO, -1, "", "%s: %s", name, strerror(errno));
        else {
            rc = aug_vtk_write_uv(o, m, u, v, mask, e);
            if (fclose(o) != 0 && !rc) rc = aug_err_set(e, AUG_EIO, -1, "", "%s: write failed", name);
        }
    }
    free(u);
    free(mask);
    aug_frame_free(&f);
    return rc;
}

int aug_pvd_add(aug_pvd *p, const aug_summary *s, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    if (!memcmp(rec->type, "fRAM", 4)) {
        p->frames = 1;
        return write_frame(p, s, rec, e);
    }
    if (p->frames) return 0;
    const aug_rectype *rt = aug_rectype_find(rec->type);
    if (!rt || !rt->perstep || rec->step <= p->cur) return 0;
    if (write_step(p, s, e)) return e->code;
    p->cur = rec->step;
    return 0;
}

/* name as an XML attribute value */
static void put_attr(FILE *o, const char *name)
{
    for (; *name; name++) {
        if (*name == '&') fputs("&amp;", o);
        else if (*name == '<') fputs("&lt;", o);
        else if (*name == '"') fputs("&quot;", o);
        else fputc(*name, o);
    }
}

/* The last step, then the collection: one DataSet per .vtu, timestep = step
   number, file relative to the .pvd's directory. */
int aug_pvd_end(aug_pvd *p, const aug_summary *s, aug_err *e)
{
    aug_err_clear(e);
    if (!p->frames && write_step(p, s, e)) return e->code;
    FILE *o = fopen(p->path, "w");
    if (!o) return aug_err_set(e, AUG_EIO, -1, "", "%s: %s", p->path, strerror(errno));
    p->wrote_pvd = 1;
    fprintf(o, "<?xml version=\"1.0\"?>\n");
    fprintf(o, "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
    fprintf(o, "  <Collection>\n");
    for (size_t i = 0; i < p->n; i++) {
        fprintf(o, "    <DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"", p->time[i]);
        put_attr(o, p->file[i] + p->base);
        fprintf(o, "\"/>\n");
    }
    fprintf(o, "  </Collection>\n</VTKFile>\n");
    int bad = ferror(o);
    if (fclose(o) != 0 || bad) return aug_err_set(e, AUG_EIO, -1, "", "%s: write failed", p->path);
    return 0;
}
