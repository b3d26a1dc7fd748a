/* `lucent serve`: flags, start-up (datasets load before the port opens),
 * signal handling and the ordered shutdown. */
#include "serve.h"

#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cost.h"
#include "crash.h"
#include "dataset_cache.h"
#include "datasets.h"
#include "gl_context.h"
#include "http.h"
#include "lc_options.h"
#include "loaders.h"
#include "metrics.h"
#include "movies.h"
#include "ranks.h"
#include "server.h"
#include "session.h"
#include "signals.h"
#include "workers.h"
#include "ws.h"

#define MOD "serve"
#define MAX_DATA 256

/* --workers by default: 2, so that one session's long still does not hold
 * every other session's frames; on llvmpipe only with LC_SOFTWARE_2_WORKERS
 * of memory, since each worker keeps its own render targets in host memory
 * (up to a 4096-pixel frame's) and both share the CPU cores. */
#define LC_SOFTWARE_2_WORKERS (8ull << 30)
static int default_workers(bool software)
{
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    unsigned long long memory = pages > 0 && page > 0 ? (unsigned long long)pages * (unsigned long long)page : 0;
    return !software || memory >= LC_SOFTWARE_2_WORKERS ? 2 : 1;
}

/* The primary GL context is created on a thread of its own while the
 * datasets load: EGL's set-up (0.1-0.2 s on llvmpipe) overlaps the scene
 * cache's read, which a warm restart spends most of its start in. */
typedef struct {
    lc_gl_desc desc;
    lc_gl *gl;
    int rc;
    lc_error err;
} gl_start;

static void *gl_start_run(void *arg)
{
    gl_start *g = arg;
    g->rc = lc_gl_create(&g->desc, &g->gl, &g->err);
    return NULL;
}

/* The workers' frame delivery: the WebSocket layer. */
static void sink_send(void *ctx, lc_session *s, unsigned char *msg, size_t len, bool binary)
{
    lc_ws_send(ctx, s, msg, len, binary);
}
static void sink_send_frame(void *ctx, lc_session *s, unsigned char *msg, size_t len, double render_ms,
                            double encode_ms)
{
    lc_ws_send_frame(ctx, s, msg, len, render_ms, encode_ms);
}

static int parse_listen(const char *arg, lc_serve_config *cfg)
{
    const char *colon;
    if (arg[0] == '[') { /* [v6]:port */
        const char *close = strchr(arg, ']');
        if (!close || close[1] != ':')
            return -1;
        snprintf(cfg->listen_host, sizeof cfg->listen_host, "%.*s", (int)(close - arg - 1), arg + 1);
        colon = close + 1;
    } else {
        colon = strrchr(arg, ':');
        if (!colon) { /* a bare port */
            snprintf(cfg->listen_host, sizeof cfg->listen_host, "127.0.0.1");
            colon = arg - 1;
        } else {
            snprintf(cfg->listen_host, sizeof cfg->listen_host, "%.*s", (int)(colon - arg), arg);
        }
    }
    char *end;
    long port = strtol(colon + 1, &end, 10);
    if (*end || end == colon + 1 || port < 0 || port > 65535 || !cfg->listen_host[0])
        return -1;
    cfg->port = (int)port;
    return 0;
}

/* A token that does not fit is refused: cutting it would accept its prefix
 * and refuse the token itself. */
static int set_token(lc_serve_config *cfg, const char *token, const char *from)
{
    if (strlen(token) >= sizeof cfg->token) {
        fprintf(stderr, "lucent serve: %s: the token is %zu bytes; at most %zu are allowed\n", from, strlen(token),
                sizeof cfg->token - 1);
        return -1;
    }
    snprintf(cfg->token, sizeof cfg->token, "%s", token);
    return 0;
}

/* ---- the flags: one table (render/base/lc_options.h) for parsing and usage */

static int opt_listen(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    (void)o;
    if (parse_listen(arg, target) == 0)
        return 0;
    snprintf(why, why_len, "expected ADDR:PORT with a port in [0, 65535], got \"%s\"", arg);
    return -1;
}

static int opt_data(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    (void)o;
    lc_serve_config *cfg = target;
    if (cfg->data_count >= MAX_DATA) {
        snprintf(why, why_len, "at most %d datasets", MAX_DATA);
        return -1;
    }
    cfg->data[cfg->data_count++] = arg;
    return 0;
}

static int opt_token(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    lc_serve_config *cfg = target;
    if (strlen(arg) < sizeof cfg->token)
        return set_token(cfg, arg, o->name);
    snprintf(why, why_len, "the token is %zu bytes; at most %zu are allowed", strlen(arg), sizeof cfg->token - 1);
    return -1;
}

static int opt_log_level(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    (void)target, (void)o;
    int level = lc_log_parse_level(arg);
    if (level < 0) {
        snprintf(why, why_len, "expected error|warn|info|debug, got \"%s\"", arg);
        return -1;
    }
    lc_log_set_level((lc_log_level)level);
    return 0;
}

static int opt_bytes(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    if (lc_memory_parse_bytes(arg, (unsigned long long *)((char *)target + o->offset)) == 0)
        return 0;
    snprintf(why, why_len, "expected bytes, e.g. 20G or 512M, got \"%s\"", arg);
    return -1;
}

#define CFG(member) LC_OPT_AT(lc_serve_config, member)
static const lc_option serve_options[] = {
    {"--listen", "ADDR:PORT", LC_OPT_CALL, .call = opt_listen, .numeric = 1,
     .help = "listen address (default 127.0.0.1:8080; port 0 picks a free one;\n"
             "IPv6 as [::1]:8080). Anything but loopback exposes the server."},
    {"--data", "PATH|DIR...", LC_OPT_CALL, .call = opt_data,
     .help = "datasets to load before the port opens: files (" LC_DATASET_EXTENSIONS "),\n"
             "folders (every such file in it), demo:NAME, or streamlines:FIELD?seeding=...\n"
             "(a streamline set traced at start; repeatable; several paths may follow one\n"
             "--data). None = all demos."},
    {"--demo", NULL, LC_OPT_BOOL, CFG(demo), .help = "also serve every built-in demo next to --data"},
    {"--demo-size", "N", LC_OPT_INT, CFG(demo_size), 1, 100000000,
     .help = "size of generated demos (lines/points/grid; default: the generator's)"},
    {"--elements", "N", LC_OPT_INT, CFG(elements), 1, 1 << 24,
     .help = "line elements or surface patches per dataset (default: derived from the data)"},
    {"--exact-positions", NULL, LC_OPT_BOOL, CFG(exact_positions),
     .help = "float GPU buffers and session opacities (images bit for bit as before the\n"
             "compact 16-bit layout; about twice the bytes per vertex)"},
    {"--max-memory", "BYTES", LC_OPT_CALL, CFG(max_memory), .call = opt_bytes, .numeric = 1,
     .help = "refuse a dataset whose estimated resident size, with the ones before it,\n"
             "exceeds BYTES (k, M, G, T suffixes; default: no limit)"},
    {"--movie-disk", "BYTES", LC_OPT_CALL, CFG(movie_disk), .call = opt_bytes, .numeric = 1,
     .help = "bytes of movie files kept at once: finished movies are deleted oldest first\n"
             "to make room, a movie that alone outgrows it fails (default 4G)"},
    {"--load-timeout", "SEC", LC_OPT_INT, CFG(load_timeout), 0, 86400, 1,
     .help = "give up on a dataset that takes longer than this to load (logged; a folder\n"
             "skips it, an explicit --data file stops the start-up); 0 = none (default 600)"},
    {"--cache", "DIR|off", LC_OPT_TEXT, CFG(cache),
     .help = "scene cache folder: data files of 1 MB or more start from a cached copy of\n"
             "their derived scene when it matches the file (default $XDG_CACHE_HOME/lucent\n"
             "or ~/.cache/lucent; off = none)"},
    {"--follow-symlinks", NULL, LC_OPT_BOOL, CFG(follow_symlinks),
     .help = "serve files and sidecars of a --data folder that link outside it"},
    {"--device", "N", LC_OPT_INT, CFG(device), 0, 64,
     .help = "EGL device index (default: LUCENT_EGL_DEVICE or the first GPU)"},
    {"--workers", "N", LC_OPT_INT, CFG(workers), 1, 64,
     .help = "render threads, one GL context each (default 2; 1 on llvmpipe with under 8 GiB of memory)"},
    {"--encoders", "N", LC_OPT_INT, CFG(encoders), 1, 64, .help = "JPEG/PNG encoder threads (default 2)"},
    {"--token", "T", LC_OPT_CALL, .call = opt_token,
     .help = "require this bearer token (default: LUCENT_TOKEN if set)"},
    {"--max-size", "N", LC_OPT_INT, CFG(limits.max_size), 16, 16384, .help = "max image width/height (default 8192)"},
    {"--max-pixels", "N", LC_OPT_INT, CFG(limits.max_pixels), 256, 1LL << 28,
     .help = "max width*height of an HTTP render (default 37748736)"},
    {"--max-stream-pixels", "N", LC_OPT_INT, CFG(max_stream_pixels), 256, 1LL << 28,
     .help = "max pixels of a WebSocket frame (default 4194304)"},
    {"--max-body", "BYTES", LC_OPT_INT, CFG(max_body), 64, 1LL << 30, .help = "max HTTP request body (default 65536)"},
    {"--max-ws-message", "BYTES", LC_OPT_INT, CFG(max_ws_message), 64, 1LL << 30,
     .help = "max WebSocket message, close 1009 beyond (default 65536)"},
    {"--max-json-depth", "N", LC_OPT_INT, CFG(limits.max_depth), 2, 1000, .help = "max JSON nesting (default 16)"},
    {"--max-sessions", "N", LC_OPT_INT, CFG(max_sessions), 1, 100000,
     .help = "max open sessions, HTTP and WebSocket (default 64)"},
    {"--max-sessions-per-client", "N", LC_OPT_INT, CFG(max_client_sessions), 1, 100000,
     .help = "max open sessions from one client address (default 16)"},
    {"--max-queue", "N", LC_OPT_INT, CFG(max_queue), 1, 100000,
     .help = "max queued HTTP renders, 503 beyond (default 32)"},
    {"--max-connections", "N", LC_OPT_INT, CFG(max_connections), 4, 100000,
     .help = "max HTTP connections (default 256)"},
    {"--max-cost", "UNITS", LC_OPT_REAL, CFG(max_cost), 0, 1e300,
     .help = "estimated cost of one frame (fragments over all passes), 400 too_expensive\n"
             "naming the field beyond; 0 = no limit (default 1e9: 20-50 s on llvmpipe)"},
    {"--render-deadline", "SEC", LC_OPT_INT, CFG(render_deadline), 0, 86400, 1,
     .help = "an HTTP render that waited this long for a worker (at most 25 s, answered while\n"
             "queued), or would take longer by the measured rate, gets 503; 0 = none (default 60)"},
    {"--max-queue-per-client", "N", LC_OPT_INT, CFG(max_queue_per_client), 1, 100000,
     .help = "queued HTTP renders of one client address or session, 429 beyond\n"
             "(default 8; clients are served round robin)"},
    {"--idle-timeout", "SEC", LC_OPT_INT, CFG(idle_timeout), 1, 86400 * 7, 1,
     .help = "close sessions unused this long (default 300)"},
    {"--still-delay", "MS", LC_OPT_INT, CFG(still_delay), 0, 60000, 0.001,
     .help = "quiet input before the full-quality still frame (default 150)"},
    {"--pass-delay", "MS", LC_OPT_INT, CFG(pass_delay), 0, 10000, 0.001,
     .help = "for tests: wait this long before every pass of every frame, so that\n"
             "progress and pre-emption are observable on any machine (default 0)"},
    {"--frame-budget", "MS", LC_OPT_INT, CFG(frame_budget_ms), 5, 10000, 1,
     .help = "render time interactive frames aim under: line detail, point stride and\n"
             "resolution adapt to it (default 70)"},
    {"--log-level", "L", LC_OPT_CALL, .call = opt_log_level, .help = "error|warn|info|debug (default info)"},
    {"--mpi", NULL, LC_OPT_BOOL, CFG(mpi),
     .help = "under mpirun/srun: each rank reads its share of line files, point clouds and\n"
             "point tables (meshes, .obj: loads all, keeps its shard); rank 0 serves\n"
             "and leads, the others render their shards of each frame (docs/MPI.md)"},
    {NULL}};

static bool flags_listed; /* --list-flags printed the table: no usage after it */

static void usage(FILE *f)
{
    if (flags_listed)
        return;
    lc_opt_set set = {serve_options, NULL};
    fprintf(f, "usage: lucent serve [options] [--data PATH|demo:NAME ...]\n\n");
    lc_opt_usage(f, &set, 1);
    fprintf(f, "  -h, --help             this text\n");
}

/* Fills cfg from argv; returns 0, 1 for --help, -1 on a usage error. */
static int parse_flags(int argc, char **argv, lc_serve_config *cfg, const char **data)
{
    /* Paths after the flags (`--data a.ply b.ply`) are data too. */
    static const char *rest[MAX_DATA];
    int nrest = 0;
    cfg->data = data;
    lc_opt_set set = {serve_options, cfg};
    int rc = lc_opt_parse("serve", &set, 1, argc, argv, rest, MAX_DATA, &nrest);
    for (int i = 1; i < argc && rc > 0; i++)
        flags_listed |= strcmp(argv[i], "--list-flags") == 0;
    for (int i = 0; i < nrest && rc == 0; i++) {
        if (cfg->data_count >= MAX_DATA)
            return -1;
        data[cfg->data_count++] = rest[i];
    }
    if (rc != 0)
        return rc;
    if (cfg->limits.max_pixels > (long long)cfg->limits.max_size * cfg->limits.max_size)
        cfg->limits.max_pixels = (long long)cfg->limits.max_size * cfg->limits.max_size;
    return 0;
}

static void config_defaults(lc_serve_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    snprintf(cfg->listen_host, sizeof cfg->listen_host, "127.0.0.1");
    cfg->port = 8080;
    cfg->device = -1;
    lc_proto_limits_default(&cfg->limits);
    cfg->max_body = 64 * 1024;
    cfg->max_ws_message = 64 * 1024;
    cfg->max_sessions = 64;
    cfg->max_client_sessions = 16;
    cfg->movie_disk = 4ULL << 30;
    cfg->max_queue = 32;
    cfg->max_connections = 256;
    cfg->idle_timeout = 300;
    cfg->max_stream_pixels = 4LL << 20;
    cfg->still_delay = 0.150;
    cfg->frame_budget_ms = 70.0;
    cfg->max_cost = LC_COST_DEFAULT_BUDGET;
    cfg->render_deadline = 60;
    cfg->load_timeout = 600;
    cfg->max_queue_per_client = 8;
}

/* A start-up that ends in an error: says so when a signal stopped it. */
static int startup_failed(void)
{
    int sig = lc_signals_received();
    if (sig)
        LC_WARN(MOD, "%s during start-up: exited before serving", lc_signals_name(sig));
    return 1;
}

static int serve_main(int argc, char **argv)
{
    static lc_server srv; /* one per process; static so signal-free code can reach it in a debugger */
    static const char *data[MAX_DATA];
    memset(&srv, 0, sizeof srv);
    config_defaults(&srv.cfg);
    const char *env_token = getenv("LUCENT_TOKEN");
    if (env_token && set_token(&srv.cfg, env_token, "LUCENT_TOKEN") != 0)
        return 2;
    int pr = parse_flags(argc, argv, &srv.cfg, data);
    if (pr != 0) {
        usage(pr > 0 ? stdout : stderr);
        return pr > 0 ? 0 : 2;
    }
    srv.cfg.data = data;
    lc_serve_config *cfg = &srv.cfg;
    lc_error err = {0};
    /* The shutdown signals go to one watcher thread from here on, so that
     * they stop a start-up too (signals.h). Before MPI_Init: its threads
     * inherit the mask, so a signal (mpirun's SIGTERM when a rank died)
     * cannot land in one of them instead of the watcher. */
    if (lc_signals_start(&err) != 0) {
        LC_ERROR(MOD, "%s", err.msg);
        return 1;
    }
    if (cfg->mpi && lc_ranks_init(&srv, &err) != 0) {
        LC_ERROR(MOD, "--mpi: %s", err.msg);
        return 1;
    }
    srv.start_time = lc_now();
    signal(SIGPIPE, SIG_IGN);
    lc_crash_report_install();

    char cache_dir[PATH_MAX] = "";
    if (!cfg->cache)
        lc_dataset_cache_default_dir(cache_dir, sizeof cache_dir);
    else if (strcmp(cfg->cache, "off") != 0)
        snprintf(cache_dir, sizeof cache_dir, "%s", cfg->cache);
    lc_datasets_options dopts = {.demo_size = cfg->demo_size,
                                 .exact_positions = cfg->exact_positions,
                                 .max_memory = cfg->max_memory,
                                 .follow_symlinks = cfg->follow_symlinks,
                                 .load_timeout = cfg->load_timeout,
                                 /* the default's upper bound until the GL says (lc_datasets_set_workers) */
                                 .workers = cfg->workers > 0 ? cfg->workers : default_workers(false),
                                 .cache_dir = cache_dir};
    lc_ranks_datasets_options(&srv, &dopts);
    /* Under MPI the ranks agree on the load first; a context is made after. */
    gl_start gls = {.desc = {.device = cfg->device}};
    pthread_t gl_thread;
    bool gl_early = !cfg->mpi && !srv.mpi && pthread_create(&gl_thread, NULL, gl_start_run, &gls) == 0;
    int rc = lc_datasets_load(cfg->data, cfg->data_count, &dopts, &srv.datasets, &err);
    if (rc == 0 && cfg->demo && cfg->data_count > 0)
        rc = lc_datasets_add_demos(srv.datasets, &err);
    if (rc == 0 && cfg->elements)
        rc = lc_datasets_set_element_budget(srv.datasets, cfg->elements, &err);
    if (srv.mpi)
        rc = lc_ranks_start(&srv, rc, &err);
    if (rc == 0 && lc_cancelled())
        rc = lc_err_cancelled(&err, "start-up");
    if (gl_early)
        pthread_join(gl_thread, NULL);
    if (rc != 0) {
        LC_ERROR(MOD, "%s", err.msg);
        if (gls.gl)
            lc_gl_destroy(gls.gl);
        lc_datasets_destroy(srv.datasets);
        return startup_failed();
    }

    /* The primary context: datasets are uploaded with it; worker 0 adopts it. */
    lc_gl *primary = NULL;
    int nworkers = 1;
    if (gl_early) {
        primary = gls.gl;
        if ((rc = gls.rc) != 0)
            err = gls.err;
    } else {
        rc = lc_gl_create(&gls.desc, &primary, &err);
    }
    if (rc == 0)
        rc = lc_gl_make_current(primary, &err);
    if (rc == 0) {
        snprintf(srv.gl_renderer, sizeof srv.gl_renderer, "%s", lc_gl_renderer(primary));
        snprintf(srv.gl_version, sizeof srv.gl_version, "%s", lc_gl_version(primary));
        snprintf(srv.gl_platform, sizeof srv.gl_platform, "%s", lc_gl_platform(primary));
        LC_INFO(MOD, "GL: %s, %s (%s)", srv.gl_renderer, srv.gl_version, srv.gl_platform);
        nworkers = cfg->workers > 0 ? cfg->workers : default_workers(lc_gl_is_software(primary));
        if (srv.mpi)
            nworkers = 1; /* frames are collective: one at a time, in one order on every rank */
        lc_datasets_set_workers(srv.datasets, nworkers);
        rc = lc_datasets_upload(srv.datasets, &err);
        if (rc != 0)
            lc_datasets_release_gpu(srv.datasets);
        lc_gl_release_current(primary);
    }
    if (srv.mpi && (rc = lc_ranks_agree(&srv, rc, &err)) == 0 && lc_ranks_follower(&srv)) {
        rc = lc_gl_make_current(primary, &err);
        if (rc == 0)
            rc = lc_ranks_follow(&srv, primary, &err);
        if (rc != 0)
            LC_ERROR(MOD, "%s", err.msg);
        lc_datasets_release_gpu(srv.datasets);
        lc_gl_release_current(primary);
        lc_gl_destroy(primary);
        lc_datasets_destroy(srv.datasets);
        return rc ? 1 : 0;
    }
    if (rc != 0) {
        LC_ERROR(MOD, "%s", err.msg);
        if (primary)
            lc_gl_destroy(primary);
        lc_datasets_destroy(srv.datasets);
        return startup_failed();
    }
    int nencoders = cfg->encoders > 0 ? cfg->encoders : 2;

    srv.metrics = lc_metrics_create();
    srv.sessions = lc_sessions_create(&srv, cfg->max_sessions);
    if (!srv.metrics || !srv.sessions) {
        LC_ERROR(MOD, "out of memory");
        return 1;
    }
    rc = lc_workers_create(&srv, primary, nworkers, nencoders, cfg->max_queue, &srv.workers, &err);
    if (rc == 0)
        rc = lc_ws_create(&srv, &srv.ws, &err);
    if (rc == 0)
        srv.sink = (lc_stream_sink){.ctx = srv.ws, .send = sink_send, .send_frame = sink_send_frame};
    int port = 0;
    if (rc == 0)
        rc = lc_movies_create(&srv, &srv.movies, &err);
    if (rc == 0)
        rc = lc_http_start(&srv, &srv.http, &port, &err);
    if (rc == 0 && srv.mpi)
        lc_ranks_serving(&srv);
    if (rc != 0) {
        LC_ERROR(MOD, "%s", err.msg);
        lc_movies_destroy(srv.movies);
        lc_ws_destroy(srv.ws);
        lc_workers_destroy(srv.workers, srv.datasets);
        if (!srv.workers && primary)
            lc_gl_destroy(primary);
        lc_sessions_destroy(srv.sessions);
        lc_metrics_destroy(srv.metrics);
        lc_datasets_destroy(srv.datasets);
        return startup_failed();
    }
    const char *host = cfg->listen_host;
    bool v6 = strchr(host, ':') != NULL;
    LC_INFO(MOD, "%d dataset(s), %d worker(s), token %s", lc_datasets_count(srv.datasets), nworkers,
            cfg->token[0] ? "required" : "off");
    LC_INFO(MOD, "listening on http://%s%s%s:%d/", v6 ? "[" : "", host, v6 ? "]" : "", port);

    lc_signals_serving();
    int sig = lc_signals_wait();
    LC_INFO(MOD, "%s: shutting down", lc_signals_name(sig));
    if (srv.mpi)
        lc_ranks_signal(&srv, lc_signals_name(sig));
    atomic_store(&srv.stopping, 1);

    /* 1. no new connections; 2. frames in hand finish, are encoded and queued
     * (queued HTTP renders get 503); 3. WebSocket clients get those frames and
     * a close frame; 4. MHD answers the resumed requests and stops. */
    lc_http_quiesce(srv.http);
    lc_movies_stop(srv.movies); /* its frame in hand finishes; the rest is cancelled */
    lc_workers_stop(srv.workers);
    if (srv.mpi)
        lc_ranks_stop(&srv);
    lc_ws_shutdown(srv.ws, 2.0);
    lc_http_stop(srv.http);
    lc_movies_destroy(srv.movies);
    lc_ws_destroy(srv.ws);
    lc_sessions_destroy(srv.sessions);
    lc_workers_destroy(srv.workers, srv.datasets);
    lc_datasets_destroy(srv.datasets);
    lc_metrics_destroy(srv.metrics);
    LC_INFO(MOD, "stopped after %.1f s", lc_now() - srv.start_time);
    return 0;
}

int lc_serve_main(int argc, char **argv)
{
    int rc = serve_main(argc, argv);
    lc_ranks_finalize();
    return rc;
}
