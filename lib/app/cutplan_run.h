/* cutplan_run.h: the cutplan tool (plan + mesh -> edits stream). */
#ifndef KT_CUTPLAN_RUN_H
#define KT_CUTPLAN_RUN_H

#include "util.h"

/* The cutplan tool: load the plan and the mesh, check them against each other, write the
 * snapped mesh when snapping moved nodes (mesh_out is then required), and stream the edits to
 * out ("-": stdout), a step at a time. A summary goes to stderr unless quiet. */
typedef struct kt_cutplan_opts {
    const char *plan, *mesh, *out;
    const char *mesh_out;       /* where to write the snapped mesh (NULL: none) */
    int binary;                 /* binary MSH for mesh_out */
    int quiet;
} kt_cutplan_opts;

int kt_cutplan_run(const kt_cutplan_opts *o, kt_err *e);

#endif
