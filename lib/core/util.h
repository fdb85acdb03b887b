/* util.h: errors, allocation, timers, progress and atomic output for every keratome module. */
#ifndef KT_UTIL_H
#define KT_UTIL_H

#include <stddef.h>
#include <stdio.h>

/* pi, the one definition every module uses. */
#define KT_PI 3.14159265358979323846

/* Exit codes, shared by every tool: run-time/numerical failure 1, bad usage or input 2. */
enum { KT_OK = 0, KT_ERUN = 1, KT_EINPUT = 2 };

/* An error: its code and one line, "file:line:col: what was expected" for bad input. */
typedef struct kt_err {
    int code;
    char msg[1024];
} kt_err;

/* Record an error (the first one wins) and return its code. */
int kt_fail(kt_err *e, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* calloc/realloc of n items with overflow check; failure is recorded as KT_ERUN.
 * Test hook (tests/alloc_fail.sh): with the environment variable KT_ALLOC_FAIL=N, the N-th
 * call of kt_calloc/kt_realloc in the process fails as if memory ran out. */
void *kt_calloc(size_t n, size_t size, kt_err *e);
void *kt_realloc(void *p, size_t n, size_t size, kt_err *e);
char *kt_strdup(const char *s, kt_err *e);

/* malloc, calloc and realloc with the C library's contract (NULL on failure, free() releases),
 * asking for transparent huge pages (madvise MADV_HUGEPAGE on the block's 2 MiB-aligned part)
 * on blocks of KT_HUGE_MIN bytes or more: a solve's big arrays (stiffness, factor, derivative
 * matrices) then take one page fault per 2 MiB instead of per 4 KiB. kt_calloc and kt_realloc
 * use them; augsolve hands them to SuiteSparse (SuiteSparse_config) for CHOLMOD's arrays. No
 * test hook here (KT_ALLOC_FAIL counts kt_calloc/kt_realloc only). */
#define KT_HUGE_MIN ((size_t)4 << 20)
void *kt_huge_malloc(size_t size);
void *kt_huge_calloc(size_t n, size_t size);
void *kt_huge_realloc(void *p, size_t size);

/* Monotonic wall-clock seconds. */
double kt_now(void);
/* The process's CPU seconds so far (user + system, every thread): what a phase costs on a shared
 * machine, where its wall seconds are the load's; NAN when the system cannot say. */
double kt_cpu_now(void);
/* The calling thread's CPU seconds (user and system; CLOCK_THREAD_CPUTIME_ID), NAN if unknown. */
double kt_thread_cpu_now(void);

/* Progress on stderr: a bar on a TTY, a plain line every 10% otherwise, nothing when quiet. */
typedef struct kt_progress {
    const char *what;
    long total;
    int quiet, tty, last;
    double t0;
} kt_progress;

void kt_progress_start(kt_progress *p, const char *what, long total, int quiet);
void kt_progress_update(kt_progress *p, long done);
void kt_progress_end(kt_progress *p);

/* A message on stderr unless quiet. */
void kt_log(int quiet, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Atomic output: written to a temporary beside the target ("NAME.tmp.HOST.PID.XXXXXX") and
 * renamed on commit, so a failed run leaves no partial file; the temporaries that dead processes
 * of this host left for the same target are removed on open. Path "-" is stdout (no rename). A
 * target that exists and is not a regular file (a device such as /dev/null, a FIFO) is written
 * to directly (direct), never replaced; a directory is refused (KT_EINPUT). A symbolic link
 * stays a link: the file it leads to is replaced. */
typedef struct kt_out {
    FILE *f;
    char *path, *tmp;
    int is_stdout, direct;
    struct kt_out_sink *sink; /* the descriptor under f and the first write error (util.c) */
} kt_out;

/* KT_OK when path can be an output target (it is not a directory, and a device or FIFO there
 * is writable): check it before any work. Opens nothing. */
int kt_out_check(const char *path, kt_err *e);
int kt_out_open(kt_out *o, const char *path, kt_err *e);
int kt_out_commit(kt_out *o, kt_err *e);
void kt_out_abort(kt_out *o);
/* Write errors: the first failed write(2) under o->f is kept with its errno, and every later
 * write fails at once (the stream's error flag is set: a writer that checks ferror stops; one
 * that does not costs no more disk). kt_out_failed: KT_OK while nothing failed, else KT_ERUN
 * recorded as "PATH: write failed: CAUSE" (kt_io_cause), the output left open for
 * kt_out_abort. kt_out_commit reports the same way, naming the file. */
int kt_out_failed(const kt_out *o, kt_err *e);
/* The cause of an I/O errno in words: ENOSPC and EDQUOT "disk full (No space left on device)",
 * EFBIG "file too large (...)", else strerror. */
const char *kt_io_cause(int err);

/* KT_OK when `bytes` more can be allocated and touched: no more than the address space left
 * under RLIMIT_AS (ulimit -v; the process's size from /proc/self/statm) and no more than the
 * machine's MemAvailable. Else KT_ERUN, "WHAT: out of memory: needs N MB, ... leaves M MB".
 * For a block the work cannot go on without (a Cholesky factor, sized exactly by the symbolic
 * analysis), checked before the work that fills it: the failure is immediate and names the
 * need, instead of an allocation failing after minutes, or the OOM killer's SIGKILL. */
int kt_mem_budget(double bytes, const char *what, kt_err *e);

/* For a caller that may run independent work side by side: the cores online less the 1-minute
 * load average (rounded), at least 1; and the bytes it may still take (MemAvailable, and under
 * RLIMIT_AS the address space left: the smaller; SIZE_MAX when neither is known). kt_as_limited:
 * 1 under an address-space (ulimit -v) or data (ulimit -d) limit, where a second thread's first
 * BLAS call could not map its work buffer (blas.h) and must not be made. */
int kt_cores_free(void);
size_t kt_mem_room(void);
int kt_as_limited(void);

/* An output must not be one of the tool's inputs: writing it would destroy the input (mesh-prep
 * S.yaml -o S.yaml). kt_out_distinct: KT_EINPUT "OUT: the output is the input IN (the same
 * file): refusing to overwrite it" when the file `out` and one of the n inputs in[] (NULL
 * entries and "-" skipped) are one file: the same device and inode, so also through a symbolic
 * link or a hard link. An output that does not exist yet is no input. kt_outdir_distinct, for a
 * tool that writes into a folder: KT_EINPUT when an input is a file the tool writes in `dir`,
 * that is, it lies in `dir` itself (the same device and inode as the folder, its symbolic links
 * resolved) and its name matches one of the nnames fnmatch(3) patterns names[]; with names NULL
 * every input anywhere below `dir` is refused (a folder that is replaced whole). */
int kt_out_distinct(const char *out, const char *const *in, int n, kt_err *e);
int kt_outdir_distinct(const char *dir, const char *const *names, int nnames, const char *const *in, int n,
                       kt_err *e);

/* At a tool's start: a closed standard stream (0, 1, 2) gets a descriptor on which every
 * read or write fails, so that no file the tool opens takes its number and an output to a
 * closed stdout is an error, not a write into that file. Then the BLAS is pinned to one
 * thread (kt_blas_pin, blas.h): the same answer on any machine; and its work buffer is taken
 * (kt_blas_warm): no hang under ulimit -v. When the address-space limit cannot hold that
 * buffer, the tool ends here: "TOOL: out of memory: ..." on stderr, exit 1.
 * CHOLMOD's allocations go through kt_huge_* (SuiteSparse_config's hooks), and its OpenMP
 * regions are bounded by the free cores (omp_set_dynamic). */
void kt_tool_start(void);
/* At the start of a thread the library starts: what kt_tool_start set for the tool's thread and
 * a new thread does not inherit (OpenMP's dynamic adjustment is per thread: without it
 * CHOLMOD's regions on that thread would take their 4 threads whatever the load). */
void kt_thread_start(void);

/* A tool's end, with exit status code: stdio flushed, then _exit, skipping the libraries'
 * destructors: OpenBLAS's joins its worker threads, and one whose buffer allocation failed
 * under a memory limit retries it for ever, so that a run that failed (or even succeeded)
 * hung at exit. Sanitizer builds exit normally, for LeakSanitizer's check at exit. */
void kt_exit(int code) __attribute__((noreturn));

/* At a tool's successful end: flush and close stdout. KT_OK, or KT_ERUN (the exit code) with
 * "TOOL: <stdout>: write failed: why" on stderr when any of its output was lost (a full disk,
 * a closed stdout). */
int kt_stdout_done(const char *tool);

/* One line of f into *buf (grown as needed; *cap its size), reading no further than a NUL byte
 * or than max bytes, so that /dev/zero or an endless line cannot grow memory: the line's
 * length (its '\n' included, NUL-terminated), -1 at the end of the stream (nothing read), -2
 * on a NUL byte, -3 on a line longer than max, -4 out of memory (recorded in e). */
long kt_line_read(FILE *f, char **buf, size_t *cap, size_t max, kt_err *e);

/* The path of file relative to the folder dir, both existing: "../mesh/eye.msh". Resolves
 * both (realpath); when either cannot be resolved or the result does not fit, file as given.
 * Run folders store their inputs this way, so a tree holding a run and its inputs can move. */
void kt_path_relative(const char *file, const char *dir, char *out, size_t size);
/* out := the folder of path ("." for a bare name or "-", "/" at the root), and the file name
 * without folder and extension: what a scene, plan or patient file resolves its paths against
 * and is named by. */
void kt_path_dir(const char *path, char *out, size_t size);
void kt_path_stem(const char *path, char *out, size_t size);

/* The 64-bit FNV-1a hash of a file's bytes into *h (run.yaml's plan_hash: a run's inputs are
 * checked against what a later reader finds). KT_EINPUT when it cannot be read. */
int kt_fnv1a_file(const char *path, unsigned long long *h, kt_err *e);

/* Make a directory (and parents) if it does not exist. */
int kt_mkdir_p(const char *path, kt_err *e);

/* The larger of a and b, NaN when either is NaN. fmax drops a NaN, so a maximum built with it
 * can let a NaN field pass the tolerance check it feeds; build such maxima with this. */
static inline double kt_nanmax(double a, double b) { return a > b || a != a ? a : b; }

/* Parse a whole string as a double / int; 0 on success. kt_parse_double takes what strtod
 * takes (also "NaN" and "inf", as tables write them); kt_parse_int a decimal integer, no
 * leading blank. */
int kt_parse_double(const char *s, double *v);
int kt_parse_int(const char *s, int *v);
/* The strict parser of a number a user types (arguments, edits values): the whole string in
 * decimal notation, [+-]digits[.digits][(e|E)[+-]digits] (digits on at least one side of the
 * point), finite, no blanks, hex, "inf" or "nan"; 0 on success, *v unchanged otherwise. */
int kt_parse_number(const char *s, double *v);

#endif
