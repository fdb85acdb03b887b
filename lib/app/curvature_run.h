/* curvature_run.h: the curvature tool (run folder -> keratometry tables, maps, summaries). */
#ifndef KT_CURVATURE_RUN_H
#define KT_CURVATURE_RUN_H

#include <stdio.h>
#include "curv.h"
#include "curv_report.h"

typedef struct kt_curv_opts {
    const char *run_dir;     /* RUN_DIR, or NULL with mesh + vtk[] */
    const char *shown_dir;   /* RUN_DIR as report.html names it, and the paths in it (NULL:
                                as given; lri-plan: the plan folder it is renamed into) */
    const char *mesh;        /* --mesh: the input mesh (MSH) */
    const char *plan;        /* --plan: overrides run.yaml's plan */
    const char *const *vtk;  /* step files, step 0 first (with mesh) */
    int nvtk;
    const char *outdir;      /* -o; default RUN_DIR (or "." with --mesh) */
    double zone;             /* keratometry zone diameter, mm (3, 5 or 7) */
    double map_zone;         /* diameter of the axial map and its fit, mm */
    int fit;                 /* KT_FIT_* */
    int order;               /* Zernike order of the zone fit */
    int map_order;           /* Zernike order of the map fit */
    double meridian;         /* incised meridian, deg; NaN: from the plan, else steep at step 0 */
    int png, vtk_out;        /* write the PNG maps / the surface VTKs */
    int quiet;
    const char *scale;       /* colour scale TSV; NULL: SHARE/colour/axial.tsv */
    const char *share;       /* share folder; NULL: $KERATOME_SHARE, else the build's share/ */
    int report;              /* write report.html (needs the maps' colour scales) */
    int json;                /* the summary as JSON instead of text */
    int scale_auto;          /* --scale auto: a relative scale over the run's powers */
    int step_sel;            /* --step N: step 0 and step N only (-1: every step) */
    double arc_sel;          /* --arc DEG: step 0 and the step with DEG of arc (NaN: none) */
    int eye_os;              /* --eye OS: the report draws a left eye (default OD) */
    const char *sens;        /* --sens FILE: finite-difference derivatives of the fd quantities */
    int no_bands;            /* --no-uncertainty: no bands even when RUN/uncertainty.tsv exists */
    const kt_report_main *main; /* the main incision the report shows (NULL: none) */
} kt_curv_opts;

void kt_curv_opts_default(kt_curv_opts *o);

/* Analyse every step, write curvature.tsv, meridians.tsv, surface-NNNN.vtk, axial-NNNN.png,
 * report.html (optics/curv_report.h) and, for a run folder, steps.pvd (a ParaView collection
 * of the step VTKs) into the output folder (all or nothing) and print the summary (text, or
 * JSON with o->json) on `summary` (NULL: none). */
int kt_curv_run(const kt_curv_opts *o, FILE *summary, kt_err *e);

/* The page comparing two runs that curvature has read (their curvature.tsv, run.yaml and
 * plan): out/compare.html (curvature(1), --compare). */
int kt_curv_compare(const char *run_a, const char *run_b, const char *outdir, kt_err *e);

#endif
