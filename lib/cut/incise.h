/* incise.h: a plan on a mesh becomes steps of edits (node duplications, constraints, forces).
 *
 * A cut is a set of interior mesh faces. A node is duplicated when the cut faces through it
 * disconnect the tets around it (tets joined across uncut faces that hold the node): inside an
 * incision patch and along its opening on the boundary that is always so, while on the patch's
 * edges inside the tissue (floor, ends, the blade's front) the tets still join around the edge,
 * so those nodes stay shared. A P2 mid-edge node is one more node under the same rule. The
 * tets on the outer side (away from the eye axis; the side a planar cut's normal points to) move
 * to the new node. Sides come from exact orientation predicates (predicates.h).
 *
 * Steps are produced one at a time (kt_incise_next), so a writer can stream them. */
#ifndef KT_INCISE_H
#define KT_INCISE_H

#include "edits.h"
#include "mesh.h"
#include "plan.h"

typedef struct kt_incise kt_incise;

typedef struct kt_incise_stats {
    int steps;          /* steps produced so far */
    long dups;          /* nodes duplicated */
    long fixes, forces; /* constraint and force edits */
    long faces;         /* faces cut */
    long skipped;       /* faces of an incision already cut by an earlier one (skipped) */
    int snapped;        /* nodes moved onto a cutting surface */
    double max_snap;    /* largest snap distance, mm */
    int nn, ne;         /* the mesh's counts before any edit */
    long work, work_done; /* progress: faces to cut plus deformation steps */
} kt_incise_stats;

/* Prepare plan p on mesh m; both must outlive the context. A cut without an incision-ready
 * surface snaps nearby nodes onto the cutting surface IN m (see stats.snapped), except those
 * whose move would invert an element or push its quality below the plan's limit (they stay).
 * Progress and notes go to stderr unless quiet. */
int kt_incise_begin(kt_incise **c, const kt_plan *p, kt_mesh *m, int quiet, kt_err *e);

/* The next step into s (cleared first): 1, or 0 when the plan is done. */
int kt_incise_next(kt_incise *c, kt_step *s, kt_err *e);

const kt_incise_stats *kt_incise_stats_get(const kt_incise *c);

void kt_incise_end(kt_incise *c);

#endif
