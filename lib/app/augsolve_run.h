/* augsolve_run.h: the augsolve tool (mesh + edits stream -> run folder). */
#ifndef KT_AUGSOLVE_RUN_H
#define KT_AUGSOLVE_RUN_H

#include "aug.h"

/* The augsolve tool: mesh + edits stream -> run folder (step-NNNN.vtk, steps.tsv, run.yaml). */
typedef struct kt_aug_run_opts {
    const char *mesh, *edits, *run_dir;
    const char *scene;        /* NULL: the scene the edits header names */
    int vtk, binary;          /* write step VTKs (binary legacy format) */
    kt_aug_opts aug;
} kt_aug_run_opts;

int kt_aug_run(const kt_aug_run_opts *o, kt_err *e);

#endif
