/* pentacam.h: a Pentacam (OCULUS) map exported as CSV: one elevation or pachymetry map on the
 * device's Cartesian grid (keratome-patient(5), THE PENTACAM EXPORT).
 *
 * Layout read: header lines (kept, not interpreted), then the grid's x coordinate row (a first
 * field that is empty or a label, then 141 x coordinates -7.0 ... 7.0 mm in 0.1 mm steps),
 * then 141 rows: the row's y coordinate (mm, on the same lattice, each once), then 141 values.
 * Fields are separated by ';' (decimal point '.' or ',') or by ',' (decimal point '.'). A cell
 * the device could not measure is empty or -1. Elevations are the sagittal height of the
 * surface below its own apex plane, mm (>= 0 towards the eye); pachymetry is in um.
 * Coordinates as the instrument sees the eye: +x the examiner's right, +y superior, for both
 * eyes (the model's frame, lib/model/eye.h). */
#ifndef KT_PENTACAM_H
#define KT_PENTACAM_H

#include "util.h"

#define KT_PENTACAM_N 141       /* grid points per side */
#define KT_PENTACAM_STEP 0.1    /* mm */
#define KT_PENTACAM_HALF 7.0    /* mm: the grid spans -7 ... 7 mm */
#define KT_PENTACAM_HEADER_MAX 64 /* header lines before the x coordinate row */
#define KT_PENTACAM_MAX_BYTES (16u << 20) /* a map of 141 x 141 numbers is about 0.2 MB */

enum { KT_PENTACAM_ELEVATION = 0, KT_PENTACAM_PACHYMETRY = 1 };

typedef struct kt_pentacam_map {
    int kind;                   /* KT_PENTACAM_* */
    int n;                      /* KT_PENTACAM_N */
    double *v;                  /* n * n values: v[j * n + i] at x = -7 + 0.1 i, y = -7 + 0.1 j;
                                   elevation in mm, pachymetry in mm (converted); NAN: no data */
    int nvalid;                 /* cells with data */
} kt_pentacam_map;

/* Read one map. A file that is not a Pentacam map (no x coordinate row of the grid within
 * KT_PENTACAM_HEADER_MAX lines), a wrong grid, a truncated file or a value out of range is
 * KT_EINPUT with "file:line:col: expected ...". On failure m holds nothing to free. */
int kt_pentacam_read(const char *path, int kind, kt_pentacam_map *m, kt_err *e);
void kt_pentacam_free(kt_pentacam_map *m);

/* The grid coordinate of index i (mm). */
double kt_pentacam_coord(int i);

#endif
