/* grid.h: the paper's structured benchmark meshes (beams 5x5xh and the refined 1x1x2 brick). */
#ifndef KT_GRID_H
#define KT_GRID_H

#include "mesh.h"

/* Box [0,lx]x[0,ly]x[0,lz] with nx*ny*nz nodes (nx,ny,nz >= 2), each cell split into six
 * tetrahedra that share the cell's main diagonal (conforming across cells). Groups:
 * region "body" (tag 1); surfaces "xmin" "xmax" "ymin" "ymax" "zmin" "zmax" (tags 1..6). */
int kt_grid_box(kt_mesh *m, int nx, int ny, int nz, double lx, double ly, double lz, kt_err *e);

#endif
