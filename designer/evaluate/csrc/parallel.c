#include "parallel.h"

#include <pthread.h>
#include <stdatomic.h>

#define MAX_THREADS 256

typedef struct {
    _Atomic int64_t next;
    int64_t n, grain;
    range_fn fn;
    void *ctx;
} loop_t;

static void *worker(void *arg)
{
    loop_t *loop = (loop_t *)arg;
    for (;;) {
        int64_t b = atomic_fetch_add(&loop->next, loop->grain);
        if (b >= loop->n)
            break;
        int64_t e = b + loop->grain < loop->n ? b + loop->grain : loop->n;
        loop->fn(loop->ctx, b, e);
    }
    return NULL;
}

void parallel_for(int64_t n, int64_t grain, int n_threads, range_fn fn, void *ctx)
{
    if (n <= 0)
        return;
    if (grain < 1)
        grain = 1;
    int64_t chunks = (n + grain - 1) / grain;
    if (n_threads > MAX_THREADS)
        n_threads = MAX_THREADS;
    if (n_threads > chunks)
        n_threads = (int)chunks;
    if (n_threads <= 1) {
        fn(ctx, 0, n);
        return;
    }
    loop_t loop = {.n = n, .grain = grain, .fn = fn, .ctx = ctx};
    atomic_init(&loop.next, 0);
    pthread_t threads[MAX_THREADS];
    int started = 0;
    for (int k = 1; k < n_threads; k++) {
        if (pthread_create(&threads[started], NULL, worker, &loop) != 0)
            break; /* fewer threads: the ones running take every item anyway */
        started++;
    }
    worker(&loop);
    for (int k = 0; k < started; k++)
        pthread_join(threads[k], NULL);
}
