/* bench_stream: a STREAM-style triad a = b + s c measuring the sustainable memory bandwidth
 * (McCalpin's convention: 24 bytes per element, write-allocate traffic not counted).
 *
 *   bench_stream [--mb MB_PER_ARRAY] [--trials N] [--threads T]
 *
 * Prints one TSV row (with header): kernel threads array_mb trials best_GBps median_GBps.
 * Best-of-N is the figure the bandwidth bounds use; the median shows the noise of a shared
 * machine. Arrays are much larger than any cache (default 256 MB each). */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util.h"

typedef struct chunk {
    double *a;
    const double *b, *c;
    size_t lo, hi;
    double s;
} chunk;

static void *triad(void *arg)
{
    chunk *k = arg;
    double *restrict a = k->a;
    const double *restrict b = k->b, *restrict c = k->c;
    for (size_t i = k->lo; i < k->hi; i++) a[i] = b[i] + k->s * c[i];
    return NULL;
}

/* First touch by the threads that will use the pages. */
static void *init(void *arg)
{
    chunk *k = arg;
    for (size_t i = k->lo; i < k->hi; i++) {
        k->a[i] = 0;
        ((double *)k->b)[i] = 1.0;
        ((double *)k->c)[i] = 2.0;
    }
    return NULL;
}

static int run_threads(int nt, chunk *ch, void *(*fn)(void *))
{
    pthread_t th[64];
    for (int t = 1; t < nt; t++)
        if (pthread_create(&th[t], NULL, fn, &ch[t])) return -1;
    fn(&ch[0]);
    for (int t = 1; t < nt; t++) pthread_join(th[t], NULL);
    return 0;
}

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

int main(int argc, char **argv)
{
    int mb = 256, trials = 10, nt = 1;
    for (int i = 1; i < argc; i++) {
        if (i + 1 < argc && !strcmp(argv[i], "--mb") && !kt_parse_int(argv[i + 1], &mb)) i++;
        else if (i + 1 < argc && !strcmp(argv[i], "--trials") && !kt_parse_int(argv[i + 1], &trials)) i++;
        else if (i + 1 < argc && !strcmp(argv[i], "--threads") && !kt_parse_int(argv[i + 1], &nt)) i++;
        else {
            fprintf(stderr, "usage: bench_stream [--mb MB] [--trials N] [--threads T]\n");
            return 2;
        }
    }
    if (mb < 1 || trials < 1 || nt < 1 || nt > 64) {
        fprintf(stderr, "bench_stream: --mb, --trials >= 1, 1 <= --threads <= 64\n");
        return 2;
    }
    size_t n = (size_t)mb * 1024 * 1024 / sizeof(double);
    double *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *c = malloc(n * sizeof *c);
    double *gbs = malloc((size_t)trials * sizeof *gbs);
    if (!a || !b || !c || !gbs) {
        fprintf(stderr, "bench_stream: out of memory for 3 x %d MB\n", mb);
        free(a), free(b), free(c), free(gbs);
        return 1;
    }
    chunk ch[64];
    for (int t = 0; t < nt; t++)
        ch[t] = (chunk){a, b, c, n * (size_t)t / nt, n * (size_t)(t + 1) / nt, 3.0};
    run_threads(nt, ch, init);
    run_threads(nt, ch, triad); /* warm-up */
    for (int k = 0; k < trials; k++) {
        double t0 = kt_now();
        if (run_threads(nt, ch, triad)) {
            fprintf(stderr, "bench_stream: cannot start threads\n");
            return 1;
        }
        gbs[k] = 24.0 * (double)n / (kt_now() - t0) / 1e9;
    }
    /* keep the result live and checked: a = 1 + 3 * 2 everywhere */
    if (a[n / 2] != 7.0) {
        fprintf(stderr, "bench_stream: wrong triad result %g\n", a[n / 2]);
        return 1;
    }
    qsort(gbs, (size_t)trials, sizeof *gbs, cmp_double);
    printf("kernel\tthreads\tarray_mb\ttrials\tbest_GBps\tmedian_GBps\n");
    printf("triad\t%d\t%d\t%d\t%.3f\t%.3f\n", nt, mb, trials, gbs[trials - 1], gbs[trials / 2]);
    free(a), free(b), free(c), free(gbs);
    return 0;
}
