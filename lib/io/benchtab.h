/* benchtab.h: the benchmark table of the planned method (issue 11): for one case, the step
 * tables of several runs over the same plan (augsolve's steps.tsv or bench_steps' TSV, read by
 * column name) and their peak memory (/usr/bin/time) -> one Markdown table of per-step figures
 * and ratios against the first run.
 *
 * Conventions (tests/bench/README.md):
 *   - a step's time is t_total_ms; the per-step statistics (median, worst) are over the steps
 *     >= 1 (step 0, the intact solve, also holds the factorization of the runs that factor once);
 *   - the whole plan is the sum of t_total_ms over every row, step 0 included;
 *   - the ratio of a run against the first is per step on the steps both completed (t_other /
 *     t_first), then the median and the minimum (the first run's worst case);
 *   - "one refactor" is the median step of the reference run (the second run: refactor with
 *     METIS); the whole plan and the peak memory are also given as multiples of it;
 *   - the bandwidth floor of a step is 8 B x nnz_L / bandwidth (every stored value of the
 *     factor read once, what a back substitution must stream); the column is the median over
 *     the steps of t / floor (blank for runs without a factor);
 *   - a run's own t_verify_ms (augsolve --verify: a fresh METIS factorization of the same cut
 *     mesh right after the step, in the same process) gives a ratio under the same load. */
#ifndef KT_BENCHTAB_H
#define KT_BENCHTAB_H

#include <stdio.h>

#include "util.h"

/* One run's rows. Owner: kt_bench_run_read / kt_bench_run_free. */
typedef struct kt_bench_run {
    char label[64];
    int n;                      /* rows */
    int *step;                  /* n: step index of each row */
    double *t;                  /* n: t_total_ms (NaN: missing) */
    double *nnz_L;              /* n: factor nonzeros (NaN or 0: none) */
    double *t_verify;           /* n: t_verify_ms, NaN where absent */
    unsigned char *ok;          /* n: 0 where a status column says the step did not complete */
    double peak_mb;             /* peak resident memory, MB (NaN: unknown) */
} kt_bench_run;

/* Read a step table (tsv.h; header line with at least "step" and "t_total_ms"; "nnz_L",
 * "t_verify_ms" and "status" are optional; a time or nnz_L field "NaN" or empty is NaN). Bad
 * input is KT_EINPUT "path:line:col: expected ...". */
int kt_bench_run_read(kt_bench_run *r, const char *label, const char *path, kt_err *e);
/* Peak memory from a /usr/bin/time record: "-v" output ("Maximum resident set size (kbytes):
 * N") or bench.sh's "-f '%U\t%S\t%M'" line. */
int kt_bench_run_peak(kt_bench_run *r, const char *path, kt_err *e);
void kt_bench_run_free(kt_bench_run *r);

/* Median of the n values of x that are not NaN (NaN when none); x is reordered. */
double kt_bench_median(double *x, int n);

/* One run's summary against the first run (base) and the reference (one refactor). */
typedef struct kt_bench_sum {
    int steps, failed;          /* steps >= 1 present, of which did not complete */
    double med, worst;          /* ms over the completed steps >= 1 (worst: the largest) */
    double whole;               /* ms, all rows */
    double ratio_med, ratio_min;/* t_this / t_base per common completed step >= 1 */
    double verify_med, verify_min; /* t_verify / t per step (NaN without --verify) */
    double bw_med;              /* median t / (8 B nnz_L / bandwidth), NaN without a factor */
} kt_bench_sum;

/* bw: bytes per second (NaN: no bandwidth column). Returns the number of common steps. */
int kt_bench_summarize(const kt_bench_run *r, const kt_bench_run *base, double bw,
                       kt_bench_sum *s, kt_err *e);

/* The Markdown table of runs[0..n) (runs[0]: the planned method, runs[1]: the reference
 * refactor), a title line first. */
int kt_bench_table(FILE *f, const char *title, const kt_bench_run *runs, int n, double bw,
                   kt_err *e);

#endif
