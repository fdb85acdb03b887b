/* vtk_int.h: what the legacy VTK reader and writer share (cell type numbers, the tet10 node
 * order, the host's byte order). Private to io/vtk_*.c. */
#ifndef KT_VTK_INT_H
#define KT_VTK_INT_H

#include <stdint.h>

enum { VTK_VERTEX = 1, VTK_POLY_VERTEX = 2, VTK_LINE = 3, VTK_POLY_LINE = 4, VTK_TRIANGLE = 5,
       VTK_TRIANGLE_STRIP = 6, VTK_POLYGON = 7, VTK_TETRA = 10, VTK_QUADRATIC_TETRA = 24 };

/* gmsh tet10 mid-edge order is 01 12 20 30 32 31, VTK's is 01 12 20 03 13 23: swap the last two. */
static const int gmsh_to_vtk_tet10[10] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};

static inline int host_is_little(void)
{
    const uint16_t one = 1;
    return *(const unsigned char *)&one == 1;
}

#endif
