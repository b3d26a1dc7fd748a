/* A daemon without threads, GL or sockets for the in-process tests: the
 * configuration `lucent serve` starts with, metrics, a session registry and
 * one small demo dataset (loaded on the CPU, never uploaded). */
#ifndef LC_DAEMON_TEST_UTIL_H
#define LC_DAEMON_TEST_UTIL_H

#include <stdio.h>
#include <string.h>

#include "cost.h"
#include "datasets.h"
#include "metrics.h"
#include "session.h"

/* The defaults of serve.c's config_defaults, as far as sessions read them. */
static inline void test_config(lc_serve_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    lc_proto_limits_default(&cfg->limits);
    cfg->max_ws_message = 64 * 1024;
    cfg->max_sessions = 64;
    cfg->idle_timeout = 300;
    cfg->max_stream_pixels = 4LL << 20;
    cfg->still_delay = 0.150;
    cfg->frame_budget_ms = 70.0;
    cfg->max_cost = LC_COST_DEFAULT_BUDGET;
}

/* 0 when srv is ready (demo:points with `points` points). */
static inline int test_daemon(lc_server *srv, unsigned long long points)
{
    memset(srv, 0, sizeof *srv);
    test_config(&srv->cfg);
    srv->start_time = lc_now();
    srv->metrics = lc_metrics_create();
    srv->sessions = lc_sessions_create(srv, srv->cfg.max_sessions);
    const char *sources[] = {"demo:points"};
    lc_datasets_options opts = {.demo_size = points, .workers = 1};
    lc_error err = {0};
    if (!srv->metrics || !srv->sessions || lc_datasets_load(sources, 1, &opts, &srv->datasets, &err) != 0) {
        fprintf(stderr, "test daemon: %s\n", err.msg);
        return -1;
    }
    return 0;
}

static inline void test_daemon_free(lc_server *srv)
{
    lc_sessions_destroy(srv->sessions);
    lc_datasets_destroy(srv->datasets);
    lc_metrics_destroy(srv->metrics);
}

#endif
