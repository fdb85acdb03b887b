/* blas.c: pins the BLAS to one thread (blas.h). The symbol is looked up at run time: the
 * build links the system's libblas.so.3, which Debian's alternatives may point at OpenBLAS,
 * BLIS or the reference BLAS, and only OpenBLAS has openblas_set_num_threads. */
#define _GNU_SOURCE
#include "blas.h"

#include <dlfcn.h>

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
