/* lriplan_int.h: what lri-plan's files share (private to lib/app/lriplan_*.c). */
#ifndef KT_LRIPLAN_INT_H
#define KT_LRIPLAN_INT_H

#include <stdint.h>

#include "curv.h"
#include "lriplan_run.h"
#include "patient.h"
#include "surffit.h"

#define KT_LRIPLAN_MAXSTEP 64

/* One family's run: the predicted astigmatism after each step (step 0: no arc). */
typedef struct kt_lri_family {
    int paired;
    int nstep;                        /* steps run, arcs step * o->step deg */
    double arc[KT_LRIPLAN_MAXSTEP + 1];
    kt_astig kerato[KT_LRIPLAN_MAXSTEP + 1], total[KT_LRIPLAN_MAXSTEP + 1]; /* simulated */
    kt_astig pred[KT_LRIPLAN_MAXSTEP + 1]; /* predicted post-operative, the target's kind */
    int best;                         /* step of the least predicted residual */
} kt_lri_family;

/* Everything the answer reports. */
typedef struct kt_lri_answer {
    kt_patient p;
    int fitted;                       /* the cornea came from a Pentacam export */
    kt_surffit fit_ant, fit_post;
    int fit_post_ok, fit_pachy_ok;
    kt_pachyfit fit_pachy;
    double t_zone;                    /* pachymetry at the zone used, mm */
    double blade;                     /* blade depth, mm */
    kt_astig pre_kerato, pre_total;   /* pre-operative (measured; total with the posterior) */
    kt_astig post_vec;                /* the posterior toricity's contribution to the total */
    kt_astig main_vec;                /* the main incision's SIA added (0 when none / simulated) */
    int nfam;
    kt_lri_family fam[2];
    int chosen;                       /* family index of the answer */
    double mesh_seconds, solve_seconds;
    int nodes;                        /* of the mesh */
    uint64_t mesh_hash;               /* kt_mesh_hash of the mesh */
} kt_lri_answer;

/* Fill the answer's prediction per step and choose (lriplan_out.c). */
void kt_lri_choose(kt_lri_answer *a);
/* plan.json into the folder and the summary text. */
int kt_lri_write_json(const kt_lri_answer *a, const kt_lriplan_opts *o, const char *path, kt_err *e);
void kt_lri_summary(const kt_lri_answer *a, const kt_lriplan_opts *o, FILE *f);

#endif
