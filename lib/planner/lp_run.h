/* lp_run.h: the planner's sixth stage (writes kt_lp_answer.run): every family kept by the
 * trimming is cut and solved in memory: its plan (lp_family.c) cut on a copy of the intact
 * mesh (lib/cut: kt_incise, the steps handed to the solver's plan as they come,
 * kt_edits_plan_add), its elasticity problem bound (lib/fem) with the physics the families
 * share (the prestress and, with the band, its derivatives: solved once on the first family's
 * intact mesh, the tunnel's snapping included, and adopted by every family whose intact mesh
 * is the same), and solved through the solver's front door (lib/solve/solver.h: the planned
 * method, one factorization for the whole family). Each solved step is read (lp_read.h) and
 * shown to the caller's sink. A fallback of the planned method is said on stderr (always) and
 * kept in the family's run. */
#ifndef KT_LP_RUN_H
#define KT_LP_RUN_H

#include "lp.h"

/* a->run := every family's readings. Reads a->eye, scene, mesh, fam, trim. */
int kt_lp_runs_make(const kt_lp_opts *o, kt_lp_answer *a, kt_err *e);

#endif
