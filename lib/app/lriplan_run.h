/* lriplan_run.h: the lri-plan tool: one patient (keratome-patient(5)) in, the limbal relaxing
 * incisions that minimize the residual astigmatism out, by simulating the patient's eye. */
#ifndef KT_LRIPLAN_RUN_H
#define KT_LRIPLAN_RUN_H

#include <stdio.h>

#include "lp.h"
#include "util.h"

typedef struct kt_lriplan_opts {
    const char *patient;        /* PATIENT.yaml */
    const char *outdir;         /* PLAN_DIR */
    const char *shown_outdir;   /* PLAN_DIR as the outputs name it (NULL: outdir; the folder
                                   written is renamed into it when whole) */
    const char *base;           /* base eye scene; NULL: the repository's plans/eye.yaml */
    double step;                /* arc added per step, deg (5) */
    int fast;                   /* coarse mesh, the floor refinement at KT_LRIPLAN_FAST_FLOOR */
    int no_band;                /* --no-uncertainty: no first-order band (augsolve without
                                   --uncertainty; lri-plan(1), BAND) */
    int quiet;
    int view;                   /* --view: how plan.html draws the eye (KT_LRI_VIEW_*,
                                   lriplan_eye.h; default temporal) */
    double plan_max_ratio;      /* --plan-max-ratio: the planned factor's limit (augsolve(1)) */
    int state;                  /* --state: KT_WOUND_HEALED (default) or KT_WOUND_IMMEDIATE */
    int jobs;                   /* --jobs: families at once (lib/planner/lp_run.h; 0: decided) */
    kt_lp_cov band_extra;       /* a covariance added to the band's (non-tissue terms), D^2 in
                                   double-angle space; zero: none (lri-plan(1), BAND) */
} kt_lriplan_opts;

void kt_lriplan_opts_default(kt_lriplan_opts *o);
/* KT_WOUND_* of "healed" or "immediate"; -1 for anything else. */
int kt_lriplan_state(const char *s);

/* Plan the patient (lib/planner/lp.h: the scene, one mesh, each allowed family cut centre-out to
 * the longest arc allowed, solved and read in memory, the arc that minimizes the predicted
 * residual astigmatism) and write PLAN_DIR: scene.yaml and eye.msh (the patient's scene and
 * mesh), run/ (the chosen family's step files up to the chosen step), report/ (its teaching
 * report), plan.json, plan.html; the one-screen summary on `summary` (NULL: none). Bad input is
 * KT_EINPUT before anything is meshed. */
int kt_lriplan_run(const kt_lriplan_opts *o, FILE *summary, kt_err *e);

#endif
