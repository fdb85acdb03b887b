/* curvature_run.c: curvature over a whole run: the run folder (or a list of step VTKs), the plan's
 * incised meridian and target, one fit per step, the table, the maps, the summary. All outputs
 * are written into a temporary folder beside the targets and renamed into place at the end. */
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
#include "curv_report.h"
#include "curv_total.h"
#include "msh.h"
#include "plan.h"
#include "axialmap.h"
#include "yml.h"

#define PATHMAX 4096

/* What one step gives. */
typedef struct step_res {
    kt_fit fit;          /* zone fit (keratometry) */
    kt_kerato k;
    double map_radius;   /* radius of the map fit, mm */
    double bfs_radius;   /* best-fit sphere over the map disk, mm */
    kt_fit map;          /* the map fit */
    kt_fit post;         /* posterior zone fit (has_post) */
    int has_post;
    kt_total tot;        /* posterior and total corneal power (NaN without a posterior surface) */
} step_res;

typedef struct run_ctx {
    const kt_curv_opts *o;
    char outdir[PATHMAX], tmpdir[PATHMAX];
    int made_outdir;     /* the output folder did not exist: removed again on failure */
    char mesh[PATHMAX], plan[PATHMAX];
    int nstep;
    char **vtk;          /* nstep step files, step 0 first */
    unsigned char *mask; /* anterior nodes of the input mesh */
    unsigned char *post_mask; /* posterior corneal nodes (NULL: none) */
    int mesh_nn, mesh_ne, mesh_order;
    kt_topo_scale scale, diff_scale;
    kt_cornea_n n;
    kt_plan *plan_in;    /* the plan read (NULL: no plan) */
    double *u0;          /* step 0's displacement by input node (for the report's section) */
    kt_section section;
    double t0;           /* start, kt_now() */
    double meridian;     /* incised meridian, deg (NaN: not known yet) */
    const char *meridian_src;
    int has_target;
    kt_astig tia;
    step_res *res;
    int nfile;
    char **file;         /* names written into tmpdir */
} run_ctx;

void kt_curv_opts_default(kt_curv_opts *o)
{
    memset(o, 0, sizeof *o);
    o->zone = 3;
    o->map_zone = 8;
    o->fit = KT_FIT_TORIC;
    o->order = 6;
    o->map_order = 8;
    o->meridian = NAN;
    o->png = o->vtk_out = o->report = 1;
}

static int join(char *dst, const char *dir, const char *name, kt_err *e)
{
    if ((size_t)snprintf(dst, PATHMAX, "%s/%s", dir, name) >= PATHMAX)
        return kt_fail(e, KT_EINPUT, "%s/%s: path too long", dir, name);
    return KT_OK;
}

/* A path from run.yaml, relative ones taken from the run folder. */
static int resolve(char *dst, const char *dir, const char *path, kt_err *e)
{
    if (path[0] == '/') {
        if (strlen(path) >= PATHMAX) return kt_fail(e, KT_EINPUT, "%s: path too long", path);
        strcpy(dst, path);
        return KT_OK;
    }
    return join(dst, dir, path, e);
}

/* An axis in [0, 180) as it will print with `decimals` decimals: what would round to 180 is 0. */
static double axis_out(double a, int decimals)
{
    if (isnan(a)) return a;
    a = fmod(fmod(a, 180) + 180, 180);
    return a >= 180 - 0.5 * pow(10, -decimals) ? 0 : a;
}

/* ---------------------------------------------------------------- the run folder */

/* run.yaml: mesh (required), plan (optional), steps (optional: the last step number). */
static int read_run_yaml(run_ctx *c, int *declared, kt_err *e)
{
    char path[PATHMAX], buf[PATHMAX];
    if (join(path, c->o->run_dir, "run.yaml", e)) return e->code;
    kt_yml y;
    if (kt_yml_load(&y, path, e) != KT_OK) return e->code;
    yaml_node_t *root = kt_yml_root(&y, e), *n;
    int rc = root ? KT_OK : e->code;
    if (rc == KT_OK && (n = kt_yml_require(&y, root, "mesh", "run.yaml", e)) == NULL) rc = e->code;
    if (rc == KT_OK && kt_yml_string(&y, n, "mesh", buf, sizeof buf, e) != KT_OK) rc = e->code;
    if (rc == KT_OK) rc = resolve(c->mesh, c->o->run_dir, buf, e);
    if (rc == KT_OK && (n = kt_yml_get(&y, root, "plan")) != NULL) {
        if (kt_yml_string(&y, n, "plan", buf, sizeof buf, e) != KT_OK) rc = e->code;
        else rc = resolve(c->plan, c->o->run_dir, buf, e);
    }
    *declared = -1;
    if (rc == KT_OK) rc = kt_yml_key_int(&y, root, "run.yaml", "steps", 0, 1000000, declared, e);
    kt_yml_free(&y);
    return rc;
}

/* "step-NNNN.vtk" -> NNNN (>= 0), else -1. */
static int step_number(const char *name)
{
    size_t n = strlen(name);
    if (n < 10 || strncmp(name, "step-", 5) != 0 || strcmp(name + n - 4, ".vtk") != 0) return -1;
    long v = 0;
    for (size_t i = 5; i < n - 4; i++) {
        if (name[i] < '0' || name[i] > '9' || v > 1000000) return -1;
        v = 10 * v + (name[i] - '0');
    }
    return (int)v;
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Every step listed in steps.tsv must have its VTK. */
static int check_steps_tsv(const char *dir, const int *have, int nhave, kt_err *e)
{
    char path[PATHMAX], line[4096];
    if (join(path, dir, "steps.tsv", e)) return e->code;
    FILE *f = fopen(path, "r");
    if (!f) return KT_OK; /* optional */
    int ln = 0, rc = KT_OK;
    while (rc == KT_OK && fgets(line, sizeof line, f)) {
        if (++ln == 1 || line[0] == '#' || line[0] == '\n') continue; /* header */
        char *end;
        long s = strtol(line, &end, 10);
        if (end == line || (*end != '\t' && *end != ' ' && *end != '\n'))
            rc = kt_fail(e, KT_EINPUT, "%s:%d:1: expected a step number", path, ln);
        else if (!bsearch(&(int){(int)s}, have, nhave, sizeof(int), cmp_int))
            rc = kt_fail(e, KT_EINPUT, "%s:%d:1: step %ld is listed but %s/step-%04ld.vtk is missing",
                         path, ln, s, dir, s);
    }
    fclose(f);
    return rc;
}

static int list_steps(run_ctx *c, int declared, kt_err *e)
{
    const char *dir = c->o->run_dir;
    DIR *d = opendir(dir);
    if (!d) return kt_fail(e, KT_EINPUT, "%s: cannot open the run folder: %s", dir, strerror(errno));
    int n = 0, cap = 64, *num = kt_calloc(cap, sizeof(int), e), rc = KT_OK;
    struct dirent *de;
    while (num && (de = readdir(d)) != NULL) {
        int s = step_number(de->d_name);
        if (s < 0) continue;
        if (n == cap) {
            int *t = kt_realloc(num, cap *= 2, sizeof(int), e);
            if (!t) break;
            num = t;
        }
        num[n++] = s;
    }
    closedir(d);
    if (e->code) {
        free(num);
        return e->code;
    }
    qsort(num, n, sizeof(int), cmp_int);
    if (n == 0) rc = kt_fail(e, KT_EINPUT, "%s: no step-NNNN.vtk files (expected an augsolve run folder)", dir);
    for (int i = 0; rc == KT_OK && i < n; i++)
        if (num[i] != i) rc = kt_fail(e, KT_EINPUT, "%s/step-%04d.vtk: missing (steps must be numbered 0, 1, 2, ... without gaps)", dir, i);
    if (rc == KT_OK && declared >= 0 && n - 1 < declared)
        rc = kt_fail(e, KT_EINPUT, "%s/step-%04d.vtk: missing (run.yaml says steps: %d)", dir, n, declared);
    if (rc == KT_OK) rc = check_steps_tsv(dir, num, n, e);
    if (rc == KT_OK) {
        c->vtk = kt_calloc(n, sizeof(char *), e);
        for (int i = 0; c->vtk && i < n && rc == KT_OK; i++) {
            char name[64], path[PATHMAX];
            snprintf(name, sizeof name, "step-%04d.vtk", i);
            if ((rc = join(path, dir, name, e)) == KT_OK && !(c->vtk[i] = kt_strdup(path, e))) rc = e->code;
            c->nstep = i + 1;
        }
        if (!c->vtk) rc = e->code;
    }
    free(num);
    return rc;
}

/* ---------------------------------------------------------------- the plan */

/* The plan's target is the cylinder it intends to correct, at that cylinder's steep meridian
 * (plan.h: "the intended correction"); the target induced astigmatism (Alpins' TIA) is that
 * magnitude on the orthogonal meridian, the change that cancels it. */
static int read_plan(run_ctx *c, kt_err *e)
{
    kt_plan *p = c->plan_in = kt_calloc(1, sizeof(kt_plan), e);
    if (!p) return e->code;
    int rc = kt_plan_load(c->plan, p, e);
    if (rc == KT_OK) {
        if (isnan(c->meridian) && p->ninc > 0) {
            c->meridian = fmod(p->inc[0].meridian, 180);
            c->meridian_src = "the plan's first incision";
        }
        if (p->target.set) {
            c->has_target = 1;
            c->tia.mag = p->target.magnitude;
            c->tia.axis = fmod(p->target.axis + 90, 180);
        }
    }
    return rc;
}

/* ---------------------------------------------------------------- outputs */

static int add_file(run_ctx *c, const char *name, kt_err *e)
{
    char **f = kt_realloc(c->file, c->nfile + 1, sizeof(char *), e);
    if (!f) return e->code;
    c->file = f;
    if (!(c->file[c->nfile] = kt_strdup(name, e))) return e->code;
    c->nfile++;
    return KT_OK;
}

static int tmp_path(run_ctx *c, char *path, const char *name, kt_err *e)
{
    return join(path, c->tmpdir, name, e);
}

/* Rename every output into place; then the temporary folder goes. */
static int commit_files(run_ctx *c, kt_err *e)
{
    for (int i = 0; i < c->nfile; i++) {
        char from[PATHMAX], to[PATHMAX];
        if (join(from, c->tmpdir, c->file[i], e) || join(to, c->outdir, c->file[i], e)) return e->code;
        if (rename(from, to) != 0)
            return kt_fail(e, KT_ERUN, "%s: cannot move into place: %s", to, strerror(errno));
    }
    return KT_OK;
}

static void drop_tmpdir(run_ctx *c)
{
    if (!c->tmpdir[0]) return;
    for (int i = 0; i < c->nfile; i++) {
        char p[PATHMAX];
        kt_err e2 = {0};
        if (join(p, c->tmpdir, c->file[i], &e2) == KT_OK) unlink(p);
    }
    rmdir(c->tmpdir);
}

static double map_power(const void *ctx, double x, double y)
{
    const kt_fit *f = ctx;
    return kt_fit_axial_power(f, x, y);
}

/* Radius around (ax, ay) that the surface covers in every direction (36 sectors). */
static double covered_radius(const kt_surf *s, double ax, double ay)
{
    double rmax[36] = {0}, cover = INFINITY;
    for (int i = 0; i < s->n; i++) {
        double dx = s->xyz[3 * i] - ax, dy = s->xyz[3 * i + 1] - ay, r = hypot(dx, dy);
        int k = (int)floor((atan2(dy, dx) + KT_CURV_PI) / (2 * KT_CURV_PI) * 36) % 36;
        if (r > rmax[k]) rmax[k] = r;
    }
    for (int k = 0; k < 36; k++) cover = fmin(cover, rmax[k]);
    return cover;
}

static int write_surface_vtk(run_ctx *c, int step, const kt_surf *s, const kt_fit *map,
                             const double bfs_c[3], double bfs_r, double map_r, kt_err *e)
{
    double *elev = kt_calloc(s->n, sizeof(double), e), *pow = kt_calloc(s->n, sizeof(double), e);
    double *ref = kt_calloc((size_t)3 * s->n, sizeof(double), e), *org = kt_calloc(s->n, sizeof(double), e);
    int rc = e->code;
    if (elev && pow && ref && org) {
        for (int i = 0; i < s->n; i++) {
            const double *q = s->xyz + 3 * i;
            elev[i] = 1000 * (sqrt((q[0] - bfs_c[0]) * (q[0] - bfs_c[0]) + (q[1] - bfs_c[1]) * (q[1] - bfs_c[1]) +
                                   (q[2] - bfs_c[2]) * (q[2] - bfs_c[2])) - bfs_r);
            pow[i] = hypot(q[0] - map->ax, q[1] - map->ay) <= map_r ? kt_fit_axial_power(map, q[0], q[1]) : NAN;
            for (int k = 0; k < 3; k++) ref[3 * i + k] = q[k] - s->disp[3 * i + k];
            org[i] = s->origin[i];
        }
        kt_vtk_field f[4];
        memset(f, 0, sizeof f);
        strcpy(f[0].name, "displacement"), f[0].ncomp = 3, f[0].v = s->disp;
        strcpy(f[1].name, "elevation"), f[1].ncomp = 1, f[1].v = elev;
        strcpy(f[2].name, "axial_power"), f[2].ncomp = 1, f[2].v = pow;
        strcpy(f[3].name, "origin"), f[3].ncomp = 1, f[3].is_int = 1, f[3].v = org;
        char name[64], path[PATHMAX];
        snprintf(name, sizeof name, "surface-%04d.vtk", step);
        rc = tmp_path(c, path, name, e);
        if (rc == KT_OK) rc = add_file(c, name, e); /* first: a failed run removes what it names */
        if (rc == KT_OK) rc = kt_vtk_write_polydata(path, s->n, ref, s->ntri, s->tri, f, 4, 1, e);
    }
    free(elev), free(pow), free(ref), free(org);
    return rc;
}

static int write_map_png(run_ctx *c, int step, const kt_fit *map, const step_res *r, kt_err *e)
{
    kt_topo_map m;
    memset(&m, 0, sizeof m);
    m.cx = map->ax, m.cy = map->ay, m.radius = r->map_radius, m.zone = c->o->zone;
    snprintf(m.title[0], sizeof m.title[0], "AXIAL POWER (D)  STEP %d  MAP %.1f MM", step, 2 * r->map_radius);
    snprintf(m.title[1], sizeof m.title[1], "SIM K %.2f@%.0f\xC2\xB0 / %.2f@%.0f\xC2\xB0  CYL %.2f  ZONE %.0f MM",
             r->k.k_steep, axis_out(r->k.axis_steep, 0), r->k.k_flat, axis_out(r->k.axis_steep + 90, 0), r->k.cyl,
             c->o->zone);
    kt_topo_image img = {0, 0, NULL};
    char name[64], path[PATHMAX];
    snprintf(name, sizeof name, "axial-%04d.png", step);
    int rc = kt_topo_render(&c->scale, &m, map_power, map, &img, e);
    if (rc == KT_OK) rc = tmp_path(c, path, name, e);
    if (rc == KT_OK) rc = add_file(c, name, e);
    if (rc == KT_OK) rc = kt_topo_write_png(path, &img, e);
    kt_topo_image_free(&img);
    return rc;
}

/* ---------------------------------------------------------------- one step */

/* The posterior corneal surface's zone fit, when the mesh has one (curv_total.h). */
static int posterior(run_ctx *c, int step, const kt_vtk *v, kt_err *e)
{
    step_res *r = c->res + step;
    kt_curv_total_none(&r->tot);
    if (!c->post_mask) return KT_OK;
    kt_surf p;
    int rc = kt_curv_extract(v, c->vtk[step], c->post_mask, c->mesh_nn, &p, e);
    if (rc == KT_OK) {
        rc = kt_curv_fit(p.xyz, p.n, KT_FIT_TORIC, c->o->order, c->o->zone, 0, 0, &r->post, NULL, 0, e);
        kt_surf_free(&p);
    }
    if (rc == KT_OK) r->has_post = 1;
    return rc;
}

/* What the report needs from the step meshes: step 0's displacement by input node, and the
 * section through the first incision of the last step. */
static int report_inputs(run_ctx *c, int step, const kt_vtk *v, kt_err *e)
{
    const kt_vtk_field *u = kt_vtk_find(v, "displacement", 0), *org = kt_vtk_find(v, "origin", 0);
    if (!u || !org) return KT_OK; /* kt_curv_extract has reported it */
    if (step == 0) {
        if (!(c->u0 = kt_calloc((size_t)3 * c->mesh_nn, sizeof(double), e))) return e->code;
        for (int i = 0; i < v->nn; i++)
            memcpy(c->u0 + 3 * ((int)org->v[i] - 1), u->v + 3 * i, 3 * sizeof(double));
    }
    if (step != c->nstep - 1 || step == 0 || !c->plan_in || c->plan_in->ninc < 1) return KT_OK;
    const kt_incision *in = c->plan_in->inc;
    return kt_curv_section(v, c->u0, c->mesh_nn, in->meridian, 0.5 * in->diameter, 1.2, &c->section, e);
}

static int do_step(run_ctx *c, int step, kt_err *e)
{
    const kt_curv_opts *o = c->o;
    step_res *r = c->res + step;
    kt_vtk v;
    memset(&v, 0, sizeof v);
    if (kt_vtk_read(c->vtk[step], &v, e) != KT_OK) return e->code;
    kt_surf s;
    int rc = kt_curv_extract(&v, c->vtk[step], c->mask, c->mesh_nn, &s, e);
    if (rc == KT_OK) rc = posterior(c, step, &v, e);
    if (rc == KT_OK && o->report) rc = report_inputs(c, step, &v, e);
    kt_vtk_free(&v);
    if (rc != KT_OK) {
        if (s.xyz) kt_surf_free(&s);
        return rc;
    }
    char note[256];
    kt_fit *map = kt_calloc(1, sizeof(kt_fit), e);
    double *pts = kt_calloc((size_t)3 * s.n, sizeof(double), e);
    if (!map || !pts) rc = e->code;
    if (rc == KT_OK) rc = kt_curv_fit(s.xyz, s.n, o->fit, o->order, o->zone, 0, 0, &r->fit, note, sizeof note, e);
    if (rc == KT_OK && note[0] && step == 0) kt_log(o->quiet, "curvature: %s\n", note);
    if (rc == KT_OK) {
        kt_curv_simk(&r->fit, &r->k);
        r->map_radius = fmin(0.5 * o->map_zone, 0.97 * covered_radius(&s, r->fit.ax, r->fit.ay));
        rc = kt_curv_fit(s.xyz, s.n, KT_FIT_ZERNIKE, o->map_order, 2 * r->map_radius, r->fit.ax, r->fit.ay,
                         map, note, sizeof note, e);
    }
    double bfs_c[3] = {0, 0, 0};
    if (rc == KT_OK) {
        int np = 0; /* best-fit sphere over the map disk */
        for (int i = 0; i < s.n; i++)
            if (hypot(s.xyz[3 * i] - map->ax, s.xyz[3 * i + 1] - map->ay) <= r->map_radius)
                memcpy(pts + 3 * np++, s.xyz + 3 * i, 3 * sizeof(double));
        rc = kt_curv_sphere_fit(pts, np, bfs_c, &r->bfs_radius, e);
    }
    if (rc == KT_OK && o->vtk_out) rc = write_surface_vtk(c, step, &s, map, bfs_c, r->bfs_radius, r->map_radius, e);
    if (rc == KT_OK && o->png) rc = write_map_png(c, step, map, r, e);
    if (rc == KT_OK) r->map = *map;
    if (rc == KT_OK && r->has_post) kt_curv_total(&r->fit, &r->post, &c->n, &r->tot);
    free(map), free(pts);
    kt_surf_free(&s);
    return rc;
}

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

static void put(FILE *f, double v, const char *fmt)
{
    if (isnan(v)) fputs("NaN", f);
    else fprintf(f, fmt, v);
}

static int write_tables(run_ctx *c, kt_err *e)
{
    char path[PATHMAX];
    kt_out out;
    if (tmp_path(c, path, "curvature.tsv", e) || add_file(c, "curvature.tsv", e) ||
        kt_out_open(&out, path, e))
        return e->code;
    FILE *f = out.f;
    fputs("step\tk_steep_D\tk_flat_D\taxis_steep_deg\tcyl_D\tk_mean_D\tdk_mean_D\tincised_deg"
          "\tk_incised_D\tk_ortho_D\tflattening_D\tsteepening_D\tcoupling_ratio\tsia_D\tsia_axis_deg"
          "\ttia_D\ttia_axis_deg\tdv_D\tdv_axis_deg\tcorrection_index\tangle_error_deg"
          "\tapex_x_mm\tapex_y_mm\tapex_z_mm\tfit_rms_um\tzone_points\tfit_order"
          "\tpost_k_steep_D\tpost_k_flat_D\tpost_axis_deg\tpost_cyl_D\tthickness_mm"
          "\ttotal_k_steep_D\ttotal_k_flat_D\ttotal_axis_deg\ttotal_cyl_D\n", f);
    for (int i = 0; i < c->nstep; i++) {
        const step_res *r = c->res + i;
        step_cmp d;
        compare(c, i, &d);
        double row[] = {r->k.k_steep, r->k.k_flat, axis_out(r->k.axis_steep, 4), r->k.cyl, r->k.k_mean, d.dk_mean,
                        axis_out(c->meridian, 4), d.k_inc, d.k_ort, d.flat, d.steep, d.coupling, d.va.sia.mag,
                        axis_out(d.va.sia.axis, 4), d.va.tia.mag, axis_out(d.va.tia.axis, 4), d.va.dv.mag,
                        axis_out(d.va.dv.axis, 4), d.va.ci,
                        d.va.ae, r->fit.ax, r->fit.ay, r->fit.az, 1000 * r->fit.rms};
        fprintf(f, "%d", i);
        for (size_t k = 0; k < sizeof row / sizeof row[0]; k++) {
            fputc('\t', f);
            put(f, row[k], k >= 20 && k <= 22 ? "%.6f" : "%.4f");
        }
        fprintf(f, "\t%d\t%d", r->fit.npts, r->fit.kind == KT_FIT_ZERNIKE ? r->fit.order : 0);
        const kt_total *t = &r->tot;
        double tot[] = {t->post_steep, t->post_flat, axis_out(t->post_axis, 4), t->post_cyl, t->thickness,
                        t->tot_steep, t->tot_flat, axis_out(t->tot_axis, 4), t->tot_cyl};
        for (size_t k = 0; k < sizeof tot / sizeof tot[0]; k++) {
            fputc('\t', f);
            put(f, tot[k], k == 4 ? "%.6f" : "%.4f");
        }
        fputc('\n', f);
    }
    if (kt_out_commit(&out, e)) return e->code;

    if (tmp_path(c, path, "meridians.tsv", e) || add_file(c, "meridians.tsv", e) ||
        kt_out_open(&out, path, e))
        return e->code;
    f = out.f;
    fputs("step", f);
    for (int t = 0; t < KT_CURV_NMERID; t += 5) fprintf(f, "\tk%03d_D", t * 180 / KT_CURV_NMERID);
    fputc('\n', f);
    for (int i = 0; i < c->nstep; i++) {
        fprintf(f, "%d", i);
        for (int t = 0; t < KT_CURV_NMERID; t += 5) fprintf(f, "\t%.4f", c->res[i].k.kmer[t]);
        fputc('\n', f);
    }
    if (kt_out_commit(&out, e)) return e->code;
    return KT_OK;
}

static void summary(const run_ctx *c, FILE *f)
{
    const kt_curv_opts *o = c->o;
    const step_res *r0 = c->res;
    char fitname[64];
    if (o->fit == KT_FIT_ZERNIKE) snprintf(fitname, sizeof fitname, "Zernike order %d", r0->fit.order);
    else snprintf(fitname, sizeof fitname, "biconic (toric)");
    fprintf(f, "curvature: %d step%s, %s fit over the central %.1f mm, K = 337.5/R (n 1.3375)\n",
            c->nstep - 1, c->nstep == 2 ? "" : "s", fitname, o->zone);
    fprintf(f, "incised meridian %.1f deg (%s)\n", axis_out(c->meridian, 1), c->meridian_src);
    fprintf(f, "pre-op (step 0): K %.2f D @ %.0f / %.2f D @ %.0f, cylinder %.2f D, mean K %.2f D\n",
            r0->k.k_steep, axis_out(r0->k.axis_steep, 0), r0->k.k_flat, axis_out(r0->k.axis_steep + 90, 0), r0->k.cyl,
            r0->k.k_mean);
    fprintf(f, "%5s %15s %7s %6s %8s %10s %10s %8s %14s\n", "step", "K steep @ axis", "K flat", "cyl",
            "dK mean", "flattening", "steepening", "coupling", "SIA @ axis");
    for (int i = 0; i < c->nstep; i++) {
        const step_res *r = c->res + i;
        step_cmp d;
        compare(c, i, &d);
        char cr[32];
        if (isnan(d.coupling)) snprintf(cr, sizeof cr, "-");
        else snprintf(cr, sizeof cr, "%.2f", d.coupling);
        fprintf(f, "%5d %7.2f @ %5.1f %7.2f %6.2f %+8.2f %+10.3f %+10.3f %8s %6.2f @ %5.1f\n", i, r->k.k_steep,
                axis_out(r->k.axis_steep, 1), r->k.k_flat, r->k.cyl, d.dk_mean, d.flat, d.steep, cr,
                d.va.sia.mag, axis_out(d.va.sia.axis, 1));
    }
    const step_res *rl = c->res + c->nstep - 1;
    if (r0->has_post)
        fprintf(f, "posterior K %.2f D @ %.0f / %.2f D (n %.3f -> %.3f), total corneal power %.2f D @ %.0f / %.2f D, "
                   "cylinder %.2f D (thick lens, %.3f mm); last step: %.2f D @ %.0f / %.2f D, cylinder %.2f D\n",
                r0->tot.post_steep, axis_out(r0->tot.post_axis, 0), r0->tot.post_flat, c->n.cornea, c->n.aqueous,
                r0->tot.tot_steep, axis_out(r0->tot.tot_axis, 0), r0->tot.tot_flat, r0->tot.tot_cyl, r0->tot.thickness,
                rl->tot.tot_steep, axis_out(rl->tot.tot_axis, 0), rl->tot.tot_flat, rl->tot.tot_cyl);
    if (c->has_target && c->nstep > 1) {
        step_cmp d;
        compare(c, c->nstep - 1, &d);
        fprintf(f, "target: correct %.2f D @ %.0f, TIA %.2f D @ %.0f; step %d: SIA %.2f D @ %.1f, "
                   "correction index %.2f, angle of error %+.1f deg, difference vector %.2f D @ %.1f\n",
                c->tia.mag, axis_out(c->tia.axis + 90, 0), c->tia.mag, axis_out(c->tia.axis, 0), c->nstep - 1,
                d.va.sia.mag, axis_out(d.va.sia.axis, 1), d.va.ci, d.va.ae, d.va.dv.mag, axis_out(d.va.dv.axis, 1));
    }
}

/* ---------------------------------------------------------------- JSON, ParaView, report */

/* Degrees of arc opened per incision at step i (the plan's first incision), NaN without one. */
static double arc_of(const run_ctx *c, int i)
{
    if (!c->plan_in || c->plan_in->ninc < 1 || !(c->plan_in->inc[0].prog.degrees_per_step > 0)) return NAN;
    return fmin(i * c->plan_in->inc[0].prog.degrees_per_step, c->plan_in->inc[0].arc);
}

static void jnum(FILE *f, const char *key, double v, int last)
{
    fprintf(f, "\"%s\": ", key);
    if (isfinite(v)) fprintf(f, "%.6g", v);
    else fputs("null", f);
    fputs(last ? "" : ", ", f);
}

static void jstr(FILE *f, const char *key, const char *v)
{
    fprintf(f, "\"%s\": \"", key);
    for (; *v; v++) {
        if (*v == '"' || *v == '\\') fprintf(f, "\\%c", *v);
        else if ((unsigned char)*v < 0x20) fprintf(f, "\\u%04x", *v);
        else fputc(*v, f);
    }
    fputs("\", ", f);
}

/* The summary as one JSON object: settings, then one object per step. */
static void summary_json(const run_ctx *c, FILE *f)
{
    fputs("{", f);
    jstr(f, "keratome", KT_VERSION);
    jstr(f, "fit", c->o->fit == KT_FIT_ZERNIKE ? "zernike" : "toric");
    jnum(f, "zone_mm", c->o->zone, 0);
    jnum(f, "incised_deg", axis_out(c->meridian, 4), 0);
    jstr(f, "incised_from", c->meridian_src);
    jnum(f, "n_cornea", c->n.cornea, 0);
    jnum(f, "n_aqueous", c->n.aqueous, 0);
    fputs("\"target\": ", f);
    if (c->has_target) {
        fputs("{", f);
        jnum(f, "tia_D", c->tia.mag, 0);
        jnum(f, "tia_axis_deg", axis_out(c->tia.axis, 4), 1);
        fputs("}, ", f);
    } else {
        fputs("null, ", f);
    }
    fputs("\"steps\": [", f);
    for (int i = 0; i < c->nstep; i++) {
        const step_res *r = c->res + i;
        step_cmp d;
        compare(c, i, &d);
        fprintf(f, "%s\n  {\"step\": %d, ", i ? "," : "", i);
        jnum(f, "arc_deg", arc_of(c, i), 0);
        jnum(f, "k_steep_D", r->k.k_steep, 0);
        jnum(f, "k_flat_D", r->k.k_flat, 0);
        jnum(f, "axis_steep_deg", axis_out(r->k.axis_steep, 4), 0);
        jnum(f, "cyl_D", r->k.cyl, 0);
        jnum(f, "k_mean_D", r->k.k_mean, 0);
        jnum(f, "flattening_D", d.flat, 0);
        jnum(f, "steepening_D", d.steep, 0);
        jnum(f, "coupling_ratio", d.coupling, 0);
        jnum(f, "sia_D", d.va.sia.mag, 0);
        jnum(f, "sia_axis_deg", axis_out(d.va.sia.axis, 4), 0);
        jnum(f, "dv_D", d.va.dv.mag, 0);
        jnum(f, "correction_index", d.va.ci, 0);
        jnum(f, "angle_error_deg", d.va.ae, 0);
        jnum(f, "index_of_success", d.va.ios, 0);
        jnum(f, "post_k_steep_D", r->tot.post_steep, 0);
        jnum(f, "post_k_flat_D", r->tot.post_flat, 0);
        jnum(f, "post_axis_deg", axis_out(r->tot.post_axis, 4), 0);
        jnum(f, "thickness_mm", r->tot.thickness, 0);
        jnum(f, "total_k_steep_D", r->tot.tot_steep, 0);
        jnum(f, "total_k_flat_D", r->tot.tot_flat, 0);
        jnum(f, "total_axis_deg", axis_out(r->tot.tot_axis, 4), 0);
        jnum(f, "total_cyl_D", r->tot.tot_cyl, 1);
        fputs("}", f);
    }
    fputs("\n]}\n", f);
}

/* steps.pvd: the step VTKs as one ParaView time series (time: degrees of arc opened per
 * incision when the plan cuts arcs, else the step number). File names are relative when the
 * collection sits beside them, absolute otherwise. */
static int write_pvd(run_ctx *c, kt_err *e)
{
    char path[PATHMAX], a[PATHMAX], b[PATHMAX];
    int beside = realpath(c->o->run_dir, a) && realpath(c->outdir, b) && strcmp(a, b) == 0;
    int by_arc = c->nstep > 1 && isfinite(arc_of(c, 1));
    for (int i = 1; by_arc && i < c->nstep; i++) by_arc = arc_of(c, i) > arc_of(c, i - 1);
    kt_out out;
    if (tmp_path(c, path, "steps.pvd", e) || kt_out_open(&out, path, e)) return e->code;
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
        fprintf(f, "    <DataSet timestep=\"%g\" part=\"0\" file=\"", by_arc ? arc_of(c, i) : i);
        for (const char *q = beside ? name : a; *q; q++) {
            if (*q == '&') fputs("&amp;", f);
            else if (*q == '"') fputs("&quot;", f);
            else if (*q == '<') fputs("&lt;", f);
            else fputc(*q, f);
        }
        fputs("\"/>\n", f);
    }
    fputs("  </Collection>\n</VTKFile>\n", f);
    if (kt_out_commit(&out, e) || add_file(c, "steps.pvd", e)) return e->code;
    return KT_OK;
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

/* Sum of steps.tsv's t_total_ms column (NaN when absent). */
static double solver_ms(const char *dir)
{
    char path[PATHMAX], line[4096];
    if ((size_t)snprintf(path, sizeof path, "%s/steps.tsv", dir) >= sizeof path) return NAN;
    FILE *f = fopen(path, "r");
    if (!f) return NAN;
    int col = -1, ln = 0;
    double sum = 0;
    while (fgets(line, sizeof line, f)) {
        int k = 0;
        char *save = NULL;
        for (char *t = strtok_r(line, "\t\n", &save); t; t = strtok_r(NULL, "\t\n", &save), k++) {
            if (ln == 0 && strcmp(t, "t_total_ms") == 0) col = k;
            else if (ln > 0 && k == col) sum += strtod(t, NULL);
        }
        ln++;
    }
    fclose(f);
    return col >= 0 ? sum : NAN;
}

static int write_report(run_ctx *c, kt_err *e)
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
        st[i].arc = arc_of(c, i);
    }
    char yaml[PATHMAX], fitname[64], path[PATHMAX];
    char *run_yaml = NULL;
    if (c->o->run_dir && join(yaml, c->o->run_dir, "run.yaml", e) == KT_OK) run_yaml = slurp(yaml);
    if (c->o->fit == KT_FIT_ZERNIKE) snprintf(fitname, sizeof fitname, "Zernike order %d", c->res[0].fit.order);
    else snprintf(fitname, sizeof fitname, "biconic (toric)");
    kt_report r;
    memset(&r, 0, sizeof r);
    r.version = KT_VERSION, r.run_dir = c->o->run_dir ? c->o->run_dir : ".", r.mesh = c->mesh;
    r.plan_path = c->plan_in ? c->plan_in->path : NULL, r.run_yaml = run_yaml, r.plan = c->plan_in;
    r.mesh_nn = c->mesh_nn, r.mesh_ne = c->mesh_ne, r.mesh_order = c->mesh_order;
    r.nstep = c->nstep, r.step = st, r.meridian = c->meridian, r.has_target = c->has_target, r.tia = c->tia;
    r.map_pre = &c->res[0].map, r.map_post = &c->res[c->nstep - 1].map;
    r.rad_pre = c->res[0].map_radius, r.rad_post = c->res[c->nstep - 1].map_radius;
    r.zone = c->o->zone, r.fit_name = fitname, r.scale = &c->scale, r.diff_scale = &c->diff_scale;
    r.section = c->section.n > 0 ? &c->section : NULL;
    r.solver_ms = c->o->run_dir ? solver_ms(c->o->run_dir) : NAN;
    r.curv_s = kt_now() - c->t0;
    r.n = &c->n;
    int rc = tmp_path(c, path, "report.html", e);
    if (rc == KT_OK) rc = kt_curv_report_write(path, &r, e);
    if (rc == KT_OK) rc = add_file(c, "report.html", e);
    free(run_yaml), free(st);
    return rc;
}

/* ---------------------------------------------------------------- driver */

static int setup(run_ctx *c, kt_err *e)
{
    const kt_curv_opts *o = c->o;
    c->meridian = o->meridian;
    c->meridian_src = "--meridian";
    if (o->run_dir) {
        int declared;
        if (read_run_yaml(c, &declared, e) || list_steps(c, declared, e)) return e->code;
    } else {
        if (!o->mesh || o->nvtk < 1) return kt_fail(e, KT_EINPUT, "expected RUN_DIR, or --mesh MESH.msh STEP.vtk...");
        if (strlen(o->mesh) >= PATHMAX) return kt_fail(e, KT_EINPUT, "%s: path too long", o->mesh);
        strcpy(c->mesh, o->mesh);
        c->vtk = kt_calloc(o->nvtk, sizeof(char *), e);
        if (!c->vtk) return e->code;
        for (int i = 0; i < o->nvtk; i++, c->nstep++)
            if (!(c->vtk[i] = kt_strdup(o->vtk[i], e))) return e->code;
    }
    if (o->plan) {
        if (strlen(o->plan) >= PATHMAX) return kt_fail(e, KT_EINPUT, "%s: path too long", o->plan);
        strcpy(c->plan, o->plan);
    }
    for (int i = 0; i < c->nstep; i++) /* every step file is there before any work starts */
        if (access(c->vtk[i], R_OK) != 0)
            return kt_fail(e, KT_EINPUT, "%s: cannot read the step file: %s", c->vtk[i], strerror(errno));
    if (c->plan[0] && read_plan(c, e)) return e->code;

    kt_mesh m;
    if (kt_msh_read(c->mesh, &m, e) != KT_OK) return e->code;
    c->mesh_nn = m.nn, c->mesh_ne = m.ne, c->mesh_order = m.order;
    int rc = kt_curv_anterior_mask(&m, c->mesh, &c->mask, e);
    if (rc == KT_OK) rc = kt_curv_posterior_mask(&m, &c->post_mask, e);
    kt_mesh_free(&m);
    if (rc) return rc;
    kt_cornea_n_default(&c->n);

    if (o->png || o->report) {
        char scale[PATHMAX];
        const char *share = o->share ? o->share : getenv("KERATOME_SHARE");
        if (!share) share = KT_SHARE_DIR;
        if (o->scale) snprintf(scale, sizeof scale, "%s", o->scale);
        else if (join(scale, share, "colour/axial.tsv", e)) return e->code;
        if (kt_topo_scale_load(scale, &c->scale, e)) return e->code;
        if (o->report && (join(scale, share, "colour/difference.tsv", e) || kt_topo_scale_load(scale, &c->diff_scale, e)))
            return e->code;
    }
    c->res = kt_calloc(c->nstep, sizeof(step_res), e);
    if (!c->res) return e->code;

    snprintf(c->outdir, sizeof c->outdir, "%s", o->outdir ? o->outdir : o->run_dir ? o->run_dir : ".");
    struct stat st;
    c->made_outdir = stat(c->outdir, &st) != 0;
    if (kt_mkdir_p(c->outdir, e)) return e->code;
    if (join(c->tmpdir, c->outdir, ".curvature.tmp.XXXXXX", e)) return e->code;
    if (!mkdtemp(c->tmpdir)) {
        int err = errno;
        c->tmpdir[0] = '\0';
        return kt_fail(e, KT_EINPUT, "%s: cannot create a temporary folder: %s", c->outdir, strerror(err));
    }
    return KT_OK;
}

static void ctx_free(run_ctx *c)
{
    for (int i = 0; i < c->nstep && c->vtk; i++) free(c->vtk[i]);
    for (int i = 0; i < c->nfile; i++) free(c->file[i]);
    free(c->vtk), free(c->file), free(c->mask), free(c->post_mask), free(c->res), free(c->u0);
    kt_section_free(&c->section);
    free(c->plan_in);
}

int kt_curv_run(const kt_curv_opts *o, FILE *out, kt_err *e)
{
    run_ctx *c = kt_calloc(1, sizeof(run_ctx), e);
    if (!c) return e->code;
    c->o = o;
    c->t0 = kt_now();
    int rc = setup(c, e);
    kt_progress pr;
    if (rc == KT_OK) kt_progress_start(&pr, "curvature", c->nstep, o->quiet);
    for (int i = 0; rc == KT_OK && i < c->nstep; i++) {
        rc = do_step(c, i, e);
        if (rc == KT_OK) kt_progress_update(&pr, i + 1);
        else if (pr.tty && !o->quiet) fputc('\n', stderr); /* end the bar before the error line */
    }
    if (rc == KT_OK) {
        kt_progress_end(&pr);
        if (isnan(c->meridian)) {
            c->meridian = c->res[0].k.axis_steep;
            c->meridian_src = "the steep meridian of step 0";
        }
        c->meridian = fmod(fmod(c->meridian, 180) + 180, 180);
        rc = write_tables(c, e);
    }
    if (rc == KT_OK && o->run_dir) rc = write_pvd(c, e);
    if (rc == KT_OK && o->report) rc = write_report(c, e);
    if (rc == KT_OK) rc = commit_files(c, e);
    if (rc == KT_OK) (o->json ? summary_json : summary)(c, out);
    drop_tmpdir(c);
    if (rc != KT_OK && c->made_outdir) rmdir(c->outdir);
    ctx_free(c);
    free(c);
    return rc;
}
