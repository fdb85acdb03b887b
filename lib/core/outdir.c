/* outdir.c: an output folder written as a unit (outdir.h). */
#define _GNU_SOURCE
#include "outdir.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

/* The temporary folder a signal must remove: the one piece of process-wide state here (a
 * signal handler has no context), set between kt_outdir_begin and commit/abort. */
static char sig_tmp[PATH_MAX];
static char sig_lock[PATH_MAX];
static struct sigaction sig_old[3];
static const int SIGS[3] = {SIGINT, SIGTERM, SIGHUP};

static int rm_one(const char *p, const struct stat *st, int flag, struct FTW *f)
{
    (void)st, (void)f;
    return flag == FTW_DP ? rmdir(p) : unlink(p);
}

/* rm -rf path (not following symbolic links); 0 on success. */
static int rm_tree(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0) return errno == ENOENT ? 0 : -1;
    if (!S_ISDIR(st.st_mode)) return unlink(path);
    return nftw(path, rm_one, 16, FTW_DEPTH | FTW_PHYS);
}

/* rm -rf of the folder `name` in the folder dfd with system calls alone (openat, getdents64,
 * unlinkat, close: async-signal-safe; opendir, nftw, malloc and fork are not: a signal that
 * arrives inside malloc would deadlock them). Depth-first, at most 16 levels, fixed buffers. */
static int rm_tree_sig(int dfd, const char *name, int depth)
{
    if (unlinkat(dfd, name, 0) == 0) return 0;
    if (depth > 16) return -1;
    int fd = openat(dfd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) return -1;
    char buf[4096];
    for (;;) {
        long n = syscall(SYS_getdents64, fd, buf, sizeof buf);
        if (n <= 0) break;
        int removed = 0;
        for (long off = 0; off < n;) {
            struct linux_dirent64_kt {
                unsigned long long d_ino;
                long long d_off;
                unsigned short d_reclen;
                unsigned char d_type;
                char d_name[];
            } *de = (void *)(buf + off);
            off += de->d_reclen;
            if (strcmp(de->d_name, ".") == 0 || strcmp(de->d_name, "..") == 0) continue;
            int gone = de->d_type == DT_DIR ? rm_tree_sig(fd, de->d_name, depth + 1) == 0
                                            : unlinkat(fd, de->d_name, 0) == 0;
            removed += gone;
        }
        if (!removed) break;     /* nothing more can go */
        lseek(fd, 0, SEEK_SET); /* the listing changed under us: read it again */
    }
    close(fd);
    return unlinkat(dfd, name, AT_REMOVEDIR);
}

/* On SIGINT, SIGTERM, SIGHUP: the temporary folder and the lock file removed, then the
 * signal's default action. */
static void on_signal(int sig)
{
    if (sig_tmp[0]) rm_tree_sig(AT_FDCWD, sig_tmp, 0);
    if (sig_lock[0]) unlink(sig_lock);
    signal(sig, SIG_DFL);
    raise(sig);
}

static void guard(const kt_outdir *d)
{
    snprintf(sig_tmp, sizeof sig_tmp, "%s", d->tmp);
    snprintf(sig_lock, sizeof sig_lock, "%s", d->lock);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    for (int i = 0; i < 3; i++) {
        struct sigaction cur;
        sigaction(SIGS[i], NULL, &cur);
        sig_old[i] = cur;
        if (cur.sa_handler != SIG_IGN) sigaction(SIGS[i], &sa, NULL); /* nohup's SIG_IGN stays */
    }
}

static void unguard(void)
{
    sigset_t set, old;
    sigemptyset(&set);
    for (int i = 0; i < 3; i++) sigaddset(&set, SIGS[i]);
    sigprocmask(SIG_BLOCK, &set, &old);
    for (int i = 0; i < 3; i++) sigaction(SIGS[i], &sig_old[i], NULL);
    sig_tmp[0] = sig_lock[0] = '\0';
    sigprocmask(SIG_SETMASK, &old, NULL);
}

/* "HOST" with '/' and '.' made '_' (as kt_out's temporaries). */
static void host_name(char *host, size_t size)
{
    if (gethostname(host, size - 1) != 0 || !host[0]) snprintf(host, size, "host");
    host[size - 1] = '\0';
    for (char *h = host; *h; h++)
        if (*h == '/' || *h == '.') *h = '_';
}

/* Remove the temporary folders of `path` left by dead processes of this host. */
static void clean_stale(const char *path)
{
    char dir[PATH_MAX], stem[PATH_MAX], host[65];
    kt_path_dir(path, dir, sizeof dir);
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    host_name(host, sizeof host);
    snprintf(stem, sizeof stem, "%s.tmp.%s.", base, host);
    size_t ls = strlen(stem);
    DIR *dd = opendir(dir);
    if (!dd) return;
    struct dirent *de;
    while ((de = readdir(dd)) != NULL) {
        if (strncmp(de->d_name, stem, ls) != 0) continue;
        char *end;
        errno = 0;
        long pid = strtol(de->d_name + ls, &end, 10);
        if (end == de->d_name + ls || errno || pid <= 0 || pid > INT_MAX || *end != '.' || strlen(end + 1) != 6) continue;
        if (pid == (long)getpid() || kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue;
        char full[2 * PATH_MAX];
        struct stat st;
        snprintf(full, sizeof full, "%s/%s", dir, de->d_name);
        if (lstat(full, &st) == 0 && S_ISDIR(st.st_mode) && st.st_uid == geteuid()) rm_tree(full);
    }
    closedir(dd);
}

/* Take DIR.lock (created if missing): flock, then check that the path still names the file
 * locked (a run that released and removed it in between). */
static int take_lock(kt_outdir *d, kt_err *e)
{
    for (int tries = 0; tries < 100; tries++) {
        int fd = open(d->lock, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
        if (fd < 0) return kt_fail(e, KT_EINPUT, "%s: cannot create the lock file: %s", d->lock, strerror(errno));
        if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
            int err = errno;
            close(fd);
            if (err == EWOULDBLOCK)
                return kt_fail(e, KT_EINPUT, "%s: locked by another run (%s): wait for it, or use another folder",
                               d->path, d->lock);
            return kt_fail(e, KT_EINPUT, "%s: cannot lock: %s", d->lock, strerror(err));
        }
        struct stat a, b;
        if (fstat(fd, &a) == 0 && stat(d->lock, &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino) {
            d->lock_fd = fd;
            return KT_OK;
        }
        close(fd);
    }
    return kt_fail(e, KT_ERUN, "%s: cannot take the lock", d->lock);
}

static void release_lock(kt_outdir *d)
{
    if (d->lock_fd < 0) return;
    unlink(d->lock); /* while held: a waiting run re-checks the inode (take_lock) */
    close(d->lock_fd);
    d->lock_fd = -1;
}

/* An earlier result at DIR: absent, an empty folder, or one this facility made (its marker);
 * removed. Anything else is refused, untouched. */
static int clear_old(const kt_outdir *d, kt_err *e)
{
    struct stat st;
    if (lstat(d->path, &st) != 0) return errno == ENOENT ? KT_OK : kt_fail(e, KT_EINPUT, "%s: %s", d->path, strerror(errno));
    if (!S_ISDIR(st.st_mode))
        return kt_fail(e, KT_EINPUT, "%s: expected a folder (or nothing) for the output, found %s", d->path,
                       S_ISLNK(st.st_mode) ? "a symbolic link" : "a file");
    char marker[PATH_MAX + 32];
    snprintf(marker, sizeof marker, "%s/%s", d->path, KT_OUTDIR_MARKER);
    int empty = 1;
    DIR *dd = opendir(d->path);
    if (!dd) return kt_fail(e, KT_EINPUT, "%s: cannot read the folder: %s", d->path, strerror(errno));
    struct dirent *de;
    while (empty && (de = readdir(dd)) != NULL) empty = strcmp(de->d_name, ".") == 0 || strcmp(de->d_name, "..") == 0;
    closedir(dd);
    if (!empty && lstat(marker, &st) != 0)
        return kt_fail(e, KT_EINPUT, "%s: the folder exists and is no earlier output of this tool (no %s in it): "
                       "refusing to replace it; name a new folder", d->path, KT_OUTDIR_MARKER);
    if (rm_tree(d->path) != 0)
        return kt_fail(e, KT_ERUN, "%s: cannot remove the earlier output: %s", d->path, strerror(errno));
    return KT_OK;
}

int kt_outdir_begin(kt_outdir *d, const char *path, kt_err *e)
{
    memset(d, 0, sizeof *d);
    d->lock_fd = -1;
    size_t n = strlen(path);
    while (n > 1 && path[n - 1] == '/') n--; /* "plan/" names the folder plan */
    if (n == 0) return kt_fail(e, KT_EINPUT, "expected an output folder name, found ''");
    char host[65];
    host_name(host, sizeof host);
    size_t size = n + strlen(host) + 64;
    d->path = kt_calloc(n + 1, 1, e);
    d->lock = kt_calloc(n + 8, 1, e);
    d->tmp = kt_calloc(size, 1, e);
    if (!d->path || !d->lock || !d->tmp) return kt_outdir_abort(d), e->code;
    memcpy(d->path, path, n);
    snprintf(d->lock, n + 8, "%s.lock", d->path);
    snprintf(d->tmp, size, "%s.tmp.%s.%ld.XXXXXX", d->path, host, (long)getpid());
    if (take_lock(d, e)) return kt_outdir_abort(d), e->code;
    clean_stale(d->path);
    if (clear_old(d, e)) return kt_outdir_abort(d), e->code;
    if (!mkdtemp(d->tmp)) {
        int err = errno;
        d->tmp[0] = '\0';
        kt_outdir_abort(d);
        return kt_fail(e, KT_EINPUT, "%s: cannot create a temporary folder beside it: %s", path, strerror(err));
    }
    mode_t mask = umask(0);
    umask(mask);
    chmod(d->tmp, 0777 & ~mask); /* a folder as mkdir would make it, not mkdtemp's 0700 */
    guard(d);
    return KT_OK;
}

int kt_outdir_commit(kt_outdir *d, kt_err *e)
{
    char marker[PATH_MAX + 32];
    snprintf(marker, sizeof marker, "%s/%s", d->tmp, KT_OUTDIR_MARKER);
    int fd = open(marker, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    static const char text[] = "a folder written whole by a keratome tool (kt_outdir): replaced whole by the next run\n";
    int bad = fd < 0 || write(fd, text, sizeof text - 1) != (ssize_t)(sizeof text - 1);
    int err = errno;
    if (fd >= 0 && close(fd) != 0 && !bad) bad = 1, err = errno;
    if (bad) {
        kt_fail(e, KT_ERUN, "%s: write failed: %s", marker, kt_io_cause(err));
        kt_outdir_abort(d);
        return e->code;
    }
    if (rename(d->tmp, d->path) != 0) {
        kt_fail(e, KT_ERUN, "%s: cannot rename the finished folder into place: %s", d->path, kt_io_cause(errno));
        kt_outdir_abort(d);
        return e->code;
    }
    unguard();
    release_lock(d);
    free(d->path), free(d->tmp), free(d->lock);
    memset(d, 0, sizeof *d);
    d->lock_fd = -1;
    return KT_OK;
}

void kt_outdir_abort(kt_outdir *d)
{
    if (d->tmp && d->tmp[0] && !strstr(d->tmp, "XXXXXX")) rm_tree(d->tmp);
    if (sig_tmp[0]) unguard();
    release_lock(d);
    free(d->path), free(d->tmp), free(d->lock);
    memset(d, 0, sizeof *d);
    d->lock_fd = -1;
}
