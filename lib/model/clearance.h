/* clearance.h: how far a limbal relaxing arc stays from the eye's through-incisions (the main
 * cataract incision's tunnel, a side port), and the longest arcs of a family that keep a stated
 * clearance (keratome-patient(5), CLEARANCE). Pure functions of the geometry; nothing is meshed.
 *
 * Seen from the front (the eye's axis +z towards the observer, angles TABO as eye.h), a wound's
 * footprint is the rectangle it opens in the cornea: along its meridian m from r_in to r_out
 * (mm from the eye axis: the internal opening and the external entry of a tunnel), across it
 * |w| <= width / 2. An arc is the part of the zone from centre - arc / 2 to centre + arc / 2
 * (deg); the zone is an ellipse of semi-axes rx (along 0 deg) and ry (along 90 deg), mm: the ring
 * of an oval cornea (keratome-scene(5), THE OVAL CORNEA), a circle when rx == ry. Its point at
 * meridian th lies at the ellipse's radius in that meridian, where the oval warp moves it.
 *
 * Outputs:
 *   kt_clearance       the arc's clearance from the wound, degrees at the zone: when the arc
 *                      and the footprint are apart, the least distance between them (mm) over
 *                      the zone's radius at that point, in degrees (on a circle where it
 *                      meets the footprint, that is the angular gap); when the arc runs through
 *                      the footprint, minus the degrees of arc inside it (negative: they cross).
 *                      NaN for a semi-axis <= 0, a negative or infinite arc or a NaN input.
 *   kt_clear_arc       the longest arc (deg, at most max) centred at `centre` whose clearance
 *                      from every wound is at least `min` degrees; 0 when the centre itself
 *                      lies within `min` of a wound; *which: the limiting wound (-1: none).
 *   kt_clear_family    for a single arc or a pair (the opposite arc at centre + 180, ratio
 *                      times as long): the longest arc of the family (the one at `centre`),
 *                      the limiting wound and arc, and a sentence saying why, for the summary.
 *
 * Depth does not enter: a tunnel runs from the outer surface at its entry to the posterior
 * surface at its opening, so over its footprint it lies at every depth from 0 to 100%; an arc
 * 90% deep crossing the footprint meets the tunnel's plane except near the opening, and is
 * counted as crossing everywhere on it (the safe side). */
#ifndef KT_CLEARANCE_H
#define KT_CLEARANCE_H

#include "plan.h"

/* The default clearance between an arc's end and a wound, deg at the zone (half a clock hour;
 * the project's rule, argued in keratome-patient(5), CLEARANCE). */
#define KT_CLEARANCE_DEG 15.0

/* A wound's footprint (named kt_footprint: lib/fem/wound.h's kt_wound is the healed bridge). */
typedef struct kt_footprint {
    double meridian;            /* deg [0, 360) */
    double width;               /* mm, across the meridian */
    double r_in, r_out;         /* mm from the eye axis, r_in < r_out */
    const char *name;           /* "the main incision", "the side port": for the reason text */
} kt_footprint;

/* The zone the arcs lie on: an ellipse of semi-axes rx along 0 deg and ry along 90 deg, mm. */
typedef struct kt_zone {
    double rx, ry;
} kt_zone;

/* The footprint of a tunnel whose plane kt_tunnel_derive derived (entry, exit set). */
void kt_footprint_of_tunnel(const kt_tunnel *t, const char *name, kt_footprint *w);

double kt_clearance(const kt_footprint *w, double centre, double arc, kt_zone z);

double kt_clear_arc(const kt_footprint *w, int nw, double centre, double max, kt_zone z, double min, int *which);

typedef struct kt_clear_result {
    double arc;                 /* deg: the longest arc at `centre` (0: the family is left out) */
    int trimmed;                /* 1 when arc < max */
    int wound;                  /* the limiting wound (-1: none) */
    int opposite;               /* 1 when the opposite arc of a pair is the limiting one */
    double at_max;              /* the family's least clearance at max (deg; < 0: crossing) */
    char reason[240];           /* "" when not trimmed */
} kt_clear_result;

/* ratio: the opposite arc over this one (1 an equal pair); paired 0: a single arc. */
void kt_clear_family(const kt_footprint *w, int nw, double centre, int paired, double ratio, double max, kt_zone z,
                     double min, kt_clear_result *r);

#endif
