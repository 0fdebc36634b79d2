/* ParaView time series (.pvd collection of one .vtu per step) of a stream's cut
   sequence; of a dynamic stream, one .vtu per time frame (fRAM, formats/stream.md
   7.9) with displacement and velocity, timestep = the frame's time; and of the
   MODE records (7.5), NAME_modes.pvd with one .vtu per record. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include "aug_modal.h"
#include "aug_stats.h"

struct aug_pvd {
    char *path;        /* DIR/NAME.pvd */
    size_t stem;       /* length of DIR/NAME */
    size_t base;       /* offset of NAME in path */
    int32_t cur;       /* the step whose records are being read */
    int32_t *step;     /* steps (frames) written, increasing */
    double *time;      /* their timesteps */
    int32_t *part;     /* frames: their series (a stream with the frames of
                          two tools, solve-aug's and modal's, has two) */
    int32_t *next;     /* per series the frame number that continues it */
    int nseries;
    char **file;       /* their .vtu paths */
    size_t n, cap;
    int wrote_pvd;
    int frames;        /* a dynamic stream: the datasets are the fRAM frames */
    char **mfile;      /* the MODE records' .vtu paths, */
    double *mtime;     /* their frames */
    int32_t *mdomain;  /* and domains */
    size_t nm, capm;
    int wrote_mpvd;
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

/* DIR/NAME_modes.pvd (malloc'd) */
static char *modes_pvd(const aug_pvd *p)
{
    size_t len = p->stem + 16;
    char *name = aug_malloc(len);
    if (name) snprintf(name, len, "%.*s_modes.pvd", (int)p->stem, p->path);
    return name;
}

void aug_pvd_free(aug_pvd *p, int discard)
{
    if (!p) return;
    for (size_t i = 0; i < p->n; i++) {
        if (discard) remove(p->file[i]);
        free(p->file[i]);
    }
    if (discard && p->wrote_pvd) remove(p->path);
    for (size_t i = 0; i < p->nm; i++) {
        if (discard) remove(p->mfile[i]);
        free(p->mfile[i]);
    }
    if (discard && p->wrote_mpvd) {
        char *mp = modes_pvd(p);
        if (mp) remove(mp);
        free(mp);
    }
    free(p->mfile);
    free(p->mtime);
    free(p->mdomain);
    free(p->file);
    free(p->step);
    free(p->time);
    free(p->part);
    free(p->next);
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
        int32_t *pt = tm ? aug_realloc(p->part, cap * sizeof *pt) : NULL;
        if (pt) p->part = pt;
        char **f = pt ? aug_realloc(p->file, cap * sizeof *f) : NULL;
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
    if (aug_out_check(name, e)) { /* not listed: a failed run removes what it lists */
        free(name);
        return NULL;
    }
    p->step[p->n] = step;
    p->time[p->n] = step;
    p->part[p->n] = 0;
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
    /* files counted, not named by frame number: a second series overwrote
       the first one's files. A frame continues the series whose last frame
       is frame - 1 (modal's frames interleave with solve-aug's it read),
       else it starts one */
    int series = 0;
    while (series < p->nseries && p->next[series] != f.frame) series++;
    if (!rc && series == p->nseries) {
        int32_t *nx = aug_realloc(p->next, (size_t)(p->nseries + 1) * sizeof *nx);
        if (!nx) rc = aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
        else p->next = nx, p->nseries++;
    }
    const char *name = rc ? NULL : next_file(p, (int32_t)p->n, e);
    if (!rc && !name) rc = e->code;
    if (!rc) {
        p->time[p->n - 1] = f.time;
        p->part[p->n - 1] = series;
        p->next[series] = f.frame + 1;
        FILE *o = aug_out_create(name, e);
        if (!o) rc = e->code;
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

/* a MODE record's .vtu, DIR/NAME_modes_KKKK.vtu (K its index among the
   MODE records), on the mesh of its step: the summary's, whose MDLT of that
   step came before */
static int write_mode(aug_pvd *p, const aug_summary *s, const aug_rec *rec, aug_err *e)
{
    const aug_mesh *m = aug_summary_mesh(s);
    if (!m) return aug_err_set(e, AUG_EDATA, rec->index, rec->type, "a MODE record before the mesh");
    if (p->nm == p->capm) {
        size_t cap = p->capm ? 2 * p->capm : 16;
        char **f = aug_realloc(p->mfile, cap * sizeof *f);
        if (f) p->mfile = f;
        double *fr = f ? aug_realloc(p->mtime, cap * sizeof *fr) : NULL;
        if (fr) p->mtime = fr;
        int32_t *dm = fr ? aug_realloc(p->mdomain, cap * sizeof *dm) : NULL;
        if (!dm) return aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
        p->mdomain = dm;
        p->capm = cap;
    }
    aug_moderec r;
    if (aug_read_mode(rec, &r, e)) return e->code;
    size_t len = p->stem + 32;
    char *name = aug_malloc(len);
    int rc = 0;
    if (!name) rc = aug_err_set(e, AUG_ENOMEM, rec->index, rec->type, "out of memory");
    else {
        snprintf(name, len, "%.*s_modes_%04ld.vtu", (int)p->stem, p->path, (long)p->nm);
        if (aug_out_check(name, e)) {
            free(name);
            aug_moderec_free(&r);
            return e->code;
        }
        p->mfile[p->nm] = name, p->mtime[p->nm] = r.frame, p->mdomain[p->nm] = r.domain;
        p->nm++;
        FILE *o = aug_out_create(name, e);
        if (!o) rc = e->code;
        else {
            rc = aug_vtk_write_modes(o, m, &r, e);
            if (rc && e->record < 0) e->record = rec->index;
            if (fclose(o) != 0 && !rc) rc = aug_err_set(e, AUG_EIO, -1, "", "%s: write failed", name);
        }
    }
    aug_moderec_free(&r);
    return rc;
}

int aug_pvd_add(aug_pvd *p, const aug_summary *s, const aug_rec *rec, aug_err *e)
{
    aug_err_clear(e);
    if (!memcmp(rec->type, "fRAM", 4)) {
        p->frames = 1;
        return write_frame(p, s, rec, e);
    }
    if (!p->frames) {
        const aug_rectype *rt = aug_rectype_find(rec->type);
        if (rt && rt->perstep && rec->step > p->cur) {
            if (write_step(p, s, e)) return e->code;
            p->cur = rec->step;
        }
    }
    if (!memcmp(rec->type, "MODE", 4)) return write_mode(p, s, rec, e);
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

/* a collection of n datasets: timestep time[i], part part[i] (NULL: 0), file
   file[i] relative to the collection's directory (its first `base` bytes);
   *wrote = 1 once the file is created */
static int write_collection(const char *path, size_t n, char **file, const double *time,
                            const int32_t *part, size_t base, int *wrote, aug_err *e)
{
    FILE *o = aug_out_create(path, e);
    if (!o) return e->code;
    *wrote = 1;
    fprintf(o, "<?xml version=\"1.0\"?>\n");
    fprintf(o, "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
    fprintf(o, "  <Collection>\n");
    for (size_t i = 0; i < n; i++) {
        fprintf(o, "    <DataSet timestep=\"%.17g\" group=\"\" part=\"%d\" file=\"", time[i],
                part ? (int)part[i] : 0);
        put_attr(o, file[i] + base);
        fprintf(o, "\"/>\n");
    }
    fprintf(o, "  </Collection>\n</VTKFile>\n");
    int bad = ferror(o);
    if (fclose(o) != 0 || bad) return aug_err_set(e, AUG_EIO, -1, "", "%s: write failed", path);
    return 0;
}

/* The last step, then the collection: one DataSet per .vtu, timestep = step
   number (frame time); NAME_modes.pvd: one per MODE record, timestep = its
   frame, part = its domain. */
int aug_pvd_end(aug_pvd *p, const aug_summary *s, aug_err *e)
{
    aug_err_clear(e);
    if (!p->frames && write_step(p, s, e)) return e->code;
    if (write_collection(p->path, p->n, p->file, p->time, p->part, p->base, &p->wrote_pvd, e))
        return e->code;
    if (!p->nm) return 0;
    char *mp = modes_pvd(p);
    if (!mp) return aug_err_set(e, AUG_ENOMEM, -1, "", "out of memory");
    int rc = write_collection(mp, p->nm, p->mfile, p->mtime, p->mdomain, p->base, &p->wrote_mpvd, e);
    free(mp);
    return rc;
}
