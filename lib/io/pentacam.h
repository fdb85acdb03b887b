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
    /* What the export's header lines say of themselves (0 / "" when they do not say), with
     * the 1-based line and column where it is said (each header field is read: a field "Eye"
     * followed by OD, OS, right or left; a field naming "Elevation" or "Pachymetry", "front" /
     * "anterior" or "back" / "posterior", and a unit in brackets, "[mm]", "[um]" or "[µm]"). */
    int eye;                    /* KT_PENTACAM_OD or KT_PENTACAM_OS */
    int eye_line, eye_col;
    int head_kind;              /* KT_PENTACAM_ELEVATION + 1 or KT_PENTACAM_PACHYMETRY + 1 */
    int surface;                /* KT_PENTACAM_FRONT or KT_PENTACAM_BACK */
    int kind_line, kind_col;    /* the field that names the kind and surface */
    char unit[8];               /* "mm" or "um" */
    int unit_line, unit_col;
} kt_pentacam_map;

enum { KT_PENTACAM_OD = 1, KT_PENTACAM_OS = 2 };
enum { KT_PENTACAM_FRONT = 1, KT_PENTACAM_BACK = 2 };

/* Read one map. A file that is not a Pentacam map (no x coordinate row of the grid within
 * KT_PENTACAM_HEADER_MAX lines), a wrong grid, a truncated file or a value out of range is
 * KT_EINPUT with "file:line:col: expected ...". On failure m holds nothing to free. */
int kt_pentacam_read(const char *path, int kind, kt_pentacam_map *m, kt_err *e);
/* The same, with every measured value checked against [lo, hi] in the file's units (mm for
 * an elevation, um for a pachymetry) instead of the reader's own limits (elevation -0.5 to
 * 8 mm, pachymetry 100 to 2000 um); `whose` names the range in the message ("the patient
 * file's"). The first value outside is refused at its line and column. */
int kt_pentacam_read_range(const char *path, int kind, double lo, double hi, const char *whose, kt_pentacam_map *m,
                           kt_err *e);
void kt_pentacam_free(kt_pentacam_map *m);

/* The grid coordinate of index i (mm). */
double kt_pentacam_coord(int i);

#endif
