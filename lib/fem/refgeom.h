/* refgeom.h: the stress-free (zero-load) reference geometry of a scene whose geometry is the
 * measured, loaded shape.
 *
 * A clinical eye is measured in vivo, already inflated by its intraocular pressure. A linear
 * model that takes that shape as stress-free and then applies the pressure describes a
 * different, over-inflated eye. The standard remedy in corneal biomechanics (Pandolfi &
 * Manganiello 2006, Biomech Model Mechanobiol 5:237; Elsheikh et al. 2013, Stress free
 * configuration of the human eye, Med Eng Phys 35:211; Sellier 2011, J Fluids Struct 27:1461)
 * is the inverse problem: find the stress-free shape X0 that the loads deform into the measured
 * shape Xm,
 *
 *     X0 + u(X0) = Xm,         u(X) the scene's linear elastic solution on coordinates X,
 *
 * by fixed-point iteration on X0 <- Xm - u(X0) from X0 = Xm. u depends on X through the element
 * geometry and the pressure faces. On a soft, nearly incompressible cornea the plain iteration
 * diverges (see refgeom.c), so it is accelerated by Anderson mixing, a multisecant quasi-Newton
 * method: each iteration is one linear solve. Every node moves: P2 mid-edge nodes too, so curved
 * elements stay curved; fixed nodes have u = 0 and keep their place. */
#ifndef KT_REFGEOM_H
#define KT_REFGEOM_H

#include "mesh.h"
#include "scene.h"

typedef struct kt_refgeom_opts {
    double tol;     /* stop when max |X0 + u(X0) - Xm| <= tol, mm (the scene's
                     * loads.reference_tolerance, default 3e-5 mm = 0.03 um) */
    int maxit;      /* solves allowed (default 40) */
    int quiet;      /* progress on stderr unless set */
} kt_refgeom_opts;

typedef struct kt_refgeom_stats {
    int iters;          /* solves made (the last one measures the final residual) */
    double initial;     /* max |u(Xm)|: the shape error of taking Xm as stress-free, mm */
    double residual;    /* max |X0 + u(X0) - Xm| at the end, mm */
    double shift;       /* max |X0 - Xm|, mm */
    double rate;        /* last residual / the one before: the contraction factor */
} kt_refgeom_stats;

/* tol from the scene (s may be NULL: 3e-5 mm), maxit 40. */
void kt_refgeom_opts_default(const kt_scene *s, kt_refgeom_opts *o);

/* u (3*nn, mm) under the scene's pressures, materials and fixation on mesh m as it stands:
 * one direct solve (kt_fem_solve). */
int kt_refgeom_solve(const kt_scene *s, const kt_mesh *m, double *u, kt_err *e);

/* Replace m's coordinates (the measured, loaded shape) by the stress-free ones. Returns KT_ERUN,
 * with m unchanged and the residual in the message, when the iteration does not reach o->tol
 * within o->maxit solves or stops contracting; an element that inverts on the way is KT_ERUN
 * too (from the assembly). A scene without loads leaves m unchanged (0 iterations). */
int kt_refgeom_unload(const kt_scene *s, kt_mesh *m, const kt_refgeom_opts *o,
                      kt_refgeom_stats *st, kt_err *e);

#endif
