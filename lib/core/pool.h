/* pool.h: n jobs on a few threads, stopped when one fails, with the answer of a serial run.
 *
 * kt_pool_run runs jobs 0 .. n-1 on up to `threads` threads (the caller's thread one of them,
 * at most KT_POOL_MAXTHREADS; a thread that cannot be started leaves its share to the others),
 * each thread taking the next job in index order. Once job f has failed, no job is begun any
 * more, and the jobs after f still running see it at their next check of kt_pool_stopped and
 * may end early by returning KT_POOL_STOPPED; the jobs before f are not stopped (one of them
 * may still fail, and its failure would be a serial run's). The pool's answer is the first
 * failure in job order, the same as with one thread, whatever the timing. Each thread begins
 * with kt_thread_start(). */
#ifndef KT_POOL_H
#define KT_POOL_H

#include "util.h"

/* What a job returns when it ended early because the pool was stopped (e untouched). */
#define KT_POOL_STOPPED (-1)

/* The most threads a pool runs on. */
#define KT_POOL_MAXTHREADS 8

/* Job i of ctx: KT_OK, a failure (e set), or KT_POOL_STOPPED. stop is for kt_pool_stopped. */
typedef int (*kt_pool_job)(void *ctx, int i, const int *stop, kt_err *e);

/* Nonzero once a job before job i has failed (job i's answer no longer matters). Safe from
 * any thread at any time. */
int kt_pool_stopped(const int *stop, int i);

/* Run jobs 0 .. n-1 of job(ctx, ...) on up to `threads` threads (at least 1); e := the first
 * failure in job order. Returns e->code. */
int kt_pool_run(int n, int threads, kt_pool_job job, void *ctx, kt_err *e);

#endif
