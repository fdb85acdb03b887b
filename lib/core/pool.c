/* pool.c: n jobs on a few threads, stopped when one fails (pool.h). */
#include "pool.h"

#include <pthread.h>
#include <stdlib.h>

typedef struct pool {
    int n, next;                /* jobs [0, n), the next to begin */
    int failed;                 /* 1 + the lowest failed job, 0 while none has failed */
    kt_pool_job job;
    void *ctx;
    kt_err *e;                  /* n: each job's error */
    int *rc;                    /* n: each job's return (KT_OK when not begun) */
    pthread_mutex_t lock;
} pool;

int kt_pool_stopped(const int *stop, int i)
{
    int f = __atomic_load_n(stop, __ATOMIC_ACQUIRE);
    return f != 0 && f - 1 < i;
}

/* failed := min(failed, i + 1) over the failures so far. */
static void mark_failed(int *failed, int i)
{
    int f = __atomic_load_n(failed, __ATOMIC_ACQUIRE);
    while ((f == 0 || i + 1 < f) &&
           !__atomic_compare_exchange_n(failed, &f, i + 1, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE))
        ;
}

/* One thread of the pool (the caller's too): jobs in order from p->next until none is left or
 * one has failed. */
static void *worker(void *arg)
{
    pool *p = arg;
    kt_thread_start();
    for (;;) {
        pthread_mutex_lock(&p->lock);
        int i = __atomic_load_n(&p->failed, __ATOMIC_ACQUIRE) || p->next == p->n ? -1 : p->next++;
        pthread_mutex_unlock(&p->lock);
        if (i < 0) return NULL;
        p->rc[i] = p->job(p->ctx, i, &p->failed, &p->e[i]);
        if (p->rc[i] != KT_OK && p->rc[i] != KT_POOL_STOPPED) mark_failed(&p->failed, i);
    }
}

int kt_pool_run(int n, int threads, kt_pool_job job, void *ctx, kt_err *e)
{
    if (n <= 0) return KT_OK;
    pool p = {.n = n, .job = job, .ctx = ctx, .lock = PTHREAD_MUTEX_INITIALIZER};
    p.e = kt_calloc((size_t)n, sizeof *p.e, e);
    p.rc = p.e ? kt_calloc((size_t)n, sizeof *p.rc, e) : NULL;
    if (!p.rc) return free(p.e), e->code;
    pthread_t th[KT_POOL_MAXTHREADS];
    int started = 0;
    for (int t = 1; t < threads && t < n && t < KT_POOL_MAXTHREADS; t++)
        if (pthread_create(&th[started], NULL, worker, &p) == 0) started++;
    worker(&p);
    for (int t = 0; t < started; t++) pthread_join(th[t], NULL);
    pthread_mutex_destroy(&p.lock);
    for (int i = 0; i < n && !e->code; i++) /* the first failure in job order */
        if (p.rc[i] != KT_OK && p.rc[i] != KT_POOL_STOPPED) {
            *e = p.e[i];
            if (!e->code) kt_fail(e, KT_ERUN, "job %d failed without saying why (status %d)", i, p.rc[i]);
        }
    free(p.e), free(p.rc);
    return e->code;
}
