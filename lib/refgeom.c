/* refgeom.c: stress-free reference geometry by fixed-point iteration X0 <- Xm - u(X0). */
#include "refgeom.h"

#include <cholmod.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fem.h"

#define DEFAULT_TOL 1e-5  /* mm: 0.01 um, about 0.003 D of K on a 3 mm zone */
#define DEFAULT_MAXIT 25

void kt_refgeom_opts_default(const kt_scene *s, kt_refgeom_opts *o)
{
    o->tol = s && s->reference_tol > 0 ? s->reference_tol : DEFAULT_TOL;
    o->maxit = DEFAULT_MAXIT;
    o->quiet = 0;
}

/* Consistent nodal forces of every scene pressure on the mesh as it stands. */
static int pressure_load(const kt_scene *s, const kt_mesh *m, double *f, kt_err *e)
{
    memset(f, 0, 3 * (size_t)m->nn * sizeof(double));
    for (int i = 0; i < s->npressure; i++) {
        const kt_group *g = kt_mesh_find_group(m, 2, s->pressure[i].surface);
        if (!g)
            return kt_fail(e, KT_EINPUT, "%s: loads.pressure: expected surface '%s' in the mesh",
                           s->path, s->pressure[i].surface);
        if (kt_fem_pressure(m, g->tag, s->pressure[i].p, f, e)) return e->code;
    }
    return KT_OK;
}

int kt_refgeom_solve(const kt_scene *s, const kt_mesh *m, double *u, kt_err *e)
{
    size_t n = 3 * (size_t)m->nn;
    kt_materials mats = {0, NULL};
    unsigned char *fixed = kt_calloc(n, 1, e);
    double *g = kt_calloc(n, sizeof(double), e), *f = kt_calloc(n, sizeof(double), e);
    if (fixed && g && f && kt_scene_materials(s, m, &mats, e) == KT_OK &&
        kt_scene_dirichlet(s, m, fixed, g, e) == KT_OK && pressure_load(s, m, f, e) == KT_OK) {
        cholmod_common c;
        cholmod_start(&c);
        kt_fem_solve(m, &mats, fixed, g, f, u, &c, e);
        cholmod_finish(&c);
    }
    free(mats.mat);
    free(fixed);
    free(g);
    free(f);
    return e->code;
}

/* max |X + u - Xm| over the nodes, and the update X <- Xm - u. */
static double residual(const double *Xm, double *X, const double *u, size_t n3, int update)
{
    double rmax = 0;
    for (size_t i = 0; i < n3; i += 3) {
        double r2 = 0;
        for (int k = 0; k < 3; k++) {
            double r = X[i + k] + u[i + k] - Xm[i + k];
            r2 += r * r;
        }
        rmax = fmax(rmax, sqrt(r2));
        if (update)
            for (int k = 0; k < 3; k++) X[i + k] = Xm[i + k] - u[i + k];
    }
    return rmax;
}

static double max_shift(const double *Xm, const double *X, size_t n3)
{
    double smax = 0;
    for (size_t i = 0; i < n3; i += 3) {
        double d2 = 0;
        for (int k = 0; k < 3; k++) d2 += (X[i + k] - Xm[i + k]) * (X[i + k] - Xm[i + k]);
        smax = fmax(smax, sqrt(d2));
    }
    return smax;
}

static int has_loads(const kt_scene *s)
{
    for (int i = 0; i < s->npressure; i++)
        if (s->pressure[i].p != 0) return 1;
    for (int i = 0; i < s->nfix; i++)
        if (s->fix[i].value[0] != 0 || s->fix[i].value[1] != 0 || s->fix[i].value[2] != 0) return 1;
    return 0;
}

int kt_refgeom_unload(const kt_scene *s, kt_mesh *m, const kt_refgeom_opts *o,
                      kt_refgeom_stats *st, kt_err *e)
{
    memset(st, 0, sizeof *st);
    st->rate = NAN;
    if (!has_loads(s)) return KT_OK;
    size_t n3 = 3 * (size_t)m->nn;
    double *Xm = kt_calloc(n3, sizeof(double), e), *u = kt_calloc(n3, sizeof(double), e);
    if (!Xm || !u) {
        free(Xm);
        free(u);
        return e->code;
    }
    memcpy(Xm, m->xyz, n3 * sizeof(double));
    double prev = HUGE_VAL;
    int done = 0;
    for (int it = 0; it < o->maxit && !done; it++) {
        if (kt_refgeom_solve(s, m, u, e)) break;
        st->iters = it + 1;
        /* The residual of the current X0; if it is not small enough, X0 <- Xm - u(X0). */
        double r = residual(Xm, m->xyz, u, n3, 0);
        if (it == 0) st->initial = r;
        else st->rate = r / prev;
        st->residual = r;
        kt_log(o->quiet, "reference: iteration %d: max |X0 + u(X0) - X_measured| = %.3g um\n",
               it + 1, 1000 * r);
        if (r <= o->tol) done = 1;
        else if (it >= 2 && !(r < prev)) break; /* not contracting: hopeless */
        else residual(Xm, m->xyz, u, n3, 1);
        prev = r;
    }
    st->shift = max_shift(Xm, m->xyz, n3);
    if (!e->code && !done)
        kt_fail(e, KT_ERUN, "reference: the stress-free geometry did not converge: max |X0 + u(X0) - "
                "X_measured| = %.3g um after %d solves (tolerance %.3g um%s); the loads deform the "
                "model too much for a linear inverse (softer material or higher pressure than it "
                "can carry), or use loads.reference: unloaded",
                1000 * st->residual, st->iters, 1000 * o->tol,
                st->rate >= 1 ? ", and it grew" : "");
    if (e->code) memcpy(m->xyz, Xm, n3 * sizeof(double));
    free(Xm);
    free(u);
    return e->code;
}
