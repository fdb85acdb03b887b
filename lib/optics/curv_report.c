/* curv_report.c: RUN/report.html, the teaching page of a curvature run (curv_report.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "curv_report.h"
#include "eye.h"
#include "html.h"
#include "svg.h"

#define DEG KT_CURV_DEG


/* ---------------------------------------------------------------- small helpers */

static double axis180(double a)
{
    if (isnan(a)) return a;
    a = fmod(fmod(a, 180) + 180, 180);
    return a >= 179.95 ? 0 : a;
}

static void cell(FILE *f, const char *fmt, double v)
{
    if (isnan(v)) fputs("<td class=\"n\">&ndash;</td>", f);
    else {
        fputs("<td class=\"n\">", f);
        fprintf(f, fmt, v);
        fputs("</td>", f);
    }
}

static void card(FILE *f, const char *value, const char *what)
{
    fputs("<div class=\"card\"><b>", f);
    kt_html_text(f, value);
    fputs("</b><span>", f);
    kt_html_text(f, what);
    fputs("</span></div>\n", f);
}

static double axis_gap(double a, double b)
{
    double d = fmod(fabs(a - b), 180);
    return d > 90 ? 180 - d : d;
}

void kt_report_verdict(kt_astig pre, kt_astig post, const kt_alpins *va, int has_target, char *buf, size_t size)
{
    int n;
    if (has_target && isfinite(va->ci)) {
        const char *what = va->ci > 1.1 ? "Over-correction" : va->ci < 0.9 ? "Under-correction" : "On target";
        n = snprintf(buf, size, "%s: the induced astigmatism is %.2f D against the %.2f D intended (correction "
                     "index %.2f; 0.9 to 1.1 reads as on target)", what, va->sia.mag, va->tia.mag, va->ci);
    } else {
        n = snprintf(buf, size, "No target in the plan: the induced astigmatism is %.2f D @ %.0f\xC2\xB0", va->sia.mag,
                     axis180(va->sia.axis));
    }
    if (n < 0 || (size_t)n >= size) return;
    if (axis_gap(pre.axis, post.axis) > 45 && post.mag >= 0.25)
        snprintf(buf + n, size - n, "; the cylinder's axis flips: %.2f D @ %.0f\xC2\xB0 before, %.2f D @ %.0f\xC2\xB0 "
                 "after (the steep meridian is now the one that was flat)", pre.mag, axis180(pre.axis), post.mag,
                 axis180(post.axis));
    else
        snprintf(buf + n, size - n, "; cylinder %.2f D @ %.0f\xC2\xB0 before, %.2f D @ %.0f\xC2\xB0 after", pre.mag,
                 axis180(pre.axis), post.mag, axis180(post.axis));
}

double kt_report_exaggeration(double max_disp, double target)
{
    if (!(max_disp > 0)) return 1;
    double raw = target / max_disp, p = pow(10, floor(log10(raw))), m = raw / p;
    double f = (m >= 5 ? 5 : m >= 2 ? 2 : 1) * p;
    return f < 1 ? 1 : f;
}

/* ---------------------------------------------------------------- maps */

typedef struct two_fits {
    const kt_fit *pre, *post;
} two_fits;

static double axial_of(const void *ctx, double x, double y) { return kt_fit_axial_power(ctx, x, y); }

/* Tangential (instantaneous) power: n - 1 times the normal curvature of the radial section
 * through the apex, -s'(r) / (1 + s^2)^1.5 with s the radial slope (central differences). */
static double tangential_of(const void *ctx, double x, double y)
{
    const kt_fit *f = ctx;
    double dx = x - f->ax, dy = y - f->ay, r = hypot(dx, dy), h = 1e-3, z, zx, zy;
    if (r < 1e-9) return kt_fit_axial_power(f, x, y);
    double ux = dx / r, uy = dy / r, s[3];
    for (int k = -1; k <= 1; k++) {
        kt_fit_eval(f, x + k * h * ux, y + k * h * uy, &z, &zx, &zy);
        s[k + 1] = zx * ux + zy * uy;
    }
    return KT_CURV_N_KERATO * -(s[2] - s[0]) / (2 * h) / pow(1 + s[1] * s[1], 1.5);
}

static double diff_of(const void *ctx, double x, double y)
{
    const two_fits *t = ctx;
    return kt_fit_axial_power(t->post, x, y) - kt_fit_axial_power(t->pre, x, y);
}

/* A rendered map as an <img>. */
static int map_img(FILE *f, const kt_topo_scale *s, const kt_topo_map *m, kt_topo_power_fn fn, const void *ctx,
                   const char *alt, kt_err *e)
{
    kt_topo_image img = {0, 0, NULL};
    unsigned char *png = NULL;
    size_t len = 0;
    int rc = kt_topo_render(s, m, fn, ctx, &img, e);
    if (rc == KT_OK) rc = kt_topo_png_bytes(&img, &png, &len, e);
    if (rc == KT_OK && kt_html_img(f, "image/png", png, len, alt, "map") != 0)
        rc = kt_fail(e, KT_ERUN, "report: write error");
    free(png);
    kt_topo_image_free(&img);
    return rc;
}

static void map_frame(kt_topo_map *m, const kt_fit *f, double rad, double zone)
{
    memset(m, 0, sizeof *m);
    m->cx = f->ax, m->cy = f->ay, m->radius = rad, m->zone = zone;
}

static int maps(FILE *f, const kt_report *r, kt_err *e)
{
    const kt_report_step *s0 = r->step, *sl = r->step + r->nstep - 1;
    kt_topo_map m;
    int rc;
    fputs("<h2>2. Axial power before and after</h2>\n<div class=\"row\">\n<figure>", f);
    map_frame(&m, r->map_pre, r->rad_pre, r->zone);
    snprintf(m.title[0], sizeof m.title[0], "PRE-OP AXIAL POWER (D)  STEP 0");
    snprintf(m.title[1], sizeof m.title[1], "SIM K %.2f@%.0f\xC2\xB0 / %.2f@%.0f\xC2\xB0  CYL %.2f", s0->k.k_steep,
             axis180(s0->k.axis_steep), s0->k.k_flat, axis180(s0->k.axis_steep + 90), s0->k.cyl);
    if ((rc = map_img(f, r->scale, &m, axial_of, r->map_pre, "pre-operative axial power map", e))) return rc;
    fprintf(f, "<figcaption><b>Pre-operative</b> axial (sagittal) power, %.1f mm map centred on the apex; "
               "dashed circle: the %.0f mm keratometry zone.</figcaption></figure>\n<figure>",
            2 * r->rad_pre, r->zone);
    map_frame(&m, r->map_post, r->rad_post, r->zone);
    snprintf(m.title[0], sizeof m.title[0], "FINAL AXIAL POWER (D)  STEP %d", r->num[r->nstep - 1]);
    snprintf(m.title[1], sizeof m.title[1], "SIM K %.2f@%.0f\xC2\xB0 / %.2f@%.0f\xC2\xB0  CYL %.2f", sl->k.k_steep,
             axis180(sl->k.axis_steep), sl->k.k_flat, axis180(sl->k.axis_steep + 90), sl->k.cyl);
    if ((rc = map_img(f, r->scale, &m, axial_of, r->map_post, "final axial power map", e))) return rc;
    fprintf(f, "<figcaption><b>After the last step</b>, same %s scale (%.2f&ndash;%.2f D, %.2f D bins): a colour "
               "means the same power on both maps.</figcaption></figure>\n</div>\n",
            r->scale_auto ? "relative" : "absolute", r->scale->lo[0], r->scale->hi[r->scale->n - 1],
            r->scale->hi[0] - r->scale->lo[0]);
    if (r->rel_scale && !r->scale_auto) {
        const kt_topo_scale *rs = r->rel_scale;
        fputs("<div class=\"row\" id=\"relative\">\n<figure>", f);
        map_frame(&m, r->map_pre, r->rad_pre, r->zone);
        snprintf(m.title[0], sizeof m.title[0], "PRE-OP AXIAL POWER (D)  RELATIVE SCALE");
        snprintf(m.title[1], sizeof m.title[1], "%.2f D BINS OVER THIS RUN", rs->hi[0] - rs->lo[0]);
        if ((rc = map_img(f, rs, &m, axial_of, r->map_pre, "pre-operative axial power map, relative scale", e))) return rc;
        fputs("<figcaption>Pre-operative, <b>relative scale</b>.</figcaption></figure>\n<figure>", f);
        map_frame(&m, r->map_post, r->rad_post, r->zone);
        snprintf(m.title[0], sizeof m.title[0], "FINAL AXIAL POWER (D)  RELATIVE SCALE");
        if ((rc = map_img(f, rs, &m, axial_of, r->map_post, "final axial power map, relative scale", e))) return rc;
        fprintf(f, "<figcaption>After the last step, <b>relative scale</b>: %.2f D bins from %.2f to %.2f D, the range of "
                   "this run's maps (the widest of 0.25, 0.5, 1, 1.5, 3 D giving at most 24 bins; curvature --scale "
                   "auto draws every map so). It shows a small toric cornea's bow-tie that the absolute 1.5 D "
                   "bins turn into two colours; its colours do not compare across eyes.</figcaption></figure>\n</div>\n",
                rs->hi[0] - rs->lo[0], rs->lo[0], rs->hi[rs->n - 1]);
    }

    fputs("<h2>3. Tangential power and the change</h2>\n<div class=\"row\">\n<figure>", f);
    map_frame(&m, r->map_post, r->rad_post, r->zone);
    snprintf(m.title[0], sizeof m.title[0], "FINAL TANGENTIAL POWER (D)  STEP %d", r->num[r->nstep - 1]);
    snprintf(m.title[1], sizeof m.title[1], "LOCAL CURVATURE ALONG EACH RADIUS");
    if ((rc = map_img(f, r->scale, &m, tangential_of, r->map_post, "final tangential power map", e))) return rc;
    fputs("<figcaption><b>Tangential</b> (instantaneous) power after surgery, same scale: the local curvature "
          "of each radial profile, so local changes show sharper than on the axial map.</figcaption></figure>\n"
          "<figure>", f);
    two_fits tf = {r->map_pre, r->map_post};
    map_frame(&m, r->map_pre, fmin(r->rad_pre, r->rad_post), r->zone);
    snprintf(m.title[0], sizeof m.title[0], "DIFFERENCE: FINAL - PRE-OP (D)");
    snprintf(m.title[1], sizeof m.title[1], "AXIAL POWER, SAME POINTS IN SPACE");
    if ((rc = map_img(f, r->diff_scale, &m, diff_of, &tf, "difference map, final minus pre-operative", e))) return rc;
    fputs("<figcaption><b>Difference map</b>, final minus pre-operative axial power at the same place: blue "
          "flattened, red steepened, white unchanged. The incised meridian flattens, the one at 90&deg; to it "
          "steepens (coupling). Legend labels (D, at bin centres): <span class=\"legend\" id=\"diff-legend\">", f);
    double val[KT_TOPO_MAXBIN + 1], pos[KT_TOPO_MAXBIN + 1];
    int nl = kt_topo_legend_labels(r->diff_scale, val, pos, KT_TOPO_MAXBIN + 1);
    for (int k = 0; k < nl; k++) {
        char b[32];
        kt_topo_legend_text(val[k], 1, b, sizeof b);
        fprintf(f, "%s%s", k ? " " : "", b);
    }
    fprintf(f, "</span>; bins %.2f D wide.</figcaption></figure>\n</div>\n", r->diff_scale->hi[0] - r->diff_scale->lo[0]);
    return KT_OK;
}

/* ---------------------------------------------------------------- eye diagram */

/* The main incision: each tunnel of the plan at its entry circle, or the patient's main
 * incision (not simulated) just inside the limbus; its width as an arc. */
static void main_incision(FILE *f, const kt_report *r, double C, double s, double wtw)
{
    for (int i = 0; r->plan && i < r->plan->ntunnel; i++) {
        const kt_tunnel *t = &r->plan->tunnel[i];
        double rr = 0.5 * t->entry_diameter, half = 0.5 * t->width / rr / DEG;
        kt_svg_arc(f, C, C, rr * s, t->meridian - half, t->meridian + half, "main");
        kt_svg_text(f, C + (rr - 1.3) * s * cos(t->meridian * DEG), C - (rr - 1.3) * s * sin(t->meridian * DEG) + 18, "middle",
                    "lbl", "main %.1f mm", t->width);
    }
    const kt_report_main *m = r->main;
    if (!m || !m->present || (m->simulated && r->plan && r->plan->ntunnel > 0)) return;
    double rr = 0.5 * wtw - 0.3, half = 0.5 * m->width / rr / DEG;
    kt_svg_arc(f, C, C, rr * s, m->meridian - half, m->meridian + half, "main");
    kt_svg_text(f, C + (rr - 1.3) * s * cos(m->meridian * DEG), C - (rr - 1.3) * s * sin(m->meridian * DEG) + 18, "middle",
                "lbl", "main %.1f mm", m->width);
}

static void eye_diagram(FILE *f, const kt_report *r)
{
    const double W = 460, C = 230;
    const kt_eye *eye = r->plan ? &r->plan->scene.eye : NULL;
    double wtw = eye && eye->wtw > 0 ? eye->wtw : 11.7;
    double s = 170 / (0.5 * wtw); /* px per mm */
    kt_svg_begin(f, W, W, "the plan on a frontal view of the eye");
    fprintf(f, "<rect class=\"sclera\" x=\"0\" y=\"0\" width=\"%.0f\" height=\"%.0f\"/>\n", W, W);
    kt_svg_circle(f, C, C, 0.5 * wtw * s, "cornea");
    for (int t = 0; t < 180; t += 30)
        kt_svg_line(f, C + 205 * cos(t * DEG), C - 205 * sin(t * DEG), C - 205 * cos(t * DEG), C + 205 * sin(t * DEG), "merid");
    for (int t = 0; t < 360; t += 30)
        kt_svg_text(f, C + 218 * cos(t * DEG), C - 218 * sin(t * DEG) + 4, "middle", "tick", "%d\xC2\xB0", t);
    kt_svg_circle(f, C, C, 0.5 * r->zone * s, "kzone");
    /* orientation: superior up; nasal toward the nose (OD: the examiner's right, 0 deg) */
    kt_svg_text(f, C + 34, 20, "middle", "nsti", "S");
    kt_svg_text(f, C + 34, W - 6, "middle", "nsti", "I");
    kt_svg_text(f, W - 10, C - 14, "middle", "nsti", "%s", r->eye_os ? "T" : "N");
    kt_svg_text(f, 10, C - 14, "middle", "nsti", "%s", r->eye_os ? "N" : "T");
    kt_svg_text(f, 6, 18, "start", "nsti", "%s", r->eye_os ? "OS" : "OD");
    kt_svg_text(f, 6, 34, "start", "small", "%s eye, front view", r->eye_os ? "left" : "right");
    kt_svg_line(f, W - 16 - 5 * s, W - 22, W - 16, W - 22, "bar");
    kt_svg_text(f, W - 16 - 2.5 * s, W - 30, "middle", "small", "5 mm");
    const kt_report_step *s0 = r->step;
    double ax = s0->k.axis_steep;
    kt_svg_line(f, C + 200 * cos(ax * DEG), C - 200 * sin(ax * DEG), C - 200 * cos(ax * DEG), C + 200 * sin(ax * DEG), "steep");
    kt_svg_text(f, C + 8 + 100 * cos(ax * DEG), C - 100 * sin(ax * DEG), "start", "lbl", "steep %.0f\xC2\xB0 (%.2f D)",
                axis180(ax), s0->k.k_steep);
    double ring = NAN;
    for (int i = 0; r->plan && i < r->plan->ninc; i++) {
        const kt_incision *in = r->plan->inc + i;
        ring = in->diameter;
        kt_svg_circle(f, C, C, 0.5 * in->diameter * s, "ring");
        for (int side = 0; side <= in->paired; side++) {
            double m = in->meridian + 180 * side, a = side && in->arc_opposite > 0 ? in->arc_opposite : in->arc;
            kt_svg_arc(f, C, C, 0.5 * in->diameter * s, m - 0.5 * a, m + 0.5 * a, "inc");
        }
    }
    if (!isnan(ring))
        kt_svg_text(f, C + 0.5 * ring * s * cos(-50 * DEG) + 6, C + 0.5 * ring * s * sin(50 * DEG) + 12, "start", "small",
                    "incisions at OZ %.1f mm", ring);
    main_incision(f, r, C, s, wtw);
    kt_svg_line(f, C - 5, C, C + 5, C, "zero");
    kt_svg_line(f, C, C - 5, C, C + 5, "zero");
    kt_svg_end(f);
}

static kt_astig astig_add(kt_astig a, kt_astig b)
{
    double x[2], y[2];
    kt_astig_xy(a, x);
    kt_astig_xy(b, y);
    return kt_astig_from_xy(x[0] + y[0], x[1] + y[1]);
}

/* What the report says of the main incision: simulated (in the steps), or the surgeon's SIA
 * added to the last step's simulated astigmatism: the prediction. */
static void main_note(FILE *f, const kt_report *r)
{
    const kt_report_main *m = r->main;
    if (!m || !m->present) return;
    fprintf(f, "<p class=\"note\">Main incision: %.1f mm at %.0f&deg;, ", m->width, m->meridian);
    if (m->simulated) {
        fputs("simulated: its tunnel is cut before the arcs, so the steps' SIA holds its effect.</p>\n", f);
        return;
    }
    const kt_report_step *l = &r->step[r->nstep - 1];
    kt_astig k = astig_add((kt_astig){l->k.cyl, l->k.axis_steep}, m->sia);
    kt_astig t = astig_add((kt_astig){l->tot.tot_cyl, l->tot.tot_axis}, m->sia);
    fprintf(f, "not simulated: the surgeon's SIA <b>%.2f D @ %.0f&deg;</b> is added to the simulated eye. The prediction "
               "with it after the last step: keratometric <b>%.2f D @ %.0f&deg;</b>, total corneal <b>%.2f D @ "
               "%.0f&deg;</b>.</p>\n", m->sia.mag, axis180(m->sia.axis), k.mag, axis180(k.axis), t.mag, axis180(t.axis));
}

/* An arc's length (chord 0) or chord (chord 1), mm seen from the front, on the plan's eye: the
 * zone follows an oval cornea (kt_eye_arc_length, kt_eye_arc_chord); without an eye, on the
 * circle of the incision's diameter. */
static double arc_mm(const kt_plan *plan, const kt_incision *in, double centre, double arc, int chord)
{
    double a = centre - 0.5 * arc, b = centre + 0.5 * arc, v = NAN;
    if (plan && plan->scene.model == KT_MODEL_EYE)
        v = chord ? kt_eye_arc_chord(&plan->scene.eye, in->diameter, a, b) : kt_eye_arc_length(&plan->scene.eye, in->diameter, a, b);
    if (isfinite(v)) return v;
    return chord ? in->diameter * sin(0.5 * arc * DEG) : arc * DEG * 0.5 * in->diameter;
}

static void plan_section(FILE *f, const kt_report *r)
{
    fputs("<h2>1. The plan on the eye</h2>\n<div class=\"row\">\n<figure style=\"flex:0 1 460px\">", f);
    eye_diagram(f, r);
    fputs("<figcaption>The eye seen from the front, as the examiner sees it (TABO: 0&deg; at the examiner's right, "
          "angles counter-clockwise). S superior, I inferior, N nasal, T temporal: for a right eye (OD) the nose is "
          "at the examiner's right; curvature --eye OS draws a left eye. Red arcs: the incisions. Orange dashed line: "
          "the pre-operative steep meridian, measured on step 0. Grey dashed circles: the incision ring (its "
          "optical-zone diameter, OZ) and the keratometry zone. The bar is 5 mm.</figcaption></figure>\n"
          "<div style=\"flex:1 1 300px\"><table>\n"
          "<tr><th>incision</th><th>centre</th><th>arc</th><th>ring</th><th>depth</th><th>blade</th></tr>\n", f);
    static const char *DIR[] = {"clockwise", "counter-clockwise", "centre out"};
    for (int i = 0; r->plan && i < r->plan->ninc; i++) {
        const kt_incision *in = r->plan->inc + i;
        fprintf(f, "<tr><td>%d%s</td>", i + 1, in->paired ? " (paired)" : "");
        fprintf(f, "<td class=\"n\">%.0f&deg;%s</td>", in->meridian, in->paired ? " and opposite" : "");
        fprintf(f, "<td class=\"n\">%.0f&deg; (arc length %.2f mm, chord %.2f mm)", in->arc,
                arc_mm(r->plan, in, in->meridian, in->arc, 0), arc_mm(r->plan, in, in->meridian, in->arc, 1));
        if (in->paired && in->arc_opposite > 0)
            fprintf(f, "; opposite %.1f&deg; (chord %.2f mm)", in->arc_opposite,
                    arc_mm(r->plan, in, in->meridian + 180, in->arc_opposite, 1));
        fputs("</td>", f);
        fprintf(f, "<td class=\"n\">%.1f mm</td>", in->diameter);
        if (in->depth_fraction > 0) fprintf(f, "<td class=\"n\">%.0f%%</td>", 100 * in->depth_fraction);
        else fprintf(f, "<td class=\"n\">%.0f &micro;m</td>", 1000 * in->depth);
        fprintf(f, "<td>%s, %.1f&deg;/step</td></tr>\n", DIR[in->direction < 0 || in->direction > 2 ? 0 : in->direction],
                in->prog.degrees_per_step);
    }
    fputs("</table>\n", f);
    if (r->has_target)
        fprintf(f, "<p class=\"note\">Target: correct %.2f D of astigmatism at %.0f&deg;; the target induced "
                   "astigmatism (TIA) is %.2f D at %.0f&deg;.</p>\n",
                r->tia.mag, axis180(r->tia.axis + 90), r->tia.mag, axis180(r->tia.axis));
    main_note(f, r);
    fprintf(f, "<p class=\"note\">Incised meridian for flattening: %.1f&deg;. Keratometry: %s fit over the central "
               "%.0f mm, K = 337.5 / R (keratometric index 1.3375).</p></div>\n</div>\n",
            r->meridian, r->fit_name, r->zone);
}

/* ---------------------------------------------------------------- plots against step */

/* band_lo/band_hi (NULL: none): a shaded 90% band drawn under the series. */
static int step_plot(FILE *f, const kt_report *r, const char *label, int nser, const double *const *y,
                     const char *const *name, const char *ytitle, const double *band_lo, const double *band_hi,
                     kt_err *e)
{
    const double W = 560, H = 300;
    int n = r->nstep;
    double lo = 0, hi = 0;
    for (int k = 0; k < nser; k++)
        for (int i = 0; i < n; i++)
            if (isfinite(y[k][i])) lo = fmin(lo, y[k][i]), hi = fmax(hi, y[k][i]);
    for (int i = 0; band_lo && i < n; i++)
        if (isfinite(band_lo[i]) && isfinite(band_hi[i])) lo = fmin(lo, band_lo[i]), hi = fmax(hi, band_hi[i]);
    kt_svg_nice_range(&lo, &hi, 5);
    kt_svg_plot p = {70, 12, W - 90, H - 70, 0, n > 1 ? r->num[n - 1] : 1, lo, hi};
    double *x = kt_calloc(n > 0 ? n : 1, sizeof(double), e);
    if (!x) return e->code;
    for (int i = 0; i < n; i++) x[i] = r->num[i];
    kt_svg_begin(f, W, H, label);
    kt_svg_axes(f, &p, "%.0f", "%.2f", "", ytitle);
    int arcs = n > 0 && isfinite(r->step[n - 1].arc);
    double sx = kt_svg_nice_step(p.x1 - p.x0, 6);
    for (double v = 0; arcs && v <= p.x1 + 1e-9; v += sx)
        for (int i = 0; i < n; i++)
            if (r->num[i] == (int)lround(v))
                kt_svg_text(f, kt_svg_px(&p, v), p.y + p.h + 30, "middle", "small", "%.0f\xC2\xB0", r->step[i].arc);
    kt_svg_text(f, p.x + p.w / 2, p.y + p.h + 50, "middle", "axtitle",
                arcs ? "step (above) and degrees of arc opened per incision (below)" : "step");
    if (band_lo) { /* the polygon: lo forwards, hi backwards, steps with a finite band only */
        double *xy = kt_calloc((size_t)4 * (n > 0 ? n : 1), sizeof(double), e);
        if (!xy) {
            free(x);
            return e->code;
        }
        int m = 0;
        for (int i = 0; i < n; i++)
            if (isfinite(band_lo[i]) && isfinite(band_hi[i]))
                xy[2 * m] = kt_svg_px(&p, x[i]), xy[2 * m + 1] = kt_svg_py(&p, band_lo[i]), m++;
        for (int i = n - 1; i >= 0; i--)
            if (isfinite(band_lo[i]) && isfinite(band_hi[i]))
                xy[2 * m] = kt_svg_px(&p, x[i]), xy[2 * m + 1] = kt_svg_py(&p, band_hi[i]), m++;
        if (m >= 4) kt_svg_poly(f, xy, m, 1, "band");
        free(xy);
    }
    for (int k = 0; k < nser; k++) {
        char cls[8];
        snprintf(cls, sizeof cls, "s%d", (k % 5) + 1); /* the style sheet has series s1..s5 */
        kt_svg_series(f, &p, x, y[k], n, cls);
        double ly = p.y + 18 + 17 * k, lx = p.x + 12;
        fprintf(f, "<g class=\"%s\"><polyline points=\"%.1f,%.1f %.1f,%.1f\"/></g>\n", cls, lx, ly - 4, lx + 22, ly - 4);
        kt_svg_text(f, lx + 27, ly, "start", "lbl", "%s", name[k]);
    }
    kt_svg_end(f);
    free(x);
    return KT_OK;
}

static int step_plots(FILE *f, const kt_report *r, kt_err *e)
{
    int n = r->nstep;
    double *v = kt_calloc((size_t)5 * n, sizeof(double), e);
    if (!v) return e->code;
    double *fl = v, *st = v + n, *sia = v + 2 * n, *cyl = v + 3 * n, *tcyl = v + 4 * n;
    for (int i = 0; i < n; i++) {
        fl[i] = r->step[i].flat, st[i] = r->step[i].steep, sia[i] = r->step[i].va.sia.mag;
        cyl[i] = r->step[i].k.cyl, tcyl[i] = r->step[i].tot.tot_cyl;
    }
    fputs("<h2>4. The cut, step by step</h2>\n<div class=\"row\">\n<figure>", f);
    const double *y1[] = {fl, st, sia};
    char l1[96], l2[96];
    snprintf(l1, sizeof l1, "flattening of the incised meridian (%.0f\xC2\xB0)", axis180(r->meridian));
    snprintf(l2, sizeof l2, "steepening of the orthogonal one (%.0f\xC2\xB0)", axis180(r->meridian + 90));
    const char *n1[] = {l1, l2, "SIA"};
    int rc = step_plot(f, r, "flattening, steepening and SIA against step", 3, y1, n1, "dioptres", r->sia_lo,
                       r->sia_hi, e);
    fprintf(f, "<figcaption><b>Flattening</b> of the incised meridian (%.0f&deg;) and <b>steepening</b> of the "
               "orthogonal one, both against step 0, and the magnitude of the <b>surgically induced "
               "astigmatism</b> (SIA, vector difference). Their ratio is the coupling ratio.%s</figcaption></figure>\n<figure>",
            r->meridian, r->sia_lo ? " The shaded band is the SIA's first-order 90% interval from the uncertainty of "
                                     "the model's inputs (section 4b)." : "");
    int have_tot = isfinite(tcyl[0]);
    const double *y2[] = {cyl, tcyl};
    const char *n2[] = {"anterior (keratometric) cylinder", "total corneal cylinder"};
    if (rc == KT_OK)
        rc = step_plot(f, r, "corneal cylinder against step", have_tot ? 2 : 1, y2, n2, "cylinder (D)", NULL, NULL, e);
    fputs("<figcaption><b>Corneal cylinder</b> as the keratometer reads it (anterior surface, index 1.3375)", f);
    if (have_tot)
        fprintf(f, " and the <b>total corneal astigmatism</b> (anterior + posterior surface, thick lens, indices "
                   "%.3f / %.3f / %.3f)", r->n->air, r->n->cornea, r->n->aqueous);
    fputs(".</figcaption></figure>\n</div>\n", f);
    if (r->axis_note) {
        fputs("<p class=\"note\" id=\"axis-note\"><b>Why the steep axis moves:</b> ", f);
        kt_html_text(f, r->axis_note);
        fputs("</p>\n", f);
    }
    free(v);
    return rc;
}

/* The tornado chart: each quantity's contribution |dSIA/dp| sd_p to the SIA's sd at the last
 * step, largest first. */
static void tornado(FILE *f, const kt_report *r)
{
    const kt_report_step *sl = r->step + r->nstep - 1;
    const double W = 560, rowh = 26, top = 16, left = 150, right = 70;
    double H = top + rowh * r->ntorn + 44, vmax = 0;
    for (int k = 0; k < r->ntorn; k++) vmax = fmax(vmax, r->torn_val[k]);
    double lo = 0, hi = vmax > 0 ? vmax : 1;
    kt_svg_nice_range(&lo, &hi, 5);
    kt_svg_plot p = {left, top, W - left - right, rowh * r->ntorn, 0, hi, 0, 1};
    fputs("<h2>4b. How sure: the SIA's band</h2>\n<div class=\"row\">\n<figure id=\"tornado\" style=\"flex:0 1 640px\">", f);
    kt_svg_begin(f, W, H, "contribution of each uncertain quantity to the SIA's standard deviation");
    double st = kt_svg_nice_step(hi, 5);
    for (double v = 0; v <= hi + 1e-12; v += st) {
        kt_svg_line(f, kt_svg_px(&p, v), p.y, kt_svg_px(&p, v), p.y + p.h, v == 0 ? "zero" : "grid");
        kt_svg_text(f, kt_svg_px(&p, v), p.y + p.h + 16, "middle", "tick", "%.2f", v);
    }
    for (int k = 0; k < r->ntorn; k++) {
        double y = p.y + rowh * k + 4, w = kt_svg_px(&p, r->torn_val[k]) - p.x;
        fprintf(f, "<rect class=\"torn\" x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\"/>\n", p.x, y,
                w > 0 ? w : 0, rowh - 8);
        kt_svg_text(f, p.x - 8, y + rowh / 2, "end", "lbl", "%s", r->torn_name[k]);
        kt_svg_text(f, p.x + (w > 0 ? w : 0) + 6, y + rowh / 2, "start", "lbl", "%.3f D", r->torn_val[k]);
    }
    kt_svg_text(f, p.x + p.w / 2, p.y + p.h + 36, "middle", "axtitle", "contribution to the SIA's sd at the last step (D)");
    kt_svg_end(f);
    double lo90 = r->sia_lo ? r->sia_lo[r->nstep - 1] : NAN, hi90 = r->sia_hi ? r->sia_hi[r->nstep - 1] : NAN;
    fprintf(f, "<figcaption><b>Which input matters most.</b> SIA %.2f D (90%%: %.2f&ndash;%.2f D), standard deviation "
               "%.2f D at the last step: each bar is one uncertain input's share, |dSIA/dp| &times; sd<sub>p</sub>, "
               "from the derivative of the solution (augsolve --uncertainty) carried through this keratometry. The "
               "inputs are taken as independent, so the shares add in squares. It is a first-order (linear) band: the "
               "sampling study (plans/studies/uq) says how far it holds.</figcaption></figure>\n</div>\n",
            sl->va.sia.mag, lo90, hi90, r->sia_sd);
}

/* ---------------------------------------------------------------- double-angle plot */

static void vec(FILE *f, double cx, double cy, double scale, kt_astig a, const char *cls)
{
    if (!isfinite(a.mag) || !isfinite(a.axis)) return;
    double xy[2];
    kt_astig_xy(a, xy);
    kt_svg_arrow(f, cx, cy, cx + scale * xy[0], cy - scale * xy[1], 12, cls);
}

static void double_angle(FILE *f, const kt_report *r)
{
    const kt_report_step *s0 = r->step, *sl = r->step + r->nstep - 1;
    kt_astig pre = {s0->k.cyl, s0->k.axis_steep}, post = {sl->k.cyl, sl->k.axis_steep};
    double m = fmax(fmax(pre.mag, post.mag), sl->va.sia.mag);
    if (r->has_target) m = fmax(m, r->tia.mag);
    double lo = 0, hi = m > 0 ? m : 1;
    kt_svg_nice_range(&lo, &hi, 4);
    const double W = 460, C = 225, R = 165, sc = R / hi;
    kt_svg_begin(f, W, W + 36, "double-angle plot of the astigmatism vectors");
    double step = kt_svg_nice_step(hi, 4);
    for (double v = step; v <= hi + 1e-9; v += step) {
        kt_svg_circle(f, C, C, v * sc, "polar");
        kt_svg_text(f, C + 3, C - v * sc - 3, "start", "small", "%.2g D", v);
    }
    for (int a = 0; a < 180; a += 15) {
        double t = 2 * a * DEG;
        kt_svg_line(f, C, C, C + R * cos(t), C - R * sin(t), a % 45 ? "grid" : "zero");
        if (a % 45 == 0) kt_svg_text(f, C + (R + 18) * cos(t), C - (R + 18) * sin(t) + 4, "middle", "lbl", "%d\xC2\xB0", a);
    }
    vec(f, C, C, sc, pre, "v-pre");
    vec(f, C, C, sc, post, "v-post");
    if (r->has_target) vec(f, C, C, sc, r->tia, "v-tia");
    vec(f, C, C, sc, sl->va.sia, "v-sia");
    if (r->has_target) vec(f, C, C, sc, sl->va.dv, "v-dv");
    static const char *CLS[] = {"v-pre", "v-post", "v-tia", "v-sia", "v-dv"},
                      *NAME[] = {"pre-op", "post-op", "target induced (TIA)", "surgically induced (SIA)", "difference vector"};
    for (int k = 0, j = 0; k < 5; k++) {
        if (!r->has_target && (k == 2 || k == 4)) continue;
        double lx = 10 + (j % 2) * 225, ly = W - 28 + (j / 2) * 18;
        kt_svg_arrow(f, lx, ly - 4, lx + 26, ly - 4, 7, CLS[k]);
        kt_svg_text(f, lx + 32, ly, "start", "small", "%s", NAME[k]);
        j++;
    }
    kt_svg_text(f, 8, 16, "start", "lbl", "DOUBLE-ANGLE PLOT: a cylinder at axis a is drawn at 2a");
    kt_svg_end(f);
}

static void alpins_table(FILE *f, const kt_report *r)
{
    const kt_report_step *s0 = r->step, *sl = r->step + r->nstep - 1;
    const kt_alpins *a = &sl->va;
    fputs("<table>\n<tr><th>vector / index</th><th>value</th><th>axis</th></tr>\n", f);
    fputs("<tr><td>pre-op astigmatism (step 0)</td>", f);
    cell(f, "%.2f D", s0->k.cyl), cell(f, "%.1f&deg;", axis180(s0->k.axis_steep));
    fprintf(f, "</tr>\n<tr><td>post-op astigmatism (step %d)</td>", r->num[r->nstep - 1]);
    cell(f, "%.2f D", sl->k.cyl), cell(f, "%.1f&deg;", axis180(sl->k.axis_steep));
    fputs("</tr>\n<tr><td>target induced astigmatism, TIA</td>", f);
    cell(f, "%.2f D", a->tia.mag), cell(f, "%.1f&deg;", axis180(a->tia.axis));
    fputs("</tr>\n<tr><td>surgically induced astigmatism, SIA</td>", f);
    cell(f, "%.2f D", a->sia.mag), cell(f, "%.1f&deg;", axis180(a->sia.axis));
    fputs("</tr>\n<tr><td>difference vector, DV = TIA &minus; SIA</td>", f);
    cell(f, "%.2f D", a->dv.mag), cell(f, "%.1f&deg;", axis180(a->dv.axis));
    fputs("</tr>\n<tr><td>correction index, CI = |SIA| / |TIA|</td>", f);
    cell(f, "%.2f", a->ci);
    fputs("<td></td></tr>\n<tr><td>magnitude of error, ME = |SIA| &minus; |TIA|</td>", f);
    cell(f, "%+.2f D", a->me);
    fputs("<td></td></tr>\n<tr><td>angle of error, AE = axis SIA &minus; axis TIA</td>", f);
    cell(f, "%+.1f&deg;", a->ae);
    fputs("<td></td></tr>\n<tr><td>index of success, IOS = |DV| / |TIA|</td>", f);
    cell(f, "%.2f", a->ios);
    fputs("<td></td></tr>\n<tr><td>flattening index, FI = flattening / |TIA|</td>", f);
    cell(f, "%.2f", r->has_target && r->tia.mag > 0 ? sl->flat / r->tia.mag : NAN);
    fputs("<td></td></tr>\n<tr><td>coupling ratio = flattening / steepening</td>", f);
    cell(f, "%.2f", fabs(sl->steep) > 1e-9 ? sl->flat / sl->steep : NAN);
    fputs("<td></td></tr>\n</table>\n", f);
    fputs("<p class=\"note\">Alpins NA, J Cataract Refract Surg 1993;19:524-533 and 2001;27:31-49. CI &gt; 1: "
          "over-correction, CI &lt; 1: under-correction; AE &gt; 0: the treatment acted counter-clockwise of its intended axis; IOS 0 is "
          "perfect.</p>\n", f);
}

/* ---------------------------------------------------------------- section */

static void section_fig(FILE *f, const kt_report *r)
{
    const kt_section *s = r->section;
    double F = kt_report_exaggeration(s->max_disp, 0.04 * (s->r1 - s->r0));
    double zlo = INFINITY, zhi = -INFINITY, rl = INFINITY, rh = -INFINITY, ztop = -INFINITY;
    for (int i = 0; i < s->n; i++)
        for (int k = 0; k < s->nv[i]; k++) {
            const double *b = s->base + 8 * i + 2 * k, *d = s->def + 8 * i + 2 * k;
            for (double g = 0; g <= F; g += F) {
                zlo = fmin(zlo, b[1] + g * d[1]), zhi = fmax(zhi, b[1] + g * d[1]);
                rl = fmin(rl, b[0] + g * d[0]), rh = fmax(rh, b[0] + g * d[0]);
            }
            if (fabs(b[0] - 0.5 * (s->r0 + s->r1)) < 0.1) ztop = fmax(ztop, b[1]);
        }
    if (!(zhi > zlo) || !(rh > rl)) zlo = 0, zhi = 1, rl = s->r0, rh = s->r1;
    zlo -= 0.05, zhi += 0.1, rl -= 0.05, rh += 0.05;
    const double W = 900;
    double pxmm = (W - 90) / (rh - rl), H = (zhi - zlo) * pxmm + 60;
    kt_svg_plot p = {60, 10, W - 90, (zhi - zlo) * pxmm, rl, rh, zlo, zhi};
    fputs("<h2>6. Through the wound</h2>\n<figure>", f);
    kt_svg_begin(f, W, H, "meridional section through an incision, displacement exaggerated");
    kt_svg_axes(f, &p, "%.1f", "%.1f", "distance from the optical axis along the meridian (mm)",
                "height z along the optical axis (mm)");
    double xy[8];
    for (int i = 0; i < s->n; i++) {
        for (int k = 0; k < s->nv[i]; k++)
            xy[2 * k] = kt_svg_px(&p, s->base[8 * i + 2 * k]), xy[2 * k + 1] = kt_svg_py(&p, s->base[8 * i + 2 * k + 1]);
        kt_svg_poly(f, xy, s->nv[i], 1, "sec-ref");
    }
    for (int i = 0; i < s->n; i++) {
        for (int k = 0; k < s->nv[i]; k++) {
            const double *b = s->base + 8 * i + 2 * k, *d = s->def + 8 * i + 2 * k;
            xy[2 * k] = kt_svg_px(&p, b[0] + F * d[0]), xy[2 * k + 1] = kt_svg_py(&p, b[1] + F * d[1]);
        }
        kt_svg_poly(f, xy, s->nv[i], 1, "sec-def");
    }
    if (isfinite(ztop)) {
        double X = kt_svg_px(&p, 0.5 * (s->r0 + s->r1)), Y = kt_svg_py(&p, ztop);
        kt_svg_arrow(f, X + 40, Y - 40, X + 4, Y - 4, 10, "v-sia");
        kt_svg_text(f, X + 44, Y - 44, "start", "lbl", "the incision: its wound gap after the last step (tan)");
    }
    kt_svg_end(f);
    fprintf(f, "<figcaption>Meridional section at %.0f&deg; through the middle of an incision, %.1f to %.1f mm from "
               "the axis, true aspect ratio. Heights z are in the model's frame: along the optical axis, the "
               "pre-operative corneal apex at z = %.3f mm (step 0's fitted apex). Tan: the tissue after the last "
               "step, its displacement since step 0 <b>exaggerated %.0f&times;</b> (largest in-plane displacement "
               "%.1f &micro;m); grey outlines: before surgery. The gap is the wound opening under intraocular "
               "pressure. <span id=\"gape\">Gape, true size: <b>%.1f &micro;m</b>, the largest distance between the "
               "two copies of a node split by the cut (the wound's two faces) among nodes within 0.5 mm of this "
               "section's plane; <b>%.1f &micro;m</b> over the whole wound (every node the plan split, in the last "
               "step's VTK)</span>.</figcaption></figure>\n",
            s->meridian, s->r0, s->r1, r->apex_z, F, 1000 * s->max_disp, 1000 * s->gape, 1000 * s->gape_all);
}

/* ---------------------------------------------------------------- provenance */

static void prov_row(FILE *f, const char *k, const char *v)
{
    fputs("<tr><th>", f);
    kt_html_text(f, k);
    fputs("</th><td>", f);
    kt_html_text(f, v ? v : "-");
    fputs("</td></tr>\n", f);
}

static void provenance(FILE *f, const kt_report *r)
{
    char buf[256];
    fputs("<h2>7. Provenance</h2>\n<table id=\"provenance\">\n", f);
    prov_row(f, "keratome", r->version);
    prov_row(f, "run folder", r->run_dir);
    prov_row(f, "scene", r->scene_path ? r->scene_path : r->plan ? r->plan->scene_path : NULL);
    prov_row(f, "plan", r->plan_path);
    snprintf(buf, sizeof buf, "%s: %d nodes, %d tets, element order %d", r->mesh, r->mesh_nn, r->mesh_ne, r->mesh_order);
    prov_row(f, "mesh", buf);
    if (isfinite(r->solver_ms)) {
        snprintf(buf, sizeof buf, "%.1f s over %d steps (steps.tsv, t_total_ms)", r->solver_ms / 1000, r->nstep);
        prov_row(f, "solver time", buf);
    }
    snprintf(buf, sizeof buf, "%.1f s (fits, maps and this page)", r->curv_s);
    prov_row(f, "curvature time", buf);
    snprintf(buf, sizeof buf, "%s over %.0f mm; K = 337.5 / R; total power: thick lens, n %.3f / %.3f / %.3f "
                              "(Gullstrand)", r->fit_name, r->zone, r->n->air, r->n->cornea, r->n->aqueous);
    prov_row(f, "keratometry", buf);
    for (int i = 0; i < r->nprov; i++) prov_row(f, r->prov[2 * i], r->prov[2 * i + 1]);
    fputs("</table>\n", f);
    if (r->run_yaml) {
        fputs("<p class=\"note\">run.yaml (augsolve's record of the solve):</p><pre>", f);
        kt_html_text(f, r->run_yaml);
        fputs("</pre>\n", f);
    }
}

/* ---------------------------------------------------------------- page */

static void step_table(FILE *f, const kt_report *r)
{
    fputs("<details><summary class=\"note\">every step (as in curvature.tsv)</summary><table>\n<tr><th>step</th>"
          "<th>arc</th><th>K steep</th><th>axis</th><th>K flat</th><th>cyl</th><th>flattening</th>"
          "<th>steepening</th><th>SIA</th><th>total cyl</th></tr>\n", f);
    for (int i = 0; i < r->nstep; i++) {
        const kt_report_step *s = r->step + i;
        fprintf(f, "<tr><td class=\"n\">%d</td>", r->num[i]);
        cell(f, "%.0f&deg;", s->arc), cell(f, "%.2f", s->k.k_steep), cell(f, "%.1f&deg;", axis180(s->k.axis_steep));
        cell(f, "%.2f", s->k.k_flat), cell(f, "%.2f", s->k.cyl), cell(f, "%+.3f", s->flat), cell(f, "%+.3f", s->steep);
        cell(f, "%.3f", s->va.sia.mag), cell(f, "%.2f", s->tot.tot_cyl);
        fputs("</tr>\n", f);
    }
    fputs("</table>", f);
    if (r->axis_note) {
        fputs("<p class=\"note\">The axis column: ", f);
        kt_html_text(f, r->axis_note);
        fputs("</p>", f);
    }
    fputs("</details>\n", f);
}

/* Every step's axial map, in a strip (a class can step through the cut without a script). */
static int strip(FILE *f, const kt_report *r, kt_err *e)
{
    if (!r->maps) return KT_OK;
    /* the relative scale when there is one: the change from step to step shows in it */
    const kt_topo_scale *sc = r->rel_scale ? r->rel_scale : r->scale;
    fprintf(f, "<details open id=\"strip\"><summary class=\"note\">every step's axial map (%s scale, %.2f&ndash;%.2f D "
               "in %.2f D bins, as in section 2)</summary><div class=\"strip\">\n",
            r->rel_scale || r->scale_auto ? "relative" : "absolute", sc->lo[0], sc->hi[sc->n - 1], sc->hi[0] - sc->lo[0]);
    for (int i = 0; i < r->nstep; i++) {
        kt_topo_map m;
        map_frame(&m, r->maps[i], r->map_rad[i], r->zone);
        const kt_report_step *s = r->step + i;
        snprintf(m.title[0], sizeof m.title[0], "STEP %d", r->num[i]);
        snprintf(m.title[1], sizeof m.title[1], "CYL %.2f@%.0f\xC2\xB0", s->k.cyl, axis180(s->k.axis_steep));
        char alt[64];
        snprintf(alt, sizeof alt, "axial power map, step %d", r->num[i]);
        fputs("<figure>", f);
        int rc = map_img(f, sc, &m, axial_of, r->maps[i], alt, e);
        if (rc) return rc;
        fprintf(f, "<figcaption>step %d", r->num[i]);
        if (isfinite(s->arc)) fprintf(f, ", %.0f&deg; of arc", s->arc);
        fprintf(f, ": %.2f D @ %.0f&deg;</figcaption></figure>\n", s->k.cyl, axis180(s->k.axis_steep));
    }
    fputs("</div></details>\n", f);
    return KT_OK;
}

static void cards(FILE *f, const kt_report *r)
{
    const kt_report_step *s0 = r->step, *sl = r->step + r->nstep - 1;
    char v[96];
    fputs("<div class=\"cards\">\n", f);
    snprintf(v, sizeof v, "%.2f D @ %.0f\xC2\xB0", s0->k.cyl, axis180(s0->k.axis_steep));
    card(f, v, "pre-op keratometric cylinder");
    snprintf(v, sizeof v, "%.2f D @ %.0f\xC2\xB0", sl->k.cyl, axis180(sl->k.axis_steep));
    card(f, v, "cylinder after the last step");
    snprintf(v, sizeof v, "%.2f D @ %.0f\xC2\xB0", sl->va.sia.mag, axis180(sl->va.sia.axis));
    card(f, v, "surgically induced astigmatism");
    if (r->sia_lo && isfinite(r->sia_lo[r->nstep - 1])) {
        snprintf(v, sizeof v, "%.2f\xE2\x80\x93%.2f D", r->sia_lo[r->nstep - 1], r->sia_hi[r->nstep - 1]);
        card(f, v, "SIA, 90% band (first order)");
    }
    if (r->has_target) {
        snprintf(v, sizeof v, "%.2f", sl->va.ci);
        card(f, v, "correction index (1 = on target)");
    }
    if (fabs(sl->steep) > 1e-9) {
        snprintf(v, sizeof v, "%.2f", sl->flat / sl->steep);
        card(f, v, "coupling ratio");
    }
    if (isfinite(s0->tot.tot_cyl)) {
        snprintf(v, sizeof v, "%.2f \xE2\x86\x92 %.2f D", s0->tot.tot_cyl, sl->tot.tot_cyl);
        card(f, v, "total corneal astigmatism");
    }
    fputs("</div>\n", f);
}

static int page(FILE *f, const kt_report *r, kt_err *e)
{
    char title[512];
    snprintf(title, sizeof title, "keratome: %s", r->plan && r->plan->scene.name[0] ? r->plan->scene.name : r->run_dir);
    kt_html_begin(f, title);
    fputs("<header><h1>Limbal relaxing incisions: what the cut does to the cornea</h1><p>", f);
    /* the plan's file name here; its path (relative to the run folder) is in the provenance */
    const char *slash = r->plan_path ? strrchr(r->plan_path, '/') : NULL;
    kt_html_text(f, slash ? slash + 1 : r->plan_path ? r->plan_path : "(no plan)");
    fprintf(f, " &middot; %d step%s &middot; simulated by keratome ", r->nstep - 1, r->nstep == 2 ? "" : "s");
    kt_html_text(f, r->version);
    fputs("</p></header>\n<main>\n", f);
    if (r->verdict) {
        fprintf(f, "<p class=\"verdict%s\" id=\"verdict\">", strncmp(r->verdict, "On target", 9) == 0 ? " ok" : "");
        kt_html_text(f, r->verdict);
        fputs("</p>\n", f);
    }
    cards(f, r);
    fputs("<p class=\"note\">A finite element model of the eye is cut step by step as the plan says; after every "
          "step the deformed cornea is measured the way a keratometer and a topographer measure a patient. "
          "Sections 1&ndash;6 show the plan, the corneal power before and after, how it changed with every "
          "step of the blade, the change as astigmatism vectors, and the wound itself. The numbers are what the "
          "model gives: nothing is tuned to clinical outcomes.</p>\n", f);
    plan_section(f, r);
    int rc = maps(f, r, e);
    if (rc == KT_OK) rc = step_plots(f, r, e);
    if (rc != KT_OK) return rc;
    step_table(f, r);
    if ((rc = strip(f, r, e)) != KT_OK) return rc;
    if (r->ntorn > 0) tornado(f, r);
    fputs("<h2>5. Astigmatism as vectors</h2>\n<div class=\"row\">\n<figure style=\"flex:0 1 460px\">", f);
    double_angle(f, r);
    fputs("<figcaption><b>Double-angle plot.</b> Astigmatism is a vector with a 180&deg; period, so each "
          "cylinder is drawn at twice its axis: 90&deg; points left, opposite to 0&deg;. Arrows from the centre: "
          "pre-op and post-op (keratometric) astigmatism, the target induced and the surgically induced "
          "astigmatism; the difference vector is what remains to do.</figcaption></figure>\n"
          "<div style=\"flex:1 1 380px\">", f);
    alpins_table(f, r);
    fputs("</div>\n</div>\n", f);
    if (r->section && r->section->n > 0) section_fig(f, r);
    provenance(f, r);
    fputs("</main>\n", f);
    kt_html_end(f);
    return KT_OK;
}

int kt_curv_report_write(const char *path, const kt_report *r, kt_err *e)
{
    if (r->nstep < 1) return kt_fail(e, KT_ERUN, "report: no steps");
    kt_out o;
    if (kt_out_open(&o, path, e) != KT_OK) return e->code;
    int rc = page(o.f, r, e);
    if (rc == KT_OK) rc = kt_out_failed(&o, e);
    if (rc != KT_OK) {
        kt_out_abort(&o);
        return rc;
    }
    return kt_out_commit(&o, e);
}
