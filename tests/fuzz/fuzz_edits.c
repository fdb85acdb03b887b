/* fuzz_edits: libFuzzer harness for the edits stream reader (kt_edits_open, kt_edits_next),
 * which reads a FILE: the bytes are given through fmemopen. */
#include <stdint.h>
#include <stdio.h>

#include "edits.h"
#include "fuzz_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!size)
        return 0;
    FILE *f = fmemopen((void *)data, size, "rb");
    if (!f)
        return 0;
    kt_edits_reader r;
    kt_err e = {0};
    if (kt_edits_open(&r, f, "fuzz.edits", &e) == KT_OK) {
        kt_step s = {0};
        while (kt_edits_next(&r, &s, &e) == 1)
            ;
        kt_step_free(&s);
    }
    fclose(f);
    kt_fuzz_report(e.code, e.msg);
    return 0;
}
