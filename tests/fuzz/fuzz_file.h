/* fuzz_file.h: what every libFuzzer harness shares: a private temporary folder, and writing the
 * fuzzer's bytes to a file in it, since the parsers read from a path. Test code only. */
#ifndef KT_FUZZ_FILE_H
#define KT_FUZZ_FILE_H

#include <stddef.h>
#include <stdint.h>

/* The harness's folder (made on first use, removed at exit), e.g. /tmp/kt-fuzz-XXXXXX. */
const char *kt_fuzz_dir(void);
/* Write data to <dir>/<name> (replacing it); its path goes to buf. 0 on success. */
int kt_fuzz_write(const char *name, const uint8_t *data, size_t size, char *buf, size_t bufsize);

/* KT_FUZZ_VERBOSE=1: print what the reader said about each input (to check the seeds). */
void kt_fuzz_report(int code, const char *msg);

#endif
