/* quality.h: element quality over all tets (their four vertices). */
#ifndef KT_QUALITY_H
#define KT_QUALITY_H

#include "mesh.h"

/* Dihedral angles in degrees; radius ratio 3 r_in / r_circ (1 for the regular tet). */
typedef struct kt_quality {
    double dihedral_min, dihedral_max;
    double ratio_min, ratio_mean;
    int worst;              /* 0-based tet with the smallest radius ratio */
} kt_quality;

void kt_mesh_quality(const kt_mesh *m, kt_quality *q);

#endif
