/* test_pool.c: n jobs on a few threads, stopped when one fails (lib/core/pool.h): every job
 * runs once when none fails, on 1-3 threads; a failure leaves later jobs unbegun and stops a
 * later running one at its next check (that job's stop is not a failure), but not an earlier
 * one; the answer is the first failure in job order, whichever failed first in time (a serial
 * run's). The waits are on events, not on time (a job waits for another's state, with a 20 s
 * bound that reports a hang as a failure). */
#define _GNU_SOURCE
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "kt_test.h"
#include "pool.h"

enum { NJOB = 4 };

/* What the jobs of one case do and what they saw. */
typedef struct scene {
    int fail[NJOB];             /* 1: job i fails */
    int after_begun[NJOB];      /* >= 0: job i waits until that job has begun, then goes on */
    int after_ran[NJOB];        /* >= 0: job i waits until that job has run, then goes on */
    int wait_stop[NJOB];        /* 1: job i waits until the pool stops it, then ends */
    int saw_stop[NJOB];         /* kt_pool_stopped as job i last saw it */
    int silent;                 /* the failing jobs return KT_ERUN without setting e */
    int begun[NJOB], ran[NJOB]; /* counts, atomically */
    int timed_out;
} scene;

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* Wait until *flag != 0 (or job i is stopped, when stop is given): 1 when it happened in 20 s. */
static int wait_for(const int *flag, const int *stop, int i)
{
    double t0 = now();
    while (now() - t0 < 20) {
        if (flag && __atomic_load_n(flag, __ATOMIC_ACQUIRE)) return 1;
        if (stop && kt_pool_stopped(stop, i)) return 1;
        usleep(1000);
    }
    return 0;
}

static int job(void *ctx, int i, const int *stop, kt_err *e)
{
    scene *s = ctx;
    __atomic_add_fetch(&s->begun[i], 1, __ATOMIC_ACQ_REL);
    if (s->after_begun[i] >= 0 && !wait_for(&s->begun[s->after_begun[i]], NULL, i)) s->timed_out = 1;
    if (s->after_ran[i] >= 0 && !wait_for(&s->ran[s->after_ran[i]], NULL, i)) s->timed_out = 1;
    if (s->wait_stop[i]) {
        if (!wait_for(NULL, stop, i)) s->timed_out = 1;
        return KT_POOL_STOPPED;
    }
    s->saw_stop[i] = kt_pool_stopped(stop, i);
    __atomic_add_fetch(&s->ran[i], 1, __ATOMIC_ACQ_REL);
    if (!s->fail[i]) return KT_OK;
    if (s->silent) return KT_ERUN;
    return kt_fail(e, KT_ERUN, "job %d: made to fail", i);
}

static scene make(void)
{
    scene s;
    memset(&s, 0, sizeof s);
    for (int i = 0; i < NJOB; i++) s.after_begun[i] = s.after_ran[i] = -1;
    return s;
}

static void all_run(void)
{
    for (int threads = 1; threads <= 3; threads++) {
        scene s = make();
        kt_err e = {0};
        int rc = kt_pool_run(NJOB, threads, job, &s, &e);
        CHECK(rc == KT_OK && e.code == KT_OK, "%d threads: %s", threads, e.msg);
        for (int i = 0; i < NJOB; i++)
            CHECK(s.begun[i] == 1 && s.ran[i] == 1, "%d threads: job %d begun %d, ran %d times", threads, i, s.begun[i], s.ran[i]);
    }
    kt_err e = {0};
    CHECK(kt_pool_run(0, 2, job, NULL, &e) == KT_OK, "no job: nothing to do");
}

/* One thread: the jobs in order; a failure leaves the later ones unbegun. */
static void one_thread_failure(void)
{
    scene s = make();
    s.fail[1] = 1;
    kt_err e = {0};
    int rc = kt_pool_run(NJOB, 1, job, &s, &e);
    CHECK(rc == KT_ERUN && strcmp(e.msg, "job 1: made to fail") == 0, "the failure: %d '%s'", rc, e.msg);
    CHECK(s.ran[0] == 1 && s.ran[1] == 1 && s.begun[2] == 0 && s.begun[3] == 0, "begun %d %d %d %d",
          s.begun[0], s.begun[1], s.begun[2], s.begun[3]);
}

/* Two threads: job 0 fails once job 1 has begun; job 1, running beside it, sees the stop and
 * ends early (not a failure); jobs 2 and 3 are never begun. */
static void stops_a_later_job(void)
{
    scene s = make();
    s.fail[0] = 1, s.after_begun[0] = 1, s.wait_stop[1] = 1;
    kt_err e = {0};
    int rc = kt_pool_run(NJOB, 2, job, &s, &e);
    CHECK(!s.timed_out, "a wait ran out: the pool did not stop job 1");
    CHECK(rc == KT_ERUN && strcmp(e.msg, "job 0: made to fail") == 0, "the failure is job 0's: %d '%s'", rc, e.msg);
    CHECK(s.begun[1] == 1 && s.ran[1] == 0, "job 1 stopped before its work (ran %d)", s.ran[1]);
    CHECK(s.begun[2] == 0 && s.begun[3] == 0, "no job begun after the failure (%d %d)", s.begun[2], s.begun[3]);
}

/* Two threads: job 1 fails while job 0 runs; job 0 is not stopped (its own failure would be a
 * serial run's answer) and ends well: the answer is job 1's, and no later job begins. */
static void not_an_earlier_job(void)
{
    scene s = make();
    s.fail[1] = 1, s.after_ran[0] = 1;
    kt_err e = {0};
    int rc = kt_pool_run(NJOB, 2, job, &s, &e);
    CHECK(!s.timed_out, "a wait ran out: job 1 did not run beside job 0");
    CHECK(s.ran[0] == 1 && s.saw_stop[0] == 0, "job 0 ran to its end, not stopped (%d, saw %d)", s.ran[0], s.saw_stop[0]);
    CHECK(rc == KT_ERUN && strcmp(e.msg, "job 1: made to fail") == 0, "the failure is job 1's: '%s'", e.msg);
    CHECK(s.begun[2] == 0 && s.begun[3] == 0, "no job begun after the failure (%d %d)", s.begun[2], s.begun[3]);
}

/* Two threads, both fail, job 1 first in time: the answer is job 0's (a serial run's). */
static void first_in_order(void)
{
    scene s = make();
    s.fail[0] = s.fail[1] = 1, s.after_ran[0] = 1;
    kt_err e = {0};
    int rc = kt_pool_run(NJOB, 2, job, &s, &e);
    CHECK(!s.timed_out, "a wait ran out: job 1 did not run beside job 0");
    CHECK(rc == KT_ERUN && strcmp(e.msg, "job 0: made to fail") == 0, "job 0's failure, not job 1's: '%s'", e.msg);
    CHECK(s.ran[0] == 1 && s.ran[1] == 1 && s.begun[2] == 0, "ran %d %d, job 2 begun %d", s.ran[0], s.ran[1], s.begun[2]);
}

/* Three threads: job 1 fails once job 2 has begun beside it (job 0 has ended; job 3 may have
 * begun before the failure too): job 2 is stopped, and its stop is not the answer. A failure
 * without a message gets one. */
static void stopped_is_not_a_failure(void)
{
    scene s = make();
    s.fail[1] = 1, s.after_begun[1] = 2, s.wait_stop[2] = 1;
    kt_err e = {0};
    int rc = kt_pool_run(NJOB, 3, job, &s, &e);
    CHECK(!s.timed_out, "a wait ran out: job 2 was not stopped");
    CHECK(rc == KT_ERUN && strcmp(e.msg, "job 1: made to fail") == 0, "job 1's failure: '%s'", e.msg);
    CHECK(s.begun[2] == 1 && s.ran[2] == 0, "job 2 stopped (begun %d, ran %d)", s.begun[2], s.ran[2]);
    s = make();
    s.fail[2] = 1, s.silent = 1;
    e = (kt_err){0};
    rc = kt_pool_run(NJOB, 1, job, &s, &e);
    CHECK(rc == KT_ERUN && strstr(e.msg, "job 2 failed without saying why") != NULL, "silent failure: '%s'", e.msg);
}

int main(void)
{
    all_run();
    one_thread_failure();
    stops_a_later_job();
    not_an_earlier_job();
    first_in_order();
    stopped_is_not_a_failure();
    return kt_test_done("test_pool");
}
