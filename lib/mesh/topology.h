/* topology.h: how keratome numbers the parts of a tetrahedron, and the adjacency tables every
 * module builds from a mesh: node -> tets, and the tets' faces sorted by vertex triple.
 *
 * Local numbering (gmsh's, kept by every reader and writer): face f of a tet is the one
 * opposite vertex f, with its vertices kt_tet_face[f] ordered so that the right-hand normal
 * points out of a positively oriented tet; edge k joins kt_tet_edge[k][0] and [1], and the P2
 * node of edge k sits at local position 4 + k (01 12 20 30 32 31); edge k of a triangle joins
 * kt_tri_edge[k], its P2 node at 3 + k. */
#ifndef KT_TOPOLOGY_H
#define KT_TOPOLOGY_H

#include "mesh.h"

extern const int kt_tet_face[4][3];
extern const int kt_tet_edge[6][2];
extern const int kt_tri_edge[3][2];

/* v[0] <= v[1] <= v[2] afterwards. */
void kt_sort3(int *v);

/* A face by its sorted vertex triple, with what the caller needs to find it again. */
typedef struct kt_face {
    int v[3];       /* sorted corner vertices */
    int id;         /* the caller's: 4 * tet + local face for kt_mesh_tet_faces */
} kt_face;

/* Order by vertex triple (kt_face_cmp_v), then by id: a total order, so a sort is the same
 * on every machine. */
int kt_face_cmp(const void *a, const void *b);
int kt_face_cmp_v(const void *a, const void *b);

/* In f (n faces sorted by kt_face_cmp): the first face with the corners v (any order), or -1. */
int kt_face_find(const kt_face *f, int n, const int v[3]);

/* Node -> tets in CSR form: the tets holding node v (at any local position, mid-edge nodes
 * too) are Ei[Ep[v] .. Ep[v+1]-1], ascending, each once. The caller frees both. */
int kt_mesh_node_tets(const kt_mesh *m, int **Ep, int **Ei, kt_err *e);

/* The 4 * ne corner faces of all tets, sorted by vertex triple, so a face two tets share sits
 * twice in a row and a boundary face once; id = 4 * tet + local face. The caller frees it. */
int kt_mesh_tet_faces(const kt_mesh *m, kt_face **faces, kt_err *e);

#endif
