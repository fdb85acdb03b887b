/* mesh.h: tetrahedral mesh (4- or 10-node) with regions and named surface groups. */
#ifndef KT_MESH_H
#define KT_MESH_H

#include <stdint.h>

#include "util.h"

#define KT_NAME_MAX 64
/* The largest mesh any file may describe (keratome-edits(5), LIMITS): node and tet numbers,
 * 10 per quadratic tet, then stay well inside an int. Readers refuse more before allocating. */
#define KT_MESH_MAX_NODES 100000000
#define KT_MESH_MAX_TETS 100000000
/* Node coordinates read from a file: finite and within +-1e6 mm (a kilometre; an eye is 24 mm),
 * so that lengths, areas and volumes computed from them stay far from overflow. */
#define KT_MESH_MAX_COORD 1e6

/* A physical group: dimension 2 (a surface of triangles) or 3 (a region of tets). */
typedef struct kt_group {
    int dim, tag;
    char name[KT_NAME_MAX];
} kt_group;

/* Node and element numbers are 0-based here; files use 1-based tags (node i is tag i+1).
 * Node order is the elimination order chosen by mesh-prep. Higher-order node order follows
 * gmsh: tet10 = 4 vertices, then edges 01 12 20 30 32 31; tri6 = 3 vertices, edges 01 12 20. */
typedef struct kt_mesh {
    int order;        /* 1 (tet4/tri3) or 2 (tet10/tri6) */
    int nn;           /* nodes */
    double *xyz;      /* 3*nn coordinates, mm */
    int ne;           /* tetrahedra */
    int *tet;         /* ne*kt_tet_nv(order) node numbers */
    int *tet_tag;     /* ne region tags (a dim-3 group's tag) */
    int nf;           /* triangles of named surfaces (boundary or embedded) */
    int *tri;         /* nf*kt_tri_nv(order) node numbers */
    int *tri_tag;     /* nf surface tags (a dim-2 group's tag); a triangle in two groups is listed twice */
    int ng;
    kt_group *group;  /* physical groups */
} kt_mesh;

int kt_tet_nv(int order);   /* 4 or 10 */
int kt_tri_nv(int order);   /* 3 or 6 */

void kt_mesh_free(kt_mesh *m);
int kt_mesh_copy(kt_mesh *dst, const kt_mesh *src, kt_err *e);

/* The content hash of a mesh: 64-bit FNV-1a over its order, node and tet counts, every
 * coordinate (the IEEE-754 bits, -0 taken as +0, little-endian) and every tet's node numbers
 * (32-bit little-endian). Independent of the file's format and bytes: the edits stream names
 * the mesh it was made for by this (keratome-edits(5)). */
uint64_t kt_mesh_hash(const kt_mesh *m);

/* Add a group; its tag must be new for its dimension. */
int kt_mesh_add_group(kt_mesh *m, int dim, int tag, const char *name, kt_err *e);
/* The group of that dimension and name, or NULL. */
const kt_group *kt_mesh_find_group(const kt_mesh *m, int dim, const char *name);
const kt_group *kt_mesh_find_tag(const kt_mesh *m, int dim, int tag);

/* Sorted, unique nodes of a surface group's triangles (dim 2) or a region's tets (dim 3).
 * *nodes is allocated; the caller frees it. */
int kt_mesh_group_nodes(const kt_mesh *m, const kt_group *g, int **nodes, int *count, kt_err *e);

/* Signed volume of the tet a,b,c,d (positive when d is on the side c x ... right-handed). */
double kt_tet_volume(const double *a, const double *b, const double *c, const double *d);

/* Structural check: node numbers in range, tags known, every tet with positive volume
 * (an inverted or degenerate element is an error naming it). */
int kt_mesh_check(const kt_mesh *m, const char *what, kt_err *e);

/* Renumber nodes: new node i is old node perm[i]. */
int kt_mesh_permute(kt_mesh *m, const int *perm, kt_err *e);

/* Order 1 -> 2: add a straight mid-edge node per edge, shared between tets and triangles. */
int kt_mesh_elevate(kt_mesh *m, kt_err *e);

#endif
