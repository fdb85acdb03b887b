/* augsolve_run.h: the augsolve tool (mesh + edits stream -> run folder). */
#ifndef KT_AUGSOLVE_RUN_H
#define KT_AUGSOLVE_RUN_H

#include "aug.h"

/* The augsolve tool: mesh + edits stream -> run folder (step-NNNN.vtk, steps.tsv, run.yaml). */
typedef struct kt_aug_run_opts {
    const char *mesh, *edits, *run_dir;
    const char *scene;        /* NULL: the scene the edits header names */
    int vtk, binary;          /* write step VTKs (binary legacy format) */
    const char *steps;        /* NULL: write every step; else a list "1,4,7-9" (step 0 always) */
    double plan_max_ratio;    /* planned: refactor with METIS beyond this factor-size ratio
                                 (kt_plan_factor_build; default KT_PLAN_MAX_RATIO, 0: never) */
    int uncertainty;          /* --uncertainty: dudp_<q> fields and uncertainty.tsv */
    kt_aug_opts aug;
} kt_aug_run_opts;

/* The tool's defaults: kt_aug_opts_default with the planned method and its default ordering
 * (aug_plan.h), step VTKs written. */
void kt_aug_run_opts_default(kt_aug_run_opts *o);

int kt_aug_run(const kt_aug_run_opts *o, kt_err *e);

#endif
