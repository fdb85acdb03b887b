/* curvature_int.h: the curvature run's state, shared by its driver (curvature_run.c) and its
 * outputs (curvature_out.c); private to lib/app. The driver owns run_ctx (setup, ctx_free). */
#ifndef KT_CURVATURE_INT_H
#define KT_CURVATURE_INT_H

#include <stdio.h>

#include "axialmap.h"
#include "curv.h"
#include "curv_report.h"
#include "curv_total.h"
#include "json.h"
#include "tsv.h"
#include "curvature_run.h"
#include "plan.h"
#include "uqread.h"

#define PATHMAX 4096

/* What one step gives. */
typedef struct step_res {
    kt_fit fit;          /* zone fit (keratometry) */
    kt_kerato k;
    double map_radius;   /* radius of the map fit, mm */
    double bfs_radius;   /* best-fit sphere over the map disk, mm */
    kt_fit map;          /* the map fit */
    kt_fit post;         /* posterior zone fit (has_post) */
    int has_post;
    kt_total tot;        /* posterior and total corneal power (NaN without a posterior surface) */
} step_res;

typedef struct run_ctx {
    const kt_curv_opts *o;
    char outdir[PATHMAX], tmpdir[PATHMAX];
    int made_outdir;     /* the output folder did not exist: removed again on failure */
    char mesh[PATHMAX], plan[PATHMAX];
    int nstep;
    char **vtk;          /* nstep step files, step 0 first */
    int *num;            /* the step number of each (its run's numbering: --step, --mesh names) */
    unsigned char *mask; /* anterior nodes of the input mesh */
    unsigned char *post_mask; /* posterior corneal nodes (NULL: none) */
    int mesh_nn, mesh_ne, mesh_order;
    unsigned long long mesh_hash, plan_hash; /* run.yaml's (RUN_DIR): checked in setup */
    int has_plan_hash;
    kt_topo_scale scale, diff_scale;
    kt_cornea_n n;
    kt_plan *plan_in;    /* the plan read (NULL: no plan) */
    double *u0;          /* step 0's displacement by input node (for the report's section) */
    kt_section section;
    double t0;           /* start, kt_now() */
    double meridian;     /* incised meridian, deg (NaN: not known yet) */
    const char *meridian_src;
    int has_target;
    kt_astig tia;
    step_res *res;
    kt_topo_scale abs_scale; /* the absolute scale (the maps' when not --scale auto) */
    kt_topo_scale rel_scale; /* the relative scale over this run's powers (auto_maps) */
    unsigned long long mesh_hash_read; /* kt_mesh_hash of the mesh read (the report's provenance) */
    int nfile;
    char **file;         /* names written into tmpdir */
    /* uncertainty bands (curvature_band.c): on when the run folder has uncertainty.tsv */
    int bands;
    kt_uq_table uq;      /* RUN/uncertainty.tsv */
    kt_uq_sens sens;     /* --sens */
    int *used;           /* uq.n: 1 when the quantity contributes (derivative, or fd with --sens rows) */
    double *deriv;       /* nstep x uq.n x KT_RD_N: dR/dp (0 for quantities left out) */
    double *eps;         /* nstep x uq.n: the central difference's step, in p's unit (NaN: fd/none) */
    double *sd;          /* nstep x KT_RD_N: the readings' standard deviations */
    double *val;         /* nstep x KT_RD_N: the readings (kt_band_readings) */
    int b0_n;            /* step 0's anterior nodes, positions and dudp (uq.n x 3 b0_n) */
    double *b0_xyz, *b0_dudp;
} run_ctx;

/* dst = dir/name (PATHMAX), KT_EINPUT when too long. */
int kt_curvrun_join(char *dst, const char *dir, const char *name, kt_err *e);
/* An axis in [0, 180) as it prints with `decimals` decimals: what would round to 180 is 0. */
double kt_curvrun_axis_out(double a, int decimals);
/* Register an output written into the temporary folder, and its path there. */
int kt_curvrun_add_file(run_ctx *c, const char *name, kt_err *e);
int kt_curvrun_tmp_path(run_ctx *c, char *path, const char *name, kt_err *e);

/* Degrees of arc opened per incision at the i-th step analysed (NaN: no arcs in the plan). */
double kt_curvrun_arc(const run_ctx *c, int i);
/* One line on over- or under-correction and an axis flip, for the summary and the page. */
void kt_curvrun_verdict(const run_ctx *c, char *buf, size_t size);

/* curvature_band.c */
int kt_curvrun_band_setup(run_ctx *c, kt_err *e);
/* The derivatives of step `step` (its VTK v and anterior surface s; step 0 first). */
int kt_curvrun_band_step(run_ctx *c, int step, const kt_vtk *v, const kt_surf *s, kt_err *e);
/* After every step: the fd rows of --sens and the standard deviations. */
int kt_curvrun_band_finish(run_ctx *c, kt_err *e);
void kt_curvrun_band_free(run_ctx *c);
/* curvature.tsv's band columns (header / one step's values, each with a leading tab). */
void kt_curvrun_band_tsv_head(const run_ctx *c, kt_tsvw *w);
void kt_curvrun_band_tsv_row(const run_ctx *c, int i, kt_tsvw *w);
int kt_curvrun_band_write(run_ctx *c, kt_err *e); /* derivatives.tsv */
void kt_curvrun_band_summary(const run_ctx *c, FILE *f);
void kt_curvrun_band_json_top(const run_ctx *c, kt_json *j);
void kt_curvrun_band_json_step(const run_ctx *c, int i, kt_json *j);
/* The contributions to the SIA's sd at the last step, largest first: names, values; count. */
int kt_curvrun_band_tornado(const run_ctx *c, const char **name, double *val);

/* curvature_out.c */
int kt_curvrun_write_tables(run_ctx *c, kt_err *e);
void kt_curvrun_summary(const run_ctx *c, FILE *f);
void kt_curvrun_summary_json(const run_ctx *c, FILE *f);
int kt_curvrun_write_pvd(run_ctx *c, kt_err *e);
int kt_curvrun_write_report(run_ctx *c, kt_err *e);

#endif
