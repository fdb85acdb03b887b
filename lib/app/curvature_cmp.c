/* curvature_cmp.c: `curvature --compare RUN_A RUN_B`: one self-contained page (inline SVG and
 * CSS, no script, no network) setting two runs that curvature has read side by side: single
 * against paired incisions, or two materials. It reads each run's curvature.tsv (the figures
 * of every step) and run.yaml (plan, scene, the provenance block of runrec.h). */
#define _XOPEN_SOURCE 700
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "curvature_run.h"

#include "html.h"
#include "svg.h"
#include "tsv.h"
#include "yml.h"

#define NCOL 10
static const char *const COL[NCOL] = {"step", "arc_deg", "cyl_D", "axis_steep_deg", "flattening_D", "steepening_D",
                                      "sia_D", "sia_axis_deg", "correction_index", "total_cyl_D"};
enum { C_STEP, C_ARC, C_CYL, C_AXIS, C_FLAT, C_STEEP, C_SIA, C_SIAAX, C_CI, C_TCYL };

/* One run: its table's columns COL by row, and what run.yaml says of it. */
typedef struct cmp_run {
    const char *dir;
    int n;
    double *v;          /* n * NCOL */
    char plan[512], scene[512], materials[1024];
} cmp_run;

static double at(const cmp_run *r, int i, int c) { return r->v[(size_t)i * NCOL + c]; }

static int read_table(cmp_run *r, kt_err *e)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/curvature.tsv", r->dir);
    kt_tsv t;
    if (access(path, F_OK) != 0)
        return kt_fail(e, KT_EINPUT, "%s: cannot read (run curvature on %s first)", path, r->dir);
    if (kt_tsv_open(&t, path, e)) return e->code;
    int idx[NCOL], cap = 0;
    for (int j = 0; j < NCOL && !e->code; j++) /* arc_deg: absent in older tables */
        idx[j] = j == C_ARC ? kt_tsv_find(&t, COL[j]) : kt_tsv_need(&t, COL[j], "a table of curvature(1)");
    while (!e->code && kt_tsv_next(&t) > 0) {
        if (r->n == cap) {
            double *v = kt_realloc(r->v, (size_t)(cap = cap ? 2 * cap : 32) * NCOL, sizeof(double), e);
            if (!v) break;
            r->v = v;
        }
        double *row = r->v + (size_t)r->n++ * NCOL;
        for (int j = 0; j < NCOL && !e->code; j++)
            if (idx[j] < 0) row[j] = NAN;
            else kt_tsv_num(&t, idx[j], j == C_STEP ? 0 : KT_TSV_NAN | KT_TSV_INF, &row[j]);
    }
    kt_tsv_close(&t);
    if (!e->code && r->n < 2) kt_fail(e, KT_EINPUT, "%s: expected step 0 and at least one step", path);
    return e->code;
}

static void read_yaml(cmp_run *r)
{
    char path[4096];
    kt_err e2 = {0};
    kt_yml y;
    snprintf(r->plan, sizeof r->plan, "-"), snprintf(r->scene, sizeof r->scene, "-");
    snprintf(r->materials, sizeof r->materials, "-");
    snprintf(path, sizeof path, "%s/run.yaml", r->dir);
    if (kt_yml_load(&y, path, &e2)) return;
    yaml_node_t *root = kt_yml_root(&y, &e2), *n, *p;
    if (root && (n = kt_yml_get(&y, root, "plan")) && n->type == YAML_SCALAR_NODE)
        snprintf(r->plan, sizeof r->plan, "%s", (const char *)n->data.scalar.value);
    if (root && (n = kt_yml_get(&y, root, "scene")) && n->type == YAML_SCALAR_NODE)
        snprintf(r->scene, sizeof r->scene, "%s", (const char *)n->data.scalar.value);
    if (root && (p = kt_yml_get(&y, root, "provenance")) && (n = kt_yml_get(&y, p, "materials")) &&
        n->type == YAML_MAPPING_NODE) {
        size_t len = 0;
        r->materials[0] = '\0';
        for (int i = 0; i < kt_yml_map_len(n) && len < sizeof r->materials; i++) {
            yaml_node_t *v, *E;
            const char *k = kt_yml_map_key(&y, n, i, NULL, &v);
            if (!k || !v) continue;
            const char *key = (E = kt_yml_get(&y, v, "E_inplane_MPa")) ? "E in-plane" : "E";
            if (!E) E = kt_yml_get(&y, v, "E_MPa");
            if (E && E->type == YAML_SCALAR_NODE)
                len += snprintf(r->materials + len, sizeof r->materials - len, "%s%s %s %s MPa", len ? ", " : "", k,
                                key, (const char *)E->data.scalar.value);
        }
    }
    kt_yml_free(&y);
}


static void cell(FILE *f, double v, const char *fmt)
{
    if (isnan(v)) fputs("<td class=\"n\">&ndash;</td>", f);
    else {
        fputs("<td class=\"n\">", f);
        fprintf(f, fmt, v);
        fputs("</td>", f);
    }
}

/* One figure against arc (or step): column c of both runs. */
static int plot(FILE *f, const cmp_run *r, int c, const char *what, const char *ytitle, kt_err *e)
{
    int by_arc = isfinite(at(r, r[0].n - 1, C_ARC)) && isfinite(at(r + 1, r[1].n - 1, C_ARC)), xc = by_arc ? C_ARC : C_STEP;
    double lo = 0, hi = 0, x1 = 1;
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < r[k].n; i++) {
            if (isfinite(at(r + k, i, c))) lo = fmin(lo, at(r + k, i, c)), hi = fmax(hi, at(r + k, i, c));
            x1 = fmax(x1, at(r + k, i, xc));
        }
    kt_svg_nice_range(&lo, &hi, 5);
    const double W = 560, H = 300;
    kt_svg_plot p = {70, 12, W - 90, H - 60, 0, x1, lo, hi};
    fputs("<figure>", f);
    kt_svg_begin(f, W, H, what);
    kt_svg_axes(f, &p, "%.0f", "%.2f", by_arc ? "degrees of arc opened per incision" : "step", ytitle);
    for (int k = 0; k < 2; k++) {
        double *x = kt_calloc(r[k].n, sizeof(double), e), *y = kt_calloc(r[k].n, sizeof(double), e);
        if (!x || !y) {
            free(x), free(y);
            return e->code;
        }
        for (int i = 0; i < r[k].n; i++) x[i] = at(r + k, i, xc), y[i] = at(r + k, i, c);
        kt_svg_series(f, &p, x, y, r[k].n, k ? "s2" : "s1");
        free(x), free(y);
        double ly = p.y + 18 + 17 * k, lx = p.x + 12;
        fprintf(f, "<g class=\"s%d\"><polyline points=\"%.1f,%.1f %.1f,%.1f\"/></g>\n", k + 1, lx, ly - 4, lx + 22, ly - 4);
        kt_svg_text(f, lx + 27, ly, "start", "lbl", "%s: %s", k ? "B" : "A", r[k].dir);
    }
    kt_svg_end(f);
    fprintf(f, "<figcaption>%s, run A (solid) and run B (dashed).</figcaption></figure>\n", what);
    return KT_OK;
}

static int page(FILE *f, const cmp_run *r, kt_err *e)
{
    kt_html_begin(f, "keratome: two runs compared");
    fputs("<header><h1>Two runs compared</h1></header>\n<main>\n<table id=\"runs\">\n<tr><th></th><th>run A</th>"
          "<th>run B</th></tr>\n", f);
    const char *what[] = {"folder", "plan", "scene", "materials (run.yaml)"};
    for (int j = 0; j < 4; j++) {
        fprintf(f, "<tr><th>%s</th>", what[j]);
        for (int k = 0; k < 2; k++) {
            fputs("<td>", f);
            kt_html_text(f, j == 0 ? r[k].dir : j == 1 ? r[k].plan : j == 2 ? r[k].scene : r[k].materials);
            fputs("</td>", f);
        }
        fputs("</tr>\n", f);
    }
    fputs("</table>\n<h2>After the last step</h2>\n<table id=\"final\">\n<tr><th>figure</th><th>run A</th><th>run B</th>"
          "<th>B &minus; A</th></tr>\n", f);
    static const struct { int c; const char *name, *fmt; } ROW[] = {
        {C_STEP, "last step", "%.0f"},
        {C_ARC, "arc opened per incision (deg)", "%.1f"},
        {C_CYL, "keratometric cylinder (D)", "%.2f"},
        {C_AXIS, "its steep axis (deg)", "%.1f"},
        {C_FLAT, "flattening of the incised meridian (D)", "%+.3f"},
        {C_STEEP, "steepening of the orthogonal one (D)", "%+.3f"},
        {C_SIA, "surgically induced astigmatism (D)", "%.3f"},
        {C_SIAAX, "its axis (deg)", "%.1f"},
        {C_CI, "correction index", "%.2f"},
        {C_TCYL, "total corneal cylinder (D)", "%.2f"}};
    for (size_t j = 0; j < sizeof ROW / sizeof ROW[0]; j++) {
        double a = at(r, r[0].n - 1, ROW[j].c), b = at(r + 1, r[1].n - 1, ROW[j].c);
        fprintf(f, "<tr><td>%s</td>", ROW[j].name);
        cell(f, a, ROW[j].fmt), cell(f, b, ROW[j].fmt);
        cell(f, ROW[j].c == C_AXIS || ROW[j].c == C_SIAAX ? NAN : b - a, "%+.3f");
        fputs("</tr>\n", f);
    }
    fprintf(f, "</table>\n<p class=\"note\">Pre-operative cylinder: A %.2f D @ %.0f&deg;, B %.2f D @ %.0f&deg; (step 0 of "
               "each run).</p>\n<h2>Step by step</h2>\n<div class=\"row\">\n",
            at(r, 0, C_CYL), at(r, 0, C_AXIS), at(r + 1, 0, C_CYL), at(r + 1, 0, C_AXIS));
    int rc = plot(f, r, C_SIA, "surgically induced astigmatism", "SIA (D)", e);
    if (rc == KT_OK) rc = plot(f, r, C_CYL, "keratometric cylinder", "cylinder (D)", e);
    if (rc == KT_OK) rc = plot(f, r, C_FLAT, "flattening of the incised meridian", "flattening (D)", e);
    fputs("</div>\n</main>\n", f);
    kt_html_end(f);
    return rc;
}

int kt_curv_compare(const char *run_a, const char *run_b, const char *outdir, kt_err *e)
{
    cmp_run r[2];
    memset(r, 0, sizeof r);
    r[0].dir = run_a, r[1].dir = run_b;
    int rc = read_table(r, e);
    if (rc == KT_OK) rc = read_table(r + 1, e);
    char path[4096];
    if (rc == KT_OK && (size_t)snprintf(path, sizeof path, "%s/compare.html", outdir) >= sizeof path)
        rc = kt_fail(e, KT_EINPUT, "%s: path too long", outdir);
    if (rc == KT_OK) rc = kt_mkdir_p(outdir, e);
    if (rc == KT_OK) {
        read_yaml(r), read_yaml(r + 1);
        kt_out o;
        if ((rc = kt_out_open(&o, path, e)) == KT_OK) {
            rc = page(o.f, r, e);
            if (rc == KT_OK) rc = kt_out_failed(&o, e);
            if (rc == KT_OK) rc = kt_out_commit(&o, e);
            else kt_out_abort(&o);
        }
    }
    free(r[0].v), free(r[1].v);
    return rc;
}
