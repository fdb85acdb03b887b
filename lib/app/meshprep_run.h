/* meshprep_run.h: the mesh-prep tool: build a scene's mesh, add the groups the scene asks for,
 * measure element quality, compare orderings, renumber in elimination order and write MSH. */
#ifndef KT_MESHPREP_RUN_H
#define KT_MESHPREP_RUN_H

#include <stdio.h>

#include "mesh.h"
#include "order.h"
#include "scene.h"

/* One row of the ordering comparison. */
typedef struct kt_prep_row {
    int method;
    double t_order;         /* seconds to compute the ordering */
    kt_order_stats st;
    kt_order_stats sector;  /* closures of the set's nodes within 30 deg of the centre meridian */
} kt_prep_row;

/* The whole run of mesh-prep. */
typedef struct kt_prep_opts {
    const char *scene, *out;    /* scene file; output MSH path or "-" */
    int ordering;               /* KT_ORDERING_*, 0: the scene's */
    int order;                  /* 1 or 2, 0: the scene's */
    int binary, quiet;
} kt_prep_opts;

/* Load, build, check, order, permute, write; the summary goes to 'summary' (NULL: none). */
int kt_prep_run(const kt_prep_opts *o, FILE *summary, kt_err *e);

/* The same with the ordering table's rows chosen: KT_PREP_TABLE_ALL (kt_prep_run's: every
 * ordering computed and analysed) or KT_PREP_TABLE_CHOSEN (mesh-prep --chosen-only: the chosen
 * ordering alone; the same mesh). A caller that discards the summary saves the other rows. */
enum { KT_PREP_TABLE_ALL, KT_PREP_TABLE_CHOSEN };
int kt_prep_run_table(const kt_prep_opts *o, int table, FILE *summary, kt_err *e);

#endif
