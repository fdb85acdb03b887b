/* vtk.h: legacy VTK files (no VTK library): UNSTRUCTURED_GRID of tets and POLYDATA of
 * triangles, ASCII or big-endian binary, with POINT_DATA and CELL_DATA; and a small reader. */
#ifndef KT_VTK_H
#define KT_VTK_H

#include "mesh.h"

/* A field: ncomp values per point or per cell (3: VECTORS; 1, 2, 4: SCALARS; 5 to
 * KT_VTK_MAXCOMP: a FIELD of one array, as the legacy SCALARS take at most 4); integer fields
 * are written as int and read back as double. */
#define KT_VTK_MAXCOMP 9
typedef struct kt_vtk_field {
    char name[KT_NAME_MAX];
    int ncomp;
    int on_cells;
    int is_int;
    double *v;      /* ncomp * count values; owned by the reader's kt_vtk, borrowed by writers */
} kt_vtk_field;

/* Tets of m (VTK_TETRA 10 or VTK_QUADRATIC_TETRA 24, node order converted from gmsh), with
 * CELL_DATA "region" from tet_tag, then the given fields. Atomic; "-" is stdout. */
int kt_vtk_write_tets(const char *path, const kt_mesh *m, const kt_vtk_field *f, int nf,
                      int binary, kt_err *e);

/* Triangles (3 nodes each) as POLYDATA with the given fields. Atomic. */
int kt_vtk_write_polydata(const char *path, int nn, const double *xyz, int ntri, const int *tri,
                          const kt_vtk_field *f, int nf, int binary, kt_err *e);
/* The same triangles as an UNSTRUCTURED_GRID of VTK_TRIANGLE (5) cells: the form that every
 * legacy reader takes, meshio included (it reads no POLYDATA). Atomic. */
int kt_vtk_write_tri_grid(const char *path, int nn, const double *xyz, int ntri, const int *tri,
                          const kt_vtk_field *f, int nf, int binary, kt_err *e);

/* What the reader returns: points, cells (VTK types and connectivity), fields. */
typedef struct kt_vtk {
    int is_polydata;
    int nn;
    double *xyz;
    int ncell;
    int *cell_type;     /* VTK cell type per cell (POLYDATA polygons: 7, or 5 for triangles) */
    int *cell_ptr;      /* ncell+1 offsets into conn */
    int *conn;          /* 0-based point numbers, VTK node order */
    int nfield;
    kt_vtk_field *field;
} kt_vtk;

/* The largest VTK file read, in bytes (4 GiB), enforced like KT_MSH_MAX_BYTES; a file not
 * starting with "# vtk DataFile Version" is read no further than its first bytes. */
#define KT_VTK_MAX_BYTES ((size_t)1 << 32)

/* Read an ASCII or binary legacy file written by this module (or by another writer of the
 * same subset). Bad input is KT_EINPUT naming file:line or byte offset. */
int kt_vtk_read(const char *path, kt_vtk *v, kt_err *e);
void kt_vtk_free(kt_vtk *v);
const kt_vtk_field *kt_vtk_find(const kt_vtk *v, const char *name, int on_cells);

#endif
