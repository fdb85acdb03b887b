/* lp_read.h: the readings of a solved step, in memory (lib/optics): the keratometric
 * astigmatism of the anterior surface (a toric fit over the central 3 mm, simulated K:
 * curvature(1)'s defaults), the total corneal one (with the posterior surface: curv_total.h),
 * and, for the band, the derivative of the keratometric SIA's double-angle vector (from the
 * run's step 0) along each band quantity (curv_band.h's central difference). What curvature
 * reads from the same step's file, without the file. Used by the run stage (lp_run.c). */
#ifndef KT_LP_READ_H
#define KT_LP_READ_H

#include "lp.h"

/* One run's reader: the surfaces' nodes of its intact mesh, and its step 0 (the band's
 * reference) once read. Owner: kt_lp_reader_init / kt_lp_reader_free. */
typedef struct kt_lp_reader {
    int nn;                     /* nodes of the run's intact mesh */
    unsigned char *ant, *post;  /* the anterior and posterior corneal nodes (post NULL: none) */
    double meridian;            /* the incised meridian, deg (the readings' flattening) */
    int nd;                     /* derivative fields */
    int n0;                     /* step 0's anterior points ... */
    double *xyz0, *dudp0;       /* ... their positions (3 n0) and du/dq (nd x 3 n0) */
} kt_lp_reader;

/* A step's readings; dsia[k] := d(SIA_x, SIA_y)/dq_k (nd of them; none at step 0 itself). */
typedef struct kt_lp_reading {
    kt_astig kerato, total;     /* total NAN without a posterior surface */
    double dsia[KT_LP_MAXQ][2];
} kt_lp_reading;

int kt_lp_reader_init(kt_lp_reader *r, const kt_mesh *intact, double meridian, kt_err *e);
/* The readings of step v (the run's step 0 first: it is the band's reference). A failed fit
 * or a derivative that is not finite at the anterior surface is KT_ERUN. */
int kt_lp_read(kt_lp_reader *r, const kt_lp_step *v, kt_lp_reading *out, kt_err *e);
void kt_lp_reader_free(kt_lp_reader *r);

#endif
