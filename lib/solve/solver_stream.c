/* solver_stream.c: the stream methods (augmented, refactor, cg, pcg-jacobi: kt_aug, aug.h) as a
 * backend of the front door (solver.h). Each step is solved as it comes, written or not (the
 * augmented method's appended rows and CG's starting guess follow every step). */
#include "solver.h"

#include <string.h>

static int stream_create(void **st, const kt_solver_in *in, char *why, size_t n, kt_err *e)
{
    (void)why, (void)n;
    kt_aug_opts o = *in->o; /* restriction and verification are the front door's */
    o.output[0] = 0;
    o.verify = 0;
    kt_aug *A = NULL;
    *st = NULL;
    if (kt_aug_create(&A, in->prob, &o, e)) return e->code;
    *st = A;
    return KT_OK;
}

static int stream_step(void *st, const kt_step *s, int mode, kt_err *e)
{
    (void)mode;
    return kt_aug_step(st, s, e);
}

static void stream_view(void *st, kt_solver_view *v)
{
    const kt_aug *A = st;
    *v = (kt_solver_view){kt_aug_mesh(A), kt_aug_displacement(A), kt_aug_origin(A), *kt_aug_last(A)};
}

static const double *stream_reaction(void *st, kt_err *e) { return kt_aug_reaction(st, e); }

static int stream_fresh(void *st, double *u, double *t, kt_err *e)
{
    return kt_aug_fresh(st, u, t, e);
}

static void stream_free(void *st) { kt_aug_free(st); }

const kt_solver_backend kt_solver_stream = {"stream", stream_create, stream_step, stream_view,
                                            stream_reaction, stream_fresh, stream_free,
                                            NULL, 0};
