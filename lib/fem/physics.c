/* physics.c: per-tet physics of a scene: fibre matrices from the eye's lamellar frames, the
 * prestress of the measured geometry under its loads, and the follower-pressure faces. */
#include "physics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "chol.h"
#include "eye.h"
#include "sens.h"

void kt_physics_free(kt_physics *ph)
{
    free(ph->td.C);
    free(ph->td.sig);
    free(ph->td.pface);
    free(ph->frame);
    free(ph->cst);
    free(ph->cellv);
    free(ph->perm);
    memset(ph, 0, sizeof *ph);
}

static const kt_region_mat *region_mat(const kt_scene *s, const char *name)
{
    const kt_region_mat *fallback = NULL;
    for (int i = 0; i < s->nmat; i++) {
        if (strcmp(s->mat[i].region, name) == 0) return &s->mat[i];
        if (strcmp(s->mat[i].region, "default") == 0) fallback = &s->mat[i];
    }
    return fallback;
}

/* The constants of an isotropic tet (E, nu) in ph->cst's form; fails on an invalid material. */
static int iso_constants(const kt_materials *mats, const kt_mesh *m, int t, double *c, kt_err *e)
{
    kt_material mt = mats->mat[m->tet_tag[t]];
    if (!(mt.E > 0) || !(mt.nu > -1 && mt.nu < 0.5))
        return kt_fail(e, KT_EINPUT, "tet %d: region without a valid material", t + 1);
    c[0] = c[1] = mt.E;
    c[2] = mt.E / (2 * (1 + mt.nu));
    c[3] = mt.nu;
    c[4] = c[5] = 0;
    return KT_OK;
}

/* ph->cst of every tet of a scene without fibre regions (as given: the assembly checks them). */
static int iso_all(const kt_mesh *m, const kt_materials *mats, kt_physics *ph, kt_err *e)
{
    ph->cst = kt_calloc(KT_PHYSICS_NCST * (size_t)(m->ne ? m->ne : 1), sizeof(double), e);
    if (!ph->cst) return e->code;
    for (int t = 0; t < m->ne; t++) {
        kt_material mt = mats->mat[m->tet_tag[t]];
        double *c = ph->cst + KT_PHYSICS_NCST * (size_t)t;
        c[0] = c[1] = mt.E;
        c[2] = mt.nu > -1 ? mt.E / (2 * (1 + mt.nu)) : NAN;
        c[3] = mt.nu;
    }
    return KT_OK;
}

/* C, the frames and the constants of every tet: fibre regions from the frames, the others
 * isotropic. */
static int fibre_matrices(const kt_scene *s, const kt_mesh *m, const kt_materials *mats,
                          kt_physics *ph, kt_err *e)
{
    size_t ne = (size_t)(m->ne ? m->ne : 1);
    ph->frame = kt_calloc(13 * ne, sizeof(double), e);
    ph->cst = kt_calloc(KT_PHYSICS_NCST * ne, sizeof(double), e);
    ph->td.C = kt_calloc(36 * ne, sizeof(double), e);
    if (e->code || kt_eye_fibre_frames(&s->eye, m, ph->frame, e)) return e->code;
    /* the relative depth of every tet, when a fibre region has a G_transverse_profile */
    double *depth = NULL;
    for (int i = 0; i < s->nmat && !depth; i++)
        if (s->mat[i].fibre && s->mat[i].gt_profile[0] > 0) {
            depth = kt_calloc(ne, sizeof(double), e);
            if (!depth || kt_eye_depth_fractions(&s->eye, m, depth, e)) {
                free(depth);
                return e->code;
            }
        }
    for (int t = 0; t < m->ne; t++) {
        const kt_group *g = kt_mesh_find_tag(m, 3, m->tet_tag[t]);
        const kt_region_mat *r = g ? region_mat(s, g->name) : NULL;
        double *C = ph->td.C + 36 * (size_t)t, *c = ph->cst + KT_PHYSICS_NCST * (size_t)t;
        if (r && r->fibre) {
            const double *f = ph->frame + 13 * (size_t)t;
            double Gt = kt_gt_profile(r, depth ? depth[t] : NAN);
            kt_fibre_material fm = {r->E1, r->E2, Gt, r->nu};
            double Ec = (s->eye.fibre_density - 1) * f[12] * 0.5 * (r->E1 + r->E2);
            kt_fem_fibre_matrix(&fm, f, f + 3, f + 6, f + 9, Ec, C);
            c[0] = r->E1, c[1] = r->E2, c[2] = Gt, c[3] = r->nu, c[4] = Ec, c[5] = 1;
        } else if (iso_constants(mats, m, t, c, e)) {
            free(depth);
            return e->code;
        } else {
            kt_fem_iso_matrix(c[0], c[3], C);
        }
    }
    free(depth);
    return KT_OK;
}

/* The apex membrane stress printed by augsolve (keratome-scene(5), LOADS): over the tets whose
 * centroid (the mean of their 4 vertices) lies within 0.5 mm of the axis and 1 mm below the
 * mesh's highest node, the volume-weighted mean of (sig_11 + sig_22 + sig_33) / 2, each tet's
 * stress its volume average over its quadrature points (kt_fem_prestress_mean: the sigma0 cell
 * field of keratome-vtk(5)) and its weight the volume of its 4 vertices: about p R / 2t less
 * p / 4. NAN when no tet is there. */
static double apex_stress(const kt_mesh *m, const kt_physics *ph, kt_err *e)
{
    int nv = kt_tet_nv(m->order);
    double ztop = -1e300, sum = 0, vol = 0;
    kt_materials mats = {0, NULL, &ph->td, NULL};
    for (int i = 0; i < m->nn; i++) ztop = fmax(ztop, m->xyz[3 * i + 2]);
    for (int t = 0; t < m->ne && !e->code; t++) {
        const double *x[4];
        double c[3] = {0, 0, 0}, s[6];
        for (int a = 0; a < 4; a++) {
            x[a] = m->xyz + 3 * (size_t)m->tet[(size_t)t * nv + a];
            for (int k = 0; k < 3; k++) c[k] += 0.25 * x[a][k];
        }
        if (hypot(c[0], c[1]) > 0.5 || c[2] < ztop - 1.0) continue;
        if (kt_fem_prestress_mean(m, &mats, t, s, e)) break;
        double v = fabs(kt_tet_volume(x[0], x[1], x[2], x[3]));
        sum += v * 0.5 * (s[0] + s[1] + s[2]);
        vol += v;
    }
    return vol > 0 ? sum / vol : NAN;
}

static int prestress(const kt_mesh *m, const kt_fem_problem *fp, kt_physics *ph,
                     cholmod_common *c, kt_fem_sens *S, kt_err *e)
{
    size_t n = 3 * (size_t)m->nn;
    double *f = kt_calloc(n, sizeof(double), e), *u = kt_calloc(n, sizeof(double), e);
    ph->td.sig = kt_calloc((size_t)(m->ne ? m->ne : 1) * KT_FEM_NQ * 6, sizeof(double), e);
    ph->td.pface = kt_calloc(4 * (size_t)(m->ne ? m->ne : 1), sizeof(double), e);
    if (!e->code) kt_fem_problem_loads(fp, m, 1.0, f, e);
    for (int k = 0; k < fp->npress && !e->code; k++)
        kt_fem_pressure_faces(m, fp->press[k].tag, fp->press[k].p, ph->td.pface, e);
    /* the material stiffness only: td holds C (or nothing) until sig is filled */
    kt_fem_tetdata mat_only = {m->ne, ph->td.C, NULL, NULL};
    kt_materials mm = fp->mats;
    mm.td = ph->td.C ? &mat_only : NULL;
    /* ordered by METIS alone (CHOLMOD's default would run AMD first and METIS after it): the
     * order kept in ph->perm is then the one augsolve's planned method would make itself for
     * the intact block (METIS), and it reuses it instead (kt_aug_problem.perm) */
    int nm = c->nmethods, ord = c->method[0].ordering;
    c->nmethods = 1;
    c->method[0].ordering = CHOLMOD_METIS;
    if (!e->code &&
        (S && S->nd ? kt_fem_sens_prestress(S, m, fp, &mm, f, u, &ph->perm, c, e)
                    : kt_fem_solve_order(m, &mm, fp->fixed, fp->g, f, u, &ph->perm, c, e)) == KT_OK &&
        kt_fem_stress(m, &mm, u, ph->td.sig, e) == KT_OK) {
        ph->prestressed = 1;
        ph->sig_apex = apex_stress(m, ph, e);
    }
    c->nmethods = nm;
    c->method[0].ordering = ord;
    free(f);
    free(u);
    return e->code;
}

/* kt_physics_build, and with S the derivative data of S's quantities (sens.h). */
static int build(const kt_scene *s, const kt_mesh *m, kt_fem_problem *fp, kt_physics *ph,
                 cholmod_common *c, kt_fem_sens *S, kt_err *e)
{
    memset(ph, 0, sizeof *ph);
    double t0 = kt_now();
    ph->td.ne = m->ne;
    for (int i = 0; i < s->nmat; i++) ph->fibre |= s->mat[i].fibre;
    if (ph->fibre && s->model != KT_MODEL_EYE)
        return kt_fail(e, KT_EINPUT, "%s: model fibre materials need the eye model", s->path);
    if (ph->fibre ? fibre_matrices(s, m, &fp->mats, ph, e) : iso_all(m, &fp->mats, ph, e))
        return e->code;
    if (S && kt_physics_sens_tensors(s, m, ph, S, e)) return e->code;
    if (s->reference == KT_REFERENCE_PRESTRESSED && prestress(m, fp, ph, c, S, e)) return e->code;
    fp->mats.td = (ph->td.C || ph->td.sig) ? &ph->td : NULL;
    if (kt_physics_cell_fields(ph, m, e)) return e->code;
    ph->t_build = kt_now() - t0;
    return KT_OK;
}

int kt_physics_build(const kt_scene *s, const kt_mesh *m, kt_fem_problem *fp, kt_physics *ph,
                     cholmod_common *c, kt_err *e)
{
    return build(s, m, fp, ph, c, NULL, e);
}

static int finish(const kt_scene *s, const kt_mesh *m, kt_fem_problem *fp, kt_physics *ph,
                  kt_fem_sens *S, kt_err *e)
{
    cholmod_common c;
    kt_chol_start(&c);
    build(s, m, fp, ph, &c, S, e);
    cholmod_finish(&c);
    if (e->code) {
        kt_physics_free(ph);
        return e->code;
    }
    kt_physics_adopt(ph, m, fp);
    return KT_OK;
}

void kt_physics_adopt(const kt_physics *ph, const kt_mesh *m, kt_fem_problem *fp)
{
    fp->mats.td = (ph->td.C || ph->td.sig) ? &ph->td : NULL;
    if (ph->prestressed) {
        memset(fp->g, 0, 3 * (size_t)m->nn * sizeof(double));
        for (int k = 0; k < fp->nfix; k++) memset(fp->fix[k].v, 0, sizeof fp->fix[k].v);
    }
}

int kt_physics_finish(const kt_scene *s, const kt_mesh *m, kt_fem_problem *fp, kt_physics *ph,
                      kt_err *e)
{
    return finish(s, m, fp, ph, NULL, e);
}

int kt_physics_finish_sens(const kt_scene *s, const kt_mesh *m, kt_fem_problem *fp,
                           kt_physics *ph, kt_fem_sens *S, kt_err *e)
{
    kt_fem_sens_pressures(fp, S);
    if (finish(s, m, fp, ph, S, e)) {
        kt_fem_sens_free(S);
        return e->code;
    }
    for (int k = 0; k < S->nd; k++) /* without prestress, iop moves only the loads */
        S->d[k].dK_zero = S->d[k].q == KT_UQ_IOP && !ph->prestressed;
    S->zero_at_0 = ph->prestressed;
    return KT_OK;
}

int kt_physics_problem(const kt_scene *s, const kt_mesh *m, kt_fem_problem *fp, kt_physics *ph,
                       kt_err *e)
{
    memset(ph, 0, sizeof *ph);
    if (kt_fem_bind(s, m, fp, e)) return e->code;
    if (kt_physics_finish(s, m, fp, ph, e)) kt_fem_problem_free(fp);
    return e->code;
}
