/* test_util.c: atomic output (a committed file appears whole, an aborted one leaves no file and
 * no temporary, an old file survives an aborted rewrite), errors (first one wins), allocation
 * overflow, the whole-string number parsers, and paths relative to a folder (run.yaml's). */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include "kt_test.h"
#include "util.h"

static char dir[64];

/* Entries in dir other than . and .. */
static int count_entries(const char *d)
{
    DIR *h = opendir(d);
    if (!h) return -1;
    int n = 0;
    struct dirent *de;
    while ((de = readdir(h)))
        if (strcmp(de->d_name, ".") && strcmp(de->d_name, "..")) n++;
    closedir(h);
    return n;
}

/* The file's whole content into buf (NUL-terminated); -1 when it cannot be read. */
static long slurp(const char *path, char *buf, size_t cap)
{
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    size_t n = fread(buf, 1, cap - 1, f);
    buf[n] = '\0';
    fclose(f);
    return (long)n;
}

static void test_atomic_output(void)
{
    char sub[128], path[192], buf[256];
    snprintf(sub, sizeof sub, "%s/out", dir);
    kt_err e = {0};
    CHECK(kt_mkdir_p(sub, &e) == 0, "%s", e.msg);
    snprintf(path, sizeof path, "%s/result.tsv", sub);

    /* aborted: nothing at all in the folder */
    kt_out o;
    CHECK(kt_out_open(&o, path, &e) == 0 && o.f, "%s", e.msg);
    fprintf(o.f, "partial line\n");
    fflush(o.f);
    CHECK(count_entries(sub) == 1, "while writing: the temporary only (%d entries)", count_entries(sub));
    CHECK(slurp(path, buf, sizeof buf) < 0, "the target exists before commit");
    kt_out_abort(&o);
    CHECK(count_entries(sub) == 0, "after abort: %d entries left", count_entries(sub));

    /* committed: the whole content, no temporary, mode 0644 */
    CHECK(kt_out_open(&o, path, &e) == 0, "%s", e.msg);
    fprintf(o.f, "a\tb\n1\t2\n");
    CHECK(kt_out_commit(&o, &e) == 0, "%s", e.msg);
    CHECK(slurp(path, buf, sizeof buf) == 8 && strcmp(buf, "a\tb\n1\t2\n") == 0, "content '%s'", buf);
    CHECK(count_entries(sub) == 1, "after commit: %d entries", count_entries(sub));
    struct stat sb;
    CHECK(stat(path, &sb) == 0 && (sb.st_mode & 0777) == 0644, "mode %o", (unsigned)(sb.st_mode & 0777));

    /* an aborted rewrite leaves the old file as it was */
    CHECK(kt_out_open(&o, path, &e) == 0, "%s", e.msg);
    fprintf(o.f, "new content that must not appear\n");
    kt_out_abort(&o);
    CHECK(slurp(path, buf, sizeof buf) == 8 && strcmp(buf, "a\tb\n1\t2\n") == 0, "old file changed: '%s'", buf);
    CHECK(count_entries(sub) == 1, "after aborted rewrite: %d entries", count_entries(sub));
    kt_out_abort(&o); /* a second abort is harmless */

    /* a folder that does not exist: input error naming the path, nothing created */
    char bad[192];
    snprintf(bad, sizeof bad, "%s/no-such-dir/x.tsv", dir);
    kt_err e2 = {0};
    CHECK(kt_out_open(&o, bad, &e2) == KT_EINPUT && strncmp(e2.msg, bad, strlen(bad)) == 0, "'%s'", e2.msg);
    CHECK(o.f == NULL && o.tmp == NULL && o.path == NULL, "a failed open holds nothing");

    /* a write that fails (the file-size limit stands in for a full disk): the error names the
     * file, and neither the target nor a temporary is left */
    char full[192];
    snprintf(full, sizeof full, "%s/full.tsv", sub);
    struct rlimit old, lim;
    CHECK(getrlimit(RLIMIT_FSIZE, &old) == 0, "getrlimit");
    lim = old;
    lim.rlim_cur = 16;
    void (*prev)(int) = signal(SIGXFSZ, SIG_IGN);
    int before = count_entries(sub);
    kt_err e3 = {0};
    CHECK(kt_out_open(&o, full, &e3) == 0 && setrlimit(RLIMIT_FSIZE, &lim) == 0, "%s", e3.msg);
    for (int i = 0; i < 100; i++) fprintf(o.f, "more than sixteen bytes\n");
    int rc = kt_out_commit(&o, &e3);
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, prev);
    CHECK(rc == KT_ERUN && strncmp(e3.msg, full, strlen(full)) == 0, "'%s'", e3.msg);
    CHECK(slurp(full, buf, sizeof buf) < 0 && count_entries(sub) == before,
          "a failed commit left files (%d entries, %d before)", count_entries(sub), before);

    /* nested folders */
    char deep[192];
    snprintf(deep, sizeof deep, "%s/a/b/c", dir);
    CHECK(kt_mkdir_p(deep, &e) == 0 && kt_mkdir_p(deep, &e) == 0, "%s", e.msg);
    CHECK(stat(deep, &sb) == 0 && S_ISDIR(sb.st_mode), "nested folder made");
}

static void test_errors_and_alloc(void)
{
    kt_err e = {0};
    CHECK(kt_fail(&e, KT_EINPUT, "first %d", 1) == KT_EINPUT, "returns its code");
    kt_fail(&e, KT_ERUN, "second");
    CHECK(e.code == KT_EINPUT && strcmp(e.msg, "first 1") == 0, "first error wins: %d '%s'", e.code, e.msg);
    kt_err e2 = {0};
    void *p = kt_calloc(SIZE_MAX / 4, 8, &e2);
    CHECK(p == NULL && e2.code == KT_ERUN, "overflowing calloc: code %d", e2.code);
    kt_err e3 = {0};
    int *q = kt_calloc(4, sizeof(int), &e3);
    CHECK(q && q[0] == 0 && q[3] == 0 && e3.code == 0, "calloc zeroes");
    int *r = kt_realloc(q, SIZE_MAX / 2, sizeof(int), &e3);
    CHECK(r == NULL && e3.code == KT_ERUN, "overflowing realloc");
    free(r ? r : q);
    kt_err e4 = {0};
    char *s = kt_strdup("cornea", &e4);
    CHECK(s && strcmp(s, "cornea") == 0, "strdup");
    free(s);
}

static void test_parse(void)
{
    struct { const char *s; double v; } okd[] = {{"1.5", 1.5}, {"-2e-3", -2e-3}, {"0", 0}, {"1e300", 1e300},
                                               {"+7", 7}, {".25", 0.25}};
    for (size_t i = 0; i < sizeof okd / sizeof okd[0]; i++) {
        double v = -1;
        CHECK(kt_parse_double(okd[i].s, &v) == 0 && v == okd[i].v, "'%s' -> %g", okd[i].s, v);
    }
    const char *badd[] = {"", "1.5x", "x", "1e999", "-1e999", "1.5 ", "1,5", "--1"};
    for (size_t i = 0; i < sizeof badd / sizeof badd[0]; i++) {
        double v;
        CHECK(kt_parse_double(badd[i], &v) != 0, "'%s' accepted as a double", badd[i]);
    }
    /* the strict parser of what a user types (issue 26: hex, blanks, inf and nan were taken) */
    struct { const char *s; double v; } okn[] = {{"0", 0}, {"40", 40}, {"-1.5", -1.5}, {"+.5", 0.5},
                                                 {"5.", 5}, {"1e-3", 1e-3}, {"2E+2", 200}, {"1e308", 1e308}};
    for (size_t i = 0; i < sizeof okn / sizeof okn[0]; i++) {
        double v = NAN;
        CHECK(kt_parse_number(okn[i].s, &v) == 0 && v == okn[i].v, "'%s' -> %g", okn[i].s, v);
    }
    const char *badn[] = {"", " 40", "40 ", "0x28", "0x1p3", "nan", "NaN", "inf", "-inf", "infinity",
                          "1e999", ".", "e5", "1e", "1e+", "--1", "1,5", "40deg", "+", "1.5.2"};
    for (size_t i = 0; i < sizeof badn / sizeof badn[0]; i++) {
        double v = 123;
        CHECK(kt_parse_number(badn[i], &v) != 0 && v == 123, "'%s' accepted as a number", badn[i]);
    }
    struct { const char *s; int v; } oki[] = {{"0", 0}, {"42", 42}, {"-7", -7}, {"2147483647", INT_MAX},
                                            {"-2147483648", INT_MIN}, {"007", 7}};
    for (size_t i = 0; i < sizeof oki / sizeof oki[0]; i++) {
        int v = -1;
        CHECK(kt_parse_int(oki[i].s, &v) == 0 && v == oki[i].v, "'%s' -> %d", oki[i].s, v);
    }
    const char *badi[] = {"", "2147483648", "-2147483649", "99999999999999999999", "1.0", "12a", "0x10", "1e3", " ", " 5", "\t5"};
    for (size_t i = 0; i < sizeof badi / sizeof badi[0]; i++) {
        int v = 123;
        CHECK(kt_parse_int(badi[i], &v) != 0, "'%s' accepted as an int", badi[i]);
        CHECK(v == 123, "'%s': rejected, yet the output changed to %d", badi[i], v);
    }
}

/* kt_path_relative: a file inside the folder, beside it, above it, and "-" as it is. (A file
 * inside the folder once read past the folder's string and got a stray "../" when that memory
 * held garbage: tests/pipeline_contract.sh checks it through augsolve, where it did.) */
static void test_path_relative(void)
{
    char run[128], sub[160], f[200], out[256];
    kt_err e = {0};
    snprintf(run, sizeof run, "%s/run", dir);
    snprintf(sub, sizeof sub, "%s/run/in", dir);
    CHECK(kt_mkdir_p(sub, &e) == 0, "%s", e.msg);
    const struct { const char *file, *want; } cases[] = {
        {"run/eye.msh", "eye.msh"}, {"run/in/eye.msh", "in/eye.msh"}, {"eye.msh", "../eye.msh"},
        {"runx.msh", "../runx.msh"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(f, sizeof f, "%s/%s", dir, cases[i].file);
        FILE *fp = fopen(f, "w");
        CHECK(fp != NULL, "cannot create %s", f);
        if (fp) fclose(fp);
        kt_path_relative(f, run, out, sizeof out);
        CHECK(strcmp(out, cases[i].want) == 0, "%s relative to %s: '%s', expected '%s'", f, run,
              out, cases[i].want);
    }
    kt_path_relative("-", run, out, sizeof out);
    CHECK(strcmp(out, "-") == 0, "'-' became '%s'", out);
}

/* Output targets that are not plain files (issue 26): a FIFO is written to, not replaced; a
 * directory is refused before anything is made; a symbolic link stays a link. */
static void test_out_targets(void)
{
    char sub[128], path[192], buf[256];
    snprintf(sub, sizeof sub, "%s/targets", dir);
    kt_err e = {0};
    CHECK(kt_mkdir_p(sub, &e) == 0, "%s", e.msg);

    snprintf(path, sizeof path, "%s/fifo", sub);
    CHECK(mkfifo(path, 0600) == 0, "mkfifo");
    int rd = open(path, O_RDONLY | O_NONBLOCK); /* a reader, so that the writer's open returns */
    kt_out o;
    CHECK(kt_out_open(&o, path, &e) == 0 && o.direct, "FIFO: %s", e.msg);
    if (o.f) {
        fputs("through the pipe\n", o.f);
        CHECK(kt_out_commit(&o, &e) == 0, "%s", e.msg);
    }
    ssize_t n = read(rd, buf, sizeof buf - 1);
    buf[n > 0 ? n : 0] = '\0';
    close(rd);
    struct stat st;
    CHECK(strcmp(buf, "through the pipe\n") == 0, "read from the FIFO: '%s'", buf);
    CHECK(lstat(path, &st) == 0 && S_ISFIFO(st.st_mode), "the FIFO is still a FIFO");
    CHECK(count_entries(sub) == 1, "no temporary beside the FIFO: %d entries", count_entries(sub));

    kt_err e2 = {0};
    CHECK(kt_out_check(sub, &e2) == KT_EINPUT && strstr(e2.msg, "is a directory"), "'%s'", e2.msg);
    kt_err e3 = {0};
    CHECK(kt_out_open(&o, sub, &e3) == KT_EINPUT && strstr(e3.msg, "is a directory"), "'%s'", e3.msg);
    CHECK(count_entries(dir) >= 1 && o.f == NULL, "a refused directory holds nothing");

    char target[192], link[192];
    snprintf(target, sizeof target, "%s/real.txt", sub);
    snprintf(link, sizeof link, "%s/link.txt", sub);
    FILE *old = fopen(target, "w");
    if (old) fclose(old);
    CHECK(symlink("real.txt", link) == 0, "symlink");
    CHECK(kt_out_open(&o, link, &e) == 0, "%s", e.msg);
    fputs("via link\n", o.f);
    CHECK(kt_out_commit(&o, &e) == 0, "%s", e.msg);
    CHECK(lstat(link, &st) == 0 && S_ISLNK(st.st_mode), "the link is still a link");
    CHECK(slurp(target, buf, sizeof buf) == 9 && strcmp(buf, "via link\n") == 0, "target '%s'", buf);
}

/* Temporaries of dead processes of this host are removed when the same target is opened;
 * a live process's, another target's and another host's are kept. */
static void test_stale_temporaries(void)
{
    char sub[128], path[192], host[65] = "", f[4][320];
    snprintf(sub, sizeof sub, "%s/stale", dir);
    kt_err e = {0};
    CHECK(kt_mkdir_p(sub, &e) == 0, "%s", e.msg);
    snprintf(path, sizeof path, "%s/out.msh", sub);
    gethostname(host, sizeof host - 1);
    for (char *h = host; *h; h++)
        if (*h == '/' || *h == '.') *h = '_';
    pid_t dead = fork();
    if (dead == 0) _exit(0);
    waitpid(dead, NULL, 0);
    snprintf(f[0], sizeof f[0], "%s/out.msh.tmp.%s.%ld.AbC123", sub, host, (long)dead);
    snprintf(f[1], sizeof f[1], "%s/out.msh.tmp.%s.%ld.AbC123", sub, host, (long)getppid());
    snprintf(f[2], sizeof f[2], "%s/other.msh.tmp.%s.%ld.AbC123", sub, host, (long)dead);
    snprintf(f[3], sizeof f[3], "%s/out.msh.tmp.elsewhere.%ld.AbC123", sub, (long)dead);
    for (int i = 0; i < 4; i++) {
        FILE *t = fopen(f[i], "w");
        if (t) fclose(t);
    }
    kt_out o;
    CHECK(kt_out_open(&o, path, &e) == 0, "%s", e.msg);
    CHECK(strstr(o.tmp, ".tmp.") && strstr(o.tmp, host), "temporary '%s' names the host", o.tmp);
    kt_out_abort(&o);
    struct stat st;
    CHECK(stat(f[0], &st) != 0, "a dead process's temporary is removed");
    CHECK(stat(f[1], &st) == 0, "a live process's temporary is kept");
    CHECK(stat(f[2], &st) == 0, "another target's temporary is kept");
    CHECK(stat(f[3], &st) == 0, "another host's temporary is kept");
}

/* Control characters in a message are escaped; bounded line reads. */
static void test_escape_and_lines(void)
{
    kt_err e = {0};
    kt_fail(&e, KT_EINPUT, "found '%s'", "\x1b]0;x\x07 \xc2\x9b ok \xc2\xb5m");
    CHECK(strcmp(e.msg, "found '\\x1b]0;x\\x07 \\u009b ok \xc2\xb5m'") == 0, "'%s'", e.msg);
    char path[192];
    snprintf(path, sizeof path, "%s/lines.txt", dir);
    FILE *f = fopen(path, "wb");
    fwrite("ab\nlonger line\nx\0y\n", 1, 19, f);
    fclose(f);
    f = fopen(path, "rb");
    char *buf = NULL;
    size_t cap = 0;
    CHECK(kt_line_read(f, &buf, &cap, 8, &e) == 3 && strcmp(buf, "ab\n") == 0, "first line");
    CHECK(kt_line_read(f, &buf, &cap, 8, &e) == -3, "a line longer than the limit");
    fclose(f);
    f = fopen("/dev/zero", "rb");
    CHECK(kt_line_read(f, &buf, &cap, 1 << 20, &e) == -2, "/dev/zero: a NUL byte, at once");
    fclose(f);
    free(buf);
}

/* kt_huge_*: the C library's contract on both sides of KT_HUGE_MIN (zeroed calloc, realloc
 * keeps the prefix, free() releases) and kt_calloc's zeroed big blocks. */
static void test_huge_alloc(void)
{
    size_t sizes[] = {16, KT_HUGE_MIN - 8, KT_HUGE_MIN, 3 * KT_HUGE_MIN + 4096 + 8};
    for (int k = 0; k < 4; k++) {
        size_t n = sizes[k];
        unsigned char *p = kt_huge_calloc(n, 1);
        CHECK(p != NULL, "kt_huge_calloc(%zu)", n);
        if (!p) continue;
        size_t nz = 0;
        for (size_t i = 0; i < n; i += 97) nz += p[i] != 0;
        CHECK(nz == 0 && p[n - 1] == 0, "kt_huge_calloc(%zu): %zu nonzero bytes", n, nz);
        for (size_t i = 0; i < n; i++) p[i] = (unsigned char)(i * 7 + 1);
        unsigned char *q = kt_huge_realloc(p, 2 * n);
        CHECK(q != NULL, "kt_huge_realloc(%zu)", 2 * n);
        if (!q) {
            free(p);
            continue;
        }
        size_t bad = 0;
        for (size_t i = 0; i < n; i++) bad += q[i] != (unsigned char)(i * 7 + 1);
        CHECK(bad == 0, "kt_huge_realloc(%zu -> %zu) changed %zu bytes", n, 2 * n, bad);
        memset(q + n, 0xab, n);
        free(q);
        double *d = kt_huge_malloc(n);
        CHECK(d != NULL, "kt_huge_malloc(%zu)", n);
        if (d) memset(d, 0, n);
        free(d);
    }
    kt_err e = {0};
    double *x = kt_calloc(KT_HUGE_MIN, sizeof(double), &e);
    CHECK(x && e.code == 0, "kt_calloc of %zu doubles: %s", (size_t)KT_HUGE_MIN, e.msg);
    double sum = 0;
    for (size_t i = 0; x && i < KT_HUGE_MIN; i += 511) sum += fabs(x[i]);
    CHECK(sum == 0, "kt_calloc's big block is not zero");
    free(x);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/kt-util-XXXXXX");
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_atomic_output();
    test_errors_and_alloc();
    test_huge_alloc();
    test_parse();
    test_path_relative();
    test_out_targets();
    test_stale_temporaries();
    test_escape_and_lines();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
    return kt_test_done("test_util");
}
