/* test_augsolve_share.c: a run that borrows the caller's physics (kt_aug_run_opts.physics,
 * what lri-plan's families share) writes the same files, byte for byte, as a run that solves
 * its own. A coarse eye (plans/eye.yaml with larger elements, no floor refinement) with a
 * temporal main incision (a tunnel: cutplan snaps nodes and writes the mesh the runs solve) and
 * two families of arcs, a single arc and a pair (two edits streams and two snapped meshes, the
 * same bytes), with --uncertainty: the physics, the prestress and its derivatives solved once
 * (kt_aug_physics_solve) on the first family's snapped mesh; each family run twice, with the
 * physics lent and with none; every step VTK (displacements, derivative fields, the physics's
 * cell fields), uncertainty.tsv and steps.tsv's result columns compared (curvature reads
 * nothing else of a run). The lent physics is not changed by the runs; a physics solved
 * without the derivatives is not borrowed by a run with them (the run solves its own: the
 * same files again). */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "augsolve_run.h"
#include "cutplan_run.h"
#include "kt_test.h"
#include "meshprep_run.h"
#include "msh.h"
#include "scene.h"
#include "scene_write.h"

static char dir[] = "/tmp/kt-share.XXXXXX";

static void path(char *out, const char *leaf)
{
    snprintf(out, 512, "%s/%s", dir, leaf);
}

/* The whole file into *buf (NUL-terminated); its size, or -1. */
static long slurp(const char *p, char **buf)
{
    *buf = NULL;
    FILE *f = fopen(p, "rb");
    if (!f) return -1;
    long n = 0, cap = 1 << 16;
    char *b = malloc((size_t)cap + 1);
    size_t r;
    while (b && (r = fread(b + n, 1, (size_t)(cap - n), f)) > 0) {
        n += (long)r;
        if (n == cap) {
            char *nb = realloc(b, (size_t)(cap *= 2) + 1);
            if (!nb) free(b);
            b = nb;
        }
    }
    fclose(f);
    if (!b) return -1;
    b[n] = 0;
    *buf = b;
    return n;
}

static int same_file(const char *a, const char *b)
{
    char *x, *y;
    long nx = slurp(a, &x), ny = slurp(b, &y);
    int same = nx >= 0 && nx == ny && memcmp(x, y, (size_t)nx) == 0;
    free(x), free(y);
    return same;
}

/* steps.tsv without its timing columns (t_*): the rows' results. */
static int same_steps(const char *a, const char *b)
{
    char *x, *y;
    long nx = slurp(a, &x), ny = slurp(b, &y);
    int same = nx > 0 && ny > 0;
    char *sx = NULL, *sy = NULL, *lx = x, *ly = y;
    int time_col[32] = {0}, row = 0;
    while (same) {
        char *ex = lx ? strchr(lx, '\n') : NULL, *ey = ly ? strchr(ly, '\n') : NULL;
        if (!ex || !ey) {
            same = !ex && !ey;
            break;
        }
        *ex = *ey = 0;
        int k = 0;
        char *tx = strtok_r(lx, "\t", &sx), *ty = strtok_r(ly, "\t", &sy);
        for (; tx && ty; k++, tx = strtok_r(NULL, "\t", &sx), ty = strtok_r(NULL, "\t", &sy)) {
            if (row == 0 && k < 32) time_col[k] = strncmp(tx, "t_", 2) == 0;
            if ((k >= 32 || !time_col[k]) && strcmp(tx, ty) != 0) same = 0;
        }
        if (tx || ty) same = 0;
        lx = ex + 1, ly = ey + 1, row++;
    }
    free(x), free(y);
    return same && row > 1;
}

/* Every step VTK and uncertainty.tsv of run folder a equal b's, steps.tsv's results too;
 * *nvtk counts the step files. */
static void compare_runs(const char *a, const char *b, const char *what, int *nvtk)
{
    char pa[600], pb[600];
    *nvtk = 0;
    DIR *d = opendir(a);
    CHECK(d != NULL, "%s: cannot list", a);
    if (!d) return;
    struct dirent *de;
    while ((de = readdir(d)) != NULL) {
        const char *n = de->d_name;
        int vtk = strncmp(n, "step-", 5) == 0 && strstr(n, ".vtk");
        int tsv = strcmp(n, "uncertainty.tsv") == 0;
        if (!vtk && !tsv) continue;
        *nvtk += vtk;
        snprintf(pa, sizeof pa, "%s/%s", a, n);
        snprintf(pb, sizeof pb, "%s/%s", b, n);
        CHECK(same_file(pa, pb), "%s: %s differs from %s", what, pa, pb);
    }
    closedir(d);
    snprintf(pa, sizeof pa, "%s/steps.tsv", a);
    snprintf(pb, sizeof pb, "%s/steps.tsv", b);
    CHECK(same_steps(pa, pb), "%s: steps.tsv's results differ (%s, %s)", what, pa, pb);
}

/* augsolve (phys: lent, or NULL) into run folder `leaf`. */
static int run(const char *mesh, const char *edits, const char *leaf, const kt_aug_physics *phys,
               int uncertainty)
{
    char rd[512];
    path(rd, leaf);
    kt_err e = {0};
    kt_aug_run_opts o;
    kt_aug_run_opts_default(&o);
    o.mesh = mesh, o.edits = edits, o.run_dir = rd, o.binary = 1, o.aug.quiet = 1;
    o.uncertainty = uncertainty, o.physics = phys;
    if (kt_aug_run(&o, &e)) {
        fprintf(stderr, "augsolve %s: %s\n", leaf, e.msg);
        return 1;
    }
    return 0;
}

/* A checksum of the lent physics's arrays (they must not change while lent). */
static uint64_t sum_of(const kt_aug_physics *p)
{
    uint64_t h = 1469598103934665603ULL;
    size_t nsig = (size_t)p->ne * KT_FEM_NQ * 6;
    const double *arr[2 + 2 * KT_UQ_N] = {p->ph.td.sig, p->ph.td.C};
    size_t len[2 + 2 * KT_UQ_N] = {nsig, p->ph.td.C ? 36 * (size_t)p->ne : 0};
    int n = 2;
    for (int k = 0; k < p->sens.nd; k++) {
        arr[n] = p->sens.d[k].td.sig, len[n++] = p->sens.d[k].td.sig ? nsig : 0;
        arr[n] = p->sens.d[k].td.C, len[n++] = 36 * (size_t)p->ne;
    }
    for (int a = 0; a < n; a++)
        for (size_t i = 0; arr[a] && i < len[a]; i++) {
            uint64_t v;
            memcpy(&v, arr[a] + i, sizeof v);
            h = (h ^ v) * 1099511628211ULL;
        }
    for (int i = 0; p->ph.perm && i < 3 * p->nn; i++) h = (h ^ (uint64_t)p->ph.perm[i]) * 1099511628211ULL;
    return h;
}

static int write_plan(const char *p, const char *name, int paired)
{
    FILE *f = fopen(p, "w");
    if (!f) return 1;
    fprintf(f, "name: share-%s\nscene: eye.yaml\nincisions:\n  - meridian: 90 deg\n    arc: 20 deg\n"
            "    depth_fraction: 0.9\n    position: {surface: incision-ring-1}\n    paired: %s\n"
            "    direction: centre-out\nprogression: {degrees_per_step: 10 deg}\n"
            "tunnels:\n  - {meridian: 180 deg, width: 2.4 mm, steps: 2}\n",
            name, paired ? "true" : "false");
    return fclose(f) != 0;
}

int main(void)
{
    if (!mkdtemp(dir)) return 1;
    char scene[512], mesh[512], plan[2][512], edits[2][512], cut[2][512];
    kt_err e = {0};
    path(scene, "eye.yaml");
    path(mesh, "eye.msh");
    /* the coarse eye: plans/eye.yaml's sizes as tests/lriplan_main.sh coarsens them */
    kt_scene *s = calloc(1, sizeof *s);
    int ok = s && kt_scene_load("plans/eye.yaml", s, &e) == KT_OK;
    CHECK(ok, "plans/eye.yaml: %s", e.msg);
    if (ok) {
        s->eye.h_optical = 0.8, s->eye.h_incision = 0.4, s->eye.h_cornea = 1.0;
        s->eye.h_sclera = 2.5, s->eye.h_floor = 0;
        FILE *f = fopen(scene, "w");
        ok = f && kt_scene_write_eye(f, s, "test_augsolve_share: a coarse eye", &e) == KT_OK;
        ok = (f && fclose(f) == 0) && ok;
        CHECK(ok, "%s: %s", scene, e.msg);
    }
    free(s);
    kt_prep_opts po = {scene, mesh, 0, 0, 1, 1};
    if (ok) {
        ok = kt_prep_run_table(&po, KT_PREP_TABLE_CHOSEN, NULL, &e) == KT_OK;
        CHECK(ok, "mesh-prep: %s", e.msg);
    }
    static const char *const fam[2] = {"single", "paired"};
    for (int k = 0; k < 2 && ok; k++) {
        char leaf[64];
        snprintf(leaf, sizeof leaf, "plan-%s.yaml", fam[k]);
        path(plan[k], leaf);
        snprintf(leaf, sizeof leaf, "%s.edits", fam[k]);
        path(edits[k], leaf);
        snprintf(leaf, sizeof leaf, "mesh-%s.msh", fam[k]);
        path(cut[k], leaf);
        ok = write_plan(plan[k], fam[k], k) == 0;
        kt_cutplan_opts co = {plan[k], mesh, edits[k], cut[k], 1, 1};
        ok = ok && kt_cutplan_run(&co, &e) == KT_OK;
        CHECK(ok, "cutplan %s: %s", fam[k], e.msg);
    }
    if (ok) {
        /* the tunnel snaps the same nodes whatever the arcs: one intact mesh for both */
        kt_mesh m0, m1, m;
        ok = kt_msh_read(cut[0], &m0, &e) == KT_OK && kt_msh_read(cut[1], &m1, &e) == KT_OK &&
             kt_msh_read(mesh, &m, &e) == KT_OK;
        CHECK(ok, "reading the meshes: %s", e.msg);
        if (ok) {
            CHECK(kt_mesh_hash(&m0) == kt_mesh_hash(&m1), "the families' snapped meshes differ");
            CHECK(kt_mesh_hash(&m0) != kt_mesh_hash(&m), "the tunnel snapped no node");
            kt_mesh_free(&m0), kt_mesh_free(&m1), kt_mesh_free(&m);
        }
    }
    kt_aug_physics P, Q;
    memset(&P, 0, sizeof P), memset(&Q, 0, sizeof Q);
    if (ok) {
        ok = kt_aug_physics_solve(&P, cut[0], scene, 1, 1, &e) == KT_OK;
        CHECK(ok, "kt_aug_physics_solve: %s", e.msg);
        CHECK(!ok || (P.ph.prestressed && P.sens.nd > 0 && P.ph.perm), "a prestressed physics with "
              "derivatives and its order (prestressed %d, %d derivatives)", P.ph.prestressed, P.sens.nd);
    }
    if (ok) {
        uint64_t before = sum_of(&P);
        for (int k = 0; k < 2 && ok; k++) {
            char own[64], lent[64], a[512], b[512];
            snprintf(own, sizeof own, "run-%s-own", fam[k]);
            snprintf(lent, sizeof lent, "run-%s-lent", fam[k]);
            ok = run(cut[k], edits[k], own, NULL, 1) == 0 && run(cut[k], edits[k], lent, &P, 1) == 0;
            CHECK(ok, "%s: the runs failed", fam[k]);
            if (!ok) break;
            path(a, own), path(b, lent);
            int nvtk = 0;
            compare_runs(a, b, fam[k], &nvtk);
            CHECK(nvtk >= 4, "%s: %d step files compared", fam[k], nvtk);
        }
        CHECK(sum_of(&P) == before, "the lent physics changed");
    }
    if (ok) {
        /* without the derivatives: not the uncertainty run's physics; it solves its own */
        ok = kt_aug_physics_solve(&Q, cut[0], scene, 0, 1, &e) == KT_OK;
        CHECK(ok, "kt_aug_physics_solve without derivatives: %s", e.msg);
        char a[512], b[512];
        if (ok && run(cut[0], edits[0], "run-single-q", &Q, 1) == 0) {
            path(a, "run-single-own"), path(b, "run-single-q");
            int nvtk = 0;
            compare_runs(a, b, "single, physics without derivatives", &nvtk);
        } else {
            CHECK(0, "the run lent a physics without derivatives failed");
        }
    }
    kt_aug_physics_free(&P);
    kt_aug_physics_free(&Q);
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
    return kt_test_done("test_augsolve_share");
}
