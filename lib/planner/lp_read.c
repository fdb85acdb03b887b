/* lp_read.c: a step's readings in memory (lp_read.h). */
#include "lp_read.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "curv_band.h"
#include "curv_total.h"

int kt_lp_reader_init(kt_lp_reader *r, const kt_mesh *intact, double meridian, kt_err *e)
{
    memset(r, 0, sizeof *r);
    r->nn = intact->nn;
    r->meridian = fmod(meridian, 180);
    if (kt_curv_anterior_mask(intact, "the patient's mesh", &r->ant, e) || kt_curv_posterior_mask(intact, &r->post, e))
        kt_lp_reader_free(r);
    return e->code;
}

void kt_lp_reader_free(kt_lp_reader *r)
{
    free(r->ant), free(r->post), free(r->xyz0), free(r->dudp0);
    memset(r, 0, sizeof *r);
}

/* The zone fit of a surface's points and its simulated keratometry. */
static int fit(const kt_surf *s, kt_fit *f, kt_err *e)
{
    return kt_curv_fit(s->xyz, s->n, KT_CURV_FIT_DEFAULT, KT_CURV_ORDER_DEFAULT, KT_CURV_ZONE_DEFAULT, 0, 0, f, NULL, 0, e);
}

/* The total corneal astigmatism from the anterior fit and the posterior surface's. */
static int total(const kt_lp_reader *r, const kt_lp_step *v, const kt_fit *ant, kt_astig *out, kt_err *e)
{
    out->mag = out->axis = NAN;
    if (!r->post) return KT_OK;
    kt_surf p;
    kt_fit *fp = kt_calloc(1, sizeof *fp, e);
    if (!fp || kt_curv_points(v->mesh, v->u, v->origin, r->post, r->nn, &p, e)) {
        free(fp);
        return e->code;
    }
    if (fit(&p, fp, e) == KT_OK) {
        kt_cornea_n n;
        kt_total t;
        kt_cornea_n_default(&n);
        kt_curv_total(ant, fp, &n, &t);
        out->mag = t.tot_cyl, out->axis = t.tot_axis;
    }
    kt_surf_free(&p);
    free(fp);
    return e->code;
}

/* The anterior points' du/dq of every derivative field (nd x 3 s->n). */
static int take_dudp(const kt_lp_step *v, const kt_surf *s, double *out, kt_err *e)
{
    for (int k = 0; k < v->nd; k++)
        for (int i = 0; i < s->n; i++)
            for (int j = 0; j < 3; j++) {
                double x = v->dudp[k][3 * (size_t)s->node[i] + j];
                if (!isfinite(x))
                    return kt_fail(e, KT_ERUN, "step %d: du/d%s is %g at an anterior node: numerical trouble in the band",
                                   v->step, kt_uq_name(v->sens->d[k].q), x);
                out[((size_t)k * s->n + i) * 3 + j] = x;
            }
    return KT_OK;
}

/* The SIA's derivatives of step v against step 0, one band quantity at a time. */
static int band(kt_lp_reader *r, const kt_lp_step *v, const kt_surf *s, kt_lp_reading *out, kt_err *e)
{
    if (v->nd == 0) return KT_OK;
    double *d = kt_calloc((size_t)v->nd * 3 * s->n, sizeof(double), e);
    if (!d || take_dudp(v, s, d, e)) return free(d), e->code;
    if (v->step == 0) { /* kept: every later step's difference moves step 0 too */
        r->n0 = s->n, r->nd = v->nd, r->dudp0 = d;
        if (!(r->xyz0 = kt_calloc((size_t)3 * s->n, sizeof(double), e))) return e->code;
        memcpy(r->xyz0, s->xyz, (size_t)3 * s->n * sizeof(double));
        return KT_OK;
    }
    for (int k = 0; k < v->nd && k < KT_LP_MAXQ && !e->code; k++) {
        kt_band_pts p0 = {r->n0, r->xyz0, r->dudp0 + (size_t)k * 3 * r->n0}, pk = {s->n, s->xyz, d + (size_t)k * 3 * s->n};
        double dr[KT_RD_N], eps;
        if (kt_band_step_deriv(&p0, &pk, KT_CURV_FIT_DEFAULT, KT_CURV_ORDER_DEFAULT, KT_CURV_ZONE_DEFAULT, r->meridian,
                               NULL, dr, &eps, e) == KT_OK) {
            out->dsia[k][0] = dr[KT_RD_SIA_X], out->dsia[k][1] = dr[KT_RD_SIA_Y];
            if (!isfinite(dr[KT_RD_SIA_X]) || !isfinite(dr[KT_RD_SIA_Y]))
                kt_fail(e, KT_ERUN, "step %d: the SIA's derivative along %s is not a number: numerical trouble in the band",
                        v->step, kt_uq_name(v->sens->d[k].q));
        }
    }
    free(d);
    return e->code;
}

int kt_lp_read(kt_lp_reader *r, const kt_lp_step *v, kt_lp_reading *out, kt_err *e)
{
    memset(out, 0, sizeof *out);
    kt_surf s;
    kt_fit *f = kt_calloc(1, sizeof *f, e);
    if (!f || kt_curv_points(v->mesh, v->u, v->origin, r->ant, r->nn, &s, e)) return free(f), e->code;
    if (fit(&s, f, e) == KT_OK) {
        kt_kerato k;
        kt_curv_simk(f, &k);
        out->kerato.mag = k.cyl, out->kerato.axis = k.axis_steep;
        if (total(r, v, f, &out->total, e) == KT_OK) band(r, v, &s, out, e);
    }
    kt_surf_free(&s);
    free(f);
    return e->code;
}
