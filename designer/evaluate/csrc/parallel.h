/* A parallel for-loop over [0, n) on POSIX threads, handed out `grain` items at a time.
 *
 * Threads are started for one call and joined before it returns, so nothing outlives a
 * call (safe across fork). Items are taken from a shared counter: a thread the system
 * delays does not hold up the others. The calling thread works too. */
#ifndef DESIGNER_PARALLEL_H
#define DESIGNER_PARALLEL_H

#include <stdint.h>

typedef void (*range_fn)(void *ctx, int64_t begin, int64_t end);

/* Run fn(ctx, b, e) over consecutive ranges covering [0, n) on up to n_threads threads. */
void parallel_for(int64_t n, int64_t grain, int n_threads, range_fn fn, void *ctx);

#endif
