/* test_benchtab.c: the benchmark table module on synthetic step tables with known medians,
 * ratios and sums; the Markdown it writes is read back; bad tables are refused with their line. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "benchtab.h"
#include "kt_test.h"

static char dir[] = "/tmp/kt_benchtab_XXXXXX";

static const char *put(const char *name, const char *text)
{
    static char path[4][256];
    static int k;
    char *p = path[k++ % 4];
    snprintf(p, 256, "%s/%s", dir, name);
    FILE *f = fopen(p, "w");
    fputs(text, f);
    fclose(f);
    return p;
}

/* planned: steps 1..4 take 10, 30, 20, 40 ms (median 25, worst 40); step 0 holds 1000 ms of
 * factorization. refactor: 500, 600, 400, 800 ms (ratios 50, 20, 20, 20: median 20, min 20). */
static const char PLANNED[] =
    "step\tn_dofs\tt_total_ms\tnnz_L\tt_verify_ms\n"
    "0\t9\t1000\t1000000\tNaN\n"
    "1\t9\t10\t1000000\t500\n"
    "2\t9\t30\t1000000\t900\n"
    "3\t9\t20\t1000000\t400\n"
    "4\t9\t40\t1000000\t1200\n";
static const char REFACTOR[] =
    "step\tt_total_ms\tnnz_L\n"
    "0\t450\t900000\n"
    "1\t500\t900000\n"
    "2\t600\t900000\n"
    "3\t400\t900000\n"
    "4\t800\t900000\n";
/* bench_steps' table: a tag first, a failed step (status fail) and one not run (budget). */
static const char PCG[] =
    "tag\tmethod\tstep\tt_total_ms\tnnz_L\tstatus\n"
    "x\tpcg-jacobi\t0\t100\t0\tok\n"
    "x\tpcg-jacobi\t1\t300\t0\tok\n"
    "x\tpcg-jacobi\t2\t900\t0\tfail\n"
    "x\tpcg-jacobi\t3\tNaN\tNaN\tbudget\n";

static void test_median(void)
{
    double a[] = {3, 1, NAN, 2}, b[] = {4, 1, 3, 2}, c[] = {NAN};
    CHECK(kt_bench_median(a, 4) == 2, "odd count, NaN skipped");
    CHECK(kt_bench_median(b, 4) == 2.5, "even count: the mean of the middle two");
    CHECK(isnan(kt_bench_median(c, 1)), "no value: NaN");
}

static void test_summary(void)
{
    kt_err e = {0};
    kt_bench_run r[3];
    CHECK(kt_bench_run_read(&r[0], "planned", put("p.tsv", PLANNED), &e) == KT_OK, "%s", e.msg);
    CHECK(kt_bench_run_read(&r[1], "refactor+metis", put("r.tsv", REFACTOR), &e) == KT_OK, "%s", e.msg);
    CHECK(kt_bench_run_read(&r[2], "pcg", put("c.tsv", PCG), &e) == KT_OK, "%s", e.msg);
    CHECK(kt_bench_run_peak(&r[0], put("p.time", "\tCommand being timed: \"x\"\n"
                                       "\tMaximum resident set size (kbytes): 204800\n"), &e) == KT_OK,
          "%s", e.msg);
    CHECK(kt_bench_run_peak(&r[1], put("r.time", "1.5\t0.2\t102400\n"), &e) == KT_OK, "%s", e.msg);
    CHECK_NEAR(r[0].peak_mb, 200, 1e-12, "peak from time -v");
    CHECK_NEAR(r[1].peak_mb, 100, 1e-12, "peak from bench.sh's time record");

    kt_bench_sum s;
    double bw = 8e9; /* 8 GB/s: the floor of 1e6 nonzeros is 1 ms */
    CHECK(kt_bench_summarize(&r[0], &r[0], bw, &s, &e) == 4, "4 common steps");
    CHECK(s.steps == 4 && s.failed == 0, "steps %d failed %d", s.steps, s.failed);
    CHECK_NEAR(s.med, 25, 1e-12, "planned median step");
    CHECK_NEAR(s.worst, 40, 1e-12, "planned worst step");
    CHECK_NEAR(s.whole, 1100, 1e-12, "whole plan: factorization + every step");
    CHECK_NEAR(s.verify_med, 30, 1e-12, "--verify ratios 50, 30, 20, 30: median");
    CHECK_NEAR(s.verify_min, 20, 1e-12, "--verify ratio minimum");
    CHECK_NEAR(s.bw_med, 25, 1e-12, "median step / 1 ms floor");
    CHECK(kt_bench_summarize(&r[1], &r[0], bw, &s, &e) == 4, "refactor: 4 common steps");
    CHECK_NEAR(s.ratio_med, 20, 1e-12, "refactor / planned, median of 50, 20, 20, 20");
    CHECK_NEAR(s.ratio_min, 20, 1e-12, "refactor / planned, minimum");
    CHECK_NEAR(s.med, 550, 1e-12, "refactor median step");
    CHECK(isnan(s.verify_med), "no --verify column: NaN");
    CHECK(kt_bench_summarize(&r[2], &r[0], bw, &s, &e) == 1, "pcg: one completed common step");
    CHECK(s.steps == 3 && s.failed == 2, "pcg: 3 steps, 2 not completed (%d, %d)", s.steps, s.failed);
    CHECK_NEAR(s.ratio_med, 30, 1e-12, "pcg / planned on step 1");
    CHECK_NEAR(s.whole, 1300, 1e-12, "pcg whole: the rows with a time");
    CHECK(isnan(s.bw_med), "no factor: no bandwidth figure");

    /* the table, read back: the refactor row's cells */
    const char *md = put("t.md", "");
    FILE *f = fopen(md, "w");
    CHECK(kt_bench_table(f, "### case", r, 3, bw, &e) == KT_OK, "%s", e.msg);
    fclose(f);
    f = fopen(md, "r");
    char line[1024];
    int rows = 0, found = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '|') rows++;
        if (strncmp(line, "| refactor+metis |", 18) == 0) {
            found = 1;
            /* steps, median, worst, ratio, whole, whole / one refactor (2750 / 550), peak, peak / ref */
            CHECK(strstr(line, "| 4 (0) | 550.0 | 800.0 | 20 (20) | 2750 | 5 | 100 | 1 |") != NULL,
                  "refactor row: %s", line);
        }
        if (strncmp(line, "| planned |", 11) == 0)
            CHECK(strstr(line, "| 1100 | 2 | 200 | 2 | 25 |") != NULL, "planned row: %s", line);
    }
    fclose(f);
    CHECK(rows == 5 && found, "header, rule and 3 rows (%d)", rows);
    for (int k = 0; k < 3; k++) kt_bench_run_free(&r[k]);
}

static void test_errors(void)
{
    kt_err e = {0};
    kt_bench_run r;
    kt_bench_run_read(&r, "x", put("b1.tsv", "step\tt_total_ms\n0\t1\n1\tabc\n"), &e);
    CHECK(e.code == KT_EINPUT && strstr(e.msg, "b1.tsv:3:3: expected a number in column t_total_ms, found 'abc'"),
          "%s", e.msg);
    kt_bench_run_free(&r);
    e = (kt_err){0};
    kt_bench_run_read(&r, "x", put("b2.tsv", "n_dofs\tt_total_ms\n"), &e);
    CHECK(e.code == KT_EINPUT && strstr(e.msg, "b2.tsv:1:1: expected a column step"), "%s", e.msg);
    kt_bench_run_free(&r);
    e = (kt_err){0};
    kt_bench_run_read(&r, "x", put("b3.tsv", "step\tt_total_ms\n-1\t4\n"), &e);
    CHECK(e.code == KT_EINPUT && strstr(e.msg, "b3.tsv:2:1: expected an integer from 0 to 1000000000 in column step, found '-1'"), "%s", e.msg);
    kt_bench_run_free(&r);
    e = (kt_err){0};
    kt_bench_run_read(&r, "x", put("b4.tsv", "step\tt_total_ms\n0\t4\n"), &e);
    CHECK(kt_bench_run_peak(&r, put("b4.time", "no figure\n"), &e) == KT_EINPUT, "no peak: refused");
    kt_bench_run_free(&r);
}

int main(void)
{
    if (!mkdtemp(dir)) return 1;
    test_median();
    test_summary();
    test_errors();
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd)) fprintf(stderr, "could not remove %s\n", dir);
    return kt_test_done("test_benchtab");
}
