/* wound.h: the healed wound as a bridge across the faces an incision separated
 * (keratome-scene(5), WOUND; docs/physics.md, "Healing").
 *
 * A cut duplicates nodes: the tets on one side of an incision surface move to new nodes, and
 * each face of the intact mesh the surface holds becomes two boundary faces, one per side, whose
 * nodes descend from the same intact nodes (a face pair). The healed scar joins them: energy
 * 1/2 k int_face |[u]|^2 dA, [u] = u(side +) - u(side -) the jump of the displacement across the
 * pair, k the bridge stiffness per area (MPa/mm = N/mm^3), integrated over the face in the
 * reference geometry with the face's own consistent mass matrix (P2: 6 nodes, P1: 3) per
 * component, one k normal and tangential. So B = k sum_pairs sum_ij M_ij J_i J_j^T per
 * component, J_i the jump of face node i as a combination of displacements. k = 0 is the
 * immediate (unbridged) wound exactly; k -> infinity glues every pair: the uncut body. The
 * bridge has no rest gap: it pulls the lips back to where they were in the intact reference (a
 * scar that has contracted the wound shut).
 *
 * Face pairs, on any mesh a plan's cuts make of the intact one (cuts keep tet numbers and only
 * move a tet from a node to a new child): slot s = 4 t + f (face f of tet t, opposite vertex f)
 * and its mate s' across the intact mesh's interior face; the pair is cut when one of its face
 * nodes differs between the two tets. Through the planned method's variables (u of a node = the
 * sum of the increments along its chain of parents, lib/solve/aug_plan.h) the jump of a face
 * node is the difference of two chains with their common part (the intact ancestor and every
 * node both sides still share) dropped: increments only, never an intact DOF. And a step k of a
 * plan: a tet's node at step k is the nearest released ancestor of its final node, so the jump
 * on step k's own mesh is the final mesh's jump with the unreleased increments zeroed (a pair
 * not cut yet has both sides on the same node: both chains end alike and the jump is zero). So
 * the final mesh's bridge restricted to step k's variables is step k's bridge: the planned
 * method's leading principal blocks hold it step by step (tests/fem/test_wound.c checks it). */
#ifndef KT_WOUND_H
#define KT_WOUND_H

#include "fem.h"

/* The bridge of one intact mesh. Owner: kt_wound_build / kt_wound_free. */
typedef struct kt_wound {
    double k;                   /* bridge stiffness per area, MPa/mm; 0: the immediate wound */
    int ne, order;              /* tets and element order of the intact mesh (and of its cuts) */
    int *mate;                  /* 4 ne: the slot across slot s in the intact mesh, -1 on its
                                   boundary */
    signed char *map;           /* 6 per slot: face node i of slot s is face node map[6 s + i]
                                   of its mate */
} kt_wound;

/* The face nodes of local face f: loc[0..fv) tet-local positions, corners kt_tet_face[f] then
 * (P2) the mid-edge nodes of their edges 01 12 20 (a tri6 in gmsh order). Returns fv. */
int kt_wound_face_local(int order, int f, int *loc);

/* w := the bridge of stiffness k on the intact mesh m (its face adjacency). */
int kt_wound_build(kt_wound *w, const kt_mesh *m, double k, kt_err *e);
void kt_wound_free(kt_wound *w);

/* 1: slot s's face (mate > s or not) is cut on mesh m (a cut of w's intact mesh). */
int kt_wound_cut(const kt_wound *w, const kt_mesh *m, int s);

/* The cut pairs of m, each once by its lower slot, ascending: *slots (allocated; caller frees),
 * *n of them. KT_EINPUT when m is not a cut of w's mesh (tet count or order). */
int kt_wound_pairs(const kt_wound *w, const kt_mesh *m, int **slots, int *n, kt_err *e);

/* The consistent mass matrix M (fv x fv, row-major) of a face with nodes xf (3 fv coordinates,
 * a tri3 or tri6 in gmsh order): M_ij = int N_i N_j dA, exact on a straight face (P1: A/12 (1 +
 * delta_ij); P2 with Radon's 7-point rule on the isoparametric face). */
void kt_wound_face_mass(int order, const double *xf, double *M);

/* The bridge's entries, scale x B: put(ctx, v, w, x) for v, w DOFs of m (3 node + component)
 * or, with parent (a node's parent in m, -1 for an intact node; the planned method's
 * variables), variables (the DOFs of the nodes of the jumps' chains); only v >= w unless all
 * (then both orientations). Entries of the same (v, w) come in several calls (to be summed).
 * kt_wound_pair_put: the pair of slot s alone; kt_wound_assemble: every cut pair of m.
 * KT_EINPUT for a chain deeper than KT_WOUND_CHAIN_MAX. */
enum { KT_WOUND_CHAIN_MAX = 256 };
typedef void (*kt_wound_put_fn)(void *ctx, int v, int w, double x);
int kt_wound_pair_put(const kt_wound *w, const kt_mesh *m, int s, const int *parent, double scale,
                      int all, kt_wound_put_fn put, void *ctx, kt_err *e);
int kt_wound_assemble(const kt_wound *w, const kt_mesh *m, const int *parent, double scale,
                      kt_wound_put_fn put, void *ctx, kt_err *e);

/* y (3 nn of m) += scale x B u: the bridge's forces (nodal form). */
int kt_wound_apply(const kt_wound *w, const kt_mesh *m, const double *u, double scale, double *y,
                   kt_err *e);

/* The bridge of mats on mesh m is there (mats->wound with k > 0). */
int kt_wound_on(const kt_materials *mats);

#endif
