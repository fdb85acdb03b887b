/* test_aug_output.c: a backward error above --tol after refinement is a loud KT_ERUN; bad
 * edits are KT_EINPUT; a 1,000-step run that only changes forces does not grow in memory.
 * (--output, for every method: test_solver.c.) */
#include <stdio.h>
#include <unistd.h>

#include "test_aug_scenario.h"
#include "kt_test.h"

/* Current resident set size in kB (Linux /proc/self/statm). */
static long rss_kb(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    long size = 0, res = 0;
    if (f) {
        if (fscanf(f, "%ld %ld", &size, &res) != 2) res = 0;
        fclose(f);
    }
    return res * (sysconf(_SC_PAGESIZE) / 1024);
}

/* A backward error that cannot be met (after one step of refinement) is a loud KT_ERUN. */
static void test_no_convergence(scenario *s)
{
    kt_err e = {0};
    kt_aug_opts o;
    kt_aug_opts_default(&o);
    o.quiet = 1;
    o.tol = 1e-30;
    kt_aug *A = NULL;
    CHECK(kt_aug_create(&A, &s->prob, &o, &e) == KT_ERUN, "expected KT_ERUN, got %d", e.code);
    CHECK(strstr(e.msg, "backward error") != NULL && strstr(e.msg, "refinement") != NULL,
          "message: %s", e.msg);
    CHECK(A == NULL, "a failed create returns no solver");
    kt_aug_free(A);
}

static void test_bad_edits(scenario *s)
{
    kt_err e = {0};
    kt_aug_opts o;
    kt_aug_opts_default(&o);
    o.quiet = 1;
    kt_aug *A = NULL;
    CHECK(kt_aug_create(&A, &s->prob, &o, &e) == KT_OK, "%s", e.msg);
    if (!A) return;
    int nn = kt_aug_mesh(A)->nn, el = 0;
    kt_step st = {0};
    st.index = 1;
    kt_edit bad_new = {.kind = KT_EDIT_DUP, .node = 0, .new_node = nn + 1, .nel = 1, .el = &el};
    kt_step_add(&st, &bad_new, &e);
    CHECK(kt_aug_step(A, &st, &e) == KT_EINPUT && strstr(e.msg, "next free"), "new node: %s",
          e.msg);
    kt_aug_free(A);
    A = NULL;
    e = (kt_err){0};
    CHECK(kt_aug_create(&A, &s->prob, &o, &e) == KT_OK, "%s", e.msg);
    kt_step_clear(&st);
    st.index = 1;
    el = 5; /* tet 6 does not hold node 1 of the grid's far corner */
    kt_edit not_there = {.kind = KT_EDIT_DUP, .node = nn - 1, .new_node = nn, .nel = 1, .el = &el};
    kt_step_add(&st, &not_there, &e);
    CHECK(kt_aug_step(A, &st, &e) == KT_EINPUT && strstr(e.msg, "does not hold"), "tet: %s",
          e.msg);
    kt_aug_free(A);
    A = NULL;
    e = (kt_err){0};
    CHECK(kt_aug_create(&A, &s->prob, &o, &e) == KT_OK, "%s", e.msg);
    kt_step_clear(&st);
    st.index = 1;
    kt_edit far = {.kind = KT_EDIT_FORCE, .node = nn + 3, .v = {1, 0, 0}};
    kt_step_add(&st, &far, &e);
    CHECK(kt_aug_step(A, &st, &e) == KT_EINPUT && strstr(e.msg, "force names node"), "force: %s",
          e.msg);
    kt_step_free(&st);
    kt_aug_free(A);
}

/* 1,000 steps that only change nodal forces: m stays 0 and memory flat. */
static void test_memory(scenario *s)
{
    kt_err e = {0};
    kt_aug_opts o;
    kt_aug_opts_default(&o);
    o.quiet = 1;
    kt_aug *A = NULL;
    CHECK(kt_aug_create(&A, &s->prob, &o, &e) == KT_OK, "%s", e.msg);
    if (!A) return;
    kt_step st = {0};
    long rss100 = 0, rss1000 = 0;
    int top = grid_node(s, 2, 2, s->nz - 1);
    for (int step = 1; step <= 1000 && !e.code; step++) {
        kt_step_clear(&st);
        st.index = step;
        kt_edit f = {.kind = KT_EDIT_FORCE, .node = top - (step % 3), .v = {1e-3 * (step % 7), 0, -1e-3}};
        kt_step_add(&st, &f, &e);
        if (kt_aug_step(A, &st, &e)) break;
        CHECK(kt_aug_last(A)->m == 0, "step %d: m %d", step, kt_aug_last(A)->m);
        if (step == 100) rss100 = rss_kb();
        if (step == 1000) rss1000 = rss_kb();
    }
    CHECK(e.code == KT_OK, "%s", e.msg);
    printf("memory: RSS %ld kB after 100 force steps, %ld kB after 1000\n", rss100, rss1000);
#ifndef __SANITIZE_ADDRESS__ /* ASan keeps freed blocks in quarantine: RSS says nothing there */
    CHECK(rss100 > 0 && rss1000 - rss100 < 512, "RSS grew by %ld kB over 900 force-only steps",
          rss1000 - rss100);
#endif
    kt_step_free(&st);
    kt_aug_free(A);
}

int main(void)
{
    kt_err e = {0};
    scenario beam;
    CHECK(scenario_box(&beam, 5, 5, 16, 1.0, 0.0, &e) == 0, "%s", e.msg);
    test_no_convergence(&beam);
    test_bad_edits(&beam);
    test_memory(&beam);
    scenario_free(&beam);
    return kt_test_done("test_aug_output");
}
