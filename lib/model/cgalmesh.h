/* cgalmesh.h: CGAL Mesh_3 tetrahedralization of surface meshes and labelled images (C interface). */
#ifndef KT_CGALMESH_H
#define KT_CGALMESH_H

#include "mesh.h"

/* Mesh the volume bounded by a closed surface (OFF or STL) with sliver exudation. Sizes in the
 * file's units. Region "body" (tag 1), boundary surface "boundary" (tag 1). */
int kt_cgal_mesh_surface(const char *path, double facet_size, double facet_distance,
                         double cell_size, kt_mesh *m, kt_err *e);

/* Mesh a labelled 3D image (INR, optionally gzipped): one region per nonzero label
 * ("label-N", tag N), boundary surface "boundary" (tag 1). */
int kt_cgal_mesh_image(const char *path, double facet_size, double facet_distance,
                       double cell_size, kt_mesh *m, kt_err *e);

#endif
