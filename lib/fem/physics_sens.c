/* physics_sens.c: the derivative data of a scene's uncertain quantities (sens.h): which
 * quantities apply, dC per tet, the prestress's derivatives from the prestress solve's own
 * factorization, the derivative loads, and a step's derivatives from scratch. */
#include "sens.h"
#include "units.h"
#include "wound.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "chol.h"
#include "fem_int.h"

static const kt_region_mat *first_fibre(const kt_scene *s)
{
    for (int i = 0; i < s->nmat; i++)
        if (s->mat[i].fibre) return &s->mat[i];
    return NULL;
}

static const kt_region_mat *find_region(const kt_scene *s, const char *name)
{
    for (int i = 0; i < s->nmat; i++)
        if (strcmp(s->mat[i].region, name) == 0) return &s->mat[i];
    return NULL;
}

void kt_fem_sens_plan(const kt_scene *s, const kt_fem_problem *fp, kt_fem_sens *S)
{
    memset(S, 0, sizeof *S);
    const kt_uncertainty *u = &s->unc;
    const kt_region_mat *fib = first_fibre(s), *cornea = find_region(s, "cornea");
    int eye = s->model == KT_MODEL_EYE;
    for (int q = 0; q < KT_UQ_N; q++) {
        S->sd[q] = u->sd[q];
        S->value[q] = NAN;
    }
    if (fib) {
        S->value[KT_UQ_E_INPLANE] = fib->E1;
        S->value[KT_UQ_G_TRANSVERSE] = 1e3 * fib->Gt;
        S->method[KT_UQ_E_INPLANE] = S->method[KT_UQ_G_TRANSVERSE] = KT_SENS_DERIVATIVE;
        if (eye) {
            S->value[KT_UQ_LIMBAL_DENSITY] = s->eye.fibre_density;
            S->method[KT_UQ_LIMBAL_DENSITY] = KT_SENS_DERIVATIVE;
        }
    }
    S->npress = fp->npress;
    for (int k = 0; k < fp->npress; k++) S->ptag[k] = fp->press[k].tag;
    if (fp->npress && fp->press[0].p != 0) {
        S->value[KT_UQ_IOP] = fp->press[0].p / KT_MMHG_MPA;
        S->method[KT_UQ_IOP] = KT_SENS_DERIVATIVE;
    }
    if (eye) {
        S->value[KT_UQ_THICKNESS] = 1e3 * s->eye.t_central;
        S->method[KT_UQ_THICKNESS] = KT_SENS_FD;
        if (s->eye.nring) {
            S->value[KT_UQ_DEPTH] = 0; /* achieved minus set depth: nominally zero */
            S->method[KT_UQ_DEPTH] = KT_SENS_FD;
        }
    }
    S->value[KT_UQ_AGE_SLOPE] = KT_UQ_AGE_SLOPE_VALUE;
    if (isfinite(u->age) && cornea) S->method[KT_UQ_AGE_SLOPE] = KT_SENS_DERIVATIVE;
    /* heal = ln(k / (1 MPa/mm)): a derivative for a healed wound; for an immediate one the
     * value a healed state would have, not applicable */
    double kh = kt_scene_wound_k_healed(s);
    if (kh > 0) S->value[KT_UQ_HEAL] = log(kh);
    if (fp->wound && fp->wound->k > 0) {
        S->value[KT_UQ_HEAL] = log(fp->wound->k);
        S->method[KT_UQ_HEAL] = KT_SENS_DERIVATIVE;
    }
    for (int q = 0; q < KT_UQ_N; q++) {
        if (!(S->sd[q] > 0)) S->method[q] = KT_SENS_NONE;
        if (S->method[q] == KT_SENS_DERIVATIVE) {
            S->d[S->nd].q = q;
            S->d[S->nd++].dwound = q == KT_UQ_HEAL;
        }
    }
}

void kt_fem_sens_free(kt_fem_sens *S)
{
    for (int k = 0; k < S->nd; k++) {
        free(S->d[k].td.C);
        free(S->d[k].td.sig);
        free(S->d[k].td.pface);
        memset(&S->d[k].td, 0, sizeof S->d[k].td);
    }
}

kt_materials kt_fem_sens_mats(const kt_fem_sens *S, int k, const kt_materials *mats)
{
    kt_materials m = *mats;
    m.td = &S->d[k].td;
    m.wound = NULL;
    return m;
}

/* The constitutive matrix of tet t with the moduli of region r shifted (dE in-plane, dG
 * transverse shear, MPa), the limbal density shifted by dd, all moduli scaled by sc. */
static void fibre_C(const kt_scene *s, const kt_region_mat *r, const double *f, double dE,
                    double dG, double dd, double sc, double C[36])
{
    double E1 = (r->E1 + dE) * sc, E2 = (r->E2 + dE) * sc;
    kt_fibre_material fm = {E1, E2, (r->Gt + dG) * sc, r->nu};
    double Ec = (s->eye.fibre_density + dd - 1) * f[12] * 0.5 * (E1 + E2);
    kt_fem_fibre_matrix(&fm, f, f + 3, f + 6, f + 9, Ec, C);
}

/* dC/dq of tet t, unit of q per kt_uq_unit: a central difference of C in q, exact up to
 * rounding because C is linear in each modulus (fixed nu) and in the limbal density. */
static void tet_dC(const kt_scene *s, const kt_mesh *m, const kt_physics *ph, int q, int t,
                   double dC[36])
{
    memset(dC, 0, 36 * sizeof(double));
    const kt_group *g = kt_mesh_find_tag(m, 3, m->tet_tag[t]);
    const kt_region_mat *r = g ? find_region(s, g->name) : NULL;
    if (!r) r = find_region(s, "default");
    if (!r) return;
    const double *f = ph->frame ? ph->frame + 13 * (size_t)t : NULL;
    double Cp[36], Cm[36], h, unit = 1;
    if (q == KT_UQ_AGE_SLOPE) {
        if (!g || strcmp(g->name, "cornea") != 0) return;
        /* moduli M = M0 (1 + slope a), a = (age - 60) / 10: dM/dslope = M a / (1 + 0.075 a) */
        double a = (s->unc.age - KT_UQ_AGE_PIVOT) / 10, rel = a / (1 + KT_UQ_AGE_SLOPE_VALUE * a);
        h = 1e-2;
        if (r->fibre && f) {
            fibre_C(s, r, f, 0, 0, 0, 1 + h * rel, Cp);
            fibre_C(s, r, f, 0, 0, 0, 1 - h * rel, Cm);
        } else {
            kt_fem_iso_matrix(r->E * (1 + h * rel), r->nu, Cp);
            kt_fem_iso_matrix(r->E * (1 - h * rel), r->nu, Cm);
        }
    } else {
        if (!r->fibre || !f) return;
        if (q == KT_UQ_E_INPLANE) {
            h = 1e-2 * r->E1;
            fibre_C(s, r, f, h, 0, 0, 1, Cp);
            fibre_C(s, r, f, -h, 0, 0, 1, Cm);
        } else if (q == KT_UQ_G_TRANSVERSE) {
            h = 1e-2 * r->Gt;
            unit = 1e-3; /* per kPa */
            fibre_C(s, r, f, 0, h, 0, 1, Cp);
            fibre_C(s, r, f, 0, -h, 0, 1, Cm);
        } else if (q == KT_UQ_LIMBAL_DENSITY) {
            h = 1e-2;
            fibre_C(s, r, f, 0, 0, h, 1, Cp);
            fibre_C(s, r, f, 0, 0, -h, 1, Cm);
        } else {
            return;
        }
    }
    for (int i = 0; i < 36; i++) dC[i] = unit * (Cp[i] - Cm[i]) / (2 * h);
}

static int any_nonzero(const double *x, int n)
{
    for (int i = 0; i < n; i++)
        if (x[i] != 0) return 1;
    return 0;
}

/* dC of every derivative quantity (zeros where it does not enter; iop: all zeros). */
static int sens_tensors(const kt_scene *s, const kt_mesh *m, const kt_physics *ph,
                        kt_fem_sens *S, kt_err *e)
{
    size_t ne = (size_t)(m->ne ? m->ne : 1);
    for (int k = 0; k < S->nd; k++) {
        kt_fem_dparam *d = &S->d[k];
        d->td.ne = m->ne;
        if (!(d->td.C = kt_calloc(36 * ne, sizeof(double), e))) return e->code;
        if (d->q == KT_UQ_IOP) continue;
        for (int t = 0; t < m->ne; t++) tet_dC(s, m, ph, d->q, t, d->td.C + 36 * (size_t)t);
    }
    return KT_OK;
}

/* The prestress solve's extra right-hand sides df_p/dq - dK0/dq u0 of every derivative, from
 * one pass over the tets: for a modulus, dK0/dq u0 = int B^T dC eps(u0), whose stress
 * dC eps(u0) is also dsig0/dq's first term (kept in d->td.sig); for iop, the pressures. */
typedef struct pre_ctx {
    kt_fem_sens *S;
    const kt_mesh *m;
    const kt_materials *mats; /* the prestress solve's (material stiffness only) */
    const kt_fem_problem *fp;
} pre_ctx;

/* Quadrature point q's strain matrix B (6 x 3nv) and weight w det J. */
static int point_B(const kt_mesh *m, const double *x, const kt_tet_rule *rule, int q, double *B,
                   double *w, kt_err *e)
{
    int nv = kt_tet_nv(m->order);
    double g[10][3], det;
    if (kt_fem_point_gradients(nv, x, rule, q, g, &det, e)) return e->code;
    kt_fem_strain_matrix(nv, g, NULL, B);
    *w = rule->w[q] * det;
    return KT_OK;
}

/* eps (6) := B ue (ld = 3nv values). */
static void strain6(const double *B, int ld, const double *ue, double *eps)
{
    for (int p = 0; p < 6; p++) {
        eps[p] = 0;
        for (int r = 0; r < ld; r++) eps[p] += B[p * ld + r] * ue[r];
    }
}

/* s (6) := C eps. */
static void stress6(const double *C, const double *eps, double *s)
{
    for (int p = 0; p < 6; p++) {
        s[p] = 0;
        for (int k = 0; k < 6; k++) s[p] += C[6 * p + k] * eps[k];
    }
}

/* Tet el's share: the moduli's dC eps(u0) into their td.sig, -int B^T dC eps(u0) into B. */
static int pre_tet(pre_ctx *P, int el, const double *u, double *b, kt_err *e)
{
    const kt_mesh *m = P->m;
    int nv = kt_tet_nv(m->order), ld = 3 * nv, on = 0;
    size_t n = 3 * (size_t)m->nn;
    for (int k = 0; k < P->S->nd; k++)
        on |= P->S->d[k].q != KT_UQ_IOP && any_nonzero(P->S->d[k].td.C + 36 * (size_t)el, 36);
    if (!on) return KT_OK;
    double x[30], ue[30], Bm[6 * 30], eps[6], w;
    const int *t = m->tet + (size_t)el * nv;
    kt_fem_gather_x(m, el, x);
    for (int a = 0; a < nv; a++) memcpy(ue + 3 * a, u + 3 * (size_t)t[a], 3 * sizeof(double));
    kt_tet_rule rule = kt_fem_rule(m->order, x);
    for (int q = 0; q < rule.n; q++) {
        if (point_B(m, x, &rule, q, Bm, &w, e)) return e->code;
        strain6(Bm, ld, ue, eps);
        for (int k = 0; k < P->S->nd; k++) {
            kt_fem_dparam *d = &P->S->d[k];
            const double *dC = d->td.C + 36 * (size_t)el;
            if (d->q == KT_UQ_IOP || !any_nonzero(dC, 36)) continue;
            double *sg = d->td.sig + ((size_t)el * KT_FEM_NQ + q) * 6;
            stress6(dC, eps, sg);
            for (int r = 0; r < ld; r++) {
                double f = 0;
                for (int p = 0; p < 6; p++) f += Bm[p * ld + r] * sg[p];
                b[k * n + 3 * (size_t)t[r / 3] + r % 3] -= w * f;
            }
        }
    }
    return KT_OK;
}

static int pre_rhs(void *ctx, const double *u, double *b, kt_err *e)
{
    pre_ctx *P = ctx;
    const kt_mesh *m = P->m;
    size_t n = 3 * (size_t)m->nn;
    for (int k = 0; k < P->S->nd; k++) {
        const kt_fem_dparam *d = &P->S->d[k];
        for (int i = 0; d->q == KT_UQ_IOP && i < P->fp->npress; i++)
            if (kt_fem_pressure(m, P->fp->press[i].tag, d->dpress[i], b + k * n, e))
                return e->code;
    }
    for (int el = 0; el < m->ne; el++)
        if (pre_tet(P, el, u, b, e)) return e->code;
    return KT_OK;
}

/* d->td.sig += C eps(du0/dq) for every derivative (C: mm's material stiffness), one pass. */
static int pre_stress(kt_fem_sens *S, const kt_mesh *m, const kt_materials *mm, const double *du,
                      kt_err *e)
{
    int nv = kt_tet_nv(m->order), ld = 3 * nv, nd = S->nd;
    size_t n = 3 * (size_t)m->nn;
    double x[30], ue[30 * KT_FEM_MULTI_MAX], C[36], Bm[6 * 30], eps[6], sg[6], w;
    if (nd > KT_FEM_MULTI_MAX)
        return kt_fail(e, KT_ERUN, "%d derivative quantities (at most %d)", nd, KT_FEM_MULTI_MAX);
    for (int el = 0; el < m->ne; el++) {
        const int *t = m->tet + (size_t)el * nv;
        kt_fem_gather_x(m, el, x);
        if (kt_fem_element_C(m, mm, el, C, e)) return e->code;
        for (int k = 0; k < nd; k++)
            for (int a = 0; a < nv; a++)
                memcpy(ue + k * ld + 3 * a, du + k * n + 3 * (size_t)t[a], 3 * sizeof(double));
        kt_tet_rule rule = kt_fem_rule(m->order, x);
        for (int q = 0; q < rule.n; q++) {
            if (point_B(m, x, &rule, q, Bm, &w, e)) return e->code;
            for (int k = 0; k < nd; k++) {
                strain6(Bm, ld, ue + k * ld, eps);
                stress6(C, eps, sg);
                double *d = S->d[k].td.sig + ((size_t)el * KT_FEM_NQ + q) * 6;
                for (int p = 0; p < 6; p++) d[p] += sg[p];
            }
        }
    }
    return KT_OK;
}

/* The prestress and its derivatives: u0 = K0^-1 f_p (Dirichlet g), du0/dq from the same
 * factorization (one substitution for all), dsig0/dq = dC/dq eps(u0) + C eps(du0/dq); dpface
 * of iop. */
int kt_fem_sens_prestress(kt_fem_sens *S, const kt_mesh *m, const kt_fem_problem *fp,
                          const kt_materials *mm, const double *f, double *u, int **perm,
                          cholmod_common *c, kt_err *e)
{
    size_t n = 3 * (size_t)m->nn, ns = (size_t)(m->ne ? m->ne : 1) * KT_FEM_NQ * 6;
    double *du = kt_calloc(n * (size_t)(S->nd ? S->nd : 1), sizeof(double), e);
    for (int k = 0; k < S->nd && !e->code; k++)
        S->d[k].td.sig = kt_calloc(ns, sizeof(double), e);
    if (e->code) goto done;
    pre_ctx P = {S, m, mm, fp};
    if (kt_fem_solve_more(m, mm, fp->fixed, fp->g, f, u, S->nd, pre_rhs, &P, du, perm, c, e) ||
        pre_stress(S, m, mm, du, e))
        goto done;
    for (int k = 0; k < S->nd; k++) {
        kt_fem_dparam *d = &S->d[k];
        if (d->q != KT_UQ_IOP) continue;
        size_t np = 4 * (size_t)(m->ne ? m->ne : 1);
        if (!(d->td.pface = kt_calloc(np, sizeof(double), e))) goto done;
        for (int i = 0; i < fp->npress; i++)
            if (kt_fem_pressure_faces(m, fp->press[i].tag, d->dpress[i], d->td.pface, e))
                goto done;
    }
done:
    free(du);
    return e->code;
}

/* The pressures' derivatives: every pressure of the problem in proportion to the first (the
 * IOP of an eye). */
void kt_fem_sens_pressures(const kt_fem_problem *fp, kt_fem_sens *S)
{
    for (int k = 0; k < S->nd; k++) {
        kt_fem_dparam *d = &S->d[k];
        if (d->q != KT_UQ_IOP) continue;
        for (int i = 0; i < fp->npress; i++) d->dpress[i] = fp->press[i].p / fp->press[0].p * KT_MMHG_MPA;
    }
}

int kt_physics_sens_tensors(const kt_scene *s, const kt_mesh *m, const kt_physics *ph,
                            kt_fem_sens *S, kt_err *e)
{
    return sens_tensors(s, m, ph, S, e);
}

int kt_fem_sens_loads(const kt_fem_sens *S, int k, const kt_mesh *m, const kt_materials *mats,
                      double *r, kt_err *e)
{
    memset(r, 0, 3 * (size_t)m->nn * sizeof(double));
    const kt_fem_dparam *d = &S->d[k];
    for (int i = 0; i < S->npress; i++)
        if (d->dpress[i] != 0 && kt_fem_pressure(m, S->ptag[i], d->dpress[i], r, e)) return e->code;
    if (!d->td.sig) return KT_OK;
    kt_materials dm = kt_fem_sens_mats(S, k, mats);
    return kt_fem_release_loads(m, &dm, r, e);
}

/* b -= dA/dq u over the tets of m where derivative d enters (element by element). */
static int sub_dK_u(const kt_mesh *m, const kt_materials *dm, const kt_fem_dparam *d,
                    const double *u, double *b, kt_err *e)
{
    int nv = kt_tet_nv(m->order), ld = 3 * nv;
    double Ke[900];
    for (int t = 0; t < m->ne; t++) {
        int on = any_nonzero(d->td.C + 36 * (size_t)t, 36) ||
                 (d->td.sig && any_nonzero(d->td.sig + (size_t)t * KT_FEM_NQ * 6, KT_FEM_NQ * 6)) ||
                 (d->td.pface && any_nonzero(d->td.pface + 4 * (size_t)t, 4));
        if (!on) continue;
        if (kt_fem_element(m, dm, t, Ke, e)) return e->code;
        const int *tv = m->tet + (size_t)t * nv;
        for (int i = 0; i < ld; i++) {
            double s = 0;
            for (int j = 0; j < ld; j++) s += Ke[i * ld + j] * u[3 * (size_t)tv[j / 3] + j % 3];
            b[3 * (size_t)tv[i / 3] + i % 3] -= s;
        }
    }
    return KT_OK;
}

typedef struct fresh_ctx {
    const kt_fem_sens *S;
    const kt_mesh *m;
    const kt_materials *mats;
    const double *u;
} fresh_ctx;

static int fresh_rhs(void *ctx, const double *u0, double *b, kt_err *e)
{
    (void)u0; /* the zero solution of the set-up solve */
    fresh_ctx *P = ctx;
    size_t n = 3 * (size_t)P->m->nn;
    for (int k = 0; k < P->S->nd; k++) {
        const kt_fem_dparam *d = &P->S->d[k];
        if (kt_fem_sens_loads(P->S, k, P->m, P->mats, b + k * n, e)) return e->code;
        if (d->dK_zero) continue;
        kt_materials dm = kt_fem_sens_mats(P->S, k, P->mats);
        if (sub_dK_u(P->m, &dm, d, P->u, b + k * n, e)) return e->code;
        if (d->dwound != 0 && kt_wound_on(P->mats) &&
            kt_wound_apply(P->mats->wound, P->m, P->u, -d->dwound, b + k * n, e))
            return e->code;
    }
    return KT_OK;
}

int kt_fem_sens_fresh(const kt_fem_sens *S, const kt_mesh *m, const kt_materials *mats,
                      const unsigned char *fixed, const double *u, double *du, kt_err *e)
{
    size_t n = 3 * (size_t)m->nn;
    double *zero = kt_calloc(n, sizeof(double), e), *u0 = kt_calloc(n, sizeof(double), e);
    if (!e->code) {
        cholmod_common c;
        kt_chol_start(&c);
        fresh_ctx P = {S, m, mats, u};
        kt_fem_solve_more(m, mats, fixed, NULL, zero, u0, S->nd, fresh_rhs, &P, du, NULL, &c, e);
        cholmod_finish(&c);
    }
    free(zero);
    free(u0);
    return e->code;
}
