/* fuzz_file.c: the harnesses' temporary folder (fuzz_file.h). */
#include "fuzz_file.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The folder outlives every input of one fuzzing process; it is the only static state here. */
static char fuzz_dir[256];

static void remove_dir(void)
{
    DIR *d = opendir(fuzz_dir);
    if (d) {
        struct dirent *ent;
        char path[512];
        while ((ent = readdir(d))) {
            if (ent->d_name[0] == '.')
                continue;
            snprintf(path, sizeof path, "%s/%s", fuzz_dir, ent->d_name);
            unlink(path);
        }
        closedir(d);
    }
    rmdir(fuzz_dir);
}

const char *kt_fuzz_dir(void)
{
    if (!fuzz_dir[0]) {
        const char *tmp = getenv("TMPDIR");
        snprintf(fuzz_dir, sizeof fuzz_dir, "%s/kt-fuzz-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
        if (!mkdtemp(fuzz_dir)) {
            perror("kt-fuzz: mkdtemp");
            abort();
        }
        atexit(remove_dir);
    }
    return fuzz_dir;
}

int kt_fuzz_write(const char *name, const uint8_t *data, size_t size, char *buf, size_t bufsize)
{
    snprintf(buf, bufsize, "%s/%s", kt_fuzz_dir(), name);
    FILE *f = fopen(buf, "wb");
    if (!f)
        return -1;
    size_t put = size ? fwrite(data, 1, size, f) : 0;
    return fclose(f) == 0 && put == size ? 0 : -1;
}

void kt_fuzz_report(int code, const char *msg)
{
    if (getenv("KT_FUZZ_VERBOSE"))
        fprintf(stderr, "kt-fuzz: %s\n", code ? msg : "accepted");
}
