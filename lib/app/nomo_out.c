/* nomo_out.c: lri-nomogram's answer as a table or as JSON (nomo_out.h). */
#include "nomo_out.h"

#include <math.h>

#include "json.h"
#include "lp_choose.h"
#include "tsv.h"

/* The table's lines the answer used (lri-nomogram(1)): the lower age's eye, then the higher
 * age's, "r0,r1" for the cases below and above the arc, one number when the same, "-": none. */
static void table_lines(const kt_nomo_answer *a, char *out, size_t n)
{
    size_t k = 0;
    out[0] = '\0';
    for (int g = 0; g < 2 && k < n; g++) {
        int r0 = a->rows[g][0], r1 = a->rows[g][1];
        const char *sep = g ? ";" : "";
        if (r0 && r1 && r0 != r1) k += (size_t)snprintf(out + k, n - k, "%s%d,%d", sep, r0, r1);
        else if (r0 || r1) k += (size_t)snprintf(out + k, n - k, "%s%d", sep, r0 ? r0 : r1);
        else k += (size_t)snprintf(out + k, n - k, "%s-", sep);
    }
}

/* What the answer's note says. */
static const char *note(const kt_nomo_answer *a)
{
    return a->reached ? (a->arc_lo == a->arc_hi ? "simulated arc" : "interpolated") : "under-corrects: the longest simulated arc";
}

/* An axis as lri-plan prints it at DEC decimals: [0, 180), one that would round to 180 shown as 0
 * (keratome-patient(5), CONVENTIONS). */
#define AXIS(a, dec) kt_lp_axis_shown((a), (dec))

static int table(FILE *f, const kt_nomo_query *q, double pre, double pre_axis, const kt_nomo_answer ans[2], kt_err *e)
{
    const kt_nomo_answer *any = ans[0].incisions ? &ans[0] : &ans[1];
    if (q->main_sia > 0)
        fprintf(f, "# keratometric %.2f D @ %g deg plus the main incision's SIA %.2f D @ %g deg: %.2f D @ %.0f deg\n",
                q->k_steep - q->k_flat, q->axis, q->main_sia, q->main_axis, pre, AXIS(pre_axis, 0));
    fprintf(f, "# pre-op %.2f D @ %.0f deg, age %g y, target %.2f D; incisions centred on %.0f deg, depth %g, diameter %g mm\n",
            pre, AXIS(pre_axis, 0), q->age, q->target, AXIS(pre_axis, 0), any->depth, any->diameter);
    if (isnan(any->sia_sd))
        fprintf(f, "# no band: the table has no sia_sd_D column (a table made before issue 21; remake it with "
                   "make -C plans/studies/nomogram)\n");
    else
        fprintf(f, "# band: the SIA's first-order sd of the simulated cases (tissue quantities only: lri-nomogram(1), BAND) "
                   "and the residual's 90%% interval\n");
    static const char *const H[] = {"incisions", "arc_deg", "sia_D", "residual_D", "residual_axis_deg", "sia_sd_D",
                                    "residual_sd_D", "residual_lo90_D", "residual_hi90_D", "between_arcs_deg", "ages_y", "note",
                                    "table_lines"};
    kt_tsvw w;
    kt_tsvw_begin(&w, f);
    for (int k = 0; k < 13; k++) kt_tsvw_text(&w, H[k]);
    kt_tsvw_end(&w);
    for (int i = 0; i < 2; i++) {
        const kt_nomo_answer *a = &ans[i];
        if (!a->incisions) continue;
        /* A residual that prints as 0.00 D has no axis: "none" (lri-nomogram(1)). */
        char axis[16] = "none", arcs[64], ages[64], lines[64];
        if (a->residual >= 0.005) snprintf(axis, sizeof axis, "%.0f", AXIS(a->residual_axis, 0));
        snprintf(arcs, sizeof arcs, "%g-%g", a->arc_lo, a->arc_hi), snprintf(ages, sizeof ages, "%g-%g", a->age_lo, a->age_hi);
        kt_tsvw_int(&w, a->incisions), kt_tsvw_num(&w, a->arc, "%.1f"), kt_tsvw_num(&w, a->sia, "%.2f");
        kt_tsvw_num(&w, a->residual < 0.005 ? 0.0 : a->residual, "%.2f"), kt_tsvw_text(&w, axis);
        kt_tsvw_num(&w, a->sia_sd, "%.2f"), kt_tsvw_num(&w, a->residual_sd, "%.2f");
        kt_tsvw_num(&w, a->residual_lo90, "%.2f"), kt_tsvw_num(&w, a->residual_hi90, "%.2f");
        table_lines(a, lines, sizeof lines);
        kt_tsvw_text(&w, arcs), kt_tsvw_text(&w, ages), kt_tsvw_text(&w, note(a)), kt_tsvw_text(&w, lines);
        kt_tsvw_end(&w);
    }
    return kt_tsvw_finish(&w, "lri-nomogram", e);
}

static void json_answer(kt_json *j, const kt_nomo_answer *a)
{
    kt_json_obj(j, NULL);
    kt_json_int(j, "incisions", a->incisions);
    kt_json_num(j, "arc_deg", a->arc, 2), kt_json_num(j, "sia_D", a->sia, 4);
    kt_json_num(j, "residual_D", a->residual, 4);
    kt_json_num(j, "residual_axis_deg", a->residual >= 0.005 ? AXIS(a->residual_axis, 1) : NAN, 1);
    kt_json_num(j, "sia_sd_D", a->sia_sd, 4), kt_json_num(j, "residual_sd_D", a->residual_sd, 4);
    kt_json_num(j, "residual_lo90_D", a->residual_lo90, 4), kt_json_num(j, "residual_hi90_D", a->residual_hi90, 4);
    kt_json_num(j, "arc_lo_deg", a->arc_lo, -6), kt_json_num(j, "arc_hi_deg", a->arc_hi, -6);
    kt_json_num(j, "age_lo_y", a->age_lo, -6), kt_json_num(j, "age_hi_y", a->age_hi, -6);
    kt_json_num(j, "depth", a->depth, -6), kt_json_num(j, "diameter_mm", a->diameter, -6);
    kt_json_bool(j, "reached", a->reached), kt_json_str(j, "note", note(a));
    char lines[64];
    table_lines(a, lines, sizeof lines);
    kt_json_str(j, "table_lines", lines);
    kt_json_end(j);
}

static int json(FILE *f, const kt_nomo_query *q, double pre, double pre_axis, const kt_nomo_answer ans[2], kt_err *e)
{
    kt_json j;
    kt_json_begin(&j, f, 2);
    kt_json_obj(&j, NULL);
    kt_json_str(&j, "tool", "lri-nomogram"), kt_json_str(&j, "version", KT_VERSION);
    kt_json_obj(&j, "query");
    kt_json_num(&j, "k_steep_D", q->k_steep, -6), kt_json_num(&j, "k_flat_D", q->k_flat, -6);
    kt_json_num(&j, "axis_deg", q->axis, -6), kt_json_num(&j, "age_y", q->age, -6);
    kt_json_num(&j, "main_sia_D", q->main_sia, -6), kt_json_num(&j, "main_sia_axis_deg", q->main_axis, -6);
    kt_json_num(&j, "target_D", q->target, -6);
    kt_json_end(&j);
    kt_json_num(&j, "pre_op_D", pre, 4), kt_json_num(&j, "pre_op_axis_deg", AXIS(pre_axis, 1), 1);
    kt_json_arr(&j, "answers");
    for (int i = 0; i < 2; i++)
        if (ans[i].incisions) json_answer(&j, &ans[i]);
    kt_json_end(&j);
    kt_json_end(&j);
    return kt_json_finish(&j, "lri-nomogram --json", e);
}

int kt_nomo_print(FILE *f, const kt_nomo_query *q, double pre, double pre_axis, const kt_nomo_answer ans[2], int as_json,
                  kt_err *e)
{
    return as_json ? json(f, q, pre, pre_axis, ans, e) : table(f, q, pre, pre_axis, ans, e);
}
