/* table.c (bench_table): the planned method's benchmark table for one case from the runs'
 * step tables (lib/io/benchtab.h has the conventions).
 *   bench_table --title TEXT [--bandwidth GB/s] LABEL=STEPS.tsv[,TIME] ...
 * The first run is the planned method, the second the reference refactor (METIS); TIME is the
 * run's /usr/bin/time record (peak memory). The Markdown goes to stdout. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "benchtab.h"

static int add_run(kt_bench_run *r, char *arg, kt_err *e)
{
    char *eq = strchr(arg, '=');
    if (!eq) return kt_fail(e, KT_EINPUT, "%s: expected LABEL=STEPS.tsv[,TIME]", arg);
    *eq = 0;
    char *comma = strchr(eq + 1, ',');
    if (comma) *comma = 0;
    if (kt_bench_run_read(r, arg, eq + 1, e)) return e->code;
    return comma ? kt_bench_run_peak(r, comma + 1, e) : KT_OK;
}

int main(int argc, char **argv)
{
    kt_err e = {0};
    const char *title = "### benchmark";
    double bw = NAN;
    int n = 0;
    kt_bench_run *runs = kt_calloc((size_t)argc, sizeof *runs, &e);
    for (int i = 1; i < argc && !e.code; i++) {
        if (!strcmp(argv[i], "--title") && i + 1 < argc) title = argv[++i];
        else if (!strcmp(argv[i], "--bandwidth") && i + 1 < argc) {
            if (kt_parse_double(argv[++i], &bw) || !(bw > 0))
                kt_fail(&e, KT_EINPUT, "--bandwidth %s: expected GB/s > 0", argv[i]);
            bw *= 1e9;
        } else if (argv[i][0] == '-') {
            kt_fail(&e, KT_EINPUT, "usage: bench_table --title TEXT [--bandwidth GB/s] "
                    "LABEL=STEPS.tsv[,TIME] ...");
        } else {
            add_run(&runs[n], argv[i], &e);
            n++;
        }
    }
    if (!e.code) kt_bench_table(stdout, title, runs, n, bw, &e);
    for (int k = 0; k < n; k++) kt_bench_run_free(&runs[k]);
    free(runs);
    if (e.code) fprintf(stderr, "bench_table: %s\n", e.msg);
    return e.code;
}
