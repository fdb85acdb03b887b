/* fuzz_msh: libFuzzer harness for the gmsh MSH 4.1 reader (kt_msh_read), built twice with
 * different seed corpora: fuzz_msh_ascii and fuzz_msh_binary. */
#include <stdint.h>

#include "fuzz_file.h"
#include "msh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    if (kt_fuzz_write("mesh.msh", data, size, path, sizeof path))
        return 0;
    kt_mesh m = {0};
    kt_err e = {0};
    if (kt_msh_read(path, &m, &e) == KT_OK)
        kt_mesh_free(&m);
    kt_fuzz_report(e.code, e.msg);
    return 0;
}
