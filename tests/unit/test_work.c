/* Work budgets (render/base/lc_work.c) and the tracer's charges
 * (render/field/trace.c): charges add up across threads, the limit is
 * sticky once passed, elapsed time is charged once at the rate, the error
 * names the budget's field; a budget large enough counts exactly the RK4
 * steps of the traced curves (their vertices less the seed), and a small one
 * stops the tracing with LC_ERR_BUDGET, keeping no curves. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "field.h"
#include "field_demo.h"
#include "lc_test.h"
#include "lc_work.h"
#include "trace.h"

#define THREADS 4
#define CHARGES 10000

static void *charge_many(void *arg)
{
    lc_work_budget *b = arg;
    for (int i = 0; i < CHARGES; i++)
        lc_work_charge(b, 1.5);
    return NULL;
}

static void test_counter(void)
{
    lc_work_budget b;
    lc_work_init(&b, 100, "surface.particles");
    CHECK(lc_work_charge(&b, 60) == 0 && lc_work_charge(&b, 40) == 0, "up to the limit is within it");
    CHECK(!lc_work_exceeded(&b) && lc_work_used(&b) == 100, "used %g", lc_work_used(&b));
    CHECK(lc_work_charge(&b, 0.5) == LC_ERR_BUDGET && lc_work_exceeded(&b), "past the limit: LC_ERR_BUDGET");
    CHECK(lc_work_charge(&b, 0) == LC_ERR_BUDGET, "and it stays past");
    lc_error err = {0};
    CHECK(lc_work_err(&b, &err, "tracing 3 curves") == LC_ERR_BUDGET && err.code == LC_ERR_BUDGET &&
              strcmp(err.field, "surface.particles") == 0 && strstr(err.msg, "tracing 3 curves") &&
              strstr(err.msg, "100.5") && strstr(err.msg, "lower surface.particles"),
          "the error names the field and the figures: %s", err.msg);
    CHECK(lc_work_charge(NULL, 1e30) == 0 && !lc_work_exceeded(NULL), "no budget: nothing to count");

    lc_work_budget open;
    lc_work_init(&open, 0, "");
    CHECK(lc_work_charge(&open, 1e30) == 0 && lc_work_used(&open) == 1e30, "no limit counts only");

    lc_work_budget shared;
    lc_work_init(&shared, 0, "");
    pthread_t t[THREADS];
    for (int i = 0; i < THREADS; i++)
        pthread_create(&t[i], NULL, charge_many, &shared);
    for (int i = 0; i < THREADS; i++)
        pthread_join(t[i], NULL);
    CHECK(lc_work_used(&shared) == THREADS * CHARGES * 1.5, "charges of %d threads add up: %g", THREADS,
          lc_work_used(&shared));
}

static void test_elapsed(void)
{
    lc_work_budget b;
    lc_work_init(&b, 0, "width");
    CHECK(lc_work_charge_elapsed(&b) == 0 && lc_work_used(&b) == 0, "no rate: time is not charged");
    lc_work_time(&b, 1e6);
    lc_work_charge(&b, 5);
    double t0 = lc_now();
    nanosleep(&(struct timespec){0, 20 * 1000 * 1000}, NULL);
    lc_work_charge_elapsed(&b);
    double first = lc_work_used(&b);
    lc_work_charge_elapsed(&b); /* again: only the time since the first charge is added */
    double second = lc_work_used(&b), t1 = lc_now();
    CHECK(first >= 5 + 0.02 * 1e6 && second >= first && second <= 5 + (t1 - t0 + 0.01) * 1e6 + 1,
          "elapsed time charged once at the rate: %g then %g over %.3f s", first, second, t1 - t0);
    lc_work_budget tight;
    lc_work_init(&tight, 1000, "width");
    lc_work_time(&tight, 1e9);
    nanosleep(&(struct timespec){0, 1000 * 1000}, NULL);
    CHECK(lc_work_charge_elapsed(&tight) == LC_ERR_BUDGET, "a millisecond at 1e9 units/s passes 1000 units");
}

static lc_seed seed_line(void)
{
    lc_seed s;
    memset(&s, 0, sizeof s);
    s.count = 2;
    double p[2][3] = {{-0.9, -0.6, 0}, {-0.9, 0.6, 0}};
    memcpy(s.points, p, sizeof p);
    return s;
}

static void test_trace_charges(void)
{
    lc_field *f = NULL;
    lc_error err = {0};
    CHECK(lc_field_demo_create("shear-flow", &f, &err) == 0, "shear-flow: %s", err.msg);
    if (!f)
        return;
    lc_seed seed = seed_line();
    CHECK(lc_seed_check(&seed, f, &err) == 0, "seed: %s", err.msg);
    enum { N = 16 };
    lc_trace_curve c[N];
    for (int dir = LC_TRACE_FORWARD; dir <= LC_TRACE_BOTH; dir++) {
        lc_work_budget b;
        lc_work_init(&b, 1e12, "surface.particles");
        lc_trace_desc d = {
            .step = 0.002, .max_length = 1.0, .direction = (lc_trace_direction)dir, .work = &b, .step_units = 3.0};
        CHECK(lc_trace_curves(f, &seed, &d, 0, N, 3, c, &err) == 0, "traced: %s", err.msg);
        double steps = 0;
        for (int i = 0; i < N; i++) /* a two-way curve holds its seed once and each half's steps */
            steps += c[i].n - 1;
        CHECK(steps > N && lc_work_used(&b) == 3.0 * steps, "direction %d: the budget counted %g units for %g steps",
              dir, lc_work_used(&b), steps);
        lc_trace_curves_free(c, N);
    }
    /* A budget of a tenth of that work stops it, on every thread, and keeps nothing. */
    lc_work_budget small;
    lc_work_init(&small, 0.1 * 3.0 * N * 500, "surface.particles");
    lc_trace_desc d = {.step = 0.002, .max_length = 1.0, .work = &small, .step_units = 3.0};
    memset(&err, 0, sizeof err);
    int rc = lc_trace_curves(f, &seed, &d, 0, N, 3, c, &err);
    CHECK(rc == LC_ERR_BUDGET && err.code == LC_ERR_BUDGET && strcmp(err.field, "surface.particles") == 0,
          "over budget: rc %d, %s", rc, err.msg);
    /* Each thread may finish its batch of steps past the limit, no more. */
    CHECK(lc_work_used(&small) <= small.limit + 3 * 3.0 * LC_TRACE_CHARGE_STEPS, "stopped at %g of %g",
          lc_work_used(&small), small.limit);
    int kept = 0;
    for (int i = 0; i < N; i++)
        kept += c[i].n != 0 || c[i].xyz != NULL;
    CHECK(kept == 0, "no curves kept (%d)", kept);
    lc_field_destroy(f);
}

int main(void)
{
    test_counter();
    test_elapsed();
    test_trace_charges();
    return lc_test_finish();
}
