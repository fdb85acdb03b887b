/* fuzz_plan: libFuzzer harness for the plan YAML reader (kt_plan_load). The plan is written
 * into the harness's folder, beside links to the scenes of plans/bench/ (KT_FUZZ_SCENES), so that
 * "scene: beam-4.yaml" resolves as it does for the committed plans. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "fuzz_file.h"
#include "plan.h"

static void link_scenes(void)
{
    DIR *d = opendir(KT_FUZZ_SCENES);
    if (!d)
        return;
    struct dirent *ent;
    char from[1024], to[1024];
    while ((ent = readdir(d))) {
        size_t n = strlen(ent->d_name);
        if (n < 5 || strcmp(ent->d_name + n - 5, ".yaml"))
            continue;
        snprintf(from, sizeof from, "%s/%s", KT_FUZZ_SCENES, ent->d_name);
        snprintf(to, sizeof to, "%s/%s", kt_fuzz_dir(), ent->d_name);
        if (symlink(from, to) != 0)
            continue; /* already there: the next one */
    }
    closedir(d);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    link_scenes();
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    if (kt_fuzz_write("fuzz-plan.yaml", data, size, path, sizeof path))
        return 0;
    static kt_plan p; /* large (it holds its scene); static keeps it off the fuzzer's stack */
    kt_err e = {0};
    kt_plan_load(path, &p, &e);
    kt_fuzz_report(e.code, e.msg);
    return 0;
}
