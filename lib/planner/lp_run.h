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

/* The memory one family's run may take, bytes, for the choice of how many run at once
 * (o->jobs 0): the default eye's paired family, the largest of a default plan, peaks at 3.4 GB
 * (plans/patients/wtr-od.yaml, 2026-12-07; the converged reference's at 7 GB); two runs at once
 * are started only when the memory left holds twice this each. */
#define KT_LP_JOB_BYTES (6.0 * 1073741824.0)

/* a->run := every family's readings. Reads a->eye, scene, mesh, fam, trim. The families run
 * one at a time, or side by side on threads of their own (o->jobs; 0: two when the load leaves
 * two cores free and the memory holds KT_LP_JOB_BYTES twice over; one under ulimit -v or -d):
 * each family's numbers are its own whatever the others do, so the answer is the same to the
 * bit. A failure of any family is the run's (the first in family order when several failed);
 * the families not yet started are not, and the later ones running stop at their next step. */
int kt_lp_runs_make(const kt_lp_opts *o, kt_lp_answer *a, kt_err *e);

#endif
