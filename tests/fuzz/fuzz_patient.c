/* fuzz_patient: libFuzzer harness for the patient YAML reader (kt_patient_load). */
#include <stdint.h>

#include "fuzz_file.h"
#include "patient.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    if (kt_fuzz_write("patient.yaml", data, size, path, sizeof path))
        return 0;
    kt_patient p;
    kt_err e = {0};
    kt_patient_load(path, &p, &e);
    kt_fuzz_report(e.code, e.msg);
    return 0;
}
