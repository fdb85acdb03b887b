/* lriplan_int.h: what lri-plan's output files share (private to lib/app/lriplan_*.c). The
 * planner (lib/planner/lp.h) returns the answer; these write it: the chosen run's folder and
 * its report (lriplan_run.c, lriplan_stage.c), plan.json and the summary (lriplan_out.c),
 * plan.html (lriplan_html.c). */
#ifndef KT_LRIPLAN_INT_H
#define KT_LRIPLAN_INT_H

#include <stdio.h>

#include "lp.h"
#include "lp_band.h"
#include "lp_choose.h"
#include "lriplan_run.h"

/* What the outputs say of the files written: the chosen run's folder and its report, relative
 * to PLAN_DIR (NULL: none, no arc). */
typedef struct kt_lri_files {
    const char *run;            /* "run" */
    const char *report;         /* "report/report.html" */
    char date[11];              /* the plan's date, YYYY-MM-DD (SOURCE_DATE_EPOCH's when set) */
} kt_lri_files;

/* The step files of every family, staged in PLAN_DIR/.run-<family>.tmp/ as the planner solves
 * them (kt_lp_opts.sink): mesh.msh and uncertainty.tsv at step 0, step-NNNN.vtk, and steps.tsv's
 * rows kept. Owner: the run (lriplan_run.c); kt_lri_stage_end keeps the chosen family's steps up
 * to `last` as PLAN_DIR/run/ (with steps.tsv, run.yaml and the chosen plan.yaml) and removes
 * every other staged file. */
typedef struct kt_lri_rows {
    int n, cap;
    kt_aug_row *r;
} kt_lri_rows;
typedef struct kt_lri_stage {
    const char *outdir;
    const kt_lp_answer *a;      /* the answer being filled (its scene, its band's state) */
    char dir[KT_LP_NFAM][1200];
    int made[KT_LP_NFAM];       /* the family's staging folder exists */
    int steps[KT_LP_NFAM];      /* the last step written */
    kt_lri_rows rows[KT_LP_NFAM]; /* steps.tsv's rows, kept until the choice */
    int order[KT_LP_NFAM], nn[KT_LP_NFAM], ne[KT_LP_NFAM]; /* the run's mesh */
    uint64_t hash[KT_LP_NFAM];
    int method[KT_LP_NFAM];     /* KT_AUG_* that ran */
    char fallback[KT_LP_NFAM][300];
} kt_lri_stage;

int kt_lri_stage_sink(void *ctx, const kt_lp_step *s, kt_err *e);
/* Keep family `fam`'s steps 0..last as PLAN_DIR/run (fam < 0: keep none) with its run.yaml and,
 * when plan is not NULL, the plan those steps cut as run/plan.yaml; every staged file else
 * goes. */
int kt_lri_stage_end(kt_lri_stage *st, int fam, int last, const kt_plan *plan, kt_err *e);

/* plan.json (lriplan_out.c; lri-plan(1), FILES), the summary, plan.html (lriplan_html.c). */
int kt_lri_write_json(const kt_lp_answer *a, const kt_lriplan_opts *o, const kt_lri_files *fl, const char *path,
                      kt_err *e);
void kt_lri_summary(const kt_lp_answer *a, const kt_lriplan_opts *o, const kt_lri_files *fl, FILE *f);
int kt_lri_write_html(const kt_lp_answer *a, const kt_lriplan_opts *o, const kt_lri_files *fl, const char *path,
                      kt_err *e);

#endif
