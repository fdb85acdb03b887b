/* blas.c: pins the BLAS to one thread and takes its work buffer at once (blas.h). The symbols
 * are looked up at run time: the build links the system's libblas.so.3, which Debian's
 * alternatives may point at OpenBLAS, BLIS or the reference BLAS, and only OpenBLAS has
 * openblas_set_num_threads. */
#define _GNU_SOURCE
#include "blas.h"

#include <dlfcn.h>
#include <stddef.h>
#include <sys/mman.h>

int kt_blas_pin(void)
{
    static const char *const setters[] = {"openblas_set_num_threads", "goto_set_num_threads"};
    for (int i = 0; i < 2; i++) {
        void *sym = dlsym(RTLD_DEFAULT, setters[i]);
        if (!sym) continue;
        void (*set_threads)(int);
        *(void **)&set_threads = sym; /* POSIX's way from an object pointer to a function pointer */
        set_threads(1);
        return 1;
    }
    return 0;
}

typedef void dgemm_fn(const char *, const char *, const int *, const int *, const int *, const double *,
                      const double *, const int *, const double *, const int *, const double *, double *,
                      const int *);

int kt_blas_warm(void)
{
    if (!dlsym(RTLD_DEFAULT, "openblas_set_num_threads")) return KT_BLAS_WARM_NONE;
    /* Room for the buffer and some: mapped without access, so nothing is touched (an address
     * space limit counts such a mapping all the same). */
    size_t room = KT_BLAS_BUFFER + ((size_t)32 << 20);
    void *probe = mmap(NULL, room, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (probe == MAP_FAILED) return KT_BLAS_WARM_NOROOM;
    munmap(probe, room);
    void *sym = dlsym(RTLD_DEFAULT, "dgemm_");
    if (!sym) return KT_BLAS_WARM_NONE;
    dgemm_fn *dgemm;
    *(void **)&dgemm = sym;
    /* One level-3 call large enough for the general kernel (not a small-matrix path): OpenBLAS
     * maps the calling thread's buffer on its first such call and keeps it to the end. */
    enum { N = 128 };
    static double a[N * N], c[N * N];
    const int n = N;
    const double one = 1, zero = 0;
    dgemm("N", "N", &n, &n, &n, &one, a, &n, a, &n, &zero, c, &n);
    return KT_BLAS_WARM_OK;
}
