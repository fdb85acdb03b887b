/* curv_band.c: readings as a vector, their directional derivatives and bands (curv_band.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "curv_band.h"

static const char *const NAMES[KT_RD_N] = {
    "k_steep_D", "k_flat_D", "axis_steep_deg", "cyl_D", "k_mean_D", "dk_mean_D", "flattening_D",
    "steepening_D", "coupling_ratio", "sia_D", "sia_x_D", "sia_y_D", "sia_axis_deg", "dv_D"};

const char *kt_band_reading_name(int r) { return r >= 0 && r < KT_RD_N ? NAMES[r] : NULL; }

int kt_band_reading_find(const char *name)
{
    for (int r = 0; r < KT_RD_N; r++)
        if (strcmp(NAMES[r], name) == 0) return r;
    return -1;
}

int kt_band_reading_kind(int r)
{
    if (r == KT_RD_AXIS || r == KT_RD_SIA_AXIS) return 1;
    if (r == KT_RD_CYL || r == KT_RD_SIA || r == KT_RD_DV) return 2;
    return 0;
}

void kt_band_readings(const kt_fit *fit0, const kt_fit *fit, double meridian, const kt_astig *tia,
                      double out[KT_RD_N])
{
    kt_kerato k0, k;
    kt_curv_simk(fit0, &k0);
    kt_curv_simk(fit, &k);
    double k_inc = kt_curv_meridian_k(fit, meridian), k_ort = kt_curv_meridian_k(fit, meridian + 90);
    double flat = kt_curv_meridian_k(fit0, meridian) - k_inc;
    double steep = k_ort - kt_curv_meridian_k(fit0, meridian + 90);
    kt_astig pre = {k0.cyl, k0.axis_steep}, post = {k.cyl, k.axis_steep};
    kt_alpins va;
    kt_curv_alpins(pre, post, tia, &va);
    double xy[2];
    kt_astig_xy(va.sia, xy);
    out[KT_RD_K_STEEP] = k.k_steep;
    out[KT_RD_K_FLAT] = k.k_flat;
    out[KT_RD_AXIS] = k.axis_steep;
    out[KT_RD_CYL] = k.cyl;
    out[KT_RD_K_MEAN] = k.k_mean;
    out[KT_RD_DK_MEAN] = k.k_mean - k0.k_mean;
    out[KT_RD_FLAT] = flat;
    out[KT_RD_STEEP] = steep;
    /* as curvature.tsv: NaN at step 0 (no steepening) */
    out[KT_RD_COUPLING] = fabs(steep) > 1e-9 ? flat / steep : NAN;
    out[KT_RD_SIA] = va.sia.mag;
    out[KT_RD_SIA_X] = xy[0];
    out[KT_RD_SIA_Y] = xy[1];
    out[KT_RD_SIA_AXIS] = va.sia.axis;
    out[KT_RD_DV] = tia ? va.dv.mag : NAN;
}

void kt_band_derivative(const double plus[KT_RD_N], const double minus[KT_RD_N], double eps, double d[KT_RD_N])
{
    for (int r = 0; r < KT_RD_N; r++) {
        double diff = plus[r] - minus[r];
        if (kt_band_reading_kind(r) == 1) diff = remainder(diff, 180); /* (-90, 90] */
        d[r] = diff / (2 * eps);
    }
}

void kt_band_sd(const double *c, int n, double sd[KT_RD_N])
{
    for (int r = 0; r < KT_RD_N; r++) {
        double s = 0;
        for (int k = 0; k < n; k++) s += c[(size_t)k * KT_RD_N + r] * c[(size_t)k * KT_RD_N + r];
        sd[r] = sqrt(s);
    }
}

void kt_band_interval(int r, double v, double sd, double *lo, double *hi)
{
    *lo = v - KT_BAND_Z90 * sd;
    *hi = v + KT_BAND_Z90 * sd;
    int kind = kt_band_reading_kind(r);
    if (kind == 2 && *lo < 0) *lo = 0;
    if (kind == 1) {
        *lo = fmod(fmod(*lo, 180) + 180, 180);
        *hi = fmod(fmod(*hi, 180) + 180, 180);
        if (isnan(sd)) *lo = *hi = NAN;
        else if (!(KT_BAND_Z90 * sd < 90)) *lo = 0, *hi = 180; /* the whole circle */
    }
}

static double max_abs(const double *d, int n3)
{
    double m = 0;
    for (int i = 0; i < n3; i++) m = fmax(m, fabs(d[i]));
    return m;
}

/* The zone fit of xyz + t dudp. */
static int fit_moved(const kt_band_pts *p, double t, int fit, int order, double zone, double *buf, kt_fit *f,
                     kt_err *e)
{
    for (int i = 0; i < 3 * p->n; i++) buf[i] = p->xyz[i] + t * p->dudp[i];
    return kt_curv_fit(buf, p->n, fit, order, zone, 0, 0, f, NULL, 0, e);
}

int kt_band_step_deriv(const kt_band_pts *s0, const kt_band_pts *s, int fit, int order, double zone, double meridian,
                       const kt_astig *tia, double d[KT_RD_N], double *eps, kt_err *e)
{
    memset(d, 0, KT_RD_N * sizeof *d);
    double m = fmax(max_abs(s0->dudp, 3 * s0->n), max_abs(s->dudp, 3 * s->n));
    *eps = 0;
    if (!(m > 0)) return KT_OK; /* the quantity moves neither surface: no change */
    *eps = KT_BAND_DELTA_MM / m;
    int nb = s->n > s0->n ? s->n : s0->n;
    double *buf = kt_calloc((size_t)3 * nb, sizeof(double), e), plus[KT_RD_N], minus[KT_RD_N];
    kt_fit *f = kt_calloc(4, sizeof(kt_fit), e); /* step 0 +, step 0 -, step +, step - */
    int rc = buf && f ? KT_OK : e->code;
    if (rc == KT_OK) rc = fit_moved(s0, *eps, fit, order, zone, buf, f, e);
    if (rc == KT_OK) rc = fit_moved(s0, -*eps, fit, order, zone, buf, f + 1, e);
    if (rc == KT_OK) rc = fit_moved(s, *eps, fit, order, zone, buf, f + 2, e);
    if (rc == KT_OK) rc = fit_moved(s, -*eps, fit, order, zone, buf, f + 3, e);
    if (rc == KT_OK) {
        kt_band_readings(f, f + 2, meridian, tia, plus);
        kt_band_readings(f + 1, f + 3, meridian, tia, minus);
        kt_band_derivative(plus, minus, *eps, d);
    }
    free(buf), free(f);
    return rc;
}
