/* test_blas.c: kt_blas_pin leaves OpenBLAS on one thread, whatever it was set to before; after
 * kt_blas_warm, a BLAS call under an address-space limit that leaves no room for OpenBLAS's
 * buffer returns (it hung, retrying the buffer's mmap for ever: blas.h). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cholmod.h>

#include "blas.h"
#include "kt_test.h"

typedef void dgemm_fn(const char *, const char *, const int *, const int *, const int *, const double *,
                      const double *, const int *, const double *, const int *, const double *, double *,
                      const int *);

/* `test_blas --child warm|cold`, a fresh process: the BLAS pinned as a tool's start leaves it,
 * warmed (kt_blas_warm) or not, then the address space limited to what the process has now plus
 * 48 MB (less than the buffer's 128 MB), then a dgemm of 300 x 300 (the general kernel, which
 * needs the buffer). Exit 0 when the dgemm returned the right product. */
static int child(int warm)
{
    cholmod_common cc; /* brings in the BLAS the tools use, as in a tool */
    cholmod_start(&cc);
    cholmod_finish(&cc);
    kt_blas_pin();
    if (warm && kt_blas_warm() != KT_BLAS_WARM_OK) return 3;
    enum { N = 300 };
    double *a = calloc(N * N, sizeof *a), *c = calloc(N * N, sizeof *c);
    dgemm_fn *dgemm;
    *(void **)&dgemm = dlsym(RTLD_DEFAULT, "dgemm_");
    if (!a || !c || !dgemm) return 4;
    for (int i = 0; i < N; i++) a[i * N + i] = 2;
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long pages = 0;
    if (!f || fscanf(f, "%lu", &pages) != 1) return 5;
    fclose(f);
    struct rlimit r;
    r.rlim_cur = r.rlim_max = pages * (rlim_t)sysconf(_SC_PAGESIZE) + ((rlim_t)48 << 20);
    if (setrlimit(RLIMIT_AS, &r) != 0) return 6;
    const int n = N;
    const double one = 1, zero = 0;
    dgemm("N", "N", &n, &n, &n, &one, a, &n, a, &n, &zero, c, &n);
    int ok = c[0] == 4 && c[N + 1] == 4 && c[1] == 0;
    free(a), free(c);
    return ok ? 0 : 7;
}

#if !defined(__SANITIZE_ADDRESS__) /* used only where the limit test runs (below) */
/* Runs the child; its exit status, or -1 when it had to be killed after 60 s (a hang). */
static int run_child(const char *mode)
{
    pid_t pid = fork();
    if (pid == 0) {
        execl("/proc/self/exe", "test_blas", "--child", mode, (char *)NULL);
        _exit(127);
    }
    int st = 0;
    for (int t = 0; t < 600; t++) {
        if (waitpid(pid, &st, WNOHANG) == pid) return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
        usleep(100000);
    }
    kill(pid, SIGKILL);
    waitpid(pid, &st, 0);
    return -1;
}
#endif

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "--child") == 0) return child(strcmp(argv[2], "warm") == 0);
    /* CHOLMOD brings in the BLAS the tools use (Debian: libblas.so.3 -> libopenblas.so.0) */
    cholmod_common cc;
    cholmod_start(&cc);
    cholmod_finish(&cc);
    void *set = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
    void *get = dlsym(RTLD_DEFAULT, "openblas_get_num_threads");
    if (!set || !get) {
        /* another BLAS behind libblas.so.3: nothing to pin, and kt_blas_pin says so */
        CHECK(kt_blas_pin() == 0, "no OpenBLAS, yet kt_blas_pin reported a pin");
        CHECK(kt_blas_warm() == KT_BLAS_WARM_NONE, "no OpenBLAS, yet kt_blas_warm reported a warm-up");
        return kt_test_done("test_blas");
    }
    void (*set_threads)(int);
    int (*get_threads)(void);
    *(void **)&set_threads = set;
    *(void **)&get_threads = get;
    set_threads(2); /* as OPENBLAS_NUM_THREADS=2 would leave it */
    CHECK(kt_blas_pin() == 1, "OpenBLAS is linked, yet kt_blas_pin did not pin it");
    CHECK(get_threads() == 1, "OpenBLAS threads after kt_blas_pin: %d", get_threads());
#if !defined(__SANITIZE_ADDRESS__) /* ASan's shadow memory cannot live under an address-space limit */
    /* `test_blas --control` also runs the child without the warm-up: with Debian's OpenBLAS
     * 0.3.21 it hangs (-1), which is what kt_blas_warm prevents. */
    int rc = run_child("warm");
    CHECK(rc == 0, "a BLAS call under ulimit -v after kt_blas_warm: %s %d",
          rc < 0 ? "hung (killed after 60 s)" : "child exit", rc);
    if (argc > 1 && strcmp(argv[1], "--control") == 0)
        printf("control: without kt_blas_warm the child %s\n", (rc = run_child("cold")) < 0 ? "hung" : "returned");
#endif
    return kt_test_done("test_blas");
}
