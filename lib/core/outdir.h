/* outdir.h: an output folder written as a unit. A tool that fills a folder (lri-plan's
 * PLAN_DIR) locks it, writes into a fresh temporary folder beside it, and renames that into
 * place only when the work is whole; a failed or interrupted run leaves no folder that looks
 * like its result and none of an earlier run's either.
 *
 *   kt_outdir d;
 *   if (kt_outdir_begin(&d, "plan", e)) ...;   write into d.tmp ...;
 *   rc == KT_OK ? kt_outdir_commit(&d, e) : kt_outdir_abort(&d);
 *
 * Outputs: after kt_outdir_begin, d.tmp is an empty folder "DIR.tmp.HOST.PID.XXXXXX" beside
 * DIR (same parent, so the final rename is atomic), DIR.lock beside it is held (flock), and an
 * earlier result at DIR is gone: DIR, when it exists, must be a folder this facility made (it
 * holds the marker file .keratome-outdir) or an empty one, else KT_EINPUT and nothing is
 * touched (so `-o ~` never removes a home folder). After kt_outdir_commit, DIR is the filled
 * folder (with its marker), the lock is released and removed. After kt_outdir_abort, or
 * SIGINT, SIGTERM or SIGHUP between begin and commit/abort, the temporary folder is removed
 * and DIR does not exist; the signal then ends the process as it would have. Temporary folders
 * of dead processes of this host are removed by the next kt_outdir_begin on the same DIR. A
 * second run on a locked DIR is KT_EINPUT "DIR: locked by another run (DIR.lock)". */
#ifndef KT_OUTDIR_H
#define KT_OUTDIR_H

#include "util.h"

#define KT_OUTDIR_MARKER ".keratome-outdir"

typedef struct kt_outdir {
    char *path;                 /* DIR as given */
    char *tmp;                  /* the temporary folder to write into */
    char *lock;                 /* DIR.lock */
    int lock_fd;                /* -1 when not held */
} kt_outdir;

int kt_outdir_begin(kt_outdir *d, const char *path, kt_err *e);
int kt_outdir_commit(kt_outdir *d, kt_err *e);
void kt_outdir_abort(kt_outdir *d);

#endif
