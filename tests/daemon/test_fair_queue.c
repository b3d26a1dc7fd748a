/* Worker fairness in process (fair_queue.c): clients take turns, one task
 * each, whatever order they queued in; a client's jobs are counted for the
 * per-client cap; an emptied client leaves the ring. */
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>

#include "fair_queue.h"
#include "lc_test.h"

static lc_task tasks[64];
static int used;

static lc_task *task(uint64_t key, bool job)
{
    lc_task *t = &tasks[used++];
    t->key = key;
    t->job = job ? (struct lc_render_job *)(uintptr_t)(0x1000 + 16 * used) : NULL; /* only compared with NULL */
    t->session = NULL;
    return t;
}

static bool is_session(const lc_task *t, void *ctx)
{
    (void)ctx;
    return t->job == NULL;
}

static bool is_task(const lc_task *t, void *ctx) { return t == ctx; }

static void count_task(const lc_task *t, void *ctx)
{
    (void)t;
    ++*(int *)ctx;
}

int main(void)
{
    lc_fair_queue q = {0};
    /* Client 1 bursts five renders, then clients 2 and 3 queue one each. */
    for (int i = 0; i < 5; i++)
        CHECK(lc_fair_push(&q, task(1, true)) == 0, "push");
    lc_fair_push(&q, task(2, true));
    lc_fair_push(&q, task(3, false)); /* a session: not a job */
    CHECK(q.tasks == 7 && q.jobs == 6 && q.clients == 3, "7 tasks, 6 jobs, 3 clients (%d %d %d)", q.tasks, q.jobs,
          q.clients);
    CHECK(lc_fair_jobs_of(&q, 1) == 5 && lc_fair_jobs_of(&q, 2) == 1 && lc_fair_jobs_of(&q, 3) == 0, "jobs per client");
    uint64_t order[7], want[7] = {1, 2, 3, 1, 1, 1, 1};
    int n = 0;
    lc_task *t;
    while ((t = lc_fair_pop(&q)) && n < 7)
        order[n++] = t->key;
    CHECK(n == 7, "every task comes out (%d)", n);
    for (int i = 0; i < n; i++)
        CHECK(order[i] == want[i], "turn %d: client %llu (want %llu)", i, (unsigned long long)order[i],
              (unsigned long long)want[i]);
    CHECK(q.tasks == 0 && q.jobs == 0 && q.clients == 0 && !lc_fair_pop(&q), "empty afterwards");

    /* A client that joins while others wait takes its turn after each of them
     * once, not after all of their work. */
    used = 0;
    for (int i = 0; i < 3; i++)
        lc_fair_push(&q, task(10, true));
    for (int i = 0; i < 3; i++)
        lc_fair_push(&q, task(20, true));
    uint64_t first = lc_fair_pop(&q)->key; /* 10 served, goes to the end */
    lc_fair_push(&q, task(30, true));
    uint64_t seq[4];
    for (int i = 0; i < 4; i++)
        seq[i] = lc_fair_pop(&q)->key;
    CHECK(first == 10 && seq[0] == 20 && seq[1] == 10 && seq[2] == 30 && seq[3] == 20,
          "10, then 20, 10, 30, 20 (got %llu, %llu %llu %llu %llu)", (unsigned long long)first,
          (unsigned long long)seq[0], (unsigned long long)seq[1], (unsigned long long)seq[2],
          (unsigned long long)seq[3]);
    while (lc_fair_pop(&q))
        ;

    /* Popping only some tasks (the pool's short ones while every other worker
     * holds a long job): the first client in ring order with such a task gives
     * its oldest one and goes to the end; the clients passed over keep their
     * places and their tasks, and the counts stay right. Here sessions are
     * the tasks taken (not jobs). */
    used = 0;
    lc_fair_push(&q, task(1, true));
    lc_fair_push(&q, task(1, true));
    lc_task *s1 = task(1, false);
    lc_fair_push(&q, s1);
    lc_fair_push(&q, task(2, true));
    lc_task *s3 = task(3, false);
    lc_fair_push(&q, s3);
    lc_task *a = lc_fair_pop_where(&q, is_session, NULL), *b = lc_fair_pop_where(&q, is_session, NULL);
    CHECK(a == s1 && b == s3, "client 1's session, then client 3's (%p %p)", (void *)a, (void *)b);
    CHECK(!lc_fair_pop_where(&q, is_session, NULL), "no session left: none taken");
    CHECK(q.tasks == 3 && q.jobs == 3 && q.clients == 2 && lc_fair_jobs_of(&q, 1) == 2,
          "3 jobs of clients 1 and 2 stay (%d %d %d)", q.tasks, q.jobs, q.clients);
    uint64_t rest[3];
    for (int i = 0; i < 3; i++)
        rest[i] = lc_fair_pop(&q)->key;
    CHECK(rest[0] == 2 && rest[1] == 1 && rest[2] == 1, "then 2 (passed over, first), 1, 1 (got %llu %llu %llu)",
          (unsigned long long)rest[0], (unsigned long long)rest[1], (unsigned long long)rest[2]);
    CHECK(q.tasks == 0 && q.clients == 0 && !lc_fair_pop(&q), "empty afterwards");

    /* Removing without serving (a render past its queue deadline): the task
     * leaves, its client keeps its place in the ring while it has more, and
     * lc_fair_each sees every task left. */
    used = 0;
    lc_fair_push(&q, task(1, true));
    lc_task *late = task(1, true);
    lc_fair_push(&q, late);
    lc_fair_push(&q, task(2, true));
    lc_task *first1 = lc_fair_remove_where(&q, is_task, late);
    CHECK(first1 == late, "the late job is removed (%p %p)", (void *)first1, (void *)late);
    int seen = 0;
    lc_fair_each(&q, count_task, &seen);
    CHECK(seen == 2 && q.tasks == 2 && q.jobs == 2 && lc_fair_jobs_of(&q, 1) == 1, "2 tasks left, each seen (%d)",
          seen);
    uint64_t k1 = lc_fair_pop(&q)->key, k2 = lc_fair_pop(&q)->key;
    CHECK(k1 == 1 && k2 == 2, "client 1 kept its turn: 1, then 2 (got %llu %llu)", (unsigned long long)k1,
          (unsigned long long)k2);
    lc_task *only = task(5, true);
    lc_fair_push(&q, only);
    CHECK(lc_fair_remove_where(&q, is_task, only) == only && q.clients == 0 && q.tasks == 0 && !lc_fair_pop(&q),
          "a client's last task removed: the client leaves the ring");
    return lc_test_finish();
}
