/* fuzz_scene: libFuzzer harness for the scene YAML reader (kt_scene_load). */
#include <stdint.h>

#include "fuzz_file.h"
#include "scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    if (kt_fuzz_write("scene.yaml", data, size, path, sizeof path))
        return 0;
    kt_scene s;
    kt_err e = {0};
    kt_scene_load(path, &s, &e);
    kt_fuzz_report(e.code, e.msg);
    return 0;
}
