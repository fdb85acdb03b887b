/* newton_plan.c: the nonlinear reference on a plan's edits: the cut mesh, its constraints and
 * loads, the path that releases the cut (newton.h). */
#include "newton.h"

#include <stdlib.h>
#include <string.h>

#include "apply.h"

/* fixed, g, f (3 * m->nn) of the cut mesh: fp's on the intact nodes (nn0 of them), the
 * fixation surfaces on the new ones, then the steps' fix and force edits. */
static void constraints(const kt_mesh *m, int nn0, const kt_fem_problem *fp,
                        const kt_step *steps, int nsteps, unsigned char *fixed, double *g,
                        double *f)
{
    memcpy(fixed, fp->fixed, 3 * (size_t)nn0);
    memcpy(g, fp->g, 3 * (size_t)nn0 * sizeof(double));
    int fv = kt_tri_nv(m->order);
    for (int t = 0; t < m->nf; t++)
        for (int k = 0; k < fp->nfix; k++) {
            if (m->tri_tag[t] != fp->fix[k].tag) continue;
            const int *tri = m->tri + (size_t)t * fv;
            for (int l = 0; l < fv; l++)
                for (int c = 0; c < 3 && tri[l] >= nn0; c++)
                    if (fp->fix[k].mask & (1u << c)) {
                        fixed[3 * (size_t)tri[l] + c] = 1;
                        g[3 * (size_t)tri[l] + c] = fp->fix[k].v[c];
                    }
        }
    for (int s = 0; s < nsteps; s++)
        for (int i = 0; i < steps[s].n; i++) {
            const kt_edit *ed = &steps[s].edit[i];
            for (int c = 0; c < 3; c++) {
                size_t j = 3 * (size_t)ed->node + c;
                if (ed->kind == KT_EDIT_FIX && (ed->mask & (1u << c))) {
                    fixed[j] = 1;
                    g[j] = ed->v[c];
                }
                if (ed->kind == KT_EDIT_FORCE) f[j] = ed->v[c];
            }
        }
}

int kt_newton_plan(kt_mesh *m, const kt_fem_problem *fp, const kt_step *steps, int nsteps,
                   const kt_newton_opts *o, double **u, kt_newton_stats *st, kt_err *e)
{
    *u = NULL;
    int nn0 = m->nn;
    if (fp->nn != nn0)
        return kt_fail(e, KT_EINPUT, "newton: problem bound to %d nodes, mesh has %d", fp->nn, nn0);
    for (int s = 0; s < nsteps; s++) {
        int *touched = NULL, nt = 0;
        int rc = kt_cut_apply(m, &steps[s], &touched, &nt, e);
        free(touched);
        if (rc) return e->code;
    }
    size_t n = 3 * (size_t)m->nn;
    const kt_fem_tetdata *td0 = fp->mats.td;
    kt_fem_tetdata td = {m->ne, td0 ? td0->C : NULL, td0 ? td0->sig : NULL,
                         td0 ? td0->pface : NULL};
    unsigned char *fixed = kt_calloc(n, 1, e);
    double *g = kt_calloc(n, sizeof(double), e), *f = kt_calloc(n, sizeof(double), e);
    double *r0 = NULL, *pface = NULL;
    *u = kt_calloc(n, sizeof(double), e);
    if (!e->code && !td.pface && fp->npress) {
        pface = kt_calloc(4 * (size_t)(m->ne ? m->ne : 1), sizeof(double), e);
        for (int k = 0; k < fp->npress && !e->code; k++)
            kt_fem_pressure_faces(m, fp->press[k].tag, fp->press[k].p, pface, e);
        td.pface = pface;
    }
    if (e->code) goto done;
    constraints(m, nn0, fp, steps, nsteps, fixed, g, f);
    kt_materials mats = fp->mats;
    mats.td = &td;
    int prestressed = td.sig != NULL;
    if (prestressed) {
        r0 = kt_calloc(n, sizeof(double), e);
        if (!r0 || kt_fem_nl_residual(m, &mats, *u, 1.0, r0, NULL, e)) goto done;
    }
    kt_newton_problem p = {m, &mats, fixed, g, f, !prestressed, r0};
    kt_newton_solve(&p, o, *u, st, e);
done:
    free(fixed);
    free(g);
    free(f);
    free(r0);
    free(pface);
    if (e->code) {
        free(*u);
        *u = NULL;
    }
    return e->code;
}
