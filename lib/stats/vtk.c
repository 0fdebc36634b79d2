/* VTK XML UnstructuredGrid (.vtu, ASCII) export of a mesh and a displacement field. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "aug_modal.h"
#include "aug_stats.h"

#define VTK_TRIANGLE 5
#define VTK_TETRA 10
#define VTK_HEXAHEDRON 12

/* ASCII readers cannot parse "nan"/"inf": undefined qualities are written as -1;
   8 values per line */
static void put_q(FILE *o, int64_t i, double v)
{
    fprintf(o, "%s%.17g", i % 8 ? " " : i ? "\n" : "", isfinite(v) ? v : -1.0);
}

static void open_array(FILE *o, const char *type, const char *name, int ncomp)
{
    fprintf(o, "        <DataArray type=\"%s\" Name=\"%s\"", type, name);
    if (ncomp > 1) fprintf(o, " NumberOfComponents=\"%d\"", ncomp);
    fprintf(o, " format=\"ascii\">\n");
}

static void close_array(FILE *o) { fprintf(o, "\n        </DataArray>\n"); }

/* one line per node / cell keeps the file diffable and the lines short */
int aug_vtk_write(FILE *o, const aug_mesh *m, const double *u, const unsigned char *mask,
                  aug_err *e)
{
    return aug_vtk_write_uv(o, m, u, NULL, mask, e);
}

/* the file up to its FieldData or Piece */
static void vtk_begin(FILE *o)
{
    fprintf(o, "<?xml version=\"1.0\"?>\n");
    fprintf(o, "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
    fprintf(o, "  <UnstructuredGrid>\n");
}

static void vtk_piece(FILE *o, const aug_mesh *m)
{
    fprintf(o, "    <Piece NumberOfPoints=\"%lld\" NumberOfCells=\"%lld\">\n", (long long)m->nn,
            (long long)m->ne);
}

/* a point array of nn tuples of ncomp values, v[i*dim + c] (c >= dim: 0) */
static void point_array(FILE *o, const char *name, const aug_mesh *m, const double *v, int ncomp)
{
    open_array(o, "Float64", name, ncomp);
    for (int64_t i = 0; i < m->nn; i++) {
        if (i) fputc('\n', o);
        for (int d = 0; d < ncomp; d++) fprintf(o, "%s%.17g", d ? " " : "", d < m->dim ? v[i * m->dim + d] : 0.0);
    }
    close_array(o);
}

static void vtk_mesh(FILE *o, const aug_mesh *m);

int aug_vtk_write_uv(FILE *o, const aug_mesh *m, const double *u, const double *v,
                     const unsigned char *mask, aug_err *e)
{
    aug_err_clear(e);
    if (!aug_etype_nv(m->etype)) return aug_err_set(e, AUG_EUSAGE, -1, "", "mesh has no elements");
    vtk_begin(o);
    vtk_piece(o, m);
    if (u) {
        fprintf(o, "      <PointData Vectors=\"displacement\" Scalars=\"displacement_mask\">\n");
        point_array(o, "displacement", m, u, 3);
        if (v) point_array(o, "velocity", m, v, 3);
        open_array(o, "UInt8", "displacement_mask", 1);
        for (int64_t i = 0; i < m->nn; i++)
            fprintf(o, "%s%d", i % 32 ? " " : i ? "\n" : "", mask ? (int)mask[i] : 1);
        close_array(o);
        fprintf(o, "      </PointData>\n");
    }
    vtk_mesh(o, m);
    if (ferror(o)) return aug_err_set(e, AUG_EIO, -1, "", "write failed");
    return 0;
}

/* cell data, points, cells and the end of the file */
static void vtk_mesh(FILE *o, const aug_mesh *m)
{
    int dim = m->dim, nv = m->nv;
    fprintf(o, "      <CellData Scalars=\"material\">\n");
    open_array(o, "Int32", "material", 1);
    for (int64_t i = 0; i < m->ne; i++) fprintf(o, "%s%d", i % 32 ? " " : i ? "\n" : "", (int)m->mat[i]);
    close_array(o);
    open_array(o, "Int32", "material_id", 1);
    for (int64_t i = 0; i < m->ne; i++)
        fprintf(o, "%s%d", i % 32 ? " " : i ? "\n" : "", (int)m->mats[m->mat[i]].id);
    close_array(o);
    open_array(o, "Float64", "aspect_ratio", 1);
    for (int64_t i = 0; i < m->ne; i++) {
        aug_quality q;
        aug_elem_quality(m, i, &q);
        put_q(o, i, q.aspect);
    }
    close_array(o);
    open_array(o, "Float64", "min_angle", 1); /* tet4: min dihedral angle */
    for (int64_t i = 0; i < m->ne; i++) {
        aug_quality q;
        aug_elem_quality(m, i, &q);
        put_q(o, i, q.min_angle);
    }
    close_array(o);
    if (nv == 8) {
        open_array(o, "Float64", "scaled_jacobian", 1);
        for (int64_t i = 0; i < m->ne; i++) put_q(o, i, aug_hex_scaled_jacobian(m, i, NULL));
        close_array(o);
    }
    fprintf(o, "      </CellData>\n");
    fprintf(o, "      <Points>\n");
    open_array(o, "Float64", "points", 3);
    for (int64_t i = 0; i < m->nn; i++) {
        if (i) fputc('\n', o);
        for (int d = 0; d < 3; d++) fprintf(o, "%s%.17g", d ? " " : "", d < dim ? m->x[i * dim + d] : 0.0);
    }
    close_array(o);
    fprintf(o, "      </Points>\n");
    fprintf(o, "      <Cells>\n");
    open_array(o, "Int64", "connectivity", 1);
    for (int64_t i = 0; i < m->ne; i++) {
        if (i) fputc('\n', o);
        for (int j = 0; j < nv; j++) fprintf(o, "%s%d", j ? " " : "", (int)m->conn[i * nv + j]);
    }
    close_array(o);
    open_array(o, "Int64", "offsets", 1);
    for (int64_t i = 0; i < m->ne; i++)
        fprintf(o, "%s%lld", i % 16 ? " " : i ? "\n" : "", (long long)((i + 1) * nv));
    close_array(o);
    open_array(o, "UInt8", "types", 1);
    for (int64_t i = 0; i < m->ne; i++)
        fprintf(o, "%s%d", i % 32 ? " " : i ? "\n" : "", nv == 8 ? VTK_HEXAHEDRON : nv == 4 ? VTK_TETRA : VTK_TRIANGLE);
    close_array(o);
    fprintf(o, "      </Cells>\n");
    fprintf(o, "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
}

/* field data sigma, domain, frame, kind; point data mode_j (dim components,
   0 off the domain) and in_domain */
int aug_vtk_write_modes(FILE *o, const aug_mesh *m, const aug_moderec *r, aug_err *e)
{
    aug_err_clear(e);
    if (!aug_etype_nv(m->etype)) return aug_err_set(e, AUG_EUSAGE, -1, "", "mesh has no elements");
    int dim = m->dim;
    if (r->dim != dim || r->nodes[r->count - 1] >= m->nn)
        return aug_err_set(e, AUG_EDATA, -1, "MODE", "domain %d: %d-D modes at node %lld of a %d-D mesh of %lld nodes",
                           (int)r->domain, (int)r->dim, (long long)r->nodes[r->count - 1], dim, (long long)m->nn);
    double *v = aug_calloc((size_t)(m->nn * dim) + 1, sizeof *v);
    if (!v) return aug_err_set(e, AUG_ENOMEM, -1, "MODE", "out of memory");
    vtk_begin(o);
    fprintf(o, "    <FieldData>\n");
    /* field data arrays need their NumberOfTuples (VTK 9 reads none without it) */
    fprintf(o, "        <DataArray type=\"Float64\" Name=\"sigma\" NumberOfTuples=\"%d\" format=\"ascii\">\n", (int)r->r);
    for (int j = 0; j < r->r; j++) put_q(o, j, r->sigma[j]);
    close_array(o);
    const char *iname[3] = {"domain", "frame", "kind"};
    int32_t ival[3] = {r->domain, r->frame, r->kind};
    for (int k = 0; k < 3; k++) {
        fprintf(o, "        <DataArray type=\"Int32\" Name=\"%s\" NumberOfTuples=\"1\" format=\"ascii\">\n%d", iname[k], (int)ival[k]);
        close_array(o);
    }
    fprintf(o, "    </FieldData>\n");
    vtk_piece(o, m);
    fprintf(o, "      <PointData Scalars=\"in_domain\">\n");
    size_t nd = (size_t)(r->count * dim);
    for (int j = 0; j < r->r; j++) {
        for (int64_t k = 0; k < r->count; k++)
            for (int c = 0; c < dim; c++) v[(size_t)r->nodes[k] * dim + c] = r->phi[j * nd + k * dim + c];
        char name[32];
        snprintf(name, sizeof name, "mode_%d", j);
        point_array(o, name, m, v, dim);
    }
    open_array(o, "UInt8", "in_domain", 1);
    for (int64_t i = 0, k = 0; i < m->nn; i++) {
        int in = k < r->count && r->nodes[k] == i;
        k += in;
        fprintf(o, "%s%d", i % 32 ? " " : i ? "\n" : "", in);
    }
    close_array(o);
    fprintf(o, "      </PointData>\n");
    vtk_mesh(o, m);
    free(v);
    if (ferror(o)) return aug_err_set(e, AUG_EIO, -1, "", "write failed");
    return 0;
}

/* The .vtu file of step `step` of a summary read up to it: its mesh and the
   displacement field of that very step (a field of an earlier step does not
   belong to this mesh). File errors name the file (AUG_EIO, record -1); the
   file is removed when writing it failed. */
int aug_vtk_step_file(const char *path, const aug_summary *s, int32_t step, aug_err *e)
{
    aug_err_clear(e);
    const aug_mesh *m = aug_summary_mesh(s);
    if (!m) return aug_err_set(e, AUG_EDATA, -1, "", "no mesh in the stream (NODE, MATL and ELEM needed)");
    int32_t fstep;
    double *u;
    unsigned char *mask;
    if (aug_summary_field(s, &fstep, &u, &mask, e)) return e->code;
    if (u && fstep != step) {
        free(u);
        free(mask);
        u = NULL;
        mask = NULL;
    }
    int rc;
    FILE *f = aug_out_create(path, e);
    if (!f) rc = e->code;
    else {
        rc = aug_vtk_write(f, m, u, mask, e);
        if (fclose(f) != 0 && !rc) rc = aug_err_set(e, AUG_EIO, -1, "", "write failed");
        if (rc) {
            char msg[sizeof e->msg];
            memcpy(msg, e->msg, sizeof msg);
            aug_err_set(e, rc, -1, "", "%s: %s", path, msg);
            remove(path);
        }
    }
    free(u);
    free(mask);
    return rc;
}
