/* build.h: a scene's mesh, built from its model (eye, box, CGAL surface or image). */
#ifndef KT_BUILD_H
#define KT_BUILD_H

#include "mesh.h"
#include "scene.h"

/* Build the scene's mesh at element order 'order' (1 or 2): the eye with gmsh; a box with its
 * fixed face renamed "fixed"; a surface or image with CGAL (sizes scaled to reach the scene's
 * target_nodes, coordinates scaled by its unit). 'below' fixations add their surface groups
 * (boundary faces under the level) before order elevation. */
int kt_build_mesh(const kt_scene *s, int order, int quiet, kt_mesh *m, kt_err *e);

/* Add surface group 'name' made of the boundary faces (faces of exactly one tet) whose
 * vertices all have coordinate axis <= level; oriented outwards. Empty is KT_EINPUT. */
int kt_build_below_group(kt_mesh *m, const char *name, int axis, double level, kt_err *e);

#endif
