/* orderset.h: the node set the scene's ordering puts last (the surfaces to be cut, grown by a
 * halo), its ranks for a sweep, and the sector a paired LRI cuts. */
#ifndef KT_ORDERSET_H
#define KT_ORDERSET_H

#include "mesh.h"
#include "scene.h"

/* The node set the constrained ordering puts last and whose closures are reported: the
 * scene's ordering.last, else the union of the eye's incision rings, grown by ordering.halo
 * layers of tet neighbours (one layer: every node whose stiffness column changes when the
 * surface is cut); none (NULL, 0) when the scene names no surface. label (>= 160 bytes) says
 * which. */
int kt_orderset_nodes(const kt_scene *s, const kt_mesh *m, int **nodes, int *count, char *label, kt_err *e);

/* Ranks for kt_order_nodes_ranked: on the eye, a set node's angular distance d (0-90 deg)
 * from the meridian s->ordering_centre or its opposite gives rank round(2 (90 - d)), so the
 * nodes an LRI centred there cuts first come last, nearest the root. *rank is NULL (no sweep)
 * for other models or a NAN centre. */
int kt_orderset_ranks(const kt_scene *s, const kt_mesh *m, const int *nodes, int count, int **rank,
                      kt_err *e);

/* The set's nodes within 30 deg of the centre meridian (what a paired 60-degree LRI cuts);
 * *out NULL and *count 0 for other models or a NAN centre. */
int kt_orderset_sector(const kt_scene *s, const kt_mesh *m, const int *set, int nset, int **out,
                       int *count, kt_err *e);

#endif
