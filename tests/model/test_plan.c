/* test_plan.c: plan files read back field by field, and every kind of bad plan refused with
 * the file, line and column of the offending field; a plan built in memory (kt_plan_add_*)
 * resolves as the same plan read from a file does, and kt_plan_write_eye writes it so that
 * kt_plan_load reads the same values back. */
#define _XOPEN_SOURCE 700
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "eye.h"
#include "grid.h"
#include "kt_test.h"
#include "plan.h"
#include "plan_write.h"

static char dir[64];
static char eye_scene[PATH_MAX], beam_scene[PATH_MAX];

/* Write a plan whose first line names the eye (or beam) scene; returns its path. */
static const char *write_plan(const char *name, const char *scene, const char *body)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (scene) fprintf(f, "scene: %s\n", scene);
    fputs(body, f);
    fclose(f);
    return path;
}

/* Load a plan that must fail with KT_EINPUT at line:col of its file. */
static void expect_bad(const char *name, const char *scene, const char *body, int line, int col,
                       const char *words)
{
    const char *path = write_plan(name, scene, body);
    kt_plan *p = calloc(1, sizeof *p);
    kt_err e = {0};
    int rc = kt_plan_load(path, p, &e);
    char where[300];
    snprintf(where, sizeof where, "%s:%d:%d: ", path, line, col);
    CHECK(rc == KT_EINPUT, "%s: expected KT_EINPUT, got %d (%s)", name, rc, e.msg);
    CHECK(strncmp(e.msg, where, strlen(where)) == 0, "%s: expected '%s...', got '%s'", name, where, e.msg);
    CHECK(!words || strstr(e.msg, words), "%s: message '%s' lacks '%s'", name, e.msg, words);
    free(p);
}

static const char *LRI =
    "incisions:\n"
    "  - meridian: 90 deg\n"
    "    arc: 60 deg\n"
    "    depth: 550 um\n"
    "    position: {diameter: 10.5 mm}\n"
    "    paired: true\n"
    "    direction: ccw\n"
    "progression: {degrees_per_step: 2.5 deg}\n"
    "target: {magnitude: 1.25 D, axis: 85 deg}\n";

static void test_good(void)
{
    kt_err e = {0};
    kt_plan *p = calloc(1, sizeof *p);
    const char *path = write_plan("good.yaml", eye_scene, LRI);
    memset(&e, 0, sizeof e);
    CHECK(kt_plan_load(path, p, &e) == 0, "good plan: %s", e.msg);
    const kt_incision *inc = &p->inc[0];
    CHECK(p->ninc == 1 && inc->meridian == 90 && inc->arc == 60 && inc->paired, "incision fields");
    CHECK_NEAR(inc->depth, 0.55, 1e-15, "depth 550 um in mm");
    CHECK(inc->direction == KT_BLADE_CCW, "direction ccw");
    CHECK(strcmp(inc->surface, "incision-ring-1") == 0, "10.5 mm names the scene's ring: '%s'", inc->surface);
    CHECK(inc->prog.degrees_per_step == 2.5, "progression applies to the incision");
    CHECK(p->target.set && p->target.magnitude == 1.25 && p->target.axis == 85, "target");
    CHECK(p->snap.fraction == 0.25 && p->snap.min_quality == 0.05, "snap defaults");
    CHECK(inc->at.line == 3 && inc->at_depth.line == 5 && inc->at_position.line == 6,
          "marks: incision %d, depth %d, position %d", inc->at.line, inc->at_depth.line,
          inc->at_position.line);

    /* the shipped demo: depth from the fraction of the local thickness */
    memset(&e, 0, sizeof e);
    CHECK(kt_plan_load("plans/lri-paired-60.yaml", p, &e) == 0, "demo: %s", e.msg);
    double t = kt_eye_thickness(&p->scene.eye, 5.25);
    CHECK_NEAR(p->inc[0].depth, 0.9 * t, 1e-12, "depth_fraction 0.9 of the thickness at 5.25 mm");
    CHECK(p->inc[0].direction == KT_BLADE_CW && p->inc[0].prog.degrees_per_step == 5, "demo blade");
    char real[PATH_MAX];
    CHECK(realpath(p->scene_path, real) && strcmp(real, eye_scene) == 0, "scene relative to the plan");

    /* a diameter without a ring: no surface, the cut is snapped onto the cylinder */
    path = write_plan("cyl.yaml", eye_scene,
                      "incisions:\n  - {meridian: 0 deg, arc: 30 deg, depth_fraction: 0.5, "
                      "position: {diameter: 9.5 mm}, direction: centre-out}\n");
    memset(&e, 0, sizeof e);
    CHECK(kt_plan_load(path, p, &e) == 0, "cylinder plan: %s", e.msg);
    CHECK(p->inc[0].surface[0] == 0 && p->inc[0].diameter == 9.5, "no ring at 9.5 mm");
    CHECK(p->inc[0].direction == KT_BLADE_CENTRE_OUT && p->inc[0].prog.degrees_per_step == 5,
          "centre-out, default 5 degrees per step");

    /* a planar cut: the advance direction is made orthogonal to the normal and unit */
    path = write_plan("planar.yaml", beam_scene,
                      "planar_cut:\n"
                      "  point: [0 mm, 2 mm, 0 mm]\n"
                      "  normal: [0, 2, 0]\n"
                      "  advance: [0, 1, -1]\n"
                      "  length: 7.5 mm\n"
                      "  nodes_per_step: 5\n"
                      "  pull_force: 10 mN\n"
                      "  pull_surface: zmax\n"
                      "snap: {fraction: 0.1, min_quality: 0.2}\n");
    memset(&e, 0, sizeof e);
    CHECK(kt_plan_load(path, p, &e) == 0, "planar plan: %s", e.msg);
    const kt_planar *pl = &p->planar;
    CHECK(pl->set && pl->normal[1] == 1 && pl->advance[1] == 0 && pl->advance[2] == -1, "planar directions");
    CHECK(pl->length == 7.5 && pl->nodes_per_step == 5 && strcmp(pl->pull_surface, "zmax") == 0, "planar fields");
    CHECK_NEAR(pl->pull_force, 0.01, 1e-15, "10 mN in N");
    CHECK(p->snap.fraction == 0.1 && p->snap.min_quality == 0.2, "snap block");

    /* deformation */
    path = write_plan("deform.yaml", beam_scene,
                      "deform:\n"
                      "  - {surface: zmax, displacement: [0 mm, 100 um, 0 mm], components: y,\n"
                      "     nodes_per_step: 1, order: [1, 0, 0]}\n"
                      "  - {region: body, force: [0 N, 0 N, -2 mN], steps: 4}\n");
    memset(&e, 0, sizeof e);
    CHECK(kt_plan_load(path, p, &e) == 0, "deform plan: %s", e.msg);
    CHECK(p->ndeform == 2 && p->deform[0].kind == KT_DEFORM_FIX && p->deform[0].mask == 2 &&
          p->deform[0].nodes_per_step == 1 && p->deform[0].set_dim == 2, "deform 1");
    CHECK_NEAR(p->deform[0].v[1], 0.1, 1e-15, "100 um");
    CHECK(p->deform[1].kind == KT_DEFORM_FORCE && p->deform[1].steps == 4 && p->deform[1].set_dim == 3,
          "deform 2");
    CHECK_NEAR(p->deform[1].v[2], -0.002, 1e-15, "-2 mN");
    free(p);
}

static void test_bad(void)
{
    /* line 1 is the scene; the plan's fields follow */
    expect_bad("arc.yaml", eye_scene,
               "incisions:\n  - meridian: 90 deg\n    arc: 400 deg\n    depth: 600 um\n"
               "    position: {diameter: 10.5 mm}\n", 4, 10, "arc");
    expect_bad("depth0.yaml", eye_scene,
               "incisions:\n  - meridian: 90 deg\n    arc: 60 deg\n    depth: 0 um\n"
               "    position: {diameter: 10.5 mm}\n", 5, 12, "depth");
    expect_bad("deep.yaml", eye_scene,
               "incisions:\n  - meridian: 90 deg\n    arc: 60 deg\n    depth: 900 um\n"
               "    position: {diameter: 10.5 mm}\n", 5, 12, "thickness");
    expect_bad("deepring.yaml", eye_scene,
               "incisions:\n  - meridian: 90 deg\n    arc: 60 deg\n    depth_fraction: 0.95\n"
               "    position: {surface: incision-ring-1}\n", 5, 21, "incision-ready");
    expect_bad("unknown.yaml", eye_scene,
               "incisions:\n  - meridian: 90 deg\n    arc: 60 deg\n    depth: 600 um\n"
               "    blade: diamond\n    position: {diameter: 10.5 mm}\n", 6, 5, "blade");
    expect_bad("axis.yaml", eye_scene,
               "incisions:\n  - meridian: steep\n    arc: 60 deg\n    depth: 600 um\n"
               "    position: {diameter: 10.5 mm}\n", 3, 15, "meridian");
    expect_bad("target.yaml", eye_scene, "target: {magnitude: 1 D, axis: vertical}\n"
               "incisions:\n  - {meridian: 90 deg, arc: 60 deg, depth: 600 um, position: {diameter: 10.5 mm}}\n",
               2, 32, "axis");
    expect_bad("noscene.yaml", NULL,
               "incisions:\n  - {meridian: 90 deg, arc: 60 deg, depth: 600 um, position: {diameter: 10.5 mm}}\n",
               1, 1, "scene");
    expect_bad("missing.yaml", "no-such-scene.yaml",
               "incisions:\n  - {meridian: 90 deg, arc: 60 deg, depth: 600 um, position: {diameter: 10.5 mm}}\n",
               1, 8, "no-such-scene.yaml");
    expect_bad("dupkey.yaml", eye_scene,
               "incisions:\n  - meridian: 90 deg\n    arc: 60 deg\n    arc: 30 deg\n    depth: 600 um\n"
               "    position: {diameter: 10.5 mm}\n", 5, 5, "arc");
    expect_bad("ring.yaml", eye_scene,
               "incisions:\n  - {meridian: 90 deg, arc: 60 deg, depth: 600 um, position: {surface: ring-9}}\n",
               3, 72, "ring-9");
    expect_bad("dir.yaml", eye_scene,
               "incisions:\n  - {meridian: 90 deg, arc: 60 deg, depth: 550 um, position: {diameter: 10.5 mm},\n"
               "     direction: sideways}\n", 4, 17, "direction");
    expect_bad("pairarc.yaml", eye_scene,
               "incisions:\n  - {meridian: 90 deg, arc: 200 deg, depth: 550 um, position: {diameter: 10.5 mm},\n"
               "     paired: true}\n", 3, 29, "paired");
    expect_bad("both.yaml", eye_scene,
               "incisions:\n  - {meridian: 90 deg, arc: 60 deg, depth: 600 um, depth_fraction: 0.5,\n"
               "     position: {diameter: 10.5 mm}}\n", 3, 68, "depth");
    expect_bad("noop.yaml", eye_scene, "name: nothing\n", 1, 1, "incisions");
    expect_bad("boxinc.yaml", beam_scene,
               "incisions:\n  - {meridian: 90 deg, arc: 60 deg, depth: 600 um, position: {diameter: 10.5 mm}}\n",
               3, 3, "eye scene");
    expect_bad("normal.yaml", beam_scene,
               "planar_cut: {point: [0 mm, 2 mm, 0 mm], normal: [0, 0, 0], advance: [0, 0, 1], nodes_per_step: 5}\n",
               2, 49, "normal");
    expect_bad("unit.yaml", beam_scene,
               "planar_cut: {point: [0, 2 mm, 0 mm], normal: [0, 1, 0], advance: [0, 0, 1], nodes_per_step: 5}\n",
               2, 22, "point");
}

/* Limits (keratome-plan(5), keratome-scene(5)): refused at load time, at the field. */
static void test_limits(void)
{
    /* 60 deg at 1e-9 deg per step would be 6e10 steps; 3600 is the most a plan may ask for */
    expect_bad("tiny-step.yaml", eye_scene,
               "incisions:\n  - {meridian: 90 deg, arc: 60 deg, depth: 550 um, position: {diameter: 10.5 mm}}\n"
               "progression: {degrees_per_step: 1e-9 deg}\n", 4, 33, "at most 3600 steps");
    /* two incisions: 2 x 60 / 0.03 = 4000 > 3600, the second one's own progression */
    expect_bad("sum-step.yaml", eye_scene,
               "incisions:\n  - {meridian: 90 deg, arc: 60 deg, depth: 550 um, position: {diameter: 10.5 mm}}\n"
               "  - {meridian: 0 deg, arc: 60 deg, depth: 550 um, position: {diameter: 10.5 mm},\n"
               "     progression: {degrees_per_step: 0.03 deg}}\n"
               "progression: {degrees_per_step: 0.03 deg}\n", 5, 38, "incisions[1]");
    /* exactly at the bound: 3600 steps of 0.1 deg over a 360 deg arc */
    const char *path = write_plan("edge.yaml", eye_scene,
               "incisions:\n  - {meridian: 90 deg, arc: 360 deg, depth: 550 um, position: {diameter: 10.5 mm}}\n"
               "progression: {degrees_per_step: 0.1 deg}\n");
    kt_plan *p = calloc(1, sizeof *p);
    kt_err e = {0};
    CHECK(p && kt_plan_load(path, p, &e) == KT_OK, "3600 steps accepted: %s", e.msg);
    free(p);
    expect_bad("deform-steps.yaml", beam_scene,
               "deform:\n  - {surface: zmax, force: [0 N, 0 N, 1 N], steps: 3601}\n", 3, 52, "steps");
    /* blocks nested 17 deep (the top-level mapping is the first) */
    char deep[256] = "name: [";
    for (int i = 0; i < 16; i++) strcat(deep, "[");
    strcat(deep, "1");
    for (int i = 0; i < 17; i++) strcat(deep, "]");
    strcat(deep, "\n");
    expect_bad("nested.yaml", eye_scene, deep, 2, 22, "nested at most 16 deep");
}

/* The plan against meshes: a missing surface is refused at the field naming it. */
static void test_mesh_check(void)
{
    kt_err e = {0};
    kt_plan *p = calloc(1, sizeof *p);
    const char *path = write_plan("good.yaml", eye_scene, LRI);
    memset(&e, 0, sizeof e);
    CHECK(kt_plan_load(path, p, &e) == 0, "%s", e.msg);
    kt_mesh m;
    memset(&e, 0, sizeof e);
    CHECK(kt_grid_box(&m, 3, 3, 3, 1, 1, 1, &e) == 0, "%s", e.msg);
    CHECK(kt_plan_check_mesh(p, &m, "box.msh", &e) == KT_EINPUT, "no anterior surface");
    char where[300];
    snprintf(where, sizeof where, "%s:3:5: expected a surface 'anterior' in mesh box.msh", path);
    CHECK(strncmp(e.msg, where, strlen(where)) == 0, "got '%s'", e.msg);
    memset(&e, 0, sizeof e);
    kt_mesh_add_group(&m, 2, 99, "anterior", &e);
    CHECK(kt_plan_check_mesh(p, &m, "box.msh", &e) == KT_EINPUT, "no ring surface");
    snprintf(where, sizeof where, "%s:6:26: expected a surface 'incision-ring-1' in mesh box.msh", path);
    CHECK(strncmp(e.msg, where, strlen(where)) == 0, "got '%s'", e.msg);
    kt_mesh_free(&m);
    free(p);
}

/* The same LRI plan built in memory and read from the file the writer makes of it. */
static void test_memory(void)
{
    kt_err e = {0};
    kt_plan *m = calloc(1, sizeof *m), *f = calloc(1, sizeof *f), *y = calloc(1, sizeof *y);
    const char *path = write_plan("mem-scene.yaml", eye_scene, "incisions:\n  - {meridian: 0 deg, arc: 10 deg, depth: 500 um, "
                                  "position: {diameter: 10.5 mm}}\n");
    CHECK(kt_plan_load(path, y, &e) == 0, "a plan to take the scene from: %s", e.msg);
    kt_plan_init(m, &y->scene, "in-memory");
    m->prog.degrees_per_step = 5;
    kt_tunnel t = {0};
    t.meridian = 180, t.width = 2.4, t.length = KT_TUNNEL_LENGTH, t.entry_diameter = y->scene.eye.wtw, t.steps = 4;
    kt_incision in;
    memset(&in, 0, sizeof in);
    in.meridian = 95, in.arc = 45, in.arc_opposite = 30, in.paired = 1, in.depth_fraction = 0.9;
    in.direction = KT_BLADE_CENTRE_OUT, in.prog = m->prog;
    snprintf(in.surface, sizeof in.surface, "incision-ring-1");
    CHECK(kt_plan_add_tunnel(m, &t, &e) == 0 && kt_plan_add_incision(m, &in, &e) == 0, "built in memory: %s", e.msg);
    double t_ring = kt_eye_thickness(&y->scene.eye, 0.5 * 10.5);
    CHECK(fabs(m->inc[0].diameter - 10.5) < 1e-12 && fabs(m->inc[0].depth - 0.9 * t_ring) < 1e-12,
          "the ring's diameter and the depth resolved (%g mm, %g mm)", m->inc[0].diameter, m->inc[0].depth);
    m->target.set = 1, m->target.magnitude = 1.25, m->target.axis = 95;
    char out[300];
    snprintf(out, sizeof out, "%s/written.yaml", dir);
    FILE *w = fopen(out, "w");
    CHECK(w && kt_plan_write_eye(w, m, "in-memory", eye_scene, "a test", &e) == 0, "written: %s", e.msg);
    if (w) fclose(w);
    CHECK(kt_plan_load(out, f, &e) == 0, "read back: %s", e.msg);
    const kt_incision *a = &m->inc[0], *b = &f->inc[0];
    CHECK(f->ninc == 1 && f->ntunnel == 1 && a->meridian == b->meridian && a->arc == b->arc && a->arc_opposite == b->arc_opposite &&
              a->depth == b->depth && a->diameter == b->diameter && a->paired == b->paired && a->direction == b->direction &&
              a->prog.degrees_per_step == b->prog.degrees_per_step && strcmp(a->surface, b->surface) == 0,
          "the incision reads back the same");
    const kt_tunnel *ta = &m->tunnel[0], *tb = &f->tunnel[0];
    CHECK(ta->meridian == tb->meridian && ta->width == tb->width && ta->length == tb->length &&
              ta->entry_diameter == tb->entry_diameter && ta->steps == tb->steps && ta->exit[2] == tb->exit[2],
          "the tunnel reads back the same, its plane derived the same");
    CHECK(f->target.set && f->target.magnitude == 1.25 && f->target.axis == 95, "the target");
    in.arc = 200;
    CHECK(kt_plan_add_incision(m, &in, &e) == KT_EINPUT, "a paired arc over 180 deg is refused");
    memset(&e, 0, sizeof e);
    in.arc = 30, in.depth_fraction = 0, in.depth = 5;
    CHECK(kt_plan_add_incision(m, &in, &e) == KT_EINPUT && strstr(e.msg, "incisions[1].depth: expected less than the local "
                                                                  "thickness"), "too deep: '%s'", e.msg);
    free(m), free(f), free(y);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/kt-test-plan-XXXXXX");
    if (!mkdtemp(dir)) return 1;
    if (!realpath("plans/eye.yaml", eye_scene) || !realpath("plans/bench/beam-16.yaml", beam_scene)) {
        fprintf(stderr, "run from the repository root\n");
        return 1;
    }
    test_good();
    test_bad();
    test_limits();
    test_mesh_check();
    test_memory();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
    return kt_test_done("test_plan");
}
