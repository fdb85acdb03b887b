/* lriplan_html.c: PLAN_DIR/plan.html, the plan sheet a surgeon takes to the operating room
 * (lri-plan(1), OUTPUT): one self-contained page (inline CSS and SVG, no script, no network),
 * the eye from the surgeon's view with the main incision and each arc, the numbers to mark and
 * set, the predicted astigmatism, the SIA curve with the chosen point, the inputs and fits, the
 * provenance and a link to the chosen run's teaching report. Every number that plan.json also
 * holds is written inside an element with data-key="<json path>" so a second reader can check
 * the two against each other (tests/lriplan_sheet.sh). */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "html.h"
#include "lriplan_int.h"
#include "svg.h"

static const char CSS[] =
    KT_HTML_CSS_PAGE
    ".card b{display:block;font-size:20px}.card span.l{font-size:12px;color:#5b6670}\n"
    ".row{display:flex;flex-wrap:wrap;gap:16px}\n"
    "figure{background:#fff;margin:0;padding:10px 12px;border-radius:8px;box-shadow:0 1px 3px rgba(0,0,0,.12);flex:1 1 420px}\n"
    "figure svg{width:100%;height:auto;display:block}\n"
    "figcaption{font-size:13px;color:#3d4750;margin-top:6px;line-height:1.4}\n"
    "table{border-collapse:collapse;font-size:13px;background:#fff;margin-bottom:10px}"
    "td,th{padding:4px 10px;border-bottom:1px solid #e2e6ea;text-align:left}\n"
    "th{background:#eef1f4}td.n{text-align:right;font-variant-numeric:tabular-nums}\n"
    "pre{background:#fff;padding:8px;font-size:12px;overflow:auto;border-radius:6px}\n"
    "svg text{font-family:'DejaVu Sans',Helvetica,Arial,sans-serif;fill:#1d232a}\n"
    ".tick{font-size:11px}.axtitle{font-size:12px}.lbl{font-size:12px}.small{font-size:10px;fill:#5b6670}\n"
    ".clock{font-size:13px;font-weight:600;fill:#18324a}\n"
    ".grid{stroke:#e4e7eb;stroke-width:1}.zero{stroke:#8a939b;stroke-width:1}.frame{fill:none;stroke:#8a939b}\n"
    ".sclera{fill:#fbfaf6;stroke:none}.cornea{fill:#e8f1f8;stroke:#7f97ad;stroke-width:2}\n"
    ".merid{stroke:#b8c3cc;stroke-width:1}.ring{fill:none;stroke:#6b7a88;stroke-width:1.2;stroke-dasharray:5 4}\n"
    ".inc{fill:none;stroke:#c0392b;stroke-width:8;stroke-linecap:round}\n"
    ".main{fill:none;stroke:#1f6fb4;stroke-width:10;stroke-linecap:butt}\n"
    ".end{fill:#fff;stroke:#c0392b;stroke-width:2}\n"
    ".steep{stroke:#e67e22;stroke-width:2.5;stroke-dasharray:10 5}\n"
    ".s1 polyline{fill:none;stroke:#1f6fb4;stroke-width:2.2}.s1 circle{fill:#1f6fb4}\n"
    ".s2 polyline{fill:none;stroke:#d35400;stroke-width:2.2}.s2 circle{fill:#d35400}\n"
    ".s3 polyline{fill:none;stroke:#8e44ad;stroke-width:2.2;stroke-dasharray:6 3}.s3 circle{fill:#8e44ad}\n"
    ".chosen{fill:none;stroke:#c0392b;stroke-width:3}.target{stroke:#27ae60;stroke-width:1.5;stroke-dasharray:6 4}\n"
    ".nsti{font-size:15px;font-weight:700;fill:#18324a}.bar{stroke:#1d232a;stroke-width:3}\n"
    ".verdict{font-size:16px;font-weight:600;margin:14px 0 0;padding:10px 14px;border-radius:8px;background:#fff;"
    "border-left:6px solid #c0392b}.verdict.ok{border-left-color:#27ae60}\n"
    ".note{font-size:13px;color:#3d4750}\n";

#define DEG (KT_CURV_PI / 180)

/* A number that plan.json holds too: <span data-key="key">value</span>. */
static void num(FILE *f, const char *key, const char *fmt, double v)
{
    fprintf(f, "<span data-key=\"%s\">", key);
    fprintf(f, fmt, v);
    fputs("</span>", f);
}

static void text_key(FILE *f, const char *key, const char *s)
{
    fprintf(f, "<span data-key=\"%s\">", key);
    kt_html_text(f, s);
    fputs("</span>", f);
}

/* The simulated SIA of step k of a family: |astigmatism(k) - astigmatism(0)| as double-angle
 * vectors, keratometric. */
static double sia(const kt_lri_family *c, int k)
{
    double a[2], b[2];
    kt_astig_xy(c->kerato[k], a);
    kt_astig_xy(c->kerato[0], b);
    return hypot(a[0] - b[0], a[1] - b[1]);
}

double kt_lri_sia(const kt_lri_family *c, int k) { return sia(c, k); }

/* ---------------------------------------------------------------- the eye */

static void eye_svg(FILE *f, const kt_lri_answer *a, const kt_lri_arc *arcs, int narc)
{
    const kt_patient *p = &a->p;
    const double W = 520, C = 260;
    int os = p->eye == KT_EYE_OS;
    double wtw = p->wtw, s = 185 / (0.5 * wtw); /* px per mm */
    kt_svg_begin(f, W, W, "the plan on the eye as the surgeon sees it");
    fprintf(f, "<rect class=\"sclera\" x=\"0\" y=\"0\" width=\"%.0f\" height=\"%.0f\"/>\n", W, W);
    kt_svg_circle(f, C, C, 0.5 * wtw * s, "cornea");
    for (int t = 0; t < 180; t += 30)
        kt_svg_line(f, C + 200 * cos(t * DEG), C - 200 * sin(t * DEG), C - 200 * cos(t * DEG), C + 200 * sin(t * DEG), "merid");
    for (int t = 0; t < 360; t += 30) {
        kt_svg_text(f, C + 212 * cos(t * DEG), C - 212 * sin(t * DEG) + 4, "middle", "tick", "%d\xC2\xB0", t);
        int h = ((3 - t / 30) % 12 + 12) % 12;
        kt_svg_text(f, C + 240 * cos(t * DEG), C - 240 * sin(t * DEG) + 5, "middle", "clock", "%d", h ? h : 12);
    }
    kt_svg_circle(f, C, C, 0.5 * p->zone * s, "ring");
    /* Orientation: superior up; the examiner's right (0 deg) is the patient's left: nasal in
     * a right eye, temporal in a left eye (keratome-patient(5), CONVENTIONS). */
    kt_svg_text(f, C - 30, 20, "middle", "nsti", "S");
    kt_svg_text(f, C - 30, W - 8, "middle", "nsti", "I");
    kt_svg_text(f, W - 12, C + 30, "middle", "nsti", "%s", os ? "T" : "N");
    kt_svg_text(f, 12, C + 30, "middle", "nsti", "%s", os ? "N" : "T");
    kt_svg_text(f, 6, 18, "start", "nsti", "%s", os ? "OS" : "OD");
    kt_svg_text(f, 6, 34, "start", "small", "%s eye, surgeon's view", os ? "left" : "right");
    kt_svg_line(f, W - 16 - 5 * s, W - 22, W - 16, W - 22, "bar");
    kt_svg_text(f, W - 16 - 2.5 * s, W - 30, "middle", "small", "5 mm");
    double ax = p->ant.axis;
    kt_svg_line(f, C + 190 * cos(ax * DEG), C - 190 * sin(ax * DEG), C - 190 * cos(ax * DEG), C + 190 * sin(ax * DEG), "steep");
    if (p->main_present) {
        /* The main incision at the limbus: its width as an arc just inside white-to-white. */
        double r = 0.5 * wtw - 0.3, half = 0.5 * p->main_width / r / DEG, m = p->main_meridian;
        kt_svg_arc(f, C, C, r * s, m - half, m + half, "main");
        double lx = C + (r - 1.3) * s * cos(m * DEG), ly = C - (r - 1.3) * s * sin(m * DEG);
        kt_svg_text(f, lx, ly + 18, "middle", "lbl", "main %.1f mm", p->main_width);
    }
    for (int i = 0; i < narc; i++) {
        const kt_lri_arc *q = &arcs[i];
        double r = 0.5 * p->zone * s;
        kt_svg_arc(f, C, C, r, q->from, q->from + q->arc, "inc");
        double ends[2] = {q->from, q->from + q->arc};
        for (int k = 0; k < 2; k++) {
            double x = C + r * cos(ends[k] * DEG), y = C - r * sin(ends[k] * DEG);
            kt_svg_circle(f, x, y, 4, "end");
            double lx = C + (r + 26) * cos(ends[k] * DEG), ly = C - (r + 26) * sin(ends[k] * DEG);
            kt_svg_text(f, lx, ly + 4, "middle", "lbl", "%.0f\xC2\xB0 (%s)", fmod(ends[k], 360), k ? q->to_clock : q->from_clock);
        }
    }
    kt_svg_line(f, C - 5, C, C + 5, C, "zero");
    kt_svg_line(f, C, C - 5, C, C + 5, "zero");
    kt_svg_end(f);
}

/* ---------------------------------------------------------------- the curves */

static void curve_svg(FILE *f, const kt_lri_answer *a, int residual)
{
    const double W = 560, H = 330;
    kt_svg_plot pl = {64, 18, W - 84, H - 70, 0, 0, 0, 0};
    double ymax = 0, xmax = 0;
    for (int i = 0; i < a->nfam; i++)
        for (int k = 0; k <= a->fam[i].nstep; k++) {
            double y = residual ? a->fam[i].pred[k].mag : sia(&a->fam[i], k);
            if (isfinite(y)) ymax = fmax(ymax, y);
            xmax = fmax(xmax, a->fam[i].arc[k]);
        }
    if (residual) ymax = fmax(ymax, a->p.target_residual);
    pl.x1 = xmax > 0 ? xmax : 1, pl.y1 = ymax > 0 ? ymax : 1;
    kt_svg_nice_range(&pl.x0, &pl.x1, 6);
    kt_svg_nice_range(&pl.y0, &pl.y1, 5);
    pl.y0 = 0;
    kt_svg_begin(f, W, H, residual ? "predicted residual astigmatism against arc" : "SIA against arc");
    kt_svg_axes(f, &pl, "%g", "%.1f", "arc (deg; an unequal pair: its longer arc)", residual ? "predicted residual (D)" : "SIA (D)");
    if (residual)
        kt_svg_line(f, kt_svg_px(&pl, pl.x0), kt_svg_py(&pl, a->p.target_residual), kt_svg_px(&pl, pl.x1),
                    kt_svg_py(&pl, a->p.target_residual), "target");
    for (int i = 0; i < a->nfam; i++) {
        const kt_lri_family *c = &a->fam[i];
        double y[KT_LRIPLAN_MAXSTEP + 1];
        for (int k = 0; k <= c->nstep; k++) y[k] = residual ? c->pred[k].mag : sia(c, k);
        char cls[8];
        snprintf(cls, sizeof cls, "s%d", i + 1);
        kt_svg_series(f, &pl, c->arc, y, c->nstep + 1, cls);
        kt_svg_text(f, pl.x + 8, pl.y + 16 + 15 * i, "start", "lbl", "%s%s", c->name, i == a->chosen ? " (chosen)" : "");
        fprintf(f, "<g class=\"%s\"><polyline points=\"%.1f,%.1f %.1f,%.1f\"/></g>\n", cls, pl.x + 120, pl.y + 12 + 15 * i,
                pl.x + 145, pl.y + 12 + 15 * i);
        if (i == a->chosen) {
            double yc = residual ? c->pred[c->best].mag : sia(c, c->best);
            kt_svg_circle(f, kt_svg_px(&pl, c->arc[c->best]), kt_svg_py(&pl, yc), 9, "chosen");
        }
    }
    kt_svg_end(f);
}

/* ---------------------------------------------------------------- the page */

static void row2(FILE *f, const char *what, const char *key, const char *fmt, double v, const char *unit)
{
    fputs("<tr><td>", f);
    kt_html_text(f, what);
    fputs("</td><td class=\"n\">", f);
    num(f, key, fmt, v);
    fprintf(f, " %s</td></tr>\n", unit);
}

static void fit_row(FILE *f, const char *what, const char *key, const kt_surffit *s, double n)
{
    char k[96];
    fputs("<tr><td>", f);
    kt_html_text(f, what);
    fputs("</td><td class=\"n\">", f);
    snprintf(k, sizeof k, "%s.r_steep_mm", key), num(f, k, "%.5f", s->r_steep);
    fputs(" / ", f);
    snprintf(k, sizeof k, "%s.r_flat_mm", key), num(f, k, "%.5f", s->r_flat);
    fprintf(f, " mm (%.2f / %.2f D)</td><td class=\"n\">", n / s->r_steep, n / s->r_flat);
    snprintf(k, sizeof k, "%s.axis_deg", key), num(f, k, "%.3f", s->axis);
    fputs("&deg;</td><td class=\"n\">", f);
    snprintf(k, sizeof k, "%s.Q", key), num(f, k, "%.4f", s->conic);
    fputs("</td><td class=\"n\">", f);
    snprintf(k, sizeof k, "%s.rms_um", key), num(f, k, "%.3f", 1000 * s->rms);
    fputs(" / ", f);
    snprintf(k, sizeof k, "%s.max_um", key), num(f, k, "%.3f", 1000 * s->max_resid);
    fputs(" um</td><td class=\"n\">", f);
    snprintf(k, sizeof k, "%s.cells", key), num(f, k, "%.0f", s->npts);
    fputs("</td></tr>\n", f);
}

static int scene_text(FILE *f, const char *outdir)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/scene.yaml", outdir);
    FILE *in = fopen(path, "r");
    if (!in) return -1;
    fputs("<pre>", f);
    char line[1024];
    while (fgets(line, sizeof line, in)) kt_html_text(f, line);
    fputs("</pre>\n", f);
    fclose(in);
    return 0;
}

static void page(FILE *f, const kt_lri_answer *a, const kt_lriplan_opts *o, const char *report)
{
    const kt_patient *p = &a->p;
    const kt_lri_family *fc = &a->fam[a->chosen];
    kt_lri_arc arcs[2];
    int narc = kt_lri_arcs(a, arcs);
    kt_astig kpost, tpost;
    kt_lri_post(a, &kpost, &tpost);
    const char *tkind = p->target_kind == KT_TARGET_TOTAL ? "total corneal" : "keratometric";
    char title[256];
    snprintf(title, sizeof title, "LRI plan: %s (%s)", p->name, p->eye == KT_EYE_OS ? "OS" : "OD");
    kt_html_begin(f, title, CSS);
    fputs("<header><h1>Limbal relaxing incisions: the plan for ", f);
    text_key(f, "patient.name", p->name);
    fputs("</h1><p>", f);
    text_key(f, "patient.eye", p->eye == KT_EYE_OS ? "OS" : "OD");
    fprintf(f, " (%s eye), ", p->eye == KT_EYE_OS ? "left" : "right");
    num(f, "patient.age", "%g", p->age);
    fputs(" years; lri-plan ", f);
    text_key(f, "version", KT_VERSION);
    fprintf(f, "%s. A simulation's answer (keratome's model), to be weighed by the surgeon.</p></header>\n<main>\n",
            o->fast ? ", --fast (coarse mesh: the arcs' effect about 10% under the default mesh's)" : "");
    int ok = fc->pred[fc->best].mag <= p->target_residual;
    fprintf(f, "<p class=\"verdict%s\">", ok ? " ok" : "");
    if (narc == 0) fprintf(f, "No arc: none lowers the %s astigmatism.", tkind);
    else if (narc == 1) fprintf(f, "One arc of %.0f&deg; at the %.1f mm zone, %.0f um deep.", arcs[0].arc, p->zone, 1000 * a->blade);
    else if (fc->unequal)
        fprintf(f, "A pair of unequal arcs, %.0f&deg; and %.1f&deg;, at the %.1f mm zone, %.0f um deep.", arcs[0].arc, arcs[1].arc,
                p->zone, 1000 * a->blade);
    else fprintf(f, "A pair of arcs of %.0f&deg; each at the %.1f mm zone, %.0f um deep.", arcs[0].arc, p->zone, 1000 * a->blade);
    fprintf(f, " Predicted %s residual %.2f D: %s the %.2f D target.</p>\n", tkind, fc->pred[fc->best].mag,
            ok ? "reaches" : "does NOT reach", p->target_residual);

    fputs("<div class=\"cards\">", f);
    fputs("<div class=\"card\"><span class=\"l\">incisions</span><b>", f);
    text_key(f, "plan.incisions", fc->name);
    fputs("</b></div><div class=\"card\"><span class=\"l\">blade depth</span><b>", f);
    num(f, "plan.blade_um", "%.0f", 1000 * a->blade);
    fputs(" um</b></div><div class=\"card\"><span class=\"l\">zone (optical-zone diameter)</span><b>", f);
    num(f, "plan.zone_mm", "%.2f", p->zone);
    fputs(" mm</b></div><div class=\"card\"><span class=\"l\">predicted residual (target kind)</span><b>", f);
    num(f, "plan.predicted_residual_D", "%.3f", fc->pred[fc->best].mag);
    fputs(" D @ ", f);
    num(f, "plan.predicted_residual_axis_deg", "%.1f", fc->pred[fc->best].axis);
    fputs("&deg;</b></div></div>\n", f);

    fputs("<h2>1. The eye, as the surgeon sees it</h2>\n<div class=\"row\">\n<figure style=\"flex:0 1 520px\">", f);
    eye_svg(f, a, arcs, narc);
    fprintf(f, "<figcaption>The %s eye from the front, superior up, as the examiner faces the patient (TABO: 0&deg; at "
               "the examiner's right, angles counter-clockwise); a surgeon seated at the head or temporally sees it turned "
               "by 180&deg; or 90&deg;, the labels turning with it. S superior, I inferior, N nasal, T temporal (%s). Inner numbers: TABO degrees; outer: "
               "clock hours (12 superior, 3 at the examiner's right). Red arcs: the relaxing incisions with their end "
               "points; blue: the main incision (its width at the limbus); orange dashed: the steep meridian; grey dashed "
               "circle: the incision zone. The bar is 5 mm.</figcaption></figure>\n",
            p->eye == KT_EYE_OS ? "left" : "right",
            p->eye == KT_EYE_OS ? "a left eye: nasal at the examiner's left, 180&deg;" : "a right eye: nasal at the examiner's right, 0&deg;");
    fputs("<div style=\"flex:1 1 420px\"><table>\n<tr><th>arc</th><th>centre</th><th>extent</th><th>from</th><th>to</th>"
          "<th>chord at the zone</th><th>arc length</th></tr>\n", f);
    for (int i = 0; i < narc; i++) {
        char k[64];
        fprintf(f, "<tr><td>%d</td><td class=\"n\">", i + 1);
        snprintf(k, sizeof k, "plan.arcs.%d.centre_deg", i), num(f, k, "%.2f", arcs[i].centre);
        fputs("&deg;</td><td class=\"n\">", f);
        snprintf(k, sizeof k, "plan.arcs.%d.arc_deg", i), num(f, k, "%.1f", arcs[i].arc);
        fputs("&deg;</td><td class=\"n\">", f);
        snprintf(k, sizeof k, "plan.arcs.%d.from_deg", i), num(f, k, "%.1f", arcs[i].from);
        fputs("&deg; (", f);
        snprintf(k, sizeof k, "plan.arcs.%d.from_clock", i), text_key(f, k, arcs[i].from_clock);
        fputs(")</td><td class=\"n\">", f);
        snprintf(k, sizeof k, "plan.arcs.%d.to_deg", i), num(f, k, "%.1f", arcs[i].to);
        fputs("&deg; (", f);
        snprintf(k, sizeof k, "plan.arcs.%d.to_clock", i), text_key(f, k, arcs[i].to_clock);
        fputs(")</td><td class=\"n\">", f);
        snprintf(k, sizeof k, "plan.arcs.%d.chord_mm", i), num(f, k, "%.2f", arcs[i].chord);
        fprintf(f, " mm</td><td class=\"n\">%.2f mm</td></tr>\n", arcs[i].arc * DEG * 0.5 * p->zone);
    }
    fputs("</table>\n<p class=\"note\">End points run counter-clockwise from <i>from</i> to <i>to</i>; clock positions "
          "h:mm (12:30 is half-way between 12 and 1). The blade depth is ", f);
    fprintf(f, "%.0f%% of the pachymetry at the zone (", 100 * a->blade / a->t_zone);
    num(f, "patient.thickness_at_zone_um", "%.1f", 1000 * a->t_zone);
    fputs(" um).</p>\n<table>\n<tr><th>astigmatism</th><th>keratometric</th><th>total corneal</th></tr>\n<tr><td>pre-op", f);
    fputs(a->main_vec.mag > 0 ? " (with the main incision's SIA)" : "", f);
    fputs("</td><td class=\"n\">", f);
    num(f, "pre_op.keratometric_D", "%.3f", a->pre_kerato.mag);
    fputs(" D @ ", f);
    num(f, "pre_op.keratometric_axis_deg", "%.1f", a->pre_kerato.axis);
    fputs("&deg;</td><td class=\"n\">", f);
    num(f, "pre_op.total_D", "%.3f", a->pre_total.mag);
    fputs(" D @ ", f);
    num(f, "pre_op.total_axis_deg", "%.1f", a->pre_total.axis);
    fputs("&deg;</td></tr>\n<tr><td>predicted post-op</td><td class=\"n\">", f);
    num(f, "plan.post_op_keratometric_D", "%.3f", kpost.mag);
    fputs(" D @ ", f);
    num(f, "plan.post_op_keratometric_axis_deg", "%.1f", kpost.axis);
    fputs("&deg;</td><td class=\"n\">", f);
    num(f, "plan.post_op_total_D", "%.3f", tpost.mag);
    fputs(" D @ ", f);
    num(f, "plan.post_op_total_axis_deg", "%.1f", tpost.axis);
    fprintf(f, "&deg;</td></tr>\n</table>\n<p class=\"note\">Target: %s residual at most ", tkind);
    num(f, "target.residual_D", "%.2f", p->target_residual);
    fputs(" D.</p>", f);
    kt_lri_band_html(a, f);
    fputs("</div>\n</div>\n", f);

    fputs("<h2>2. SIA and residual against arc</h2>\n<div class=\"row\">\n<figure>", f);
    curve_svg(f, a, 0);
    fputs("<figcaption>The simulated surgically induced astigmatism (keratometric, double-angle difference from the "
          "pre-operative eye) of each candidate family as the arc opens centre-out, one step per point; the red circle "
          "marks the chosen plan.</figcaption></figure>\n<figure>", f);
    curve_svg(f, a, 1);
    fprintf(f, "<figcaption>The predicted %s residual (pre-operative astigmatism, simulated arcs%s by double-angle vector "
               "sum); green dashed: the target.</figcaption></figure>\n</div>\n",
            tkind, a->main_vec.mag > 0 ? " and the main incision's SIA" : "");
    fputs("<table>\n<tr><th>candidate</th><th>centred on</th><th>opposite arc / arc</th><th>best arc</th><th>residual</th></tr>\n", f);
    for (int i = 0; i < a->nfam; i++) {
        const kt_lri_family *c = &a->fam[i];
        char k[64];
        fprintf(f, "<tr><td>%s%s</td><td class=\"n\">%.0f&deg;</td><td class=\"n\">", c->name, i == a->chosen ? " (chosen)" : "",
                c->meridian);
        snprintf(k, sizeof k, "candidates.%d.ratio", i), num(f, k, "%.4f", c->ratio);
        fputs("</td><td class=\"n\">", f);
        snprintf(k, sizeof k, "candidates.%d.best_arc_deg", i), num(f, k, "%.1f", c->arc[c->best]);
        if (c->paired) {
            fputs("&deg; + ", f);
            snprintf(k, sizeof k, "candidates.%d.best_arc_opposite_deg", i), num(f, k, "%.1f", c->arc_opp[c->best]);
        }
        fputs("&deg;</td><td class=\"n\">", f);
        snprintf(k, sizeof k, "candidates.%d.best_residual_D", i), num(f, k, "%.3f", c->pred[c->best].mag);
        fputs(" D</td></tr>\n", f);
    }
    fputs("</table>\n", f);
    for (int k = 0; k < 3; k++)
        if (a->clear_note[k][0]) {
            fputs("<p class=\"note\">Clearance: ", f);
            kt_html_text(f, a->clear_note[k]);
            fputs(".</p>\n", f);
        }

    fputs("<h2>3. Inputs and fitted surfaces</h2>\n<div class=\"row\"><div style=\"flex:1 1 420px\"><table>\n", f);
    fputs("<tr><th>input</th><th>value</th></tr>\n", f);
    fputs("<tr><td>patient file</td><td>", f);
    kt_html_text(f, p->path);
    fputs("</td></tr>\n", f);
    row2(f, "K steep", "patient.anterior.k_steep_D", "%.3f", kt_patient_k(p->ant.r_steep), "D");
    row2(f, "K flat", "patient.anterior.k_flat_D", "%.3f", kt_patient_k(p->ant.r_flat), "D");
    row2(f, "steep axis", "patient.anterior.steep_axis_deg", "%.2f", p->ant.axis, "deg");
    row2(f, "posterior K steep", "patient.posterior.k_steep_D", "%.3f", kt_patient_post_k(p->post.r_steep), "D");
    row2(f, "posterior K flat", "patient.posterior.k_flat_D", "%.3f", kt_patient_post_k(p->post.r_flat), "D");
    row2(f, "posterior steep axis", "patient.posterior.steep_axis_deg", "%.2f", p->post.axis, "deg");
    fprintf(f, "<tr><td>posterior from</td><td>%s</td></tr>\n",
            p->post.source == KT_SOURCE_DEFAULT ? "population default (Koch et al. 2012)"
            : p->post.source == KT_SOURCE_PENTACAM ? "the Pentacam export" : "the posterior keratometry given");
    row2(f, "central thickness", "patient.central_thickness_um", "%.1f", 1000 * p->t_central, "um");
    row2(f, "white-to-white", "patient.white_to_white_mm", "%.2f", p->wtw, "mm");
    row2(f, "IOP", "patient.iop_mmHg", "%.2f", p->iop / 133.322387415e-6, "mmHg");
    if (p->main_present) {
        fprintf(f, "<tr><td>main incision</td><td>%.1f mm %s at ", p->main_width,
                p->main_kind == KT_MAIN_LIMBAL ? "limbal" : "clear corneal");
        num(f, "main_incision.meridian_deg", "%.1f", p->main_meridian);
        fprintf(f, "&deg;; %s", p->main_simulate ? "simulate: not in this model yet, its SIA left out" : "the surgeon's SIA ");
        if (!p->main_simulate) {
            num(f, "main_incision.sia_added_D", "%.3f", a->main_vec.mag);
            fputs(" D @ ", f);
            num(f, "main_incision.sia_axis_deg", "%.1f", a->main_vec.axis);
            fputs("&deg; added", f);
        }
        fputs("</td></tr>\n", f);
    }
    fputs("</table></div>\n", f);
    if (a->fitted) {
        fputs("<div style=\"flex:1 1 520px\"><table>\n<tr><th>Pentacam fit</th><th>radii (K)</th><th>steep axis</th><th>Q</th>"
              "<th>residual rms / max</th><th>cells</th></tr>\n", f);
        fit_row(f, "anterior", "fit.anterior", &a->fit_ant, 337.5);
        if (a->fit_post_ok) fit_row(f, "posterior", "fit.posterior", &a->fit_post, -KT_PATIENT_N_POST);
        fputs("</table>\n", f);
        if (a->fit_pachy_ok) {
            fputs("<p class=\"note\">Pachymetry: t(r) = ", f);
            num(f, "fit.pachymetry.t0_um", "%.2f", 1000 * a->fit_pachy.t0);
            fputs(" um + ", f);
            num(f, "fit.pachymetry.t2_um_per_mm2", "%.4f", 1000 * a->fit_pachy.t2);
            fputs(" r&sup2; + ", f);
            num(f, "fit.pachymetry.t4_um_per_mm4", "%.5f", 1000 * a->fit_pachy.t4);
            fputs(" r&#8308;, residual rms ", f);
            num(f, "fit.pachymetry.rms_um", "%.3f", 1000 * a->fit_pachy.rms);
            fputs(" um.</p>\n", f);
        }
        if (a->halves_ok) {
            fputs("<p class=\"note\">Half-meridians (axial power over the 3 mm zone): ", f);
            num(f, "halves.astig_at_axis_D", "%.3f", a->half_a);
            fprintf(f, " D of astigmatism at %.0f&deg;, ", p->ant.axis);
            num(f, "halves.astig_opposite_D", "%.3f", a->half_b);
            fprintf(f, " D at %.0f&deg;; ratio ", fmod(p->ant.axis + 180, 360));
            num(f, "halves.ratio", "%.4f", a->ratio);
            fprintf(f, " (%s).</p>\n", a->ratio < KT_LRIPLAN_SYMMETRIC ? "asymmetric: unequal pairs tried, the longer arc on the steeper half"
                                                                       : "symmetric");
        }
        fputs("</div>\n", f);
    }
    fputs("</div>\n", f);

    fputs("<h2>4. Provenance</h2>\n<table>\n", f);
    fputs("<tr><td>tool</td><td>lri-plan (keratome) ", f);
    kt_html_text(f, KT_VERSION);
    fputs("</td></tr>\n<tr><td>mesh</td><td>eye.msh, content hash ", f);
    char hash[32];
    snprintf(hash, sizeof hash, "%016llx", (unsigned long long)a->mesh_hash);
    text_key(f, "provenance.mesh_hash", hash);
    fputs(", ", f);
    num(f, "provenance.mesh_nodes", "%.0f", a->nodes);
    fprintf(f, " nodes%s</td></tr>\n", o->fast ? " (--fast)" : "");
    fputs("<tr><td>step</td><td>", f);
    num(f, "provenance.step_deg", "%g", o->step);
    fprintf(f, " deg per step, centre-out; meshing %.1f s, solves %.1f s</td></tr>\n", a->mesh_seconds, a->solve_seconds);
    fputs("<tr><td>the chosen run's teaching report</td><td>", f);
    if (report) {
        fputs("<a href=\"", f);
        kt_html_text(f, report);
        fputs("\">", f);
        kt_html_text(f, report);
        fputs("</a> (what the cut does to the cornea, step by step)", f);
    } else fputs("none (no arc)", f);
    fputs("</td></tr>\n</table>\n<p class=\"note\">The scene written (scene.yaml), from which the mesh was made:</p>\n", f);
    if (scene_text(f, o->outdir) != 0) fputs("<p class=\"note\">(scene.yaml could not be read back)</p>\n", f);
    fputs("</main>\n", f);
    kt_html_end(f);
}

int kt_lri_write_html(const kt_lri_answer *a, const kt_lriplan_opts *o, const char *report, const char *path, kt_err *e)
{
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    page(out.f, a, o, report);
    if (kt_out_failed(&out, e)) return kt_out_abort(&out), e->code;
    return kt_out_commit(&out, e);
}
