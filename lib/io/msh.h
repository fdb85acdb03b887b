/* msh.h: gmsh MSH 4.1 reader and writer (ASCII and binary). */
#ifndef KT_MSH_H
#define KT_MSH_H

#include "mesh.h"

/* The largest MSH file read, in bytes (4 GiB): a larger one is refused before it is read, a
 * stream once it passes this; a file not starting with "$MeshFormat" is read no further than
 * its first bytes. */
#define KT_MSH_MAX_BYTES ((size_t)1 << 32)

/* Read a MSH 4.1 file ("-" for stdin). Keeps 4-node or 10-node tets, 3- or 6-node triangles
 * that belong to physical groups, and the physical names; other elements are skipped. Node
 * tags are compacted to 0..nn-1 in tag order. A malformed file is KT_EINPUT naming
 * file:line (ASCII) or file:byte offset (binary) and what was expected. */
int kt_msh_read(const char *path, kt_mesh *m, kt_err *e);

/* Write MSH 4.1 ("-" for stdout) atomically: node i has tag i+1, tets have element tags
 * 1..ne, triangles ne+1..ne+nf; one entity per physical group. */
int kt_msh_write(const char *path, const kt_mesh *m, int binary, kt_err *e);
int kt_msh_write_file(FILE *f, const kt_mesh *m, int binary, kt_err *e);

#endif
