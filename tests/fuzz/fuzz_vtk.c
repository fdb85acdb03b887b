/* fuzz_vtk: libFuzzer harness for the legacy VTK reader (kt_vtk_read). */
#include <stdint.h>

#include "fuzz_file.h"
#include "vtk.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    if (kt_fuzz_write("data.vtk", data, size, path, sizeof path))
        return 0;
    kt_vtk v = {0};
    kt_err e = {0};
    if (kt_vtk_read(path, &v, &e) == KT_OK)
        kt_vtk_free(&v);
    kt_fuzz_report(e.code, e.msg);
    return 0;
}
