/* apply.h: apply a step of edits to a mesh and report which nodes' stiffness columns changed. */
#ifndef KT_CUT_H
#define KT_CUT_H

#include "edits.h"
#include "mesh.h"

/* Apply the DUP edits of a step: each new node copies its original's coordinates; the listed
 * tets, and the surface triangles lying on a face of a listed tet, switch to the new node.
 * A bad node or tet number, or a new node that is not the next free number, is KT_EINPUT.
 * On return *touched (allocated, sorted, unique; caller frees) holds every node whose
 * stiffness column changed: the nodes of the moved tets, including the new ones. */
int kt_cut_apply(kt_mesh *m, const kt_step *s, int **touched, int *ntouched, kt_err *e);

#endif
