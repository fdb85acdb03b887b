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
#include "tsv.h"
#include "yml.h"

#include "curvature_int.h"


void kt_curv_opts_default(kt_curv_opts *o)
{
    memset(o, 0, sizeof *o);
    o->zone = KT_CURV_ZONE_DEFAULT;
    o->map_zone = 8;
    o->fit = KT_CURV_FIT_DEFAULT;
    o->order = KT_CURV_ORDER_DEFAULT;
    o->map_order = 8;
    o->meridian = NAN;
    o->step_sel = -1;
    o->arc_sel = NAN;
    o->png = o->vtk_out = o->report = 1;
}

int kt_curvrun_join(char *dst, const char *dir, const char *name, kt_err *e)
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
    return kt_curvrun_join(dst, dir, path, e);
}

/* An axis in [0, 180) as it will print with `decimals` decimals: what would round to 180 is 0. */
double kt_curvrun_axis_out(double a, int decimals)
{
    if (isnan(a)) return a;
    a = fmod(fmod(a, 180) + 180, 180);
    return a >= 180 - 0.5 * pow(10, -decimals) ? 0 : a;
}

/* ---------------------------------------------------------------- the run folder */

/* A 16-hex-digit hash from run.yaml (a quoted string). */
static int yml_hash(kt_yml *y, yaml_node_t *root, const char *key, int required,
                    unsigned long long *v, int *has, kt_err *e)
{
    char buf[64], *end;
    yaml_node_t *n = required ? kt_yml_require(y, root, key, "run.yaml", e) : kt_yml_get(y, root, key);
    *has = 0;
    if (!n) return e->code;
    if (kt_yml_string(y, n, key, buf, sizeof buf, e)) return e->code;
    errno = 0;
    *v = strtoull(buf, &end, 16);
    if (strlen(buf) != 16 || *end || errno)
        return kt_yml_fail(y, n, e, "expected %s as 16 hex digits, found '%s'", key, buf);
    *has = 1;
    return KT_OK;
}

/* run.yaml's step_files: the step numbers whose files the run wrote, 0 first, increasing, none
 * beyond steps: (declared); into c->num, c->nstep. */
static int read_step_files(run_ctx *c, kt_yml *y, yaml_node_t *n, int declared, kt_err *e)
{
    int len = kt_yml_seq_len(n);
    if (kt_yml_check_seq(y, n, "step_files", 1, declared + 1, e)) return e->code;
    if (!(c->num = kt_calloc((size_t)len, sizeof(int), e))) return e->code;
    for (int i = 0; i < len; i++) {
        yaml_node_t *it = kt_yml_seq_item(y, n, i);
        if (kt_yml_int(y, it, "step_files", i ? c->num[i - 1] + 1 : 0, i ? declared : 0, &c->num[i], e))
            return e->code;
    }
    c->nstep = len;
    return KT_OK;
}

/* run.yaml: mesh, steps (the last step number) and mesh_hash (required), plan and plan_hash
 * (optional), step_files (optional: the steps written, augsolve --steps; without it every step
 * 0..steps): what the run is, checked against what is read (setup). */
static int read_run_yaml(run_ctx *c, int *declared, kt_err *e)
{
    char path[PATHMAX], buf[PATHMAX];
    if (kt_curvrun_join(path, c->o->run_dir, "run.yaml", e)) return e->code;
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
    if (rc == KT_OK && !kt_yml_require(&y, root, "steps", "run.yaml", e)) rc = e->code;
    if (rc == KT_OK) rc = kt_yml_key_int(&y, root, "run.yaml", "steps", 0, 1000000, declared, e);
    if (rc == KT_OK && (n = kt_yml_get(&y, root, "step_files")) != NULL) rc = read_step_files(c, &y, n, *declared, e);
    int has;
    if (rc == KT_OK) rc = yml_hash(&y, root, "mesh_hash", 1, &c->mesh_hash, &has, e);
    if (rc == KT_OK) rc = yml_hash(&y, root, "plan_hash", 0, &c->plan_hash, &c->has_plan_hash, e);
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

/* Every step listed in steps.tsv (its column step) must have its VTK. */
static int check_steps_tsv(const char *dir, const int *have, int nhave, kt_err *e)
{
    char path[PATHMAX];
    if (kt_curvrun_join(path, dir, "steps.tsv", e)) return e->code;
    if (access(path, F_OK) != 0) return KT_OK; /* optional */
    kt_tsv t;
    if (kt_tsv_open(&t, path, e)) return e->code;
    int col = kt_tsv_need(&t, "step", "a table of augsolve(1)");
    long long s;
    while (col >= 0 && kt_tsv_next(&t) > 0 && kt_tsv_int(&t, col, 0, 1000000, &s) == KT_OK)
        if (!bsearch(&(int){(int)s}, have, nhave, sizeof(int), cmp_int)) {
            kt_tsv_fail(&t, col, "step %lld is listed but %s/step-%04lld.vtk is missing", s, dir, s);
            break;
        }
    kt_tsv_close(&t);
    return e->code;
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
    /* the steps run.yaml records: step_files as listed, else every step 0..steps */
    int listed = c->num != NULL;
    if (!listed) {
        c->nstep = declared + 1;
        if (!(c->num = kt_calloc((size_t)c->nstep, sizeof(int), e))) rc = e->code;
        for (int i = 0; rc == KT_OK && i < c->nstep; i++) c->num[i] = i;
    }
    /* exactly the steps run.yaml records: one more is another run's (or a mix), one fewer a
     * run cut short */
    for (int i = 0, k = 0; rc == KT_OK && i < n; i++) {
        while (k < c->nstep && c->num[k] < num[i]) k++;
        if (k == c->nstep || c->num[k] != num[i])
            rc = kt_fail(e, KT_EINPUT, listed ? "%s/step-%04d.vtk: not a step of this run (run.yaml's step_files do "
                         "not list it): a previous run's file? remove it, or run augsolve again" :
                         "%s/step-%04d.vtk: not a step of this run (run.yaml says steps: %d): a previous "
                         "run's file? remove it, or run augsolve again", dir, num[i], declared);
    }
    for (int i = 0; rc == KT_OK && i < c->nstep; i++)
        if (!bsearch(&c->num[i], num, n, sizeof(int), cmp_int))
            rc = listed ? kt_fail(e, KT_EINPUT, "%s/step-%04d.vtk: missing (run.yaml's step_files list it)", dir, c->num[i])
                        : kt_fail(e, KT_EINPUT, "%s/step-%04d.vtk: missing (run.yaml says steps: %d, "
                                  "numbered 0, 1, 2, ... without gaps)", dir, c->num[i], declared);
    if (rc == KT_OK) rc = check_steps_tsv(dir, num, n, e);
    if (rc == KT_OK) {
        c->vtk = kt_calloc((size_t)c->nstep, sizeof(char *), e);
        for (int i = 0; c->vtk && i < c->nstep && rc == KT_OK; i++) {
            char name[64], path[PATHMAX];
            snprintf(name, sizeof name, "step-%04d.vtk", c->num[i]);
            if ((rc = kt_curvrun_join(path, dir, name, e)) == KT_OK && !(c->vtk[i] = kt_strdup(path, e))) rc = e->code;
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

int kt_curvrun_add_file(run_ctx *c, const char *name, kt_err *e)
{
    char **f = kt_realloc(c->file, c->nfile + 1, sizeof(char *), e);
    if (!f) return e->code;
    c->file = f;
    if (!(c->file[c->nfile] = kt_strdup(name, e))) return e->code;
    c->nfile++;
    return KT_OK;
}

int kt_curvrun_tmp_path(run_ctx *c, char *path, const char *name, kt_err *e)
{
    return kt_curvrun_join(path, c->tmpdir, name, e);
}

/* No output may replace an input (a step file, the mesh, the plan, --sens, the colour scale). */
static int outputs_distinct(run_ctx *c, kt_err *e)
{
    const char **in = kt_calloc((size_t)c->nstep + 5, sizeof *in, e);
    if (!in) return e->code;
    int n = 0;
    for (int i = 0; i < c->nstep && c->vtk; i++) in[n++] = c->vtk[i];
    in[n++] = c->mesh, in[n++] = c->plan, in[n++] = c->o->sens, in[n++] = c->o->scale;
    for (int i = 0; i < c->nfile && !e->code; i++) {
        char to[PATHMAX];
        if (kt_curvrun_join(to, c->outdir, c->file[i], e) == KT_OK) kt_out_distinct(to, in, n, e);
    }
    free(in);
    return e->code;
}

/* Rename every output into place (none of them an input); then the temporary folder goes. */
static int commit_files(run_ctx *c, kt_err *e)
{
    if (outputs_distinct(c, e)) return e->code;
    for (int i = 0; i < c->nfile; i++) {
        char from[PATHMAX], to[PATHMAX];
        if (kt_curvrun_join(from, c->tmpdir, c->file[i], e) || kt_curvrun_join(to, c->outdir, c->file[i], e)) return e->code;
        struct stat st; /* never rename over a device, a FIFO or a directory */
        if (lstat(to, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode))
            return kt_fail(e, KT_EINPUT, "%s: exists and is not a regular file: not replaced", to);
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
        if (kt_curvrun_join(p, c->tmpdir, c->file[i], &e2) == KT_OK) unlink(p);
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
        snprintf(name, sizeof name, "surface-%04d.vtk", c->num[step]);
        rc = kt_curvrun_tmp_path(c, path, name, e);
        if (rc == KT_OK) rc = kt_curvrun_add_file(c, name, e); /* first: a failed run removes what it names */
        if (rc == KT_OK) rc = kt_vtk_write_tri_grid(path, s->n, ref, s->ntri, s->tri, f, 4, 1, e);
    }
    free(elev), free(pow), free(ref), free(org);
    return rc;
}

static int write_map_png(run_ctx *c, int step, const kt_fit *map, const step_res *r, kt_err *e)
{
    kt_topo_map m;
    memset(&m, 0, sizeof m);
    m.cx = map->ax, m.cy = map->ay, m.radius = r->map_radius, m.zone = c->o->zone;
    snprintf(m.title[0], sizeof m.title[0], "AXIAL POWER (D)  STEP %d  MAP %.1f MM", c->num[step], 2 * r->map_radius);
    snprintf(m.title[1], sizeof m.title[1], "SIM K %.2f@%.0f\xC2\xB0 / %.2f@%.0f\xC2\xB0  CYL %.2f  ZONE %.0f MM",
             r->k.k_steep, kt_curvrun_axis_out(r->k.axis_steep, 0), r->k.k_flat, kt_curvrun_axis_out(r->k.axis_steep + 90, 0), r->k.cyl,
             c->o->zone);
    kt_topo_image img = {0, 0, NULL};
    char name[64], path[PATHMAX];
    snprintf(name, sizeof name, "axial-%04d.png", c->num[step]);
    int rc = kt_topo_render(&c->scale, &m, map_power, map, &img, e);
    if (rc == KT_OK) rc = kt_curvrun_tmp_path(c, path, name, e);
    if (rc == KT_OK) rc = kt_curvrun_add_file(c, name, e);
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
    /* a step of this mesh: its tets, and step 0 its nodes (later steps add duplicates) */
    if (rc == KT_OK && (v.ncell != c->mesh_ne || (step == 0 ? v.nn != c->mesh_nn : v.nn < c->mesh_nn)))
        rc = kt_fail(e, KT_EINPUT, "%s: %d points and %d cells, expected %s%d points and %d "
                     "tets (the mesh %s): a step of another mesh", c->vtk[step], v.nn, v.ncell,
                     step ? "at least " : "", c->mesh_nn, c->mesh_ne, c->mesh);
    if (rc == KT_OK) rc = kt_curvrun_band_step(c, step, &v, &s, e);
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
    if (rc == KT_OK && o->png && !o->scale_auto) rc = write_map_png(c, step, map, r, e);
    if (rc == KT_OK) r->map = *map;
    if (rc == KT_OK && r->has_post) kt_curv_total(&r->fit, &r->post, &c->n, &r->tot);
    free(map), free(pts);
    kt_surf_free(&s);
    return rc;
}

/* The range of a map fit's axial power over its disk (a 41 x 41 grid). */
static void map_range(const step_res *r, double *lo, double *hi)
{
    for (int i = 0; i <= 40; i++)
        for (int j = 0; j <= 40; j++) {
            double x = (i - 20) / 20.0 * r->map_radius, y = (j - 20) / 20.0 * r->map_radius;
            if (hypot(x, y) > r->map_radius) continue;
            double p = kt_fit_axial_power(&r->map, r->map.ax + x, r->map.ay + y);
            if (isfinite(p)) *lo = fmin(*lo, p), *hi = fmax(*hi, p);
        }
}

/* The relative scale (documented cases: the report's second row of maps, and --scale auto for
 * every map): one scale over the powers of every step's map, so colours compare across steps. */
static int auto_maps(run_ctx *c, kt_err *e)
{
    if (!c->o->png && !c->o->report) return KT_OK;
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < c->nstep; i++) map_range(c->res + i, &lo, &hi);
    if (kt_topo_scale_auto(&c->abs_scale, lo, hi, &c->rel_scale, e)) return e->code;
    if (!c->o->scale_auto) return KT_OK;
    c->scale = c->rel_scale;
    for (int i = 0; c->o->png && i < c->nstep; i++)
        if (write_map_png(c, i, &c->res[i].map, c->res + i, e)) return e->code;
    return KT_OK;
}

/* ---------------------------------------------------------------- step numbers, --step, --arc */

/* A run folder's steps are those run.yaml records (list_steps); files named step-NNNN.vtk after --mesh keep NNNN when the
 * numbers increase from 0, else they are numbered in the order given. */
static int number_steps(run_ctx *c, kt_err *e)
{
    if (c->o->run_dir) return KT_OK; /* numbered by run.yaml (list_steps) */
    if (!(c->num = kt_calloc(c->nstep, sizeof(int), e))) return e->code;
    int named = !c->o->run_dir;
    for (int i = 0; i < c->nstep; i++) {
        const char *b = strrchr(c->vtk[i], '/') ? strrchr(c->vtk[i], '/') + 1 : c->vtk[i];
        c->num[i] = named ? step_number(b) : i;
        if (named && (c->num[i] < 0 || (i == 0 && c->num[i] != 0) || (i > 0 && c->num[i] <= c->num[i - 1]))) named = 0;
    }
    if (!named)
        for (int i = 0; i < c->nstep; i++) c->num[i] = i;
    return KT_OK;
}

/* --step N / --arc DEG: keep step 0 and that step. */
static int select_step(run_ctx *c, kt_err *e)
{
    const kt_curv_opts *o = c->o;
    int k = -1;
    if (o->step_sel >= 0) {
        for (int i = 0; i < c->nstep; i++)
            if (c->num[i] == o->step_sel) k = i;
        if (k < 0)
            return kt_fail(e, KT_EINPUT, "--step %d: expected a step of the run, 0 to %d", o->step_sel, c->num[c->nstep - 1]);
    } else if (isfinite(o->arc_sel)) {
        if (!isfinite(kt_curvrun_arc(c, c->nstep - 1)))
            return kt_fail(e, KT_EINPUT, "--arc %g: expected a plan that cuts arcs (run.yaml's plan or --plan)", o->arc_sel);
        for (int i = 0; i < c->nstep && k < 0; i++)
            if (fabs(kt_curvrun_arc(c, i) - o->arc_sel) < 0.01) k = i;
        if (k < 0)
            return kt_fail(e, KT_EINPUT, "--arc %g: expected the arc of a step, %g to %g deg in steps of %g", o->arc_sel,
                           kt_curvrun_arc(c, 0), kt_curvrun_arc(c, c->nstep - 1),
                           c->plan_in->inc[0].prog.degrees_per_step);
    } else {
        return KT_OK;
    }
    if (k == 0) return kt_fail(e, KT_EINPUT, "--step/--arc: expected a step after step 0 (step 0 is the reference)");
    for (int i = 1; i < c->nstep; i++)
        if (i != k) free(c->vtk[i]);
    c->vtk[1] = c->vtk[k], c->num[1] = c->num[k];
    c->nstep = 2;
    return KT_OK;
}

/* The arc opened per incision at step i. cutplan cuts a plan's tunnels (main incisions) before
 * its incisions, each in its `steps` advances (keratome-plan(5), TUNNELS): those steps open no
 * arc (0), and the first incision's arc grows by degrees_per_step a step after them. (A tunnel
 * advance that split no node merges into the next one; on meshes that resolve the tunnel's site
 * every advance splits some, as lri-plan's scenes do.) */
double kt_curvrun_arc(const run_ctx *c, int i)
{
    if (!c->plan_in || c->plan_in->ninc < 1 || !(c->plan_in->inc[0].prog.degrees_per_step > 0)) return NAN;
    int ntun = 0;
    for (int k = 0; k < c->plan_in->ntunnel; k++) ntun += c->plan_in->tunnel[k].steps;
    int s = c->num[i] - ntun;
    if (s <= 0) return 0;
    return fmin(s * c->plan_in->inc[0].prog.degrees_per_step, c->plan_in->inc[0].arc);
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
    if (c->has_plan_hash && c->plan[0]) {
        unsigned long long h;
        if (kt_fnv1a_file(c->plan, &h, e)) return e->code;
        if (h != c->plan_hash)
            return kt_fail(e, KT_EINPUT, "%s: not the plan this run was made from (its bytes hash "
                           "to %016llx, run.yaml's plan_hash is %016llx): the plan changed since "
                           "the run, or --plan names another", c->plan, h, c->plan_hash);
    }
    if (c->plan[0] && read_plan(c, e)) return e->code;
    if (number_steps(c, e) || select_step(c, e)) return e->code;
    if (kt_curvrun_band_setup(c, e)) return e->code;

    kt_mesh m;
    if (kt_msh_read(c->mesh, &m, e) != KT_OK) return e->code;
    c->mesh_nn = m.nn, c->mesh_ne = m.ne, c->mesh_order = m.order;
    c->mesh_hash_read = kt_mesh_hash(&m);
    if (o->run_dir && c->mesh_hash_read != c->mesh_hash) {
        kt_mesh_free(&m);
        return kt_fail(e, KT_EINPUT, "%s: not the mesh this run was solved on (it hashes to "
                       "%016llx, run.yaml's mesh_hash is %016llx)", c->mesh, c->mesh_hash_read,
                       c->mesh_hash);
    }
    int rc = kt_curv_anterior_mask(&m, c->mesh, &c->mask, e);
    if (rc == KT_OK) rc = kt_curv_posterior_mask(&m, &c->post_mask, e);
    kt_mesh_free(&m);
    if (rc) return rc;
    kt_cornea_n_default(&c->n);

    if (o->png || o->report) {
        char scale[PATHMAX];
        const char *share = o->share ? o->share : getenv("KERATOME_SHARE");
        if (!share) share = KT_SHARE_DIR;
        if (o->scale && !o->scale_auto) snprintf(scale, sizeof scale, "%s", o->scale);
        else if (kt_curvrun_join(scale, share, "colour/axial.tsv", e)) return e->code;
        if (kt_topo_scale_load(scale, &c->scale, e)) return e->code;
        c->abs_scale = c->scale;
        if (o->report && (kt_curvrun_join(scale, share, "colour/difference.tsv", e) || kt_topo_scale_load(scale, &c->diff_scale, e)))
            return e->code;
    }
    c->res = kt_calloc(c->nstep, sizeof(step_res), e);
    if (!c->res) return e->code;

    snprintf(c->outdir, sizeof c->outdir, "%s", o->outdir ? o->outdir : o->run_dir ? o->run_dir : ".");
    struct stat st;
    c->made_outdir = stat(c->outdir, &st) != 0;
    if (kt_mkdir_p(c->outdir, e)) return e->code;
    if (kt_curvrun_join(c->tmpdir, c->outdir, ".curvature.tmp.XXXXXX", e)) return e->code;
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
    free(c->vtk), free(c->num), free(c->file), free(c->mask), free(c->post_mask), free(c->res), free(c->u0);
    kt_section_free(&c->section);
    free(c->plan_in);
    kt_curvrun_band_free(c);
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
        rc = auto_maps(c, e);
        if (rc == KT_OK) rc = kt_curvrun_band_finish(c, e);
        if (rc == KT_OK) rc = kt_curvrun_write_tables(c, e);
        if (rc == KT_OK) rc = kt_curvrun_band_write(c, e);
    }
    if (rc == KT_OK && o->run_dir) rc = kt_curvrun_write_pvd(c, e);
    if (rc == KT_OK && o->report) rc = kt_curvrun_write_report(c, e);
    if (rc == KT_OK) rc = commit_files(c, e);
    if (rc == KT_OK && out) (o->json ? kt_curvrun_summary_json : kt_curvrun_summary)(c, out);
    drop_tmpdir(c);
    if (rc != KT_OK && c->made_outdir) rmdir(c->outdir);
    ctx_free(c);
    free(c);
    return rc;
}
