/* test_blas.c: kt_blas_pin leaves OpenBLAS on one thread, whatever it was set to before. */
#define _GNU_SOURCE
#include <dlfcn.h>

#include <cholmod.h>

#include "blas.h"
#include "kt_test.h"

int main(void)
{
    /* CHOLMOD brings in the BLAS the tools use (Debian: libblas.so.3 -> libopenblas.so.0) */
    cholmod_common cc;
    cholmod_start(&cc);
    cholmod_finish(&cc);
    void *set = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
    void *get = dlsym(RTLD_DEFAULT, "openblas_get_num_threads");
    if (!set || !get) {
        /* another BLAS behind libblas.so.3: nothing to pin, and kt_blas_pin says so */
        CHECK(kt_blas_pin() == 0, "no OpenBLAS, yet kt_blas_pin reported a pin");
        return kt_test_done("test_blas");
    }
    void (*set_threads)(int);
    int (*get_threads)(void);
    *(void **)&set_threads = set;
    *(void **)&get_threads = get;
    set_threads(2); /* as OPENBLAS_NUM_THREADS=2 would leave it */
    CHECK(kt_blas_pin() == 1, "OpenBLAS is linked, yet kt_blas_pin did not pin it");
    CHECK(get_threads() == 1, "OpenBLAS threads after kt_blas_pin: %d", get_threads());
    return kt_test_done("test_blas");
}
