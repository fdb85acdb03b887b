/* lriplan_run.h: the lri-plan tool: one patient (keratome-patient(5)) in, the limbal relaxing
 * incisions that minimize the residual astigmatism out, by simulating the patient's eye. */
#ifndef KT_LRIPLAN_RUN_H
#define KT_LRIPLAN_RUN_H

#include <stdio.h>

#include "util.h"

typedef struct kt_lriplan_opts {
    const char *patient;        /* PATIENT.yaml */
    const char *outdir;         /* PLAN_DIR */
    const char *base;           /* base eye scene; NULL: the repository's plans/eye.yaml */
    double step;                /* arc added per step, deg (5) */
    int fast;                   /* coarse mesh, the floor refinement at KT_LRIPLAN_FAST_FLOOR */
    int no_band;                /* --no-uncertainty: no first-order band (augsolve without
                                   --uncertainty; lri-plan(1), BAND) */
    int quiet;
} kt_lriplan_opts;

void kt_lriplan_opts_default(kt_lriplan_opts *o);

/* Load and check the patient (fit a Pentacam export), write PLAN_DIR/scene.yaml, mesh it once
 * (eye.msh), cut each allowed family (one arc; a pair) centre-out to the longest arc allowed
 * (plan-<family>.yaml, <family>.edits, run-<family>/ with its curvature tables), pick the arc
 * that minimizes the predicted residual astigmatism, write PLAN_DIR/plan.json and print the
 * one-screen summary on `summary`. Bad input is KT_EINPUT before anything is meshed. */
int kt_lriplan_run(const kt_lriplan_opts *o, FILE *summary, kt_err *e);

#endif
