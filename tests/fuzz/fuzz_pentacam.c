/* fuzz_pentacam: libFuzzer harness for the Pentacam map reader (kt_pentacam_read), as an
 * elevation map and as a pachymetry map. */
#include <stdint.h>

#include "fuzz_file.h"
#include "pentacam.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    if (kt_fuzz_write("map.csv", data, size, path, sizeof path))
        return 0;
    for (int kind = 0; kind < 2; kind++) {
        kt_pentacam_map m;
        kt_err e = {0};
        if (kt_pentacam_read(path, kind, &m, &e) == KT_OK) kt_pentacam_free(&m);
        kt_fuzz_report(e.code, e.msg);
    }
    return 0;
}
