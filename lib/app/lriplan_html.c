/* lriplan_html.c: PLAN_DIR/plan.html, the plan sheet a surgeon takes to the operating room
 * (lri-plan(1), FILES): one self-contained page (inline CSS and SVG, no script, no network),
 * the eye from the surgeon's view with the main incision and each arc, the numbers to mark and
 * set, the predicted astigmatism, the SIA curve with the chosen point, the inputs and fits, the
 * provenance and a link to the chosen run's teaching report. Every number that plan.json also
 * holds is written inside an element with data-key="<json path>" so a second reader can check
 * the two against each other (tests/lriplan_sheet.sh). */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#define _POSIX_C_SOURCE 200809L
#include "html.h"
#include "lp_family.h"
#include "lriplan_eye.h"
#include "lriplan_int.h"
#include "scene_write.h"
#include "svg.h"
#include "units.h"


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


/* ---------------------------------------------------------------- the curves */

static void curve_svg(FILE *f, const kt_lp_answer *a, int residual)
{
    const double W = 560, H = 330;
    kt_svg_plot pl = {64, 18, W - 84, H - 70, 0, 0, 0, 0};
    double ymax = 0, xmax = 0;
    for (int i = 0; i < a->fam.n; i++)
        for (int k = 0; a->run.r[i].ran && k <= a->run.r[i].nstep; k++) {
            double y = residual ? a->choice.pred[i][k].mag : kt_lp_sia(&a->run.r[i], k);
            if (isfinite(y)) ymax = fmax(ymax, y);
            xmax = fmax(xmax, a->run.r[i].arc[k]);
        }
    if (residual) ymax = fmax(ymax, a->eye.p.target_residual);
    pl.x1 = xmax > 0 ? xmax : 1, pl.y1 = ymax > 0 ? ymax : 1;
    kt_svg_nice_range(&pl.x0, &pl.x1, 6);
    kt_svg_nice_range(&pl.y0, &pl.y1, 5);
    pl.y0 = 0;
    kt_svg_begin(f, W, H, residual ? "predicted residual astigmatism against arc" : "SIA against arc");
    kt_svg_axes(f, &pl, "%g", "%.1f", "arc (deg; an unequal pair: its longer arc)", residual ? "predicted residual (D)" : "SIA (D)");
    if (residual)
        kt_svg_line(f, kt_svg_px(&pl, pl.x0), kt_svg_py(&pl, a->eye.p.target_residual), kt_svg_px(&pl, pl.x1),
                    kt_svg_py(&pl, a->eye.p.target_residual), "target");
    for (int i = 0; i < a->fam.n; i++) {
        const kt_lp_run *c = &a->run.r[i];
        if (!c->ran) continue;
        double y[KT_LP_MAXSTEP + 1];
        int b = a->choice.best[i];
        for (int k = 0; k <= c->nstep; k++) y[k] = residual ? a->choice.pred[i][k].mag : kt_lp_sia(c, k);
        char cls[16];
        snprintf(cls, sizeof cls, "s%d", i + 1);
        kt_svg_series(f, &pl, c->arc, y, c->nstep + 1, cls);
        kt_svg_text(f, pl.x + 8, pl.y + 16 + 15 * i, "start", "lbl", "%s%s", a->fam.f[i].name,
                    i == a->choice.chosen ? " (chosen)" : "");
        fprintf(f, "<g class=\"%s\"><polyline points=\"%.1f,%.1f %.1f,%.1f\"/></g>\n", cls, pl.x + 120, pl.y + 12 + 15 * i,
                pl.x + 145, pl.y + 12 + 15 * i);
        if (i == a->choice.chosen) {
            double yc = residual ? a->choice.pred[i][b].mag : kt_lp_sia(c, b);
            kt_svg_circle(f, kt_svg_px(&pl, c->arc[b]), kt_svg_py(&pl, yc), 9, "chosen");
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

/* The scene as scene.yaml holds it (the same writer, into memory). */
static int scene_text(FILE *f, const kt_lp_answer *a)
{
    char *buf = NULL;
    size_t n = 0;
    FILE *m = open_memstream(&buf, &n);
    kt_err e = {0};
    if (!m) return -1;
    int rc = kt_scene_write_eye(m, &a->scene.s, NULL, &e);
    fclose(m);
    if (rc == KT_OK) {
        fputs("<pre>", f);
        kt_html_text(f, buf);
        fputs("</pre>\n", f);
    }
    free(buf);
    return rc ? -1 : 0;
}

/* The band's paragraph (lri-plan(1), BAND). */
static void band_html(const kt_lp_answer *a, FILE *f)
{
    const kt_lp_bands *b = &a->band;
    if (!b->on) return;
    fprintf(f, "<p class=\"note band\">Band (the prediction as a 2-D distribution; tissue quantities: ");
    for (int q = 0; q < a->run.nq; q++) fprintf(f, "%s%s", q ? ", " : "", kt_uq_name(a->run.q[q]));
    fprintf(f, "): predicted residual 90%% interval <b><span data-key=\"band.predicted_residual.lo90_D\">%.2f</span>&ndash;"
               "<span data-key=\"band.predicted_residual.hi90_D\">%.2f</span> D</b> (the SIA's own sd at this arc %.2f D); "
               "post-operative keratometric %.2f&ndash;%.2f D, total corneal %.2f&ndash;%.2f D.",
            b->residual.lo, b->residual.hi, b->sia_sd, b->post_kerato.lo, b->post_kerato.hi, b->post_total.lo, b->post_total.hi);
    if (a->run.left[0]) fprintf(f, " Left out (no derivative): %s.", a->run.left);
    double cv = a->scene.s.unc.nontissue_cv;
    if (cv > 0)
        fprintf(f, " With the tissue's, the eye-to-eye spread that no tissue quantity carries (healing, the blade, "
                   "keratometry): a coefficient of variation of %.2f of the SIA along itself, from the clinical "
                   "studies' SDs (docs/validation.md).</p>\n", cv);
    else
        fprintf(f, " The surgeon, the blade and healing's eye-to-eye spread are not in it (uncertainty.nontissue_cv 0).</p>\n");
}

/* An astigmatism as the sheet prints it: 0.01 D @ 1 deg, each number tied to plan.json. */
static void astig(FILE *f, const char *key, kt_astig v)
{
    char k[128];
    snprintf(k, sizeof k, "%s_D", key), num(f, k, "%.2f", v.mag);
    fputs(" D @ ", f);
    snprintf(k, sizeof k, "%s_axis_deg", key), num(f, k, "%.0f", kt_lp_axis_shown(v.axis, 0));
    fputs("&deg;", f);
}

/* The class of a steep axis (deg): with the rule 60-120, against 0-30 and 150-180, else oblique. */
static const char *axis_class(double axis)
{
    double x = fmod(fmod(axis, 180) + 180, 180);
    return x >= 60 && x <= 120 ? "with-the-rule" : x <= 30 || x >= 150 ? "against-the-rule" : "oblique";
}

/* The angle between two axes, deg [0, 90]. */
static double axis_gap(double a, double b)
{
    double d = fmod(fabs(a - b), 180);
    return d > 90 ? 180 - d : d;
}

/* The flip of a residual's axis, in words, when it lies more than 45 deg from the pre-operative
 * axis (the residual's projection on the pre-operative astigmatism is then negative: an
 * over-correction along the original meridian). */
static void flip_words(FILE *f, const char *kind, kt_astig pre, kt_astig res, int narc)
{
    if (!(res.mag >= 0.005) || !(pre.mag >= 0.005) || !(axis_gap(pre.axis, res.axis) > 45)) return;
    const char *to = axis_class(res.axis);
    int same = strcmp(to, axis_class(pre.axis)) == 0;
    fprintf(f, "<p class=\"flip\">%s the %s residual turns to %s%s (%.0f&deg;, %.0f&deg; from the pre-operative "
               "%.0f&deg;).</p>\n",
            narc ? "The plan over-corrects on purpose:" : "The main incision alone over-corrects:", kind,
            same ? "the other " : "", to, kt_lp_axis_shown(res.axis, 0), axis_gap(pre.axis, res.axis),
            kt_lp_axis_shown(pre.axis, 0));
}

/* The patient block: who, which eye (large), the plan's date, what the prediction is of. */
static void patient_block(FILE *f, const kt_lp_answer *a, const kt_lriplan_opts *o, const kt_lri_files *fl)
{
    const kt_patient *p = &a->eye.p;
    const kt_wound_scene *w = &a->scene.s.wound;
    fputs("<section class=\"patient\"><div class=\"opeye\">", f);
    text_key(f, "patient.eye", p->eye == KT_EYE_OS ? "OS" : "OD");
    fprintf(f, "<small>%s eye</small></div>\n<table class=\"who\">\n<tr><th>patient</th><td>", p->eye == KT_EYE_OS ? "LEFT" : "RIGHT");
    text_key(f, "patient.name", p->name);
    fputs("</td></tr>\n", f);
    if (p->id[0]) fputs("<tr><th>ID</th><td>", f), text_key(f, "patient.id", p->id), fputs("</td></tr>\n", f);
    if (p->dob[0])
        fputs("<tr><th>date of birth</th><td>", f), text_key(f, "patient.date_of_birth", p->dob), fputs("</td></tr>\n", f);
    fputs("<tr><th>age</th><td>", f);
    num(f, "patient.age", "%g", p->age);
    fputs(" years</td></tr>\n", f);
    if (p->surgeon[0]) fputs("<tr><th>surgeon</th><td>", f), text_key(f, "patient.surgeon", p->surgeon), fputs("</td></tr>\n", f);
    fputs("<tr><th>date of the plan</th><td>", f);
    text_key(f, "provenance.date", fl->date);
    fputs("</td></tr>\n</table>\n<p class=\"wound\">", f);
    if (w->state == KT_WOUND_HEALED && isfinite(w->months))
        fprintf(f, "Predicted at %g months after surgery (healed wound; identified on published outcomes, validated: see "
                   "docs/validation.md).", w->months);
    else if (w->state == KT_WOUND_HEALED)
        fputs("Predicted for the fully healed wound (healed wound, its asymptotic scar; identified on published outcomes, "
              "validated: see docs/validation.md).", f);
    else fputs("Predicted at the instant of cutting (immediate wound).", f);
    fprintf(f, "</p></section>\n<p class=\"note\">lri-plan %s%s. A simulation's answer (keratome's model), to be weighed by "
               "the surgeon.</p>\n",
            KT_VERSION, o->fast ? ", --fast (coarse mesh: the arcs' effect about 10% under the default mesh's)" : "");
}

/* Marking with a degree gauge (Mendez ring): per arc, its centre meridian, then its end points
 * in the order marked (clockwise as the surgeon sees the eye). */
static void marking(FILE *f, const kt_patient *p, double blade, const kt_lp_arc *arcs, int narc)
{
    if (narc == 0) return;
    fputs("<h3>Marking with a degree gauge (Mendez ring)</h3>\n<ol class=\"mark\">\n<li>Patient sitting upright: mark "
          "the limbus at 0&deg; and 180&deg; (the horizontal). Under the microscope, set the gauge's 0&deg;&ndash;180&deg; "
          "on those marks.</li>\n",
          f);
    for (int i = 0; i < narc; i++) {
        const kt_lp_arc *q = &arcs[i];
        double c = kt_lp_deg_mark(q->centre), fr = kt_lp_deg_mark(q->from), to = kt_lp_deg_mark(q->to);
        fprintf(f, "<li>Arc %d, <b>%.0f&deg;</b> long: its centre at <b>%.0f&deg;</b>; mark first <b>%.0f&deg;</b> (%s), "
                   "then <b>%.0f&deg;</b> (%s), clockwise.",
                i + 1, q->arc, c, fr, q->from_clock, to, q->to_clock);
        if (c >= 180 || fr >= 180 || to >= 180)
            fprintf(f, " On a gauge numbered 0&ndash;180&deg; on each half, read %.0f&deg;, %.0f&deg; and %.0f&deg; on the "
                       "inferior half.",
                    fmod(c, 180), fmod(fr, 180), fmod(to, 180));
        fputs("</li>\n", f);
    }
    fprintf(f, "<li>Cut at the %.1f mm zone, %.0f um deep, between the two marks of each arc.</li>\n</ol>\n", p->zone, 1000 * blade);
}

/* The astigmatism table: the main incision's SIA, the pre-operative astigmatism without and
 * with it, the predicted residuals (the target's kind in bold), and each residual's flip. */
static void astig_table(FILE *f, const kt_lp_answer *a, int narc)
{
    const kt_patient *p = &a->eye.p;
    const kt_lp_choice *c = &a->choice;
    int tot = p->target_kind == KT_TARGET_TOTAL;
    kt_astig kpost, tpost;
    kt_lp_post(a, &kpost, &tpost);
    fprintf(f, "<table class=\"astig\">\n<tr><th>astigmatism</th><th>%skeratometric (what the biometer reads)%s</th>"
               "<th>%stotal corneal%s</th></tr>\n",
            tot ? "" : "<b>", tot ? "" : " &mdash; the target</b>", tot ? "<b>" : "", tot ? " &mdash; the target</b>" : "");
    if (p->main_present) {
        fprintf(f, "<tr><td>the main incision's SIA (%s)</td><td class=\"n\">",
                p->main_simulate ? "simulated: its tunnel cut before the arcs" : "the surgeon's vector, as given");
        astig(f, "main_incision.sia_keratometric", c->sia_kerato);
        fputs("</td><td class=\"n\">", f);
        astig(f, "main_incision.sia_total", c->sia_total);
        fputs("</td></tr>\n", f);
    }
    fputs("<tr><td>pre-op, without the main incision</td><td class=\"n\">", f);
    astig(f, "pre_op.without_main_incision.keratometric", c->bare_kerato);
    fputs("</td><td class=\"n\">", f);
    astig(f, "pre_op.without_main_incision.total", c->bare_total);
    fputs("</td></tr>\n<tr><td>pre-op, with the main incision (what the arcs treat)</td><td class=\"n\">", f);
    astig(f, "pre_op.with_main_incision.keratometric", c->with_kerato);
    fputs("</td><td class=\"n\">", f);
    astig(f, "pre_op.with_main_incision.total", c->with_total);
    fprintf(f, "</td></tr>\n<tr><td>predicted residual</td><td class=\"n\">%s", tot ? "" : "<b>");
    astig(f, "plan.post_op_keratometric", kpost);
    fprintf(f, "%s</td><td class=\"n\">%s", tot ? "" : "</b>", tot ? "<b>" : "");
    astig(f, "plan.post_op_total", tpost);
    fprintf(f, "%s</td></tr>\n</table>\n", tot ? "</b>" : "");
    flip_words(f, "keratometric", c->bare_kerato, kpost, narc);
    flip_words(f, "total corneal", c->bare_total, tpost, narc);
    fprintf(f, "<p class=\"note\">Target: the <b>%s</b> residual at most ", tot ? "total corneal" : "keratometric");
    num(f, "target.residual_D", "%.2f", p->target_residual);
    fputs(" D. Dioptres to 0.01 D, axes to 1&deg; (TABO); the astigmatism treated (above) also in the 0.25 D steps a surgeon marks.</p>", f);
}

/* The arcs' table: centre, extent, the end points in the order marked, chord, length. */
static void arcs_table(FILE *f, const kt_lp_answer *a, const kt_lp_arc *arcs, int narc)
{
    const kt_patient *p = &a->eye.p;
    fputs("<table>\n<tr><th>arc</th><th>centre</th><th>extent</th><th>mark first</th><th>then</th>"
          "<th>chord at the zone</th><th>arc length</th></tr>\n", f);
    for (int i = 0; i < narc; i++) {
        char k[64];
        fprintf(f, "<tr><td>%d</td><td class=\"n\">", i + 1);
        snprintf(k, sizeof k, "plan.arcs.%d.centre_deg", i), num(f, k, "%.0f", kt_lp_deg_mark(arcs[i].centre));
        fputs("&deg;</td><td class=\"n\">", f);
        snprintf(k, sizeof k, "plan.arcs.%d.arc_deg", i), num(f, k, "%.0f", arcs[i].arc);
        fputs("&deg;</td><td class=\"n\">", f);
        snprintf(k, sizeof k, "plan.arcs.%d.from_deg", i), num(f, k, "%.0f", kt_lp_deg_mark(arcs[i].from));
        fputs("&deg; (", f);
        snprintf(k, sizeof k, "plan.arcs.%d.from_clock", i), text_key(f, k, arcs[i].from_clock);
        fputs(")</td><td class=\"n\">", f);
        snprintf(k, sizeof k, "plan.arcs.%d.to_deg", i), num(f, k, "%.0f", kt_lp_deg_mark(arcs[i].to));
        fputs("&deg; (", f);
        snprintf(k, sizeof k, "plan.arcs.%d.to_clock", i), text_key(f, k, arcs[i].to_clock);
        fputs(")</td><td class=\"n\">", f);
        snprintf(k, sizeof k, "plan.arcs.%d.chord_mm", i), num(f, k, "%.2f", arcs[i].chord);
        fprintf(f, " mm</td><td class=\"n\">%.2f mm</td></tr>\n", arcs[i].arc * DEG * 0.5 * p->zone);
    }
    fputs("</table>\n<p class=\"note\">End points in the order they are marked: clockwise as the surgeon sees the eye, "
          "from the first to the second (a turn of the view keeps clockwise clockwise). Clock positions h:mm (12 superior; "
          "12:30 is half-way between 12 and 1). The blade depth is ",
          f);
    fprintf(f, "%.0f%% of the pachymetry at the zone (", 100 * a->eye.blade / a->eye.t_zone);
    num(f, "patient.thickness_at_zone_um", "%.0f", 1000 * a->eye.t_zone);
    fputs(" um).</p>\n", f);
}

/* The verdict and the cards: what is cut, in the steps a surgeon sets and marks. */
static void verdict(FILE *f, const kt_lp_answer *a, const kt_lp_arc *arcs, int narc)
{
    const kt_patient *p = &a->eye.p;
    int ci = a->choice.chosen, cb = a->choice.best[ci];
    const kt_lp_family *fc = &a->fam.f[ci];
    const kt_astig *cres = &a->choice.pred[ci][cb];
    const char *tkind = p->target_kind == KT_TARGET_TOTAL ? "total corneal" : "keratometric";
    int ok = cres->mag <= p->target_residual;
    fprintf(f, "<p class=\"verdict%s\">", ok ? " ok" : "");
    if (narc == 0) fprintf(f, "No arc: none lowers the %s astigmatism.", tkind);
    else if (narc == 1) fprintf(f, "One arc of %.0f&deg; at the %.1f mm zone, %.0f um deep.", arcs[0].arc, p->zone, 1000 * a->eye.blade);
    else if (fc->unequal)
        fprintf(f, "A pair of unequal arcs, %.0f&deg; and %.0f&deg;, at the %.1f mm zone, %.0f um deep.", arcs[0].arc, arcs[1].arc,
                p->zone, 1000 * a->eye.blade);
    else fprintf(f, "A pair of arcs of %.0f&deg; each at the %.1f mm zone, %.0f um deep.", arcs[0].arc, p->zone, 1000 * a->eye.blade);
    int dg = kt_lp_res_digits(cres->mag, p->target_residual);
    fprintf(f, " Predicted <b>%s</b> residual %.*f D: %s the %.*f D target.</p>\n", tkind, dg, cres->mag,
            ok ? "reaches" : "does NOT reach", dg, p->target_residual);
    fputs("<div class=\"cards\">", f);
    fputs("<div class=\"card\"><span class=\"l\">incisions</span><b>", f);
    text_key(f, "plan.incisions", fc->name);
    fputs("</b></div><div class=\"card\"><span class=\"l\">blade depth</span><b>", f);
    num(f, "plan.blade_um", "%.0f", 1000 * a->eye.blade);
    fputs(" um</b></div><div class=\"card\"><span class=\"l\">zone (optical-zone diameter)</span><b>", f);
    num(f, "plan.zone_mm", "%.1f", p->zone);
    fprintf(f, " mm</b></div><div class=\"card\"><span class=\"l\">treated (with the main incision, %s, 0.25 D steps)</span>"
               "<b>%.2f D @ %.0f&deg;</b></div>",
            tkind, 0.25 * round(4 * (p->target_kind == KT_TARGET_TOTAL ? a->choice.with_total : a->choice.with_kerato).mag),
            kt_lp_axis_shown((p->target_kind == KT_TARGET_TOTAL ? a->choice.with_total : a->choice.with_kerato).axis, 0));
    fprintf(f, "<div class=\"card\"><span class=\"l\">predicted residual (<strong>%s</strong>)</span><b>", tkind);
    num(f, "plan.predicted_residual_D", "%.2f", cres->mag);
    fputs(" D @ ", f);
    num(f, "plan.predicted_residual_axis_deg", "%.0f", kt_lp_axis_shown(cres->axis, 0));
    fputs("&deg;</b></div></div>\n", f);
}

static void page(FILE *f, const kt_lp_answer *a, const kt_lriplan_opts *o, const kt_lri_files *fl)
{
    const kt_patient *p = &a->eye.p;
    const char *report = fl->report;
    kt_lp_arc arcs[2];
    int narc = kt_lp_arcs(a, arcs);
    const char *tkind = p->target_kind == KT_TARGET_TOTAL ? "total corneal" : "keratometric";
    char title[256];
    snprintf(title, sizeof title, "LRI plan: %s (%s)", p->name, p->eye == KT_EYE_OS ? "OS" : "OD");
    kt_html_begin(f, title);
    fputs("<style>.patient{display:flex;gap:24px;align-items:center;background:#fff;padding:10px 16px;border-radius:8px;"
          "margin-top:14px}.opeye{font-size:56px;font-weight:800;color:#8e1b10;line-height:1}.opeye small{display:block;"
          "font-size:18px;font-weight:700}.who th{background:none;text-align:right;color:#5b6670}.wound{font-size:15px;"
          "font-weight:600;max-width:420px}.flip{font-weight:600;color:#8e1b10}.mark li{margin:4px 0}</style>\n",
          f);
    fputs("<header><h1>Limbal relaxing incisions: the plan for ", f);
    kt_html_text(f, p->name);
    fputs("</h1><p>lri-plan ", f);
    text_key(f, "version", KT_VERSION);
    fputs("</p></header>\n<main>\n", f);
    patient_block(f, a, o, fl);
    verdict(f, a, arcs, narc);
    fprintf(f, "<h2>1. The eye, as %s</h2>\n<div class=\"row\">\n<figure style=\"flex:0 1 520px\">",
            o->view == KT_LRI_VIEW_EXAMINER ? "the examiner sees it" : "the surgeon sees it");
    kt_lri_labels lab;
    kt_lri_eye_svg(f, p, arcs, narc, o->view, &lab);
    fprintf(f, "<figcaption>The %s eye from the front as %s (lri-plan --view %s; the default: temporal). TABO degrees "
               "(inner ring) and clock hours (outer; 12 superior) turn with the eye. S superior, I inferior, N nasal, "
               "T temporal. Red arcs: the relaxing incisions, their end points labelled in the order marked "
               "(clockwise); blue: the main incision (its width at the limbus); orange dashed: the steep meridian; grey "
               "dashed circle: the incision zone. The bar is 5 mm.</figcaption></figure>\n",
            p->eye == KT_EYE_OS ? "left" : "right", kt_lri_view_words(o->view), kt_lri_view_name(o->view));
    fputs("<div style=\"flex:1 1 420px\">", f);
    arcs_table(f, a, arcs, narc);
    marking(f, p, a->eye.blade, arcs, narc);
    astig_table(f, a, narc);
    band_html(a, f);
    fputs("</div>\n</div>\n", f);

    fputs("<h2>2. SIA and residual against arc</h2>\n<div class=\"row\">\n<figure>", f);
    curve_svg(f, a, 0);
    fputs("<figcaption>The simulated surgically induced astigmatism (keratometric, double-angle difference from the "
          "pre-operative eye) of each candidate family as the arc opens centre-out, one step per point; the red circle "
          "marks the chosen plan.</figcaption></figure>\n<figure>", f);
    curve_svg(f, a, 1);
    fprintf(f, "<figcaption>The predicted %s residual (pre-operative astigmatism, simulated arcs%s by double-angle vector "
               "sum); green dashed: the target.</figcaption></figure>\n</div>\n",
            tkind, a->choice.main_vec.mag > 0 ? " and the main incision's SIA" : "");
    fputs("<table>\n<tr><th>candidate</th><th>centred on</th><th>opposite arc / arc</th><th>best arc</th><th>residual</th></tr>\n", f);
    for (int i = 0; i < a->fam.n; i++) {
        const kt_lp_family *c = &a->fam.f[i];
        const kt_lp_run *r = &a->run.r[i];
        int b = a->choice.best[i];
        char k[64];
        fprintf(f, "<tr><td>%s%s</td><td class=\"n\">%.0f&deg;</td><td class=\"n\">", c->name,
                i == a->choice.chosen ? " (chosen)" : "", a->trim.t[i].meridian);
        snprintf(k, sizeof k, "candidates.%d.ratio", i), num(f, k, "%.4f", c->ratio);
        fputs("</td><td class=\"n\">", f);
        if (!r->ran) {
            fputs("&ndash;</td><td>", f);
            kt_html_text(f, a->trim.t[i].why);
            fputs("</td></tr>\n", f);
            continue;
        }
        snprintf(k, sizeof k, "candidates.%d.best_arc_deg", i), num(f, k, "%.1f", r->arc[b]);
        if (c->paired) {
            fputs("&deg; + ", f);
            snprintf(k, sizeof k, "candidates.%d.best_arc_opposite_deg", i), num(f, k, "%.1f", r->arc_opp[b]);
        }
        fputs("&deg;</td><td class=\"n\">", f);
        snprintf(k, sizeof k, "candidates.%d.best_residual_D", i), num(f, k, "%.3f", a->choice.pred[i][b].mag);
        fputs(" D</td></tr>\n", f);
    }
    fputs("</table>\n", f);
    for (int i = 0; i < a->fam.n; i++) /* the clearance's trimming (lri-plan(1), CLEARANCE) */
        if (a->trim.t[i].why[0] && a->run.r[i].ran) {
            fputs("<p class=\"note\">Clearance: ", f);
            kt_html_text(f, a->trim.t[i].why);
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
            p->post.source == KT_SOURCE_DEFAULT ? "population default (Eom et al. 2015)"
            : p->post.source == KT_SOURCE_PENTACAM ? "the Pentacam export" : "the posterior keratometry given");
    row2(f, "central thickness", "patient.central_thickness_um", "%.1f", 1000 * p->t_central, "um");
    row2(f, "white-to-white", "patient.white_to_white_mm", "%.2f", p->wtw, "mm");
    row2(f, "IOP", "patient.iop_mmHg", "%.2f", p->iop / KT_MMHG_MPA, "mmHg");
    if (p->main_present) {
        fprintf(f, "<tr><td>main incision</td><td>%.1f mm %s at ", p->main_width,
                p->main_kind == KT_MAIN_LIMBAL ? "limbal" : "clear corneal");
        num(f, "main_incision.meridian_deg", "%.1f", p->main_meridian);
        fprintf(f, "&deg;; %s", p->main_simulate ? "simulated: its tunnel cut before the arcs, its SIA in the prediction (below)" : "the surgeon's SIA ");
        if (!p->main_simulate) {
            num(f, "main_incision.sia_added_D", "%.3f", a->choice.main_vec.mag);
            fputs(" D @ ", f);
            num(f, "main_incision.sia_axis_deg", "%.1f", kt_lp_axis_shown(a->choice.main_vec.axis, 1));
            fputs("&deg; added", f);
        }
        fputs("</td></tr>\n", f);
    }
    fputs("</table></div>\n", f);
    if (a->eye.fitted) {
        fputs("<div style=\"flex:1 1 520px\"><table>\n<tr><th>Pentacam fit</th><th>radii (K)</th><th>steep axis</th><th>Q</th>"
              "<th>residual rms / max</th><th>cells</th></tr>\n", f);
        fit_row(f, "anterior", "fit.anterior", &a->eye.fit_ant, KT_CURV_N_KERATO);
        if (a->eye.fit_post_ok) fit_row(f, "posterior", "fit.posterior", &a->eye.fit_post, -KT_PATIENT_N_POST);
        fputs("</table>\n", f);
        if (a->eye.fit_pachy_ok) {
            fputs("<p class=\"note\">Pachymetry: t(r) = ", f);
            num(f, "fit.pachymetry.t0_um", "%.2f", 1000 * a->eye.fit_pachy.t0);
            fputs(" um + ", f);
            num(f, "fit.pachymetry.t2_um_per_mm2", "%.4f", 1000 * a->eye.fit_pachy.t2);
            fputs(" r&sup2; + ", f);
            num(f, "fit.pachymetry.t4_um_per_mm4", "%.5f", 1000 * a->eye.fit_pachy.t4);
            fputs(" r&#8308;, residual rms ", f);
            num(f, "fit.pachymetry.rms_um", "%.3f", 1000 * a->eye.fit_pachy.rms);
            fputs(" um.</p>\n", f);
        }
        if (a->eye.halves_ok) {
            fputs("<p class=\"note\">Half-meridians (axial power over the 3 mm zone): ", f);
            num(f, "halves.astig_at_axis_D", "%.3f", a->eye.half_a);
            fprintf(f, " D of astigmatism at %.0f&deg;, ", p->ant.axis);
            num(f, "halves.astig_opposite_D", "%.3f", a->eye.half_b);
            fprintf(f, " D at %.0f&deg;; ratio ", fmod(p->ant.axis + 180, 360));
            num(f, "halves.ratio", "%.4f", a->eye.ratio);
            fprintf(f, " (%s).</p>\n", a->eye.ratio < KT_LP_SYMMETRIC ? "asymmetric: unequal pairs tried, the longer arc on the steeper half"
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
    snprintf(hash, sizeof hash, "%016llx", (unsigned long long)a->mesh.hash);
    text_key(f, "provenance.mesh_hash", hash);
    fputs(", ", f);
    num(f, "provenance.mesh_nodes", "%.0f", a->mesh.m.nn);
    fprintf(f, " nodes%s</td></tr>\n", o->fast ? " (--fast)" : "");
    fputs("<tr><td>step</td><td>", f);
    num(f, "provenance.step_deg", "%g", o->step);
    fprintf(f, " deg per step, centre-out; meshing %.1f s, solves %.1f s</td></tr>\n", a->mesh.seconds, a->run.solve_seconds);
    fputs("<tr><td>the chosen run's teaching report</td><td>", f);
    if (report) {
        fputs("<a href=\"", f);
        kt_html_text(f, report);
        fputs("\">", f);
        kt_html_text(f, report);
        fputs("</a> (what the cut does to the cornea, step by step)", f);
    } else fputs("none (no arc)", f);
    fputs("</td></tr>\n</table>\n<p class=\"note\">The scene written (scene.yaml), from which the mesh was made:</p>\n", f);
    if (scene_text(f, a) != 0) fputs("<p class=\"note\">(the scene could not be written)</p>\n", f);
    fputs("</main>\n", f);
    kt_html_end(f);
}

int kt_lri_write_html(const kt_lp_answer *a, const kt_lriplan_opts *o, const kt_lri_files *fl, const char *path,
                      kt_err *e)
{
    kt_out out;
    if (kt_out_open(&out, path, e)) return e->code;
    page(out.f, a, o, fl);
    if (kt_out_failed(&out, e)) return kt_out_abort(&out), e->code;
    return kt_out_commit(&out, e);
}
