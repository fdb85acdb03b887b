/* lp_mesh.h: the planner's third stage (writes kt_lp_answer.mesh): the patient's scene meshed
 * once, as mesh-prep --chosen-only makes it (lib/model/build.h; the stress-free shape for a
 * loads.reference loaded scene; the scene's ordering of the ordering set, lib/model/orderset.h),
 * its nodes renumbered in elimination order. Every family's run cuts a copy of it. */
#ifndef KT_LP_MESH_H
#define KT_LP_MESH_H

#include "lp.h"

/* mh := the mesh of scene s (its order, its ordering). A mesh that gmsh cannot make or that
 * fails its checks is KT_ERUN (bad sizes in the scene: KT_EINPUT from the builder). */
int kt_lp_mesh_make(const kt_scene *s, int quiet, kt_lp_mesh *mh, kt_err *e);
void kt_lp_mesh_free(kt_lp_mesh *mh);

#endif
