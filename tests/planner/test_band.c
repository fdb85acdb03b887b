/* test_band.c: the planner's 2-D band (lib/planner/lp_band.h) against closed forms and a brute
 * quadrature, on synthetic predictions and derivatives (no mesh, no solve):
 * - a zero mean with an isotropic covariance: |v| is Rayleigh (quantiles, mean and sd exact);
 * - rank 1 (one quantity): |v| = |m + s z|, the folded normal, along and across the mean;
 * - an elliptical covariance with a mean: the CDF against a 2-D midpoint sum;
 * - no spread: a point (lo = hi = |mean|, sd 0), the band of every sd 0;
 * - the covariance J diag(sd^2) J^T + extra;
 * - the non-tissue term cv^2 s s^T: a spread of cv |s| along the SIA s and none across it; on a
 *   residual of zero it alone gives |v| the folded normal of sd cv |s|;
 * - the band never collapses: whenever the prediction is below the SIA's sd (its projection on
 *   itself, as curvature reports it), the 95% end is at least that sd;
 * - the magnitude's sd stays right when the spread is small against the mean (against a brute
 *   2-D sum), along and across the major axis;
 * - a NaN prediction has no band (NaN, and the quantile search ends). */
#include <math.h>
#include <string.h>

#include "kt_test.h"
#include "lp_band.h"

static double Phi(double z) { return 0.5 * erfc(-z / sqrt(2.0)); }

static void rayleigh(void)
{
    double m[2] = {0, 0}, s = 0.3;
    kt_lp_cov c = {s * s, 0, s * s};
    kt_lp_band b;
    kt_lp_band_of(m, &c, &b);
    CHECK_NEAR(b.lo, s * sqrt(-2 * log(0.95)), 1e-7, "Rayleigh 5% quantile");
    CHECK_NEAR(b.hi, s * sqrt(-2 * log(0.05)), 1e-7, "Rayleigh 95% quantile");
    CHECK_NEAR(b.sd, s * sqrt((4 - M_PI) / 2), 1e-6, "Rayleigh sd");
    for (double r = 0.05; r < 1.5; r += 0.25)
        CHECK_NEAR(kt_lp_band_cdf(m, &c, r), 1 - exp(-r * r / (2 * s * s)), 1e-9, "Rayleigh CDF");
}

static void rank_one(void)
{
    double s = 0.2;
    /* along the mean: |v| = |m + s z| */
    double m[2] = {0.1, 0}, e = 0;
    kt_lp_cov c = {s * s, 0, 0};
    for (double r = 0.02; r < 1; r += 0.1) {
        double want = Phi((r - 0.1) / s) - Phi((-r - 0.1) / s);
        e = fmax(e, fabs(kt_lp_band_cdf(m, &c, r) - want));
    }
    CHECK(e < 1e-12, "rank 1 along the mean: folded normal CDF (worst %.2e)", e);
    kt_lp_band b;
    kt_lp_band_of(m, &c, &b);
    CHECK_NEAR(Phi((b.hi - 0.1) / s) - Phi((-b.hi - 0.1) / s), 0.95, 1e-9, "rank 1: F(hi) = 0.95");
    CHECK_NEAR(Phi((b.lo - 0.1) / s) - Phi((-b.lo - 0.1) / s), 0.05, 1e-9, "rank 1: F(lo) = 0.05");
    /* across the mean: |v| = sqrt(m^2 + s^2 z^2) >= m */
    double m2[2] = {0, 0.15};
    CHECK(kt_lp_band_cdf(m2, &c, 0.149) == 0, "rank 1 across the mean: nothing below |mean|");
    double r = 0.3, a = sqrt(r * r - 0.15 * 0.15);
    CHECK_NEAR(kt_lp_band_cdf(m2, &c, r), Phi(a / s) - Phi(-a / s), 1e-12, "rank 1 across the mean: CDF");
}

/* P(|v| <= r) by a midpoint sum over a fine grid of the 2-D density. */
static double brute_cdf(const double m[2], const kt_lp_cov *c, double r)
{
    double det = c->xx * c->yy - c->xy * c->xy, ixx = c->yy / det, ixy = -c->xy / det, iyy = c->xx / det;
    int n = 2000;
    double h = 2 * r / n, sum = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double x = -r + (i + 0.5) * h, y = -r + (j + 0.5) * h;
            if (x * x + y * y > r * r) continue;
            double dx = x - m[0], dy = y - m[1], q = ixx * dx * dx + 2 * ixy * dx * dy + iyy * dy * dy;
            sum += exp(-0.5 * q);
        }
    return sum * h * h / (2 * M_PI * sqrt(det));
}

static void ellipse(void)
{
    double m[2] = {0.12, -0.05};
    kt_lp_cov c = {0.04, 0.012, 0.01};
    double worst = 0;
    for (double r = 0.15; r < 0.7; r += 0.25) worst = fmax(worst, fabs(kt_lp_band_cdf(m, &c, r) - brute_cdf(m, &c, r)));
    CHECK(worst < 2e-4, "elliptical CDF against the 2-D midpoint sum (worst %.2e)", worst);
    kt_lp_band b;
    kt_lp_band_of(m, &c, &b);
    CHECK_NEAR(kt_lp_band_cdf(m, &c, b.lo), 0.05, 1e-9, "F(lo) = 0.05");
    CHECK_NEAR(kt_lp_band_cdf(m, &c, b.hi), 0.95, 1e-9, "F(hi) = 0.95");
    CHECK(b.lo < b.mag && b.mag < b.hi, "the band holds the prediction (%.3f < %.3f < %.3f)", b.lo, b.mag, b.hi);
    /* a far mean: the magnitude is nearly normal along the mean */
    double far[2] = {3, 0};
    kt_lp_cov cf = {0.01, 0, 0.0025};
    kt_lp_band_of(far, &cf, &b);
    CHECK_NEAR(b.sd, 0.1, 2e-3, "far from zero the magnitude's sd is the sd along the mean");
    CHECK_NEAR(b.hi - b.lo, 2 * 1.6448536 * 0.1, 2e-3, "and its 90% interval is +- 1.645 sd");
}

static void point(void)
{
    double m[2] = {0.2, 0.1};
    kt_lp_cov c = {0, 0, 0};
    kt_lp_band b;
    kt_lp_band_of(m, &c, &b);
    CHECK(b.sd == 0 && b.lo == b.mag && b.hi == b.mag, "no spread: a point (sd %g, %g-%g about %g)", b.sd, b.lo, b.hi, b.mag);
    double d[2][2] = {{0.1, 0.2}, {-0.3, 0.05}}, sd0[2] = {0, 0};
    kt_lp_band_cov(2, (const double(*)[2])d, sd0, NULL, &c);
    CHECK(c.xx == 0 && c.xy == 0 && c.yy == 0, "every sd 0: no covariance");
}

static void covariance(void)
{
    double d[2][2] = {{0.1, 0.2}, {-0.3, 0.05}}, sd[2] = {2, 0.5};
    kt_lp_cov extra = {0.001, -0.0005, 0.002}, c;
    kt_lp_band_cov(2, (const double(*)[2])d, sd, &extra, &c);
    CHECK_NEAR(c.xx, 0.1 * 0.1 * 4 + 0.09 * 0.25 + 0.001, 1e-15, "cov xx");
    CHECK_NEAR(c.xy, 0.1 * 0.2 * 4 - 0.3 * 0.05 * 0.25 - 0.0005, 1e-15, "cov xy");
    CHECK_NEAR(c.yy, 0.04 * 4 + 0.0025 * 0.25 + 0.002, 1e-15, "cov yy");
    double s[2] = {1, 0};
    CHECK_NEAR(kt_lp_band_along(s, 2, (const double(*)[2])d, sd), sqrt(0.04 + 0.0225), 1e-15, "the SIA's sd along x");
}

static void nontissue(void)
{
    double s[2] = {0.6, -0.8}; /* |s| = 1 D */
    kt_lp_cov extra = {0.001, 0.0002, 0.003}, c;
    kt_lp_band_nontissue(s, 0.4, &extra, &c);
    /* along s: u^T C u = 0.16 |s|^2 + u^T extra u; across: only extra's */
    double u[2] = {0.6, -0.8}, w[2] = {0.8, 0.6};
    double along = u[0] * u[0] * c.xx + 2 * u[0] * u[1] * c.xy + u[1] * u[1] * c.yy;
    double across = w[0] * w[0] * c.xx + 2 * w[0] * w[1] * c.xy + w[1] * w[1] * c.yy;
    double ea = u[0] * u[0] * 0.001 + 2 * u[0] * u[1] * 0.0002 + u[1] * u[1] * 0.003;
    double ew = w[0] * w[0] * 0.001 + 2 * w[0] * w[1] * 0.0002 + w[1] * w[1] * 0.003;
    CHECK_NEAR(along, 0.16 + ea, 1e-15, "the non-tissue variance along the SIA: (cv |s|)^2");
    CHECK_NEAR(across, ew, 1e-15, "none across it");
    kt_lp_band_nontissue(s, 0.4, NULL, &c);
    double z[2] = {0, 0};
    kt_lp_band b;
    kt_lp_band_of(z, &c, &b);
    /* |v| = 0.4 |z|: the folded normal; its 95% quantile 0.4 Phi^-1(0.975) */
    CHECK_NEAR(b.hi, 0.4 * 1.959963984540054, 1e-7, "a zero residual's 95%% end from the non-tissue term alone");
    CHECK_NEAR(b.lo, 0.4 * 0.0627067779432, 1e-7, "its 5%% end");
    kt_lp_band_nontissue(s, NAN, NULL, &c);
    kt_lp_band_of(z, &c, &b);
    CHECK(isnan(b.hi), "a NaN cv gives no band, not a point");
}

/* The case: the SIA's sd about 0.3 D, the prediction near zero in every direction. */
static void no_collapse(void)
{
    double d[3][2] = {{0.12, 0.03}, {0.05, -0.02}, {0.02, 0.06}}, sd[3] = {1.5, 2.0, 1.0};
    int bad = 0, n = 0;
    for (int sa = 0; sa < 180; sa += 30) {
        double s[2] = {cos(2 * sa * M_PI / 180), sin(2 * sa * M_PI / 180)};
        double sia_sd = kt_lp_band_along(s, 3, (const double(*)[2])d, sd);
        kt_lp_cov c;
        kt_lp_band_cov(3, (const double(*)[2])d, sd, NULL, &c);
        for (int ma = 0; ma < 180; ma += 45)
            for (double mag = 0; mag < sia_sd; mag += sia_sd / 4) {
                double m[2] = {mag * cos(ma * M_PI / 90), mag * sin(ma * M_PI / 90)};
                kt_lp_band b;
                kt_lp_band_of(m, &c, &b);
                n++;
                if (!(b.hi >= sia_sd)) bad++, fprintf(stderr, "hi %.4f < sia sd %.4f at %.3f D\n", b.hi, sia_sd, mag);
            }
    }
    CHECK(bad == 0 && n >= 96, "the 95%% end >= the SIA's sd whenever the prediction is below it (%d cases, %d not)", n, bad);
    double z[2] = {0, 0};
    kt_lp_cov c;
    kt_lp_band_cov(3, (const double(*)[2])d, sd, NULL, &c);
    kt_lp_band b;
    kt_lp_band_of(z, &c, &b);
    CHECK(b.hi > 0.2 && b.sd > 0.05, "a zero prediction keeps its band: %.3f-%.3f D, sd %.3f D", b.lo, b.hi, b.sd);
}

/* E|v| and sd|v| for a diagonal cov by a midpoint sum over +-9 sd in each direction. */
static void brute_moments(const double m[2], double sx, double sy, double *mean, double *sd)
{
    int n = 1200;
    double s0 = 0, s1 = 0, s2 = 0;
    for (int i = 0; i < n; i++) {
        double zx = -9 + 18 * (i + 0.5) / n, px = exp(-0.5 * zx * zx);
        for (int j = 0; j < n; j++) {
            double zy = -9 + 18 * (j + 0.5) / n, w = px * exp(-0.5 * zy * zy);
            double r = hypot(m[0] + sx * zx, m[1] + sy * zy);
            s0 += w, s1 += w * r, s2 += w * r * r;
        }
    }
    *mean = s1 / s0;
    *sd = sqrt(fmax(0, s2 / s0 - *mean * *mean));
}

static void small_spread(void)
{
    struct { double m[2], sx, sy; const char *what; } c[] = {
        {{3, 0}, 0.005, 0.005, "isotropic, sd/|mean| 1/600"},
        {{2, 0}, 0.005, 0.005, "isotropic, sd/|mean| 1/400"},
        {{1, 0}, 0.002, 0.002, "isotropic, sd/|mean| 1/500"},
        {{1, 0}, 1e-4, 0.1, "the mean across the major axis"},
        {{0, 1.5}, 0.01, 0.2, "the mean along the major axis"},
        {{0.3, 0}, 0.2, 0.2, "near the origin (the integral)"},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        kt_lp_cov cov = {c[i].sx * c[i].sx, 0, c[i].sy * c[i].sy};
        kt_lp_band b;
        kt_lp_band_of(c[i].m, &cov, &b);
        double mean, sd;
        brute_moments(c[i].m, c[i].sx, c[i].sy, &mean, &sd);
        CHECK(fabs(b.sd - sd) <= 0.01 * sd, "%s: the magnitude's sd %.6g against %.6g (brute sum)", c[i].what, b.sd, sd);
    }
}

static void nan_mean(void)
{
    double m[2] = {NAN, NAN};
    kt_lp_cov cov = {0.45, 0.10, 0.023};
    kt_lp_band b;
    kt_lp_band_of(m, &cov, &b);
    CHECK(isnan(b.lo) && isnan(b.hi) && isnan(b.sd), "a NaN prediction: no band (lo %g, hi %g, sd %g)", b.lo, b.hi, b.sd);
}

int main(void)
{
    rayleigh();
    rank_one();
    ellipse();
    point();
    covariance();
    nontissue();
    no_collapse();
    small_spread();
    nan_mean();
    return kt_test_done("test_band");
}
