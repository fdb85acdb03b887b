/* curvature_out.c: what curvature writes after the steps: curvature.tsv and meridians.tsv,
 * the summary (text and JSON), the ParaView collection steps.pvd and report.html. */
#define _XOPEN_SOURCE 700
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "curvature_run.h"

#include "curv.h"
#include "curv_band.h"
#include "curv_report.h"
#include "curv_total.h"
#include "json.h"
#include "msh.h"
#include "plan.h"
#include "axialmap.h"
#include "tsv.h"
#include "yml.h"

#include "curvature_int.h"

/* ---------------------------------------------------------------- table and summary */

/* Per-step numbers against step 0. */
typedef struct step_cmp {
    double k_inc, k_ort, flat, steep, coupling, dk_mean;
    kt_alpins va;
} step_cmp;

static void compare(const run_ctx *c, int i, step_cmp *d)
{
    const step_res *r0 = c->res, *r = c->res + i;
    d->k_inc = kt_curv_meridian_k(&r->fit, c->meridian);
    d->k_ort = kt_curv_meridian_k(&r->fit, c->meridian + 90);
    d->flat = kt_curv_meridian_k(&r0->fit, c->meridian) - d->k_inc;
    d->steep = d->k_ort - kt_curv_meridian_k(&r0->fit, c->meridian + 90);
    d->coupling = i > 0 && fabs(d->steep) > 1e-9 ? d->flat / d->steep : NAN;
    d->dk_mean = r->k.k_mean - r0->k.k_mean;
    kt_astig pre = {r0->k.cyl, r0->k.axis_steep}, post = {r->k.cyl, r->k.axis_steep};
    kt_curv_alpins(pre, post, c->has_target ? &c->tia : NULL, &d->va);
}

static const char *const CURV_HEAD[] = {
    "step", "k_steep_D", "k_flat_D", "axis_steep_deg", "cyl_D", "k_mean_D", "dk_mean_D", "incised_deg", "k_incised_D",
    "k_ortho_D", "flattening_D", "steepening_D", "coupling_ratio", "sia_D", "sia_axis_deg", "tia_D", "tia_axis_deg", "dv_D",
    "dv_axis_deg", "correction_index", "angle_error_deg", "apex_x_mm", "apex_y_mm", "apex_z_mm", "fit_rms_um",
    "zone_points", "fit_order", "post_k_steep_D", "post_k_flat_D", "post_axis_deg", "post_cyl_D", "thickness_mm",
    "total_k_steep_D", "total_k_flat_D", "total_axis_deg", "total_cyl_D", "arc_deg"};

/* One step's row of curvature.tsv. */
static void curv_row(const run_ctx *c, int i, kt_tsvw *w)
{
    const step_res *r = c->res + i;
    step_cmp d;
    compare(c, i, &d);
    double row[] = {r->k.k_steep, r->k.k_flat, kt_curvrun_axis_out(r->k.axis_steep, 4), r->k.cyl, r->k.k_mean, d.dk_mean,
                    kt_curvrun_axis_out(c->meridian, 4), d.k_inc, d.k_ort, d.flat, d.steep, d.coupling, d.va.sia.mag,
                    kt_curvrun_axis_out(d.va.sia.axis, 4), d.va.tia.mag, kt_curvrun_axis_out(d.va.tia.axis, 4), d.va.dv.mag,
                    kt_curvrun_axis_out(d.va.dv.axis, 4), d.va.ci,
                    d.va.ae, r->fit.ax, r->fit.ay, r->fit.az, 1000 * r->fit.rms};
    kt_tsvw_int(w, c->num[i]);
    for (size_t k = 0; k < sizeof row / sizeof row[0]; k++) kt_tsvw_num(w, row[k], k >= 20 && k <= 22 ? "%.6f" : "%.4f");
    kt_tsvw_int(w, r->fit.npts), kt_tsvw_int(w, r->fit.kind == KT_FIT_ZERNIKE ? r->fit.order : 0);
    const kt_total *t = &r->tot;
    double tot[] = {t->post_steep, t->post_flat, kt_curvrun_axis_out(t->post_axis, 4), t->post_cyl, t->thickness,
                    t->tot_steep, t->tot_flat, kt_curvrun_axis_out(t->tot_axis, 4), t->tot_cyl};
    for (size_t k = 0; k < sizeof tot / sizeof tot[0]; k++) kt_tsvw_num(w, tot[k], k == 4 ? "%.6f" : "%.4f");
    kt_tsvw_num(w, kt_curvrun_arc(c, i), "%.4f");
    kt_curvrun_band_tsv_row(c, i, w);
    kt_tsvw_end(w);
}

/* A table into the temporary folder: its writer, committed by done(). */
static int table_open(run_ctx *c, const char *name, kt_out *out, kt_tsvw *w, char *path, kt_err *e)
{
    if (kt_curvrun_tmp_path(c, path, name, e) || kt_curvrun_add_file(c, name, e) || kt_out_open(out, path, e)) return e->code;
    kt_tsvw_begin(w, out->f);
    return KT_OK;
}

static int table_done(kt_out *out, kt_tsvw *w, const char *path, kt_err *e)
{
    if (kt_tsvw_finish(w, path, e)) return kt_out_abort(out), e->code;
    return kt_out_commit(out, e);
}

int kt_curvrun_write_tables(run_ctx *c, kt_err *e)
{
    char path[PATHMAX];
    kt_out out;
    kt_tsvw w;
    if (table_open(c, "curvature.tsv", &out, &w, path, e)) return e->code;
    for (size_t k = 0; k < sizeof CURV_HEAD / sizeof *CURV_HEAD; k++) kt_tsvw_text(&w, CURV_HEAD[k]);
    kt_curvrun_band_tsv_head(c, &w);
    kt_tsvw_end(&w);
    for (int i = 0; i < c->nstep; i++) curv_row(c, i, &w);
    if (table_done(&out, &w, path, e) || table_open(c, "meridians.tsv", &out, &w, path, e)) return e->code;
    kt_tsvw_text(&w, "step");
    char name[16];
    for (int t = 0; t < KT_CURV_NMERID; t += 5) snprintf(name, sizeof name, "k%03d_D", t * 180 / KT_CURV_NMERID), kt_tsvw_text(&w, name);
    kt_tsvw_end(&w);
    for (int i = 0; i < c->nstep; i++) {
        kt_tsvw_int(&w, c->num[i]);
        for (int t = 0; t < KT_CURV_NMERID; t += 5) kt_tsvw_num(&w, c->res[i].k.kmer[t], "%.4f");
        kt_tsvw_end(&w);
    }
    return table_done(&out, &w, path, e);
}

static int axis_note(const run_ctx *c, char *buf, size_t size);

void kt_curvrun_summary(const run_ctx *c, FILE *f)
{
    const kt_curv_opts *o = c->o;
    const step_res *r0 = c->res;
    char fitname[64];
    if (o->fit == KT_FIT_ZERNIKE) snprintf(fitname, sizeof fitname, "Zernike order %d", r0->fit.order);
    else snprintf(fitname, sizeof fitname, "biconic (toric)");
    fprintf(f, "curvature: %d step%s, %s fit over the central %.1f mm, K = 337.5/R (n 1.3375)\n",
            c->nstep - 1, c->nstep == 2 ? "" : "s", fitname, o->zone);
    fprintf(f, "incised meridian %.1f deg (%s)\n", kt_curvrun_axis_out(c->meridian, 1), c->meridian_src);
    fprintf(f, "pre-op (step 0): K %.2f D @ %.0f / %.2f D @ %.0f, cylinder %.2f D, mean K %.2f D\n",
            r0->k.k_steep, kt_curvrun_axis_out(r0->k.axis_steep, 0), r0->k.k_flat, kt_curvrun_axis_out(r0->k.axis_steep + 90, 0), r0->k.cyl,
            r0->k.k_mean);
    fprintf(f, "%5s %6s %15s %7s %6s %8s %10s %10s %8s %14s\n", "step", "arc", "K steep @ axis", "K flat", "cyl",
            "dK mean", "flattening", "steepening", "coupling", "SIA @ axis");
    for (int i = 0; i < c->nstep; i++) {
        const step_res *r = c->res + i;
        step_cmp d;
        compare(c, i, &d);
        char cr[32];
        if (isnan(d.coupling)) snprintf(cr, sizeof cr, "-");
        else snprintf(cr, sizeof cr, "%.2f", d.coupling);
        char arc[32];
        double a = kt_curvrun_arc(c, i);
        if (isnan(a)) snprintf(arc, sizeof arc, "-");
        else snprintf(arc, sizeof arc, "%.1f", a);
        fprintf(f, "%5d %6s %7.2f @ %5.1f %7.2f %6.2f %+8.2f %+10.3f %+10.3f %8s %6.2f @ %5.1f\n", c->num[i], arc, r->k.k_steep,
                kt_curvrun_axis_out(r->k.axis_steep, 1), r->k.k_flat, r->k.cyl, d.dk_mean, d.flat, d.steep, cr,
                d.va.sia.mag, kt_curvrun_axis_out(d.va.sia.axis, 1));
    }
    const step_res *rl = c->res + c->nstep - 1;
    if (r0->has_post)
        fprintf(f, "posterior K %.2f D @ %.0f / %.2f D (n %.3f -> %.3f), total corneal power %.2f D @ %.0f / %.2f D, "
                   "cylinder %.2f D (thick lens, %.3f mm); last step: %.2f D @ %.0f / %.2f D, cylinder %.2f D\n",
                r0->tot.post_steep, kt_curvrun_axis_out(r0->tot.post_axis, 0), r0->tot.post_flat, c->n.cornea, c->n.aqueous,
                r0->tot.tot_steep, kt_curvrun_axis_out(r0->tot.tot_axis, 0), r0->tot.tot_flat, r0->tot.tot_cyl, r0->tot.thickness,
                rl->tot.tot_steep, kt_curvrun_axis_out(rl->tot.tot_axis, 0), rl->tot.tot_flat, rl->tot.tot_cyl);
    if (c->has_target && c->nstep > 1) {
        step_cmp d;
        compare(c, c->nstep - 1, &d);
        fprintf(f, "target: correct %.2f D @ %.0f, TIA %.2f D @ %.0f; step %d: SIA %.2f D @ %.1f, "
                   "correction index %.2f, angle of error %+.1f deg, difference vector %.2f D @ %.1f\n",
                c->tia.mag, kt_curvrun_axis_out(c->tia.axis + 90, 0), c->tia.mag, kt_curvrun_axis_out(c->tia.axis, 0), c->num[c->nstep - 1],
                d.va.sia.mag, kt_curvrun_axis_out(d.va.sia.axis, 1), d.va.ci, d.va.ae, d.va.dv.mag, kt_curvrun_axis_out(d.va.dv.axis, 1));
    }
    if (c->nstep > 1) {
        char v[512], note[512];
        kt_curvrun_verdict(c, v, sizeof v);
        fprintf(f, "verdict: %s\n", v);
        if (axis_note(c, note, sizeof note)) fprintf(f, "note: %s\n", note);
    }
    kt_curvrun_band_summary(c, f);
}

/* The largest angle between two axes, 0 to 90 deg. */
static double axis_gap(double a, double b)
{
    double d = fmod(fabs(a - b), 180);
    return d > 90 ? 180 - d : d;
}

void kt_curvrun_verdict(const run_ctx *c, char *buf, size_t size)
{
    const step_res *r0 = c->res, *rl = c->res + c->nstep - 1;
    step_cmp d;
    compare(c, c->nstep - 1, &d);
    kt_astig pre = {r0->k.cyl, r0->k.axis_steep}, post = {rl->k.cyl, rl->k.axis_steep};
    kt_report_verdict(pre, post, &d.va, c->has_target, buf, size);
}

/* When the steep axis swings between steps while an arc is partly cut, say why (1: a note). */
static int axis_note(const run_ctx *c, char *buf, size_t size)
{
    double most = 0;
    for (int i = 1; i < c->nstep; i++) most = fmax(most, axis_gap(c->res[i].k.axis_steep, c->res[0].k.axis_steep));
    if (!(most > 10) || !c->plan_in || c->plan_in->ninc < 1) return 0;
    int dir = c->plan_in->inc[0].direction;
    snprintf(buf, size, "the steep axis moves by up to %.0f deg over the steps. %s The axis column is the axis "
             "of the cylinder that remains, read about the apex; the cornea does not rotate.", most,
             dir == KT_BLADE_CENTRE_OUT ? "While the cylinder nears zero its axis is poorly defined and swings."
                      : "While an arc is partly cut the blade has opened one side of the meridian only (it cuts "
                        "from one end of the arc), so the flattening is off-centre and the remaining cylinder's "
                        "axis turns with it until the arc is complete.");
    return 1;
}

/* ---------------------------------------------------------------- JSON, ParaView, report */

/* The summary as one JSON object (the one JSON writer, lib/io/json.h; %.6g numbers, a NaN as
 * null): settings, then one object per step. */
void kt_curvrun_summary_json(const run_ctx *c, FILE *f)
{
    kt_json j;
    kt_json_begin(&j, f, 2); /* a step a line */
    kt_json_obj(&j, NULL);
    kt_json_str(&j, "keratome", KT_VERSION);
    kt_json_str(&j, "fit", c->o->fit == KT_FIT_ZERNIKE ? "zernike" : "toric");
    kt_json_num(&j, "zone_mm", c->o->zone, -6);
    kt_json_num(&j, "incised_deg", kt_curvrun_axis_out(c->meridian, 4), -6);
    kt_json_str(&j, "incised_from", c->meridian_src);
    kt_json_num(&j, "n_cornea", c->n.cornea, -6);
    kt_json_num(&j, "n_aqueous", c->n.aqueous, -6);
    if (c->has_target) {
        kt_json_obj(&j, "target");
        kt_json_num(&j, "tia_D", c->tia.mag, -6);
        kt_json_num(&j, "tia_axis_deg", kt_curvrun_axis_out(c->tia.axis, 4), -6);
        kt_json_end(&j);
    } else {
        kt_json_null(&j, "target");
    }
    kt_curvrun_band_json_top(c, &j);
    kt_json_arr(&j, "steps");
    for (int i = 0; i < c->nstep; i++) {
        const step_res *r = c->res + i;
        step_cmp d;
        compare(c, i, &d);
        kt_json_obj(&j, NULL);
        kt_json_int(&j, "step", c->num[i]);
        const char *key[] = {"arc_deg", "k_steep_D", "k_flat_D", "axis_steep_deg", "cyl_D", "k_mean_D", "flattening_D",
                             "steepening_D", "coupling_ratio", "sia_D", "sia_axis_deg", "dv_D", "correction_index",
                             "angle_error_deg", "index_of_success", "post_k_steep_D", "post_k_flat_D", "post_axis_deg",
                             "thickness_mm", "total_k_steep_D", "total_k_flat_D", "total_axis_deg", "total_cyl_D"};
        double val[] = {kt_curvrun_arc(c, i), r->k.k_steep, r->k.k_flat, kt_curvrun_axis_out(r->k.axis_steep, 4), r->k.cyl,
                        r->k.k_mean, d.flat, d.steep, d.coupling, d.va.sia.mag, kt_curvrun_axis_out(d.va.sia.axis, 4),
                        d.va.dv.mag, d.va.ci, d.va.ae, d.va.ios, r->tot.post_steep, r->tot.post_flat,
                        kt_curvrun_axis_out(r->tot.post_axis, 4), r->tot.thickness, r->tot.tot_steep, r->tot.tot_flat,
                        kt_curvrun_axis_out(r->tot.tot_axis, 4), r->tot.tot_cyl};
        for (size_t k = 0; k < sizeof val / sizeof *val; k++) kt_json_num(&j, key[k], val[k], -6);
        kt_curvrun_band_json_step(c, i, &j);
        kt_json_end(&j);
    }
    kt_json_end(&j);
    kt_json_end(&j);
    kt_err e = {0};
    if (kt_json_finish(&j, "curvature --json", &e)) fprintf(stderr, "curvature: %s\n", e.msg);
}

/* steps.pvd: the step VTKs as one ParaView time series (time: degrees of arc opened per
 * incision when the plan cuts arcs, else the step number). File names are relative to the
 * collection's folder (bare when it sits beside them), so that the run and its maps move
 * together (lri-plan writes them in a folder it then renames). */
int kt_curvrun_write_pvd(run_ctx *c, kt_err *e)
{
    char path[PATHMAX], a[PATHMAX], b[PATHMAX];
    int beside = realpath(c->o->run_dir, a) && realpath(c->outdir, b) && strcmp(a, b) == 0;
    int by_arc = c->nstep > 1 && isfinite(kt_curvrun_arc(c, 1));
    for (int i = 1; by_arc && i < c->nstep; i++) by_arc = kt_curvrun_arc(c, i) > kt_curvrun_arc(c, i - 1);
    kt_out out;
    /* registered first: a failed run removes what it names */
    if (kt_curvrun_tmp_path(c, path, "steps.pvd", e) || kt_curvrun_add_file(c, "steps.pvd", e) ||
        kt_out_open(&out, path, e))
        return e->code;
    FILE *f = out.f;
    fprintf(f, "<?xml version=\"1.0\"?>\n<!-- keratome %s: the step meshes of this run; timestep = %s -->\n"
               "<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n",
            KT_VERSION, by_arc ? "degrees of arc opened per incision" : "step number");
    for (int i = 0; i < c->nstep; i++) {
        const char *name = strrchr(c->vtk[i], '/') ? strrchr(c->vtk[i], '/') + 1 : c->vtk[i];
        if (!beside && !realpath(c->vtk[i], a)) {
            kt_out_abort(&out);
            return kt_fail(e, KT_ERUN, "%s: cannot resolve the path", c->vtk[i]);
        }
        if (!beside) kt_path_relative(a, c->outdir, b, sizeof b); /* the run and its maps move together */
        fprintf(f, "    <DataSet timestep=\"%g\" part=\"0\" file=\"", by_arc ? kt_curvrun_arc(c, i) : c->num[i]);
        for (const char *q = beside ? name : b; *q; q++) {
            if (*q == '&') fputs("&amp;", f);
            else if (*q == '"') fputs("&quot;", f);
            else if (*q == '<') fputs("&lt;", f);
            else fputc(*q, f);
        }
        fputs("\"/>\n", f);
    }
    fputs("  </Collection>\n</VTKFile>\n", f);
    return kt_out_commit(&out, e);
}

/* A whole small file as a string (NULL when it cannot be read). */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f) return NULL;
    char *buf = malloc(65536);
    size_t n = buf ? fread(buf, 1, 65535, f) : 0;
    fclose(f);
    if (buf) buf[n] = '\0';
    return buf;
}

/* *ms := the sum of steps.tsv's t_total_ms column (NaN when the file or the column is absent).
 * KT_EINPUT on a field that is not a number. */
static int solver_ms(const char *dir, double *ms, kt_err *e)
{
    char path[PATHMAX];
    *ms = NAN;
    if ((size_t)snprintf(path, sizeof path, "%s/steps.tsv", dir) >= sizeof path || access(path, F_OK) != 0)
        return KT_OK;
    kt_tsv t;
    if (kt_tsv_open(&t, path, e)) return e->code;
    int col = kt_tsv_find(&t, "t_total_ms");
    double sum = 0, v;
    while (col >= 0 && kt_tsv_next(&t) > 0 && kt_tsv_num(&t, col, KT_TSV_NAN | KT_TSV_INF, &v) == KT_OK) sum += v;
    kt_tsv_close(&t);
    if (col >= 0 && !e->code) *ms = sum;
    return e->code;
}

/* The scalar text of key in a mapping (NULL: absent or not a scalar). */
static const char *scalar(kt_yml *y, const yaml_node_t *map, const char *key)
{
    yaml_node_t *n = map ? kt_yml_get(y, map, key) : NULL;
    return n && n->type == YAML_SCALAR_NODE ? (const char *)n->data.scalar.value : NULL;
}

/* A mapping's scalars (one level of nested flow maps) as "k v, k v; ..." text. */
static void map_text(kt_yml *y, const yaml_node_t *n, char *buf, size_t size)
{
    size_t len = strlen(buf);
    for (int i = 0; n && n->type == YAML_MAPPING_NODE && i < kt_yml_map_len(n) && len < size; i++) {
        yaml_node_t *v;
        const char *k = kt_yml_map_key(y, n, i, NULL, &v);
        if (!k || !v) continue;
        if (v->type == YAML_SCALAR_NODE)
            len += snprintf(buf + len, size - len, "%s%s %s", i ? ", " : "", k, (const char *)v->data.scalar.value);
        else if (v->type == YAML_MAPPING_NODE) {
            len += snprintf(buf + len, size - len, "%s%s: ", i ? "; " : "", k);
            if (len < size) map_text(y, v, buf, size), len = strlen(buf);
        }
    }
}

/* Report rows from run.yaml's provenance block (runrec.h; absent in older runs): text pairs in
 * rows[] (ROWS of ROWLEN bytes), their count. */
enum { ROWS = 12, ROWLEN = 1024 };
static int prov_rows(const run_ctx *c, char (*rows)[ROWLEN], const char **ptr)
{
    char path[PATHMAX];
    kt_err e2 = {0};
    kt_yml y;
    if (!c->o->run_dir || kt_curvrun_join(path, c->o->run_dir, "run.yaml", &e2) || kt_yml_load(&y, path, &e2)) return 0;
    yaml_node_t *root = kt_yml_root(&y, &e2), *p = root ? kt_yml_get(&y, root, "provenance") : NULL;
    int n = 0;
    if (p && p->type == YAML_MAPPING_NODE) {
        const char *v;
        /* run.yaml's top-level mesh_hash (its one copy): setup refused a mesh that differs */
        snprintf(rows[n++], ROWLEN, "mesh hash (run.yaml)");
        snprintf(rows[n++], ROWLEN, "%016llx: the mesh read here, as run.yaml records it", c->mesh_hash_read);
        snprintf(rows[n++], ROWLEN, "scene as solved");
        v = scalar(&y, p, "scene_fnv1a");
        snprintf(rows[n++], ROWLEN, "file hash %s (FNV-1a), reference %s; run.yaml keeps its text (scene_text)",
                 v ? v : "-", scalar(&y, p, "reference") ? scalar(&y, p, "reference") : "-");
        snprintf(rows[n++], ROWLEN, "materials (as solved)");
        rows[n][0] = '\0';
        map_text(&y, kt_yml_get(&y, p, "materials"), rows[n++], ROWLEN);
        snprintf(rows[n++], ROWLEN, "tools");
        snprintf(rows[n++], ROWLEN, "keratome %s, CHOLMOD %s, METIS %s, compiler %s",
                 scalar(&y, p, "keratome") ? scalar(&y, p, "keratome") : "-",
                 scalar(&y, p, "cholmod") ? scalar(&y, p, "cholmod") : "-",
                 scalar(&y, p, "metis") ? scalar(&y, p, "metis") : "-",
                 scalar(&y, p, "compiler") ? scalar(&y, p, "compiler") : "-");
        snprintf(rows[n++], ROWLEN, "solver figures");
        rows[n][0] = '\0';
        snprintf(rows[n], ROWLEN, "method %s, ordering %s, factor %s; ", scalar(&y, root, "method") ? scalar(&y, root, "method") : "-",
                 scalar(&y, root, "ordering") ? scalar(&y, root, "ordering") : "-",
                 scalar(&y, root, "factor") ? scalar(&y, root, "factor") : "-");
        map_text(&y, kt_yml_get(&y, p, "solver"), rows[n++], ROWLEN);
    }
    kt_yml_free(&y);
    for (int i = 0; i < n; i++) ptr[i] = rows[i];
    return n / 2;
}

/* path as report.html names it: RUN_DIR's prefix said as o->shown_dir (when set). */
static const char *shown(const kt_curv_opts *o, const char *path, char *buf, size_t n)
{
    size_t l = o->run_dir ? strlen(o->run_dir) : 0;
    if (!path || !o->shown_dir || !l || strncmp(path, o->run_dir, l) != 0 || (path[l] && path[l] != '/'))
        return path;
    snprintf(buf, n, "%s%s", o->shown_dir, path + l);
    return buf;
}

int kt_curvrun_write_report(run_ctx *c, kt_err *e)
{
    kt_report_step *st = kt_calloc(c->nstep, sizeof(kt_report_step), e);
    if (!st) return e->code;
    for (int i = 0; i < c->nstep; i++) {
        step_cmp d;
        compare(c, i, &d);
        st[i].k = c->res[i].k;
        st[i].k_inc = d.k_inc, st[i].k_ort = d.k_ort, st[i].flat = d.flat, st[i].steep = d.steep;
        st[i].va = d.va;
        st[i].tot = c->res[i].tot;
        st[i].arc = kt_curvrun_arc(c, i);
    }
    char yaml[PATHMAX], fitname[64], path[PATHMAX];
    char *run_yaml = NULL;
    if (c->o->run_dir && kt_curvrun_join(yaml, c->o->run_dir, "run.yaml", e) == KT_OK) run_yaml = slurp(yaml);
    if (c->o->fit == KT_FIT_ZERNIKE) snprintf(fitname, sizeof fitname, "Zernike order %d", c->res[0].fit.order);
    else snprintf(fitname, sizeof fitname, "biconic (toric)");
    kt_report r;
    memset(&r, 0, sizeof r);
    char sd[PATHMAX], sm[PATHMAX], sp[PATHMAX], ss[PATHMAX];
    r.version = KT_VERSION, r.run_dir = c->o->run_dir ? shown(c->o, c->o->run_dir, sd, sizeof sd) : ".";
    r.mesh = shown(c->o, c->mesh, sm, sizeof sm);
    r.plan_path = c->plan_in ? shown(c->o, c->plan_in->path, sp, sizeof sp) : NULL, r.run_yaml = run_yaml, r.plan = c->plan_in;
    r.scene_path = c->plan_in ? shown(c->o, c->plan_in->scene_path, ss, sizeof ss) : NULL;
    r.mesh_nn = c->mesh_nn, r.mesh_ne = c->mesh_ne, r.mesh_order = c->mesh_order;
    r.nstep = c->nstep, r.step = st, r.meridian = c->meridian, r.has_target = c->has_target, r.tia = c->tia;
    r.map_pre = &c->res[0].map, r.map_post = &c->res[c->nstep - 1].map;
    r.rad_pre = c->res[0].map_radius, r.rad_post = c->res[c->nstep - 1].map_radius;
    r.zone = c->o->zone, r.fit_name = fitname, r.scale = &c->scale, r.diff_scale = &c->diff_scale;
    r.section = c->section.n > 0 ? &c->section : NULL;
    r.solver_ms = NAN;
    if (c->o->run_dir && solver_ms(c->o->run_dir, &r.solver_ms, e)) {
        free(run_yaml), free(st);
        return e->code;
    }
    r.curv_s = kt_now() - c->t0;
    r.n = &c->n;
    char verdict[512], note[512];
    kt_curvrun_verdict(c, verdict, sizeof verdict);
    r.verdict = c->nstep > 1 ? verdict : NULL;
    r.axis_note = axis_note(c, note, sizeof note) ? note : NULL;
    r.num = c->num;
    r.rel_scale = &c->rel_scale, r.scale_auto = c->o->scale_auto;
    r.apex_z = c->res[0].fit.az;
    r.eye_os = c->o->eye_os;
    r.main = c->o->main;
    char (*rows)[ROWLEN] = kt_calloc(ROWS, ROWLEN, e);
    const char *ptr[ROWS];
    const kt_fit **maps = kt_calloc(c->nstep, sizeof *maps, e);
    double *rad = kt_calloc(c->nstep, sizeof(double), e);
    if (!rows || !maps || !rad) {
        free(rows), free(maps), free(rad), free(run_yaml), free(st);
        return e->code;
    }
    r.nprov = prov_rows(c, rows, ptr), r.prov = ptr;
    double *band = c->bands ? kt_calloc((size_t)2 * c->nstep, sizeof(double), e) : NULL;
    const char **tname = c->bands ? kt_calloc(c->uq.n > 0 ? c->uq.n : 1, sizeof(char *), e) : NULL;
    double *tval = c->bands ? kt_calloc(c->uq.n > 0 ? c->uq.n : 1, sizeof(double), e) : NULL;
    if (c->bands && (!band || !tname || !tval)) {
        free(band), free(tname), free(tval), free(rows), free(maps), free(rad), free(run_yaml), free(st);
        return e->code;
    }
    if (c->bands) {
        for (int i = 0; i < c->nstep; i++)
            kt_band_interval(KT_RD_SIA, c->val[(size_t)i * KT_RD_N + KT_RD_SIA], c->sd[(size_t)i * KT_RD_N + KT_RD_SIA],
                             band + i, band + c->nstep + i);
        r.sia_lo = band, r.sia_hi = band + c->nstep;
        r.ntorn = kt_curvrun_band_tornado(c, tname, tval);
        r.torn_name = tname, r.torn_val = tval;
        r.sia_sd = c->sd[(size_t)(c->nstep - 1) * KT_RD_N + KT_RD_SIA];
    }
    for (int i = 0; i < c->nstep; i++) maps[i] = &c->res[i].map, rad[i] = c->res[i].map_radius;
    r.maps = maps, r.map_rad = rad;
    int rc = kt_curvrun_tmp_path(c, path, "report.html", e);
    if (rc == KT_OK) rc = kt_curvrun_add_file(c, "report.html", e); /* first: a failed run removes it */
    if (rc == KT_OK) rc = kt_curv_report_write(path, &r, e);
    free(run_yaml), free(st), free(rows), free(maps), free(rad), free(band), free(tname), free(tval);
    return rc;
}

