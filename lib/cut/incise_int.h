/* incise_int.h: internals shared by the incise module's files (incise.c: topology, splitting
 * and steps; incise_ring.c: arcs on incision-ready surfaces; incise_snap.c: cuts snapped onto
 * a plane or a cylinder; incise_deform.c: constraint and force steps). Not a public header. */
#ifndef KT_INCISE_INT_H
#define KT_INCISE_INT_H

#include "incise.h"
#include "topology.h"

/* A face to cut: slot = 4*tet + local face (the face opposite local vertex j), the side of that
 * tet (-1: stays with the original nodes, +1: moves to the new ones), and the blade travel at
 * which the face is cut (degrees of arc, or mm of a planar front). */
typedef struct kt_cutface {
    int slot;
    int side;
    double key;
} kt_cutface;

enum { KT_PHASE_DEFORM = 1, KT_PHASE_CUT = 2 };
enum { KT_KEY_DEG = 1, KT_KEY_MM = 2 };

typedef struct kt_phase {
    int kind;
    char name[48];              /* "incision 1", "planar cut", "deform 2": for notes */
    kt_mark at;                 /* where the plan gives it */
    /* a cut */
    kt_cutface *face;
    int nface, pos;
    int key_unit;               /* KT_KEY_DEG or KT_KEY_MM */
    double total;               /* the travel of the whole cut (for labels) */
    double dps;                 /* travel per step (degrees), or 0 */
    int nps;                    /* duplicated nodes per step, or 0 */
    double done;                /* travel reached so far */
    long skipped;               /* faces already cut by an earlier phase */
    /* pull-apart forces of a planar cut */
    double pull_force, pull_dir[3];
    unsigned char *pull_node;   /* by input node: on the pull surface (NULL: first step's) */
    int *pair, npair, cappair;  /* pulled (stay-side node, new node) pairs */
    /* a deformation */
    const kt_deform *def;
    int *nodes, nnodes;
    int nsteps;
    int k;                      /* steps made in this phase */
} kt_phase;

struct kt_incise {
    const kt_plan *plan;
    kt_mesh *m;
    int quiet;
    int nv;                     /* nodes per tet */
    int *cur;                   /* ne*nv: the tets' current nodes */
    int nn, cap;
    int *origin;                /* current node -> input node */
    int *nbr;                   /* 4*ne: slot across each face, -1 on the boundary */
    unsigned char *cut;         /* 4*ne: face cut */
    signed char *side;          /* 4*ne: side of the slot's tet across a cut face */
    int *n2t_p, *n2t_i;         /* input node -> tets (CSR, tets ascending) */
    int maxdeg;
    kt_face *ftab;              /* every tet face, sorted (kt_mesh_tet_faces; id = slot) */
    int nftab;
    int nphase, iphase, maxphase;
    kt_phase *phase;
    int *s_tet, *s_loc, *s_par, *s_lab, *s_cand; /* scratch */
    int ncand, capcand;
    unsigned char *held;        /* input node -> the scene fixes one of its DOFs */
    int nheld;
    kt_incise_stats st;
};

/* incise_mesh.c: the current tets, the face table and neighbours, node -> tets, scratch. */
int kt_incise_tables(kt_incise *c, kt_err *e);
/* Local positions (0..9) of the nodes of face j of a tet of the given order; returns 3 or 6. */
int kt_incise_face_pos(int order, int j, int *pos);
/* The slot of the tet face with vertices a, b, c (any order), -1 if none (the lower slot of
 * the two tets sharing it). */
int kt_incise_find_face(const kt_incise *c, int a, int b, int d);
/* Cut the faces and split the nodes they disconnect; the DUP edits go to s. */
int kt_incise_cut(kt_incise *c, kt_phase *ph, const kt_cutface *f, int n, kt_step *s,
                  int *ndup, kt_err *e);
/* The root of a in the union-find forest par (with path halving). */
int kt_incise_uf_find(int *par, int a);
/* incise_anchor.c: which input nodes the scene fixes; then, after a cut step, KT_EINPUT if a
 * piece of the current mesh holds none of them. */
int kt_incise_anchor_init(kt_incise *c, kt_err *e);
int kt_incise_anchor_check(kt_incise *c, const kt_phase *ph, int step, kt_err *e);
/* Sort a phase's faces by key (then slot). */
void kt_incise_sort_faces(kt_phase *ph);

/* Distance of each listed node to the surfaces 'anterior' and 'outer' (those present). */
int kt_incise_depths(const kt_mesh *m, const int *nodes, int n, double *depth, kt_err *e);

/* Phases. */
int kt_incise_ring_phase(kt_incise *c, const kt_incision *inc, int index, kt_phase *ph,
                         kt_err *e);
int kt_incise_cylinder_phase(kt_incise *c, const kt_incision *inc, int index, kt_phase *ph,
                             kt_err *e);
int kt_incise_planar_phase(kt_incise *c, kt_phase *ph, kt_err *e);
int kt_incise_deform_phase(kt_incise *c, const kt_deform *d, int index, kt_phase *ph,
                           kt_err *e);
int kt_incise_deform_step(kt_incise *c, kt_phase *ph, kt_step *s, kt_err *e);

/* incise_snap.c, for the tunnels (incise_tunnel.c): the faces between the tets whose
 * centroids lie on either side of the plane (point, normal), into ph->face (slot on the minus
 * side, key 0); snapping the vertices of ph's faces onto that plane; is tet t in the cornea or
 * the limbus (any tet when the mesh names neither). */
int kt_incise_plane_faces(kt_incise *c, const double *point, const double *normal, kt_phase *ph, kt_err *e);
int kt_incise_snap_plane(kt_incise *c, kt_phase *ph, const double *point, const double *normal, const char *what,
                         kt_err *e);
int kt_incise_in_front(const kt_mesh *m, int t);
/* Leave no tet hanging by one face (its other faces cut, on the boundary or in ph): each such tet
 * is moved across the cut when ok allows every face it would then cut and that leaves it held by
 * two faces or more (the cut surface is the plane (point, normal): sides by the centroid, the
 * faces rebuilt with key 0), else its faces in ph are dropped; ok NULL: drop only (ph's faces
 * and keys kept). *moved, *dropped: tets. */
typedef int (*kt_incise_face_ok)(const kt_incise *c, const void *ctx, int slot);
int kt_incise_unhang(kt_incise *c, kt_phase *ph, const double *point, const double *normal, kt_incise_face_ok ok,
                     const void *ctx, int *moved, int *dropped, kt_err *e);
/* incise_tunnel.c: tunnel `index` of the plan as a cut phase. */
int kt_incise_tunnel_phase(kt_incise *c, const kt_tunnel *t, int index, kt_phase *ph, kt_err *e);

/* Snap the vertex nodes listed (flag by input node) onto a surface, checking every element
 * they touch; proj puts the projection of x in y and returns the distance. */
typedef double (*kt_incise_proj)(const void *surf, const double *x, double *y);
int kt_incise_snap(kt_incise *c, const unsigned char *flag, kt_incise_proj proj,
                   const void *surf, const char *what, kt_err *e);

/* Angle of a point about the eye axis, degrees in (-180, 180]. */
double kt_incise_theta(const double *x);
/* Signed angle of theta from an arc's centre, degrees in (-180, 180]. */
double kt_incise_rel_angle(double theta, double centre);
/* Blade travel (deg) at which a face with vertices at relative angles d[3] is cut, or -1 when
 * the face is not on the incision's arc. */
double kt_incise_arc_key(const kt_incision *inc, const double *d, int side);
/* Set up phase ph as incision `index` along an arc: name, unit (deg), travel and progression. */
void kt_incise_arc_phase(const kt_incision *inc, int index, kt_phase *ph);
/* Median edge length of the listed surface triangles. */
double kt_incise_median_edge(const kt_mesh *m, const int *tris, int nt, kt_err *e);

#endif
