/* The one CPU fan-out of render/: a loop of independent jobs over threads it starts and joins before returning. */
#include "lc_parallel.h"

#include <pthread.h>
#include <unistd.h>

typedef struct trampoline {
    void (*fn)(void *job);
    void *job;
} trampoline;

static void *run_trampoline(void *arg)
{
    trampoline *t = arg;
    t->fn(t->job);
    return NULL;
}

void lc_parallel_for(uint32_t n, void (*fn)(void *job), void *jobs, size_t size)
{
    pthread_t tid[LC_PARALLEL_MAX];
    trampoline tr[LC_PARALLEL_MAX];
    int started[LC_PARALLEL_MAX] = {0};
    uint32_t threaded = n < LC_PARALLEL_MAX ? n : LC_PARALLEL_MAX;
    for (uint32_t t = 1; t < threaded; t++) {
        tr[t] = (trampoline){fn, (char *)jobs + t * size};
        started[t] = pthread_create(&tid[t], NULL, run_trampoline, &tr[t]) == 0;
    }
    /* No thread to spare (or none asked for): the caller does that share itself. */
    for (uint32_t t = 0; t < n; t++)
        if (t >= threaded || !started[t])
            fn((char *)jobs + t * size);
    for (uint32_t t = 1; t < threaded; t++)
        if (started[t])
            pthread_join(tid[t], NULL);
}

uint32_t lc_parallel_cores(uint32_t max)
{
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    if (max < 1)
        max = 1;
    return cpus < 1 ? 1 : (uint64_t)cpus > max ? max : (uint32_t)cpus;
}
