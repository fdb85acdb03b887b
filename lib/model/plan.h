/* plan.h: the incision plan (man5 keratome-plan): limbal relaxing incisions on an eye scene,
 * or benchmark plans (an advancing planar cut, progressive constraints and forces).
 *
 * Angles follow the TABO convention of eye.h: degrees counter-clockwise from +x seen from the
 * front (+z), the eye axis +z. Internal units: mm, N, deg, D. Every field keeps the file
 * position it came from, so checks made later (against the mesh) still name file:line:col. */
#ifndef KT_PLAN_H
#define KT_PLAN_H

#include "mesh.h"
#include "scene.h"

#define KT_PLAN_MAX 16
/* The most steps a plan may ask for (keratome-plan(5), LIMITS): the arcs' steps (arc over
 * degrees_per_step, summed over the incisions, a paired incision counted once) and each
 * deform's steps. A plan beyond it is refused at load time, before any mesh is read. */
#define KT_PLAN_MAX_STEPS 3600

/* How the blade advances along an arc. */
enum { KT_BLADE_CW = 0, KT_BLADE_CCW = 1, KT_BLADE_CENTRE_OUT = 2 };
/* What a deformation entry prescribes. */
enum { KT_DEFORM_FIX = 1, KT_DEFORM_FORCE = 2 };

/* A position in the plan file (1-based; 0 when the field was absent). */
typedef struct kt_mark {
    int line, col;
} kt_mark;

/* How much each step adds: degrees of arc (arcs only) or duplicated nodes (any cut). */
typedef struct kt_progression {
    double degrees_per_step; /* > 0, or 0 when nodes_per_step is used */
    int nodes_per_step;      /* > 0, or 0 */
    kt_mark at;              /* where degrees_per_step / nodes_per_step was given */
} kt_progression;

typedef struct kt_incision {
    double meridian;            /* the arc's centre, deg in [0, 360) */
    double arc;                 /* arc length, deg in (0, 360] */
    double depth;               /* mm below the anterior surface (resolved from the fraction) */
    double depth_fraction;      /* as given (0 when depth was given as a length) */
    double diameter;            /* the ring's diameter, mm (given, or the named ring's) */
    char surface[KT_NAME_MAX];  /* the incision-ready surface; empty when the scene has no ring
                                 * at that diameter: the cut is then snapped onto the cylinder */
    int paired;                 /* 1: also the opposite arc (meridian + 180) */
    double arc_opposite;        /* paired: the opposite arc's extent, deg (0: the same as arc);
                                 * it grows in proportion, reaching it when arc is reached */
    int direction;              /* KT_BLADE_* */
    kt_progression prog;        /* the plan's progression unless the incision has its own */
    kt_mark at, at_depth, at_position;
} kt_incision;

typedef struct kt_deform {
    int kind;                   /* KT_DEFORM_FIX or KT_DEFORM_FORCE */
    char set[KT_NAME_MAX];      /* a surface (dim 2) or region (dim 3) group of the mesh */
    int set_dim;
    unsigned mask;              /* FIX: components prescribed (bit c) */
    double v[3];                /* FIX: displacement, mm; FORCE: total force on the set, N */
    int steps;                  /* ramp: every node of the set, value k/steps at step k */
    int nodes_per_step;         /* or: this many more nodes per step, each at the full value */
    int max_nodes;              /* only the first max_nodes nodes of the set (0: all) */
    double order[3];            /* nodes are taken by increasing x . order (then x, y, z) */
    kt_mark at, at_set;
} kt_deform;

typedef struct kt_planar {
    int set;                    /* 1 when the plan has a planar_cut block */
    double point[3];            /* a point of the plane, mm */
    double normal[3];           /* unit normal; the side it points to moves to new nodes */
    double advance[3];          /* unit direction of the blade, in the plane */
    double length;              /* how far the front advances, mm (0: through the whole body) */
    int nodes_per_step;
    double pull_force;          /* N on each side, split over the pulled nodes; 0: none */
    char pull_surface[KT_NAME_MAX]; /* pulled nodes: the cut's nodes on this surface
                                     * (empty: the nodes duplicated in the first step) */
    kt_mark at, at_pull;
} kt_planar;

/* A shelved tunnel through the full corneal thickness: the main cataract incision as a flat
 * keratome blade makes it (keratome-plan(5), TUNNELS). Cut before every arc, in `steps` steps
 * of the blade's advance. The plane and its frame are derived from the scene's eye at load time
 * (plan_tunnel.c): entry is the external entry on the outer surface at the tunnel's meridian,
 * along points from it through the stroma to the internal (Descemet) opening on the posterior
 * surface `length` away, across is the width direction (the circumferential tangent at the
 * meridian), normal = across x along (pointing to the roof, the anterior lip). */
/* Defaults of a tunnel (keratome-plan(5), TUNNELS; sources in docs/references.md). */
#define KT_TUNNEL_LENGTH 2.0 /* mm: Mackool et al. 1996: clear-corneal tunnels of 2.0 mm or more
                                resist leakage like scleral tunnels */
#define KT_TUNNEL_STEPS 4    /* the blade's advance in 4 steps */

typedef struct kt_tunnel {
    double meridian;            /* deg, [0, 360) */
    double width;               /* mm, the blade's width (chord along the circumference) */
    double length;              /* mm, external entry to internal opening, in the meridian */
    double entry_diameter;      /* mm, twice the external entry's distance from the eye axis */
    int steps;                  /* the blade's advance in this many steps */
    double entry[3], exit[3];   /* derived: the two lips' points on the meridian, mm */
    double along[3], across[3], normal[3]; /* derived: the plane's unit frame */
    kt_mark at;
} kt_tunnel;

/* The intended correction, for curvature's vector analysis. */
typedef struct kt_target {
    int set;
    double magnitude;           /* D */
    double axis;                /* deg, [0, 180) */
} kt_target;

/* Cuts made without an incision-ready surface snap nearby nodes onto the cutting surface. */
typedef struct kt_snap {
    double fraction;            /* snap a node closer than this fraction of its shortest edge */
    double min_quality;         /* refuse when an element's mean-ratio quality would fall
                                 * below this (and below its value before snapping) */
} kt_snap;

typedef struct kt_plan {
    char path[1024];            /* as given ("-": stdin) */
    char scene_path[1024];      /* resolved relative to the plan's folder */
    kt_scene scene;
    int ninc;
    kt_incision inc[KT_PLAN_MAX];
    int ndeform;
    kt_deform deform[KT_PLAN_MAX];
    kt_planar planar;
    kt_progression prog;        /* default progression: 5 degrees per step */
    kt_snap snap;
    kt_target target;
    int ntunnel;                /* tunnels (main incisions), cut before the incisions */
    kt_tunnel tunnel[KT_PLAN_MAX];
} kt_plan;

/* Load and validate a plan and the scene it names. Bad input (unknown or duplicate key, wrong
 * type or unit, arc outside (0, 360], depth not positive or beyond the local corneal
 * thickness or the incision-ready surface, missing scene) is KT_EINPUT "file:line:col: ...". */
int kt_plan_load(const char *path, kt_plan *p, kt_err *e);

/* Plans built in memory (lri-plan's families), resolved and checked as the reader resolves a
 * plan file. kt_plan_init: p := no cut yet on a copy of scene s (its path names it), named
 * `name` (p->path: for messages), with keratome-plan(5)'s defaults (5 deg per step, snapping).
 * kt_plan_add_incision: in's meridian, arc, paired, arc_opposite, direction, prog, the ring by
 * surface (set) or diameter, the depth as depth_fraction (> 0) or depth: the ring and the
 * depth resolved as incisions[] are; KT_EINPUT "name: incisions[i].depth: expected ..."
 * otherwise, or beyond KT_PLAN_MAX_STEPS. kt_plan_add_tunnel: t's meridian, width, length,
 * entry_diameter, steps, its plane derived (kt_tunnel_derive); KT_EINPUT naming the field. */
void kt_plan_init(kt_plan *p, const kt_scene *s, const char *name);
int kt_plan_add_incision(kt_plan *p, const kt_incision *in, kt_err *e);
int kt_plan_add_tunnel(kt_plan *p, const kt_tunnel *t, kt_err *e);

/* Check tunnel t (meridian, width, length, entry_diameter set) against the eye and derive its
 * plane (entry, exit, along, across, normal). KT_EINPUT with the offending field's name in
 * *field and "expected ..." in msg when the entry is not on the peripheral cornea or the
 * limbus, the length does not reach the anterior chamber, or the width does not fit. */
int kt_tunnel_derive(const kt_eye *eye, kt_tunnel *t, const char **field, char *msg, size_t size);

/* Check the plan against the mesh it will cut: every named surface and region exists (KT_EINPUT
 * at the naming field otherwise), eye plans need the 'anterior' surface. */
int kt_plan_check_mesh(const kt_plan *p, const kt_mesh *m, const char *mesh_name, kt_err *e);

/* "file:line:col" of a mark (the plan path alone when the mark is unset). */
void kt_plan_where(const kt_plan *p, kt_mark at, char *buf, size_t size);

#endif
