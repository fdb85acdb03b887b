/* prep.h: the mesh-prep pipeline: build a scene's mesh, add the groups the scene asks for,
 * measure element quality, compare orderings, renumber in elimination order and write MSH. */
#ifndef KT_PREP_H
#define KT_PREP_H

#include <stdio.h>

#include "mesh.h"
#include "order.h"
#include "scene.h"

/* Build the scene's mesh at element order 'order' (1 or 2): the eye with gmsh; a box with its
 * fixed face renamed "fixed"; a surface or image with CGAL (sizes scaled to reach the scene's
 * target_nodes, coordinates scaled by its unit). 'below' fixations add their surface groups
 * (boundary faces under the level) before order elevation. */
int kt_prep_build(const kt_scene *s, int order, int quiet, kt_mesh *m, kt_err *e);

/* Add surface group 'name' made of the boundary faces (faces of exactly one tet) whose
 * vertices all have coordinate axis <= level; oriented outwards. Empty is KT_EINPUT. */
int kt_prep_below_group(kt_mesh *m, const char *name, int axis, double level, kt_err *e);

/* Element quality over all tets (their four vertices). Dihedral angles in degrees; radius
 * ratio 3 r_in / r_circ (1 for the regular tet). */
typedef struct kt_quality {
    double dihedral_min, dihedral_max;
    double ratio_min, ratio_mean;
    int worst;              /* 0-based tet with the smallest radius ratio */
} kt_quality;

void kt_prep_quality(const kt_mesh *m, kt_quality *q);

/* The node set the constrained ordering puts last and whose closures are reported: the
 * scene's ordering.last, else the union of the eye's incision rings, grown by ordering.halo
 * layers of tet neighbours (one layer: every node whose stiffness column changes when the
 * surface is cut); none (NULL, 0) when the scene names no surface. label (>= 160 bytes) says
 * which. */
int kt_prep_set(const kt_scene *s, const kt_mesh *m, int **nodes, int *count, char *label, kt_err *e);

/* Ranks for kt_order_nodes_ranked: on the eye, a set node's angular distance d (0-90 deg)
 * from the meridian s->ordering_centre or its opposite gives rank round(2 (90 - d)), so the
 * nodes an LRI centred there cuts first come last, nearest the root. *rank is NULL (no sweep)
 * for other models or a NAN centre. */
int kt_prep_set_ranks(const kt_scene *s, const kt_mesh *m, const int *nodes, int count, int **rank,
                      kt_err *e);

/* One row of the ordering comparison. */
typedef struct kt_prep_row {
    int method;
    double t_order;         /* seconds to compute the ordering */
    kt_order_stats st;
    kt_order_stats sector;  /* closures of the set's nodes within 30 deg of the centre meridian */
} kt_prep_row;

/* The whole run of mesh-prep. */
typedef struct kt_prep_opts {
    const char *scene, *out;    /* scene file; output MSH path or "-" */
    int ordering;               /* KT_ORDERING_*, 0: the scene's */
    int order;                  /* 1 or 2, 0: the scene's */
    int binary, quiet;
} kt_prep_opts;

/* Load, build, check, order, permute, write; the summary goes to 'summary' (NULL: none). */
int kt_prep_run(const kt_prep_opts *o, FILE *summary, kt_err *e);

#endif
