/* test_outdir.c: an output folder written as a unit (lib/core/outdir.h): commit renames the
 * whole into place with its marker; an earlier output is removed at begin only when it bears
 * the marker (or is empty); a second begin on a locked folder is refused; abort and SIGINT
 * leave no temporary folder, no lock and no folder; dead runs' temporaries are cleaned. */
#define _GNU_SOURCE
#include <dirent.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "kt_test.h"
#include "outdir.h"

static int exists(const char *dir, const char *name)
{
    char p[4096];
    struct stat st;
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return lstat(p, &st) == 0;
}

/* Entries of dir starting with prefix. */
static int count(const char *dir, const char *prefix)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *de;
    while (d && (de = readdir(d)) != NULL) n += strncmp(de->d_name, prefix, strlen(prefix)) == 0;
    if (d) closedir(d);
    return n;
}

static void put(const char *dir, const char *name, const char *text)
{
    char p[4096];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "w");
    if (f) fputs(text, f), fclose(f);
}

int main(void)
{
    char root[] = "/tmp/kt_test_outdir.XXXXXX", out[128], mine[128];
    if (!mkdtemp(root)) return 1;
    snprintf(out, sizeof out, "%s/plan", root);
    snprintf(mine, sizeof mine, "%s/mine", root);
    kt_err e = {0};
    kt_outdir d;

    /* a fresh folder: written in the temporary, renamed whole into place */
    CHECK(kt_outdir_begin(&d, out, &e) == KT_OK, "begin: %s", e.msg);
    CHECK(!exists(root, "plan") && exists(root, "plan.lock") && count(root, "plan.tmp.") == 1, "during the run");
    put(d.tmp, "plan.json", "new\n");
    CHECK(kt_outdir_commit(&d, &e) == KT_OK, "commit: %s", e.msg);
    CHECK(exists(out, "plan.json") && exists(out, KT_OUTDIR_MARKER), "the committed folder");
    CHECK(count(root, "plan.") == 0, "a temporary or the lock left after commit");

    /* a re-run: the earlier output goes at begin; an abort leaves no folder at all */
    CHECK(kt_outdir_begin(&d, out, &e) == KT_OK, "re-run begin: %s", e.msg);
    CHECK(!exists(root, "plan"), "the earlier plan is still there during the re-run");
    put(d.tmp, "plan.json", "partial\n");
    kt_outdir_abort(&d);
    CHECK(!exists(root, "plan") && count(root, "plan.") == 0, "after abort: a folder, temporary or lock left");

    /* a folder that is no earlier output: refused, untouched */
    mkdir(mine, 0755);
    put(mine, "notes.txt", "keep\n");
    e.code = KT_OK;
    CHECK(kt_outdir_begin(&d, mine, &e) == KT_EINPUT && strstr(e.msg, "no earlier output"), "mine: %s", e.msg);
    CHECK(exists(mine, "notes.txt") && count(root, "mine.") == 0, "mine was touched");

    /* locked: a second begin (another process) is refused while the first holds it */
    e.code = KT_OK;
    CHECK(kt_outdir_begin(&d, out, &e) == KT_OK, "begin for the lock: %s", e.msg);
    pid_t pid = fork();
    if (pid == 0) {
        kt_err ce = {0};
        kt_outdir c;
        int rc = kt_outdir_begin(&c, out, &ce);
        _exit(rc == KT_EINPUT && strstr(ce.msg, "locked by another run") ? 0 : 1);
    }
    int st = 0;
    waitpid(pid, &st, 0);
    CHECK(WIFEXITED(st) && WEXITSTATUS(st) == 0, "a second run on a locked folder was not refused as locked");
    kt_outdir_abort(&d);

    /* SIGINT between begin and commit: the temporary and the lock go, the signal ends the run */
    pid = fork();
    if (pid == 0) {
        signal(SIGINT, SIG_DFL);
        kt_err ce = {0};
        kt_outdir c;
        if (kt_outdir_begin(&c, out, &ce)) _exit(3);
        put(c.tmp, "plan.html", "partial\n");
        raise(SIGINT);
        _exit(4);
    }
    waitpid(pid, &st, 0);
    CHECK(WIFSIGNALED(st) && WTERMSIG(st) == SIGINT, "the run did not end by SIGINT (status %d)", st);
    CHECK(!exists(root, "plan") && count(root, "plan.") == 0, "after SIGINT: a folder, temporary or lock left");

    /* a dead run's temporary folder is removed by the next begin */
    pid = fork();
    if (pid == 0) _exit(0);
    waitpid(pid, &st, 0);
    char host[65] = "", stale[256];
    gethostname(host, sizeof host - 1);
    for (char *h = host; *h; h++)
        if (*h == '/' || *h == '.') *h = '_';
    snprintf(stale, sizeof stale, "%s/plan.tmp.%s.%ld.AbCdEf", root, host, (long)pid);
    mkdir(stale, 0755);
    put(stale, "plan.json", "dead\n");
    e.code = KT_OK;
    CHECK(kt_outdir_begin(&d, out, &e) == KT_OK, "begin after a dead run: %s", e.msg);
    struct stat sb;
    CHECK(stat(stale, &sb) != 0, "a dead run's temporary folder was left");
    kt_outdir_abort(&d);

    char cmd[256];
    snprintf(cmd, sizeof cmd, "rm -rf %s", root);
    if (system(cmd) != 0) return 1;
    return kt_test_done("test_outdir");
}
