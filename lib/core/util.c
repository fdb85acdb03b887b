/* util.c: errors, allocation, timers, progress and atomic output. */
#define _GNU_SOURCE
#include "util.h"
#include "blas.h"

#include <SuiteSparse_config.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <fcntl.h>
#include <fnmatch.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

int kt_fail(kt_err *e, int code, const char *fmt, ...)
{
    if (!e || e->code != KT_OK) return e ? e->code : code;
    char raw[sizeof e->msg];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(raw, sizeof raw, fmt, ap);
    va_end(ap);
    /* Control characters of the input a message quotes are shown escaped, never sent to the
     * terminal: C0 and DEL as \xNN, C1 (UTF-8 c2 80..9f) as \u00NN. */
    size_t o = 0, cap = sizeof e->msg;
    for (const unsigned char *p = (const unsigned char *)raw; *p && o + 7 < cap; p++) {
        if (*p < 0x20 || *p == 0x7f)
            o += (size_t)snprintf(e->msg + o, cap - o, "\\x%02x", *p);
        else if (*p == 0xc2 && p[1] >= 0x80 && p[1] <= 0x9f)
            o += (size_t)snprintf(e->msg + o, cap - o, "\\u00%02x", *++p);
        else
            e->msg[o++] = (char)*p;
    }
    e->msg[o] = '\0';
    e->code = code;
    return code;
}

/* The allocation-failure test hook: the count of calls so far and the one to fail (0: none),
 * read once from KT_ALLOC_FAIL. The only mutable file-scope state of the library, used by the
 * test alone. It is atomic: lri-plan's families may run on threads of their own
 * (lib/planner/lp_run.h), and then which of them meets the failing call is theirs to race for
 * (either ends the run the same way). */
static _Atomic long alloc_calls;
static _Atomic long alloc_fail_at = -1;

static int alloc_should_fail(void)
{
    if (alloc_fail_at < 0) {
        const char *v = getenv("KT_ALLOC_FAIL");
        alloc_fail_at = v ? atol(v) : 0;
    }
    return alloc_fail_at > 0 && ++alloc_calls == alloc_fail_at;
}

/* 0 when n x size bytes may be asked for (n raised to 1), else KT_ERUN recorded: the test
 * hook's failure, or a product that overflows. */
static int alloc_check(size_t *n, size_t size, kt_err *e)
{
    if (alloc_should_fail())
        return kt_fail(e, KT_ERUN, "out of memory: %zu x %zu bytes (KT_ALLOC_FAIL)", *n, size);
    if (*n == 0) *n = 1;
    if (size && *n > SIZE_MAX / size)
        return kt_fail(e, KT_ERUN, "out of memory: %zu x %zu bytes", *n, size);
    return KT_OK;
}

/* Transparent huge pages for a block of KT_HUGE_MIN bytes or more: the 2 MiB-aligned part of
 * [p, p + bytes) is advised MADV_HUGEPAGE, so that its first touch faults once per 2 MiB instead
 * of once per 4 KiB (with THP in "madvise" mode; "always" needs no advice, "never" ignores it).
 * The block stays the C library's (free() releases it); advice that fails changes nothing. */
static void *huge_advise(void *p, size_t bytes)
{
    if (!p || bytes < KT_HUGE_MIN) return p;
    const uintptr_t page = (uintptr_t)2 << 20;
    uintptr_t lo = ((uintptr_t)p + page - 1) & ~(page - 1), hi = ((uintptr_t)p + bytes) & ~(page - 1);
    if (hi > lo) (void)madvise((void *)lo, hi - lo, MADV_HUGEPAGE);
    return p;
}

void *kt_huge_malloc(size_t size)
{
    return huge_advise(malloc(size), size);
}

void *kt_huge_calloc(size_t n, size_t size)
{
    return huge_advise(calloc(n, size), size && n <= SIZE_MAX / size ? n * size : 0);
}

void *kt_huge_realloc(void *p, size_t size)
{
    return huge_advise(realloc(p, size), size);
}

void *kt_calloc(size_t n, size_t size, kt_err *e)
{
    if (alloc_check(&n, size, e)) return NULL;
    void *p = kt_huge_calloc(n, size);
    if (!p) kt_fail(e, KT_ERUN, "out of memory: %zu x %zu bytes", n, size);
    return p;
}

void *kt_realloc(void *p, size_t n, size_t size, kt_err *e)
{
    if (alloc_check(&n, size, e)) return NULL;
    void *q = kt_huge_realloc(p, n * size);
    if (!q) kt_fail(e, KT_ERUN, "out of memory: %zu x %zu bytes", n, size);
    return q;
}

char *kt_strdup(const char *s, kt_err *e)
{
    size_t n = strlen(s) + 1;
    char *d = kt_calloc(n, 1, e);
    if (d) memcpy(d, s, n);
    return d;
}

double kt_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double kt_thread_cpu_now(void)
{
    struct timespec t;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t) != 0) return NAN;
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

double kt_cpu_now(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return NAN;
    return (double)(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) + 1e-6 * (double)(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

void kt_progress_start(kt_progress *p, const char *what, long total, int quiet)
{
    p->what = what;
    p->total = total > 0 ? total : 1;
    p->quiet = quiet;
    p->tty = isatty(STDERR_FILENO);
    p->last = -1;
    p->t0 = kt_now();
    kt_progress_update(p, 0);
}

void kt_progress_update(kt_progress *p, long done)
{
    if (p->quiet) return;
    int pct = (int)(100.0 * (double)done / (double)p->total);
    if (pct > 100) pct = 100;
    if (p->tty) {
        if (pct == p->last) return;
        int w = pct / 4;
        fprintf(stderr, "\r%-24s [%-25.*s] %3d%%", p->what, w, "#########################", pct);
    } else {
        if (p->last >= 0 && pct / 10 == p->last / 10) return;
        fprintf(stderr, "%s: %d%% (%ld/%ld, %.1f s)\n", p->what, pct, done, p->total,
                kt_now() - p->t0);
    }
    p->last = pct;
}

void kt_progress_end(kt_progress *p)
{
    if (p->quiet) return;
    if (p->tty)
        fprintf(stderr, "\r%-24s done in %.2f s%24s\n", p->what, kt_now() - p->t0, "");
    else
        fprintf(stderr, "%s: done in %.2f s\n", p->what, kt_now() - p->t0);
}

void kt_log(int quiet, const char *fmt, ...)
{
    if (quiet) return;
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
}

/* The name stem of the temporaries of target `path` (the file name part only) for this host:
 * "NAME.tmp.HOST." ; a temporary is the stem, the writer's pid, '.', six random characters. */
static void tmp_stem(const char *path, char *stem, size_t size)
{
    char host[65] = "";
    if (gethostname(host, sizeof host - 1) != 0 || !host[0]) snprintf(host, sizeof host, "host");
    for (char *h = host; *h; h++)
        if (*h == '/' || *h == '.') *h = '_';
    const char *base = strrchr(path, '/');
    snprintf(stem, size, "%s.tmp.%s.", base ? base + 1 : path, host);
}

/* Remove the temporaries of `path` left by dead processes of this host: regular files of ours
 * named STEM PID '.' XXXXXX whose PID no longer exists. A live writer's file is never touched
 * (its pid exists), nor another host's (the stem names the host), nor another user's. */
static void clean_stale(const char *path)
{
    char dir[4096], stem[512];
    const char *slash = strrchr(path, '/');
    if (slash) snprintf(dir, sizeof dir, "%.*s", (int)(slash - path == 0 ? 1 : slash - path), path);
    else snprintf(dir, sizeof dir, ".");
    tmp_stem(path, stem, sizeof stem);
    size_t ls = strlen(stem);
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *de;
    while ((de = readdir(d)) != NULL) {
        const char *n = de->d_name;
        if (strncmp(n, stem, ls) != 0) continue;
        char *end;
        errno = 0;
        long pid = strtol(n + ls, &end, 10);
        if (end == n + ls || errno || pid <= 0 || pid > INT_MAX || *end != '.' || strlen(end + 1) != 6)
            continue;
        if (pid == (long)getpid() || kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue;
        struct stat st;
        char full[4096 + 256];
        snprintf(full, sizeof full, "%s/%s", dir, n);
        if (lstat(full, &st) == 0 && S_ISREG(st.st_mode) && st.st_uid == geteuid()) unlink(full);
    }
    closedir(d);
}

/* The file an output to `path` replaces: path itself, or the end of its chain of symbolic
 * links (so that the link stays a link), into real (PATH_MAX bytes). */
static void target_of(const char *path, char *real)
{
    struct stat st;
    snprintf(real, PATH_MAX, "%s", path);
    if (lstat(path, &st) == 0 && S_ISLNK(st.st_mode)) {
        char r[PATH_MAX];
        if (realpath(path, r)) snprintf(real, PATH_MAX, "%s", r);
    }
}

const char *kt_io_cause(int err)
{
    if (err == ENOSPC) return "disk full (No space left on device)";
    if (err == EDQUOT) return "disk full (Disk quota exceeded)";
    if (err == EFBIG) return "file too large (File too large)";
    return strerror(err);
}

/* The stream under a kt_out: its descriptor, and the first write error. A write after one has
 * failed fails at once, so the rest of a file is not attempted. */
struct kt_out_sink {
    int fd;
    int err;
};

static ssize_t sink_write(void *cookie, const char *buf, size_t n)
{
    struct kt_out_sink *s = cookie;
    if (s->err) {
        errno = s->err;
        return -1;
    }
    size_t done = 0;
    while (done < n) {
        ssize_t w = write(s->fd, buf + done, n - done);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            s->err = w < 0 ? errno : EIO;
            errno = s->err;
            return done ? (ssize_t)done : -1;
        }
        done += (size_t)w;
    }
    return (ssize_t)n;
}

static int sink_close(void *cookie)
{
    struct kt_out_sink *s = cookie;
    int rc = s->fd >= 0 ? close(s->fd) : 0;
    if (rc != 0 && !s->err) s->err = errno;
    s->fd = -1;
    return rc;
}

/* o->f over fd, through a sink (o->sink) that keeps the first write error; fd is closed on
 * failure. */
static int sink_open(kt_out *o, int fd, const char *path, kt_err *e)
{
    o->sink = kt_calloc(1, sizeof *o->sink, e);
    if (!o->sink) {
        close(fd);
        return e->code;
    }
    o->sink->fd = fd;
    cookie_io_functions_t io = {NULL, sink_write, NULL, sink_close};
    o->f = fopencookie(o->sink, "w", io);
    if (!o->f) {
        close(fd);
        free(o->sink);
        o->sink = NULL;
        return kt_fail(e, KT_ERUN, "%s: cannot open a stream: %s", path, strerror(errno));
    }
    setvbuf(o->f, NULL, _IOFBF, 1 << 16);
    return KT_OK;
}

int kt_out_failed(const kt_out *o, kt_err *e)
{
    if (!o->f || !ferror(o->f)) return KT_OK;
    int err = o->sink && o->sink->err ? o->sink->err : EIO;
    return kt_fail(e, KT_ERUN, "%s: write failed: %s", o->is_stdout ? "<stdout>" : o->path ? o->path : "?",
                   kt_io_cause(err));
}

int kt_out_check(const char *path, kt_err *e)
{
    if (strcmp(path, "-") == 0) return KT_OK;
    struct stat st;
    if (!path[0]) return kt_fail(e, KT_EINPUT, "expected an output file name, found ''");
    if (stat(path, &st) != 0) return KT_OK; /* made by kt_out_open, which reports failures */
    if (S_ISDIR(st.st_mode))
        return kt_fail(e, KT_EINPUT, "%s: cannot write the output file: is a directory", path);
    if (!S_ISREG(st.st_mode) && access(path, W_OK) != 0)
        return kt_fail(e, KT_EINPUT, "%s: cannot write the output: %s", path, strerror(errno));
    return KT_OK;
}

int kt_out_open(kt_out *o, const char *path, kt_err *e)
{
    memset(o, 0, sizeof *o);
    if (strcmp(path, "-") == 0) {
        o->f = stdout;
        o->is_stdout = 1;
        return KT_OK;
    }
    if (kt_out_check(path, e)) return e->code;
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        /* A device or FIFO is written to as it is: renaming a file over it would replace it. */
        int fd = open(path, O_WRONLY | O_NOCTTY);
        if (fd < 0) return kt_fail(e, KT_EINPUT, "%s: cannot open the output: %s", path, strerror(errno));
        if (!(o->path = kt_strdup(path, e))) {
            close(fd);
            return e->code;
        }
        if (sink_open(o, fd, path, e)) {
            kt_out_abort(o);
            return e->code;
        }
        o->direct = 1;
        return KT_OK;
    }
    char real[PATH_MAX], stem[512];
    target_of(path, real);
    clean_stale(real);
    tmp_stem(real, stem, sizeof stem);
    const char *slash = strrchr(real, '/');
    int dirlen = slash ? (int)(slash - real + 1) : 0;
    size_t size = strlen(real) + strlen(stem) + 32;
    o->path = kt_strdup(real, e);
    o->tmp = kt_calloc(size, 1, e);
    if (!o->path || !o->tmp) {
        kt_out_abort(o);
        return e->code;
    }
    snprintf(o->tmp, size, "%.*s%s%ld.XXXXXX", dirlen, real, stem, (long)getpid());
    int fd = mkstemp(o->tmp);
    if (fd < 0) {
        int err = errno;
        free(o->tmp);
        o->tmp = NULL;
        kt_out_abort(o);
        return kt_fail(e, KT_EINPUT, "%s: cannot create output file: %s", path, strerror(err));
    }
    fchmod(fd, 0644);
    if (sink_open(o, fd, path, e)) {
        kt_out_abort(o);
        return e->code;
    }
    return KT_OK;
}

int kt_out_commit(kt_out *o, kt_err *e)
{
    if (o->is_stdout) {
        errno = 0;
        if (fflush(stdout) != 0 || ferror(stdout))
            return kt_fail(e, KT_ERUN, "<stdout>: write failed%s%s", errno ? ": " : "", errno ? kt_io_cause(errno) : "");
        o->f = NULL;
        return KT_OK;
    }
    int bad = ferror(o->f) != 0;
    if (fclose(o->f) != 0) bad = 1;
    o->f = NULL;
    if (bad) {
        int err = o->sink && o->sink->err ? o->sink->err : EIO;
        kt_fail(e, KT_ERUN, "%s: write failed: %s", o->path, kt_io_cause(err));
        kt_out_abort(o);
        return e->code;
    }
    if (o->direct) {
        free(o->path);
        free(o->sink);
        memset(o, 0, sizeof *o);
        return KT_OK;
    }
    if (rename(o->tmp, o->path) != 0) {
        kt_fail(e, KT_ERUN, "%s: cannot rename the output into place: %s", o->path, kt_io_cause(errno));
        kt_out_abort(o);
        return e->code;
    }
    free(o->tmp);
    free(o->path);
    free(o->sink);
    o->tmp = o->path = NULL;
    o->sink = NULL;
    return KT_OK;
}

void kt_out_abort(kt_out *o)
{
    if (o->f && !o->is_stdout) fclose(o->f); /* a direct output keeps what it got */
    if (o->tmp) unlink(o->tmp);
    free(o->tmp);
    free(o->path);
    free(o->sink);
    memset(o, 0, sizeof *o);
}

static int skip_input(const char *in)
{
    return !in || !in[0] || strcmp(in, "-") == 0;
}

int kt_out_distinct(const char *out, const char *const *in, int n, kt_err *e)
{
    struct stat so, si;
    if (skip_input(out) || stat(out, &so) != 0 || !S_ISREG(so.st_mode)) return KT_OK;
    for (int i = 0; i < n; i++)
        if (!skip_input(in[i]) && stat(in[i], &si) == 0 && si.st_dev == so.st_dev && si.st_ino == so.st_ino)
            return kt_fail(e, KT_EINPUT, "%s: the output is the input %s (the same file): refusing to overwrite it", out,
                           in[i]);
    return KT_OK;
}

/* 1 when the folder `dir` (resolved) is the folder d (device and inode). */
static int same_dir(const char *dir, const struct stat *d)
{
    struct stat s;
    return stat(dir, &s) == 0 && s.st_dev == d->st_dev && s.st_ino == d->st_ino;
}

int kt_outdir_distinct(const char *dir, const char *const *names, int nnames, const char *const *in, int n,
                       kt_err *e)
{
    struct stat sd;
    if (stat(dir, &sd) != 0 || !S_ISDIR(sd.st_mode)) return KT_OK; /* made later: holds no input */
    for (int i = 0; i < n; i++) {
        char real[PATH_MAX];
        if (skip_input(in[i]) || !realpath(in[i], real)) continue;
        char *slash = strrchr(real, '/');
        const char *base = slash + 1;
        int hit = 0;
        if (names) {
            *slash = '\0';
            if (same_dir(real[0] ? real : "/", &sd))
                for (int k = 0; k < nnames && !hit; k++) hit = fnmatch(names[k], base, 0) == 0;
        } else {
            while (!hit && slash) { /* every folder above the input, up to the root */
                *slash = '\0';
                hit = same_dir(real[0] ? real : "/", &sd);
                slash = real[0] ? strrchr(real, '/') : NULL;
            }
        }
        if (hit)
            return kt_fail(e, KT_EINPUT, "%s: the output folder holds the input %s, which this run would %s: refusing",
                           dir, in[i], names ? "overwrite" : "replace with the folder");
    }
    return KT_OK;
}

void kt_tool_start(void)
{
    for (int fd = 0; fd <= 2; fd++) {
        if (fcntl(fd, F_GETFD) != -1 || errno != EBADF) continue;
        /* stdin write-only, stdout and stderr read-only: every use fails with EBADF. */
        int g = open("/dev/null", fd == 0 ? O_WRONLY : O_RDONLY);
        if (g >= 0 && g != fd) {
            dup2(g, fd);
            close(g);
        }
    }
    kt_blas_pin(); /* the same answer on any machine (blas.h) */
    if (kt_blas_warm() == KT_BLAS_WARM_NOROOM) {
        /* a BLAS call would hang (blas.h): end now, with a message */
        fprintf(stderr, "%s: out of memory: the address space left under the limit (ulimit -v) cannot hold "
                "the BLAS's %zu MB work buffer\n", program_invocation_short_name, KT_BLAS_BUFFER >> 20);
        kt_exit(KT_ERUN);
    }
    /* CHOLMOD's arrays (the factor above all) on transparent huge pages (kt_huge_*), set once
     * before any CHOLMOD call; their free stays the C library's */
    SuiteSparse_config.malloc_func = kt_huge_malloc;
    SuiteSparse_config.calloc_func = kt_huge_calloc;
    SuiteSparse_config.realloc_func = kt_huge_realloc;
#ifdef _OPENMP
    /* CHOLMOD (SuiteSparse 5) opens an OpenMP region of a fixed 4 threads for each large
     * supernode's clearing and scatter (data-parallel loops: the numbers do not depend on the
     * thread count); dynamic adjustment gives it at most the cores the load leaves free, instead
     * of threads that spin and sleep on a busy 2-core machine */
    omp_set_dynamic(1);
#endif
}

void kt_thread_start(void)
{
#ifdef _OPENMP
    omp_set_dynamic(1);
#endif
}

/* The bytes of address space left under RLIMIT_AS (SIZE_MAX without a limit). */
static size_t as_room(void)
{
    struct rlimit r;
    if (getrlimit(RLIMIT_AS, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return SIZE_MAX;
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long pages = 0;
    int ok = f && fscanf(f, "%lu", &pages) == 1;
    if (f) fclose(f);
    if (!ok) return SIZE_MAX;
    size_t used = (size_t)pages * (size_t)sysconf(_SC_PAGESIZE);
    return used < r.rlim_cur ? (size_t)r.rlim_cur - used : 0;
}

/* MemAvailable of /proc/meminfo in bytes (SIZE_MAX when it cannot be read). */
static size_t mem_available(void)
{
    FILE *f = fopen("/proc/meminfo", "r");
    if (!f) return SIZE_MAX;
    char line[256];
    size_t kb = SIZE_MAX;
    unsigned long v;
    while (fgets(line, sizeof line, f))
        if (sscanf(line, "MemAvailable: %lu kB", &v) == 1) {
            kb = v;
            break;
        }
    fclose(f);
    return kb == SIZE_MAX || kb > SIZE_MAX / 1024 ? SIZE_MAX : kb * 1024;
}

int kt_cores_free(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    double load[1];
    if (n < 1) n = 1;
    if (getloadavg(load, 1) == 1 && load[0] >= 0) n -= (long)(load[0] + 0.5);
    return n < 1 ? 1 : (int)n;
}

size_t kt_mem_room(void)
{
    size_t as = as_room(), avail = mem_available();
    return as < avail ? as : avail;
}

int kt_as_limited(void)
{
    struct rlimit r;
    int as = getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY;
    int data = getrlimit(RLIMIT_DATA, &r) == 0 && r.rlim_cur != RLIM_INFINITY;
    return as || data;
}

int kt_mem_budget(double bytes, const char *what, kt_err *e)
{
    if (!(bytes >= 0)) return kt_fail(e, KT_ERUN, "%s: out of memory: needs an unknown amount", what);
    size_t as = as_room(), avail = mem_available();
    if (as != SIZE_MAX && !(bytes <= (double)as))
        return kt_fail(e, KT_ERUN, "%s: out of memory: needs %.0f MB, the address-space limit (ulimit -v) leaves %.0f MB",
                       what, bytes / 1048576, (double)as / 1048576);
    if (avail != SIZE_MAX && !(bytes <= (double)avail))
        return kt_fail(e, KT_ERUN, "%s: out of memory: needs %.0f MB, the machine has %.0f MB available (MemAvailable)",
                       what, bytes / 1048576, (double)avail / 1048576);
    return KT_OK;
}

void kt_exit(int code)
{
    fflush(NULL);
#if defined(__SANITIZE_ADDRESS__)
    exit(code); /* LeakSanitizer checks at exit; ASan cannot run under ulimit -v anyway */
#else
    _exit(code);
#endif
}

int kt_stdout_done(const char *tool)
{
    errno = 0;
    int bad = fflush(stdout) != 0 || ferror(stdout);
    int err = errno;
    if (fclose(stdout) != 0 && !bad) bad = 1, err = errno;
    if (!bad) return KT_OK;
    fprintf(stderr, "%s: <stdout>: write failed: %s\n", tool, err ? kt_io_cause(err) : "output lost");
    return KT_ERUN;
}

long kt_line_read(FILE *f, char **buf, size_t *cap, size_t max, kt_err *e)
{
    size_t n = 0;
    int ch;
    while ((ch = getc(f)) != EOF) {
        if (ch == '\0') return -2;
        if (n + 2 > *cap) {
            if (n >= max) return -3;
            size_t nc = *cap ? 2 * *cap : 256;
            char *nb = kt_realloc(*buf, nc, 1, e);
            if (!nb) return -4;
            *buf = nb, *cap = nc;
        }
        (*buf)[n++] = (char)ch;
        if (ch == '\n') break;
    }
    if (n == 0) return -1;
    (*buf)[n] = '\0';
    return n > max ? -3 : (long)n;
}

void kt_path_relative(const char *file, const char *dir, char *out, size_t size)
{
    char f[PATH_MAX], d[PATH_MAX];
    snprintf(out, size, "%s", file);
    if (strcmp(file, "-") == 0 || !realpath(file, f) || !realpath(dir, d)) return;
    size_t i = 0, common = 0; /* f[0, common) and d[0, common): the shared whole components */
    while (f[i] && f[i] == d[i])
        if (f[i++] == '/') common = i;
    int inside = d[i] == '\0' && f[i] == '/'; /* file lies inside dir: no "../" at all */
    if (inside) common = i + 1;
    char rel[PATH_MAX];
    size_t len = 0;
    if (!inside && d[common]) { /* one "../" per component of dir after the shared ones */
        len += (size_t)snprintf(rel, sizeof rel, "../");
        for (const char *q = d + common; *q && len + 4 < sizeof rel; q++)
            if (*q == '/') len += (size_t)snprintf(rel + len, sizeof rel - len, "../");
    }
    if (len + strlen(f + common) + 1 > sizeof rel || len + strlen(f + common) + 1 > size) return;
    snprintf(rel + len, sizeof rel - len, "%s", f + common);
    snprintf(out, size, "%s", rel);
}

int kt_mkdir_p(const char *path, kt_err *e)
{
    char buf[4096];
    size_t n = strlen(path);
    if (n == 0 || n >= sizeof buf) return kt_fail(e, KT_EINPUT, "%s: bad directory name", path);
    memcpy(buf, path, n + 1);
    for (size_t i = 1; i <= n; i++) {
        if (buf[i] != '/' && buf[i] != '\0') continue;
        char c = buf[i];
        buf[i] = '\0';
        if (mkdir(buf, 0755) != 0 && errno != EEXIST)
            return kt_fail(e, KT_EINPUT, "%s: cannot create directory: %s", buf, strerror(errno));
        buf[i] = c;
    }
    return KT_OK;
}

int kt_parse_double(const char *s, double *v)
{
    char *end;
    errno = 0;
    *v = strtod(s, &end);
    return (end == s || *end != '\0' || errno == ERANGE) ? -1 : 0;
}

int kt_parse_number(const char *s, double *v)
{
    const char *p = s;
    int digits = 0;
    if (*p == '+' || *p == '-') p++;
    for (; *p >= '0' && *p <= '9'; p++) digits++;
    if (*p == '.')
        for (p++; *p >= '0' && *p <= '9'; p++) digits++;
    if (!digits) return -1;
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-') p++;
        if (!(*p >= '0' && *p <= '9')) return -1;
        while (*p >= '0' && *p <= '9') p++;
    }
    double x;
    if (*p || kt_parse_double(s, &x) != 0 || !isfinite(x)) return -1;
    *v = x;
    return 0;
}

int kt_parse_int(const char *s, int *v)
{
    char *end;
    if (!((*s >= '0' && *s <= '9') || *s == '-' || *s == '+')) return -1; /* no leading blank */
    errno = 0;
    long l = strtol(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE || l < INT_MIN || l > INT_MAX) return -1;
    *v = (int)l;
    return 0;
}

int kt_fnv1a_file(const char *path, unsigned long long *h, kt_err *e)
{
    FILE *f = fopen(path, "rb");
    if (!f) return kt_fail(e, KT_EINPUT, "%s: cannot open: %s", path, strerror(errno));
    uint64_t v = 14695981039346656037ull;
    unsigned char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0)
        for (size_t i = 0; i < n; i++) v = (v ^ buf[i]) * 1099511628211ull;
    int bad = ferror(f);
    fclose(f);
    if (bad) return kt_fail(e, KT_EINPUT, "%s: read error", path);
    *h = (unsigned long long)v;
    return KT_OK;
}

void kt_path_dir(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (strcmp(path, "-") == 0 || !slash) snprintf(out, size, ".");
    else if (slash == path) snprintf(out, size, "/");
    else snprintf(out, size, "%.*s", (int)(slash - path), path);
}

void kt_path_stem(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    const char *b = slash ? slash + 1 : path;
    const char *dot = strrchr(b, '.');
    int len = dot && dot != b ? (int)(dot - b) : (int)strlen(b);
    snprintf(out, size, "%.*s", len, b);
}
