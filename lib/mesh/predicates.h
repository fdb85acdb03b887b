/* predicates.h: exact signs of the geometric tests that decide which side of a cut an element
 * is on. Each test first evaluates in double precision with a forward error bound; only when the
 * value is within the bound is it recomputed exactly with floating-point expansions (sums of
 * non-overlapping doubles, built from error-free two-sum and fma-based two-product), so the
 * answer never depends on round-off: +1, -1, or 0 for an exactly degenerate input. */
#ifndef KT_PREDICATES_H
#define KT_PREDICATES_H

/* Sign of det[b-a, c-a, d-a]: +1 when d lies on the side of plane abc that (b-a)x(c-a) points
 * to (a positively oriented tet a,b,c,d, as kt_tet_volume counts it). */
int kt_pred_orient3d(const double *a, const double *b, const double *c, const double *d);

/* Sign of n . (x_0 + ... + x_{k-1} - k p): the side of the plane through p with normal n on
 * which the centroid of the k points (1 <= k <= 10) lies. */
int kt_pred_plane_side(const double *p, const double *n, const double *const *x, int k);

/* Sign of |c_xy|^2 - r^2 for the centroid c of the k points (1 <= k <= 10): outside (+1) or
 * inside (-1) the cylinder of radius r about the z axis. */
int kt_pred_cylinder_side(double r, const double *const *x, int k);

/* Counters for tests: how many calls fell back to exact arithmetic (per predicate context). */
typedef struct kt_pred_stats {
    long calls, exact;
} kt_pred_stats;
int kt_pred_orient3d_counted(const double *a, const double *b, const double *c, const double *d,
                             kt_pred_stats *st);

#endif
