/* augsolve_run.h: the augsolve tool (mesh + edits stream -> run folder). */
#ifndef KT_AUGSOLVE_RUN_H
#define KT_AUGSOLVE_RUN_H

#include <stdint.h>

#include <stdio.h>

#include "aug.h"
#include "physics.h"
#include "sens.h"
#include "tsv.h"

/* The physics of the measured geometry (kt_physics: the per-tet data, the prestress under the
 * loads and the order its solve factored with; with uncertainty the quantities' derivative
 * data, kt_fem_sens, the prestress's derivatives among them) solved once by a caller that runs
 * several edits streams on one intact mesh and scene (lri-plan's families) and lent to each
 * kt_aug_run (kt_aug_run_opts.physics). The caller owns it: kt_aug_physics_solve fills it,
 * kt_aug_physics_free frees it; a run only reads it. */
typedef struct kt_aug_physics {
    int solved;
    kt_physics ph;
    kt_fem_sens sens;           /* uncertainty: the derivative data (else nothing) */
    int uncertainty;            /* solved with the derivatives */
    uint64_t mesh_hash;         /* kt_mesh_hash of the intact mesh it was solved on */
    int nn, ne;                 /* its nodes and tets */
    unsigned long long scene_hash; /* kt_fnv1a_file of the scene file's bytes */
    double seconds;             /* the whole solve: mesh read, scene, prestress */
} kt_aug_physics;

/* p := the physics of scene file `scene` on mesh file `mesh` (uncertainty: with the
 * derivative data augsolve --uncertainty needs), exactly as a kt_aug_run on that mesh and scene
 * would solve it itself; the prestress line on stderr unless quiet. On failure p holds nothing
 * to free. */
int kt_aug_physics_solve(kt_aug_physics *p, const char *mesh, const char *scene, int uncertainty,
                         int quiet, kt_err *e);
void kt_aug_physics_free(kt_aug_physics *p);

/* The augsolve tool: mesh + edits stream -> run folder (step-NNNN.vtk, steps.tsv, run.yaml). */
typedef struct kt_aug_run_opts {
    const char *mesh, *edits, *run_dir;
    const char *scene;        /* NULL: the scene the edits header names */
    int vtk, binary;          /* write step VTKs (binary legacy format) */
    const char *steps;        /* NULL: write every step; else a list "1,4,7-9" (step 0 always) */
    double plan_max_ratio;    /* planned: refactor with METIS beyond this factor-size ratio
                                 (kt_plan_factor_build; default KT_PLAN_MAX_RATIO, 0: never) */
    int uncertainty;          /* --uncertainty: dudp_<q> fields and uncertainty.tsv */
    const kt_aug_physics *physics; /* NULL: the run solves its physics itself; else the
                                 caller's, borrowed (not copied) when it was solved on the
                                 run's mesh and scene (their content hashes) with the run's
                                 uncertainty; otherwise the run solves its own and says why on
                                 stderr. The results are byte for byte the same either way. */
    kt_aug_opts aug;
} kt_aug_run_opts;

/* The tool's defaults: kt_aug_opts_default with the planned method and its default ordering
 * (aug_plan.h), step VTKs written. */
void kt_aug_run_opts_default(kt_aug_run_opts *o);

int kt_aug_run(const kt_aug_run_opts *o, kt_err *e);

/* The run folder's files (augsolve(1), FILES), for augsolve and for a run made in memory
 * (lri-plan's chosen run, lib/planner): each one writer.
 * kt_aug_step_vtk: step-NNNN.vtk at path: the cut mesh, its displacement u (3 nn), origin (nn,
 * 0-based), reactions (NULL: none), with sens the dudp_<q> fields (dudp[k], 3 nn each), with ph
 * (step 0) the per-tet inputs, with a healed wound (wound, the bridge of the intact mesh) the
 * cell field bridge (keratome-vtk(5)).
 * kt_aug_run_yaml: run.yaml from ri (paths made relative to the run folder, NULL ones left out).
 * kt_aug_uncertainty_tsv: RUN/uncertainty.tsv of S's quantities.
 * kt_aug_steps_head / _row: steps.tsv's header and one step's row. */
struct kt_wound;
typedef struct kt_aug_step_fields {
    const kt_mesh *mesh;
    const double *u;
    const int *origin;
    const double *react;        /* NULL: none */
    const kt_fem_sens *sens;    /* NULL: no dudp_<q> */
    const double *const *dudp;
    const kt_physics *ph;       /* NULL: no per-tet inputs (a step after 0) */
    const struct kt_wound *wound; /* NULL: no bridge (the immediate wound) */
} kt_aug_step_fields;
int kt_aug_step_vtk(const char *path, const kt_aug_step_fields *f, int binary, kt_err *e);
typedef struct kt_aug_run_info {
    const char *run_dir, *mesh, *scene, *plan, *edits;
    const kt_aug_opts *aug;     /* the method that ran */
    int order, nn, ne;          /* the mesh the run was solved on: element order, counts, */
    uint64_t hash;              /* kt_mesh_hash */
    int steps;                  /* the last step */
    int has_plan_hash;
    unsigned long long plan_hash;
    const char *output, *fallback, *written_steps; /* NULL or "": left out */
    const unsigned char *step_files; /* NULL: none written; else step k's file written when
                                   step_files[k] (k < nstep_files): run.yaml's step_files */
    int nstep_files;
    int uncertainty;
    const kt_scene *scene_s;    /* for the provenance block (runrec.h) */
} kt_aug_run_info;
int kt_aug_run_yaml(const kt_aug_run_info *ri, kt_err *e);
int kt_aug_uncertainty_tsv(const char *run_dir, const kt_fem_sens *S, kt_err *e);
void kt_aug_steps_head(kt_tsvw *w);
void kt_aug_steps_row(kt_tsvw *w, const kt_aug_row *r);

#endif
