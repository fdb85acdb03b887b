/* lp_band.c: the 2-D band of a prediction (lp_band.h). */
#include "lp_band.h"

#include "lp_choose.h"

#include <math.h>
#include <string.h>

#define SQRT2 1.41421356237309504880
#define SQRT2PI 2.50662827463100050242
#define POINT 1e-12 /* D: a larger sd than this is a distribution, not a point */
#define RANK1 1e-9  /* the minor axis's sd below this fraction of the major's: rank 1 */

void kt_lp_band_cov(int nq, const double (*d)[2], const double *sd, const kt_lp_cov *extra, kt_lp_cov *cov)
{
    memset(cov, 0, sizeof *cov);
    for (int q = 0; q < nq; q++) {
        double v = sd[q] * sd[q];
        cov->xx += d[q][0] * d[q][0] * v, cov->xy += d[q][0] * d[q][1] * v, cov->yy += d[q][1] * d[q][1] * v;
    }
    if (extra) cov->xx += extra->xx, cov->xy += extra->xy, cov->yy += extra->yy;
}

double kt_lp_band_along(const double s[2], int nq, const double (*d)[2], const double *sd)
{
    double n = hypot(s[0], s[1]), var = 0;
    for (int q = 0; q < nq; q++) {
        double p = n > 1e-9 ? (s[0] * d[q][0] + s[1] * d[q][1]) / n : hypot(d[q][0], d[q][1]) / SQRT2;
        var += p * p * sd[q] * sd[q];
    }
    return sqrt(var);
}

/* The distribution in the principal frame of cov: x along the minor axis, y along the major. */
typedef struct frame {
    double mx, my, sx, sy;
    double r;                   /* the radius being integrated */
} frame;

static void principal(const double mean[2], const kt_lp_cov *c, frame *f)
{
    double h = 0.5 * (c->xx + c->yy), disc = hypot(0.5 * (c->xx - c->yy), c->xy);
    double l1 = h + disc, l2 = fmax(0, h - disc), e1[2];
    if (fabs(c->xy) > 0) e1[0] = l1 - c->yy, e1[1] = c->xy;
    else e1[0] = c->xx >= c->yy, e1[1] = c->xx < c->yy;
    double n = hypot(e1[0], e1[1]);
    e1[0] /= n, e1[1] /= n;
    f->my = mean[0] * e1[0] + mean[1] * e1[1];  /* major axis e1 */
    f->mx = -mean[0] * e1[1] + mean[1] * e1[0]; /* minor axis e2 = e1 turned by 90 deg */
    f->sy = sqrt(fmax(0, l1)), f->sx = sqrt(l2);
    if (isnan(c->xx + c->xy + c->yy)) f->sy = f->sx = NAN; /* fmax would hide it: no band */
}

/* Phi(a) - Phi(b), a >= b, without cancellation in the tails. */
static double phi_diff(double a, double b)
{
    if (b > 0) return 0.5 * (erfc(b / SQRT2) - erfc(a / SQRT2));
    if (a < 0) return 0.5 * (erfc(-a / SQRT2) - erfc(-b / SQRT2));
    return 1 - 0.5 * erfc(a / SQRT2) - 0.5 * erfc(-b / SQRT2);
}

/* The integrand of F(r) in t (x = r cos t). */
static double integrand(const frame *f, double t)
{
    double x = f->r * cos(t), s = f->r * sin(t), z = (x - f->mx) / f->sx;
    return exp(-0.5 * z * z) / (f->sx * SQRT2PI) * phi_diff((s - f->my) / f->sy, (-s - f->my) / f->sy) * s;
}

typedef double (*fun)(const void *ctx, double t);

/* Gauss-Legendre, 16 points: the positive nodes and their weights on [-1, 1]. */
static const double GL_X[8] = {0.095012509837637454, 0.28160355077925892, 0.45801677765722737, 0.61787624440264377,
                               0.755404408355003,    0.86563120238783176, 0.9445750230732326,  0.98940093499164994};
static const double GL_W[8] = {0.18945061045506859, 0.18260341504492361, 0.16915651939500262, 0.14959598881657676,
                               0.12462897125553403, 0.095158511682492591, 0.062253523938647706, 0.027152459411754037};

/* The integral of g over [a, b]: PANELS panels of 16-point Gauss-Legendre (the integrands are
 * smooth; a peak is at least a few panels wide: lp_band.h). */
#define PANELS 16
static double integrate(fun g, const void *ctx, double a, double b)
{
    double h = (b - a) / PANELS, sum = 0;
    for (int i = 0; i < PANELS; i++) {
        double c = a + (i + 0.5) * h, r = 0.5 * h;
        for (int k = 0; k < 8; k++) sum += GL_W[k] * r * (g(ctx, c - r * GL_X[k]) + g(ctx, c + r * GL_X[k]));
    }
    return sum;
}

static double integrand_t(const void *ctx, double t) { return integrand(ctx, t); }

static double cdf_frame(frame f, double r)
{
    if (!(r > 0)) return 0;
    double rho = hypot(f.mx, f.my);
    if (f.sy <= POINT) return r >= rho ? 1 : 0;
    if (f.sx <= RANK1 * f.sy) { /* rank 1: x = mx exactly */
        if (r <= fabs(f.mx)) return 0;
        double s = sqrt(r * r - f.mx * f.mx);
        return phi_diff((s - f.my) / f.sy, (-s - f.my) / f.sy);
    }
    double x0 = fmax(-r, f.mx - 12 * f.sx), x1 = fmin(r, f.mx + 12 * f.sx);
    if (!(x1 > x0)) return r > rho ? 1 : 0; /* the minor axis's whole mass is outside |x| < r */
    f.r = r;
    double v = integrate(integrand_t, &f, acos(x1 / r), acos(x0 / r));
    return fmin(1, fmax(0, v));
}

double kt_lp_band_cdf(const double mean[2], const kt_lp_cov *cov, double r)
{
    frame f;
    principal(mean, cov, &f);
    return cdf_frame(f, r);
}

/* The radius where F reaches p (bisection); NaN when no bracket is found. */
static double quantile(const frame *f, double p)
{
    double lo = 0, hi = hypot(f->mx, f->my) + 12 * f->sy + 1e-12;
    for (int up = 0; !(cdf_frame(*f, hi) >= p); up++) {
        if (up == 64) return NAN;
        hi *= 2;
    }
    for (int it = 0; it < 100 && hi - lo > 1e-12 * (1 + hi); it++) {
        double m = 0.5 * (lo + hi);
        if (cdf_frame(*f, m) < p) lo = m;
        else hi = m;
    }
    return 0.5 * (lo + hi);
}

static double survival(const void *ctx, double r) { return 1 - cdf_frame(*(const frame *)ctx, r); }

/* Gauss-Hermite rule of GH_N points for the weight exp(-x^2): nodes x[] and weights w[] (Newton
 * on the orthonormal Hermite recurrence from the asymptotic first guesses; symmetric pairs). */
#define GH_N 32
static void gauss_hermite(double x[GH_N], double w[GH_N])
{
    const int n = GH_N;
    double z = 0, pp = 0;
    for (int i = 0; i < (n + 1) / 2; i++) {
        if (i == 0) z = sqrt(2.0 * n + 1) - 1.85575 * pow(2.0 * n + 1, -1.0 / 6);
        else if (i == 1) z -= 1.14 * pow(n, 0.426) / z;
        else if (i == 2) z = 1.86 * z - 0.86 * x[0];
        else if (i == 3) z = 1.91 * z - 0.91 * x[1];
        else z = 2 * z - x[i - 2];
        for (int it = 0; it < 100; it++) {
            double p1 = 0.7511255444649425 /* pi^(-1/4) */, p2 = 0;
            for (int j = 1; j <= n; j++) {
                double p3 = p2;
                p2 = p1;
                p1 = z * sqrt(2.0 / j) * p2 - sqrt((j - 1.0) / j) * p3;
            }
            pp = sqrt(2.0 * n) * p2;
            double dz = p1 / pp;
            z -= dz;
            if (fabs(dz) <= 1e-15 * fabs(z)) break;
        }
        x[i] = z, x[n - 1 - i] = -z;
        w[i] = w[n - 1 - i] = 2 / (pp * pp);
    }
}

/* E|v| for v ~ N(mean, cov) in frame f by a GH_N x GH_N Gauss-Hermite product rule: exact to
 * rounding when |v| is smooth over the distribution's mass, i.e. the origin is many sds away
 * (|mean| > 6 sy: the cone at |v| = 0 then weighs below e^-18). */
static double mean_far(const frame *f)
{
    double x[GH_N], w[GH_N], sum = 0;
    gauss_hermite(x, w);
    for (int i = 0; i < GH_N; i++)
        for (int j = 0; j < GH_N; j++)
            sum += w[i] * w[j] * hypot(f->mx + SQRT2 * f->sx * x[i], f->my + SQRT2 * f->sy * x[j]);
    return sum / M_PI;
}

void kt_lp_band_of(const double mean[2], const kt_lp_cov *cov, kt_lp_band *b)
{
    frame f;
    principal(mean, cov, &f);
    b->mean[0] = mean[0], b->mean[1] = mean[1], b->cov = *cov;
    b->mag = hypot(mean[0], mean[1]);
    if (!isfinite(b->mag)) { /* no prediction (NaN readings): no band */
        b->sd = b->lo = b->hi = NAN;
        return;
    }
    if (!(f.sy > POINT)) { /* no spread (or a NaN one: no band) */
        b->sd = isnan(f.sy) ? NAN : 0;
        b->lo = b->hi = isnan(b->sd) ? NAN : b->mag;
        return;
    }
    b->lo = quantile(&f, KT_LP_BAND_LO), b->hi = quantile(&f, KT_LP_BAND_HI);
    /* E|v|^2 is exact; E|v| by Gauss-Hermite where |v| is smooth, else as the integral of the
     * survival 1 - F over the range where it falls from 1 to 0 (|v| >= |x|, |v| >= |y|). */
    double m1;
    if (b->mag > 6 * f.sy) m1 = mean_far(&f);
    else {
        double a = fmax(0, fmax(fabs(f.mx) - 12 * f.sx, fabs(f.my) - 12 * f.sy));
        m1 = a + integrate(survival, &f, a, hypot(fabs(f.mx) + 12 * f.sx, fabs(f.my) + 12 * f.sy));
    }
    double m2 = b->mag * b->mag + f.sx * f.sx + f.sy * f.sy;
    b->sd = sqrt(fmax(0, m2 - m1 * m1));
}

void kt_lp_band_nontissue(const double s[2], double cv, const kt_lp_cov *extra, kt_lp_cov *out)
{
    kt_lp_cov z = {0, 0, 0};
    if (!extra) extra = &z;
    double c2 = cv * cv;
    out->xx = extra->xx + c2 * s[0] * s[0], out->xy = extra->xy + c2 * s[0] * s[1];
    out->yy = extra->yy + c2 * s[1] * s[1];
}

/* The band of the prediction v of arc step k of family i: the tissue quantities', the caller's
 * extra and the scene's non-tissue term along the step's SIA from the intact eye. */
static void band_at(const kt_lp_opts *o, const kt_lp_answer *a, int i, int k, kt_astig v, kt_lp_band *b)
{
    const kt_lp_runs *rs = &a->run;
    const kt_lp_run *r = &rs->r[i];
    kt_lp_cov cov, extra;
    double m[2], s[2];
    kt_astig_xy(kt_lp_astig_sub(r->kerato[k], r->kerato_intact), s);
    kt_lp_band_nontissue(s, a->scene.s.unc.nontissue_cv, &o->band_extra, &extra);
    kt_lp_band_cov(rs->nq, (const double(*)[2])r->dsia[k], rs->sd, &extra, &cov);
    kt_astig_xy(v, m);
    kt_lp_band_of(m, &cov, b);
}

void kt_lp_bands_make(const kt_lp_opts *o, const kt_lp_answer *a, kt_lp_bands *b)
{
    memset(b, 0, sizeof *b);
    int c = a->choice.chosen;
    if (o->no_band || c < 0) return;
    b->on = 1;
    int k = a->choice.best[c];
    kt_astig kpost, tpost;
    kt_lp_post(a, &kpost, &tpost);
    band_at(o, a, c, k, a->choice.pred[c][k], &b->residual);
    band_at(o, a, c, k, kpost, &b->post_kerato);
    band_at(o, a, c, k, tpost, &b->post_total);
    for (int i = 0; i < a->fam.n; i++)
        if (a->run.r[i].ran) band_at(o, a, i, a->choice.best[i], a->choice.pred[i][a->choice.best[i]], &b->best[i]);
    const kt_lp_run *r = &a->run.r[c];
    kt_astig sia = kt_lp_astig_sub(r->kerato[k], r->kerato_intact);
    double s[2];
    kt_astig_xy(sia, s);
    b->sia_sd_tissue = kt_lp_band_along(s, a->run.nq, (const double(*)[2])r->dsia[k], a->run.sd);
    b->sia_sd = hypot(b->sia_sd_tissue, a->scene.s.unc.nontissue_cv * hypot(s[0], s[1]));
}
