/* `lucent serve`: flags, start-up (datasets load before the port opens),
 * signal handling and the ordered shutdown. */
#include "serve.h"

#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "datasets.h"
#include "gl_context.h"
#include "http.h"
#include "lc_mpi.h"
#include "loaders.h"
#include "metrics.h"
#include "serve_mpi.h"
#include "server.h"
#include "session.h"
#include "signals.h"
#include "workers.h"
#include "ws.h"

#define MOD "serve"
#define MAX_DATA 256

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

static void usage(FILE *f)
{
    fprintf(f,
            "usage: lucent serve [options] [--data PATH|demo:NAME ...]\n"
            "\n"
            "  --listen ADDR:PORT     listen address (default 127.0.0.1:8080; port 0 picks a free one;\n"
            "                         IPv6 as [::1]:8080). Anything but loopback exposes the server.\n"
            "  --data PATH|DIR...     datasets to load before the port opens: files (" LC_DATASET_EXTENSIONS "),\n"
            "                         folders (every such file in it) or demo:NAME (repeatable; several paths may\n"
            "                         follow one --data). None = all demos.\n"
            "  --demo                 also serve every built-in demo next to --data\n"
            "  --demo-size N          size of generated demos (lines/points/grid; default: the generator's)\n"
            "  --elements N           line elements or surface patches per dataset (default: derived from the data)\n"
            "  --exact-positions      float GPU buffers and session opacities (images bit for bit as before the\n"
            "                         compact 16-bit layout; about twice the bytes per vertex)\n"
            "  --max-memory BYTES     refuse a dataset whose estimated resident size, with the ones before it,\n"
            "                         exceeds BYTES (k, M, G, T suffixes; default: no limit)\n"
            "  --follow-symlinks      serve files and sidecars of a --data folder that link outside it\n"
            "  --device N             EGL device index (default: LUCENT_EGL_DEVICE or the first GPU)\n"
            "  --workers N            render threads, one GL context each (default 1 on llvmpipe, 2 on a GPU)\n"
            "  --encoders N           JPEG/PNG encoder threads (default 2)\n"
            "  --token T              require this bearer token (default: LUCENT_TOKEN if set)\n"
            "  --max-size N           max image width/height (default 4096)\n"
            "  --max-pixels N         max width*height of an HTTP render (default 16777216)\n"
            "  --max-stream-pixels N  max pixels of a WebSocket frame (default 4194304)\n"
            "  --max-body BYTES       max HTTP request body (default 65536)\n"
            "  --max-ws-message BYTES max WebSocket message, close 1009 beyond (default 65536)\n"
            "  --max-json-depth N     max JSON nesting (default 16)\n"
            "  --max-sessions N       max open sessions, HTTP and WebSocket (default 64)\n"
            "  --max-queue N          max queued HTTP renders, 503 beyond (default 32)\n"
            "  --max-connections N    max HTTP connections (default 256)\n"
            "  --max-cost UNITS       estimated cost of one frame (fragments over all passes), 400 too_expensive\n"
            "                         naming the field beyond; 0 = no limit (default 1e9: 20-50 s on llvmpipe)\n"
            "  --render-deadline SEC  an HTTP render that waited this long for a worker, or would take longer by\n"
            "                         the measured rate, gets 503; 0 = none (default 60)\n"
            "  --max-queue-per-client N  queued HTTP renders of one client address or session, 429 beyond\n"
            "                         (default 8; clients are served round robin)\n"
            "  --idle-timeout SEC     close sessions unused this long (default 300)\n"
            "  --still-delay MS       quiet input before the full-quality still frame (default 150)\n"
            "  --frame-budget MS      render time interactive frames aim under: line detail, point stride and\n"
            "                         resolution adapt to it (default 70)\n"
            "  --log-level L          error|warn|info|debug (default info)\n"
            "  --mpi                  under mpirun/srun: each rank reads its share of line files, point clouds and\n"
            "                         point tables (meshes, .obj: loads all, keeps its shard); rank 0 serves\n"
            "                         and leads, the others render their shards of each frame (docs/MPI.md)\n"
            "  -h, --help             this text\n");
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

static int parse_long(const char *flag, const char *arg, long long lo, long long hi, long long *out)
{
    char *end;
    long long v = strtoll(arg, &end, 10);
    if (*end || end == arg || v < lo || v > hi) {
        fprintf(stderr, "lucent serve: %s: \"%s\" is not an integer in [%lld, %lld]\n", flag, arg, lo, hi);
        return -1;
    }
    *out = v;
    return 0;
}

enum {
    OPT_LISTEN = 256,
    OPT_DATA,
    OPT_DEMO,
    OPT_DEMO_SIZE,
    OPT_DEVICE,
    OPT_WORKERS,
    OPT_ENCODERS,
    OPT_TOKEN,
    OPT_MAX_SIZE,
    OPT_MAX_PIXELS,
    OPT_MAX_STREAM_PIXELS,
    OPT_MAX_BODY,
    OPT_MAX_WS,
    OPT_MAX_DEPTH,
    OPT_MAX_SESSIONS,
    OPT_MAX_QUEUE,
    OPT_MAX_CONN,
    OPT_IDLE,
    OPT_STILL,
    OPT_FRAME_BUDGET,
    OPT_LOG,
    OPT_ELEMENTS,
    OPT_MAX_COST,
    OPT_DEADLINE,
    OPT_QUEUE_PER_CLIENT,
    OPT_MPI,
    OPT_EXACT_POSITIONS,
    OPT_MAX_MEMORY,
    OPT_FOLLOW_SYMLINKS
};

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

/* Fills cfg from argv; returns 0, 1 for --help, -1 on a usage error. */
static int parse_flags(int argc, char **argv, lc_serve_config *cfg, const char **data)
{
    static const struct option opts[] = {{"listen", required_argument, NULL, OPT_LISTEN},
                                         {"data", required_argument, NULL, OPT_DATA},
                                         {"demo", no_argument, NULL, OPT_DEMO},
                                         {"demo-size", required_argument, NULL, OPT_DEMO_SIZE},
                                         {"elements", required_argument, NULL, OPT_ELEMENTS},
                                         {"device", required_argument, NULL, OPT_DEVICE},
                                         {"workers", required_argument, NULL, OPT_WORKERS},
                                         {"encoders", required_argument, NULL, OPT_ENCODERS},
                                         {"token", required_argument, NULL, OPT_TOKEN},
                                         {"max-size", required_argument, NULL, OPT_MAX_SIZE},
                                         {"max-pixels", required_argument, NULL, OPT_MAX_PIXELS},
                                         {"max-stream-pixels", required_argument, NULL, OPT_MAX_STREAM_PIXELS},
                                         {"max-body", required_argument, NULL, OPT_MAX_BODY},
                                         {"max-ws-message", required_argument, NULL, OPT_MAX_WS},
                                         {"max-json-depth", required_argument, NULL, OPT_MAX_DEPTH},
                                         {"max-sessions", required_argument, NULL, OPT_MAX_SESSIONS},
                                         {"max-queue", required_argument, NULL, OPT_MAX_QUEUE},
                                         {"max-connections", required_argument, NULL, OPT_MAX_CONN},
                                         {"idle-timeout", required_argument, NULL, OPT_IDLE},
                                         {"still-delay", required_argument, NULL, OPT_STILL},
                                         {"frame-budget", required_argument, NULL, OPT_FRAME_BUDGET},
                                         {"log-level", required_argument, NULL, OPT_LOG},
                                         {"max-cost", required_argument, NULL, OPT_MAX_COST},
                                         {"render-deadline", required_argument, NULL, OPT_DEADLINE},
                                         {"max-queue-per-client", required_argument, NULL, OPT_QUEUE_PER_CLIENT},
                                         {"mpi", no_argument, NULL, OPT_MPI},
                                         {"exact-positions", no_argument, NULL, OPT_EXACT_POSITIONS},
                                         {"max-memory", required_argument, NULL, OPT_MAX_MEMORY},
                                         {"follow-symlinks", no_argument, NULL, OPT_FOLLOW_SYMLINKS},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    optind = 1;
    int opt;
    long long v;
    while ((opt = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        switch (opt) {
        case OPT_LISTEN:
            if (parse_listen(optarg, cfg) != 0) {
                fprintf(stderr, "lucent serve: --listen: expected ADDR:PORT, got \"%s\"\n", optarg);
                return -1;
            }
            break;
        case OPT_DATA:
            if (cfg->data_count >= MAX_DATA)
                return -1;
            data[cfg->data_count++] = optarg;
            break;
        case OPT_DEMO: cfg->demo = true; break;
        case OPT_DEMO_SIZE:
            if (parse_long("--demo-size", optarg, 1, 100000000, &v))
                return -1;
            cfg->demo_size = (unsigned long long)v;
            break;
        case OPT_ELEMENTS:
            if (parse_long("--elements", optarg, 1, 1 << 24, &v))
                return -1;
            cfg->elements = (unsigned)v;
            break;
        case OPT_DEVICE:
            if (parse_long("--device", optarg, 0, 64, &v))
                return -1;
            cfg->device = (int)v;
            break;
        case OPT_WORKERS:
            if (parse_long("--workers", optarg, 1, 64, &v))
                return -1;
            cfg->workers = (int)v;
            break;
        case OPT_ENCODERS:
            if (parse_long("--encoders", optarg, 1, 64, &v))
                return -1;
            cfg->encoders = (int)v;
            break;
        case OPT_TOKEN:
            if (set_token(cfg, optarg, "--token") != 0)
                return -1;
            break;
        case OPT_MAX_SIZE:
            if (parse_long("--max-size", optarg, 16, 16384, &v))
                return -1;
            cfg->limits.max_size = (int)v;
            break;
        case OPT_MAX_PIXELS:
            if (parse_long("--max-pixels", optarg, 256, 1LL << 28, &v))
                return -1;
            cfg->limits.max_pixels = v;
            break;
        case OPT_MAX_STREAM_PIXELS:
            if (parse_long("--max-stream-pixels", optarg, 256, 1LL << 28, &v))
                return -1;
            cfg->max_stream_pixels = v;
            break;
        case OPT_MAX_BODY:
            if (parse_long("--max-body", optarg, 64, 1LL << 30, &v))
                return -1;
            cfg->max_body = (size_t)v;
            break;
        case OPT_MAX_WS:
            if (parse_long("--max-ws-message", optarg, 64, 1LL << 30, &v))
                return -1;
            cfg->max_ws_message = (size_t)v;
            break;
        case OPT_MAX_DEPTH:
            if (parse_long("--max-json-depth", optarg, 2, 1000, &v))
                return -1;
            cfg->limits.max_depth = (int)v;
            break;
        case OPT_MAX_SESSIONS:
            if (parse_long("--max-sessions", optarg, 1, 100000, &v))
                return -1;
            cfg->max_sessions = (int)v;
            break;
        case OPT_MAX_QUEUE:
            if (parse_long("--max-queue", optarg, 1, 100000, &v))
                return -1;
            cfg->max_queue = (int)v;
            break;
        case OPT_MAX_CONN:
            if (parse_long("--max-connections", optarg, 4, 100000, &v))
                return -1;
            cfg->max_connections = (int)v;
            break;
        case OPT_IDLE:
            if (parse_long("--idle-timeout", optarg, 1, 86400 * 7, &v))
                return -1;
            cfg->idle_timeout = (double)v;
            break;
        case OPT_STILL:
            if (parse_long("--still-delay", optarg, 0, 60000, &v))
                return -1;
            cfg->still_delay = (double)v / 1000.0;
            break;
        case OPT_FRAME_BUDGET:
            if (parse_long("--frame-budget", optarg, 5, 10000, &v))
                return -1;
            cfg->frame_budget_ms = (double)v;
            break;
        case OPT_LOG: {
            int level = lc_log_parse_level(optarg);
            if (level < 0) {
                fprintf(stderr, "lucent serve: --log-level: expected error|warn|info|debug\n");
                return -1;
            }
            lc_log_set_level((lc_log_level)level);
            break;
        }
        case OPT_MAX_COST: {
            char *end;
            double d = strtod(optarg, &end);
            if (*end || !(d >= 0) || !isfinite(d)) {
                fprintf(stderr, "lucent serve: --max-cost: expected a number >= 0, got \"%s\"\n", optarg);
                return -1;
            }
            cfg->max_cost = d;
            break;
        }
        case OPT_DEADLINE:
            if (parse_long("--render-deadline", optarg, 0, 86400, &v))
                return -1;
            cfg->render_deadline = (double)v;
            break;
        case OPT_QUEUE_PER_CLIENT:
            if (parse_long("--max-queue-per-client", optarg, 1, 100000, &v))
                return -1;
            cfg->max_queue_per_client = (int)v;
            break;
        case OPT_MPI: cfg->mpi = true; break;
        case OPT_EXACT_POSITIONS: cfg->exact_positions = true; break;
        case OPT_FOLLOW_SYMLINKS: cfg->follow_symlinks = true; break;
        case OPT_MAX_MEMORY:
            if (lc_memory_parse_bytes(optarg, &cfg->max_memory) != 0) {
                fprintf(stderr, "lucent serve: --max-memory: expected bytes, e.g. 20G or 512M, got \"%s\"\n", optarg);
                return -1;
            }
            break;
        case 'h': return 1;
        default: return -1;
        }
    }
    /* Paths after the flags (`--data a.ply b.ply`) are data too. */
    for (int i = optind; i < argc; i++) {
        if (cfg->data_count >= MAX_DATA)
            return -1;
        data[cfg->data_count++] = argv[i];
    }
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
    cfg->max_queue = 32;
    cfg->max_connections = 256;
    cfg->idle_timeout = 300;
    cfg->max_stream_pixels = 4LL << 20;
    cfg->still_delay = 0.150;
    cfg->frame_budget_ms = 70.0;
    cfg->max_cost = LC_COST_DEFAULT_BUDGET;
    cfg->render_deadline = 60;
    cfg->max_queue_per_client = 8;
}

static lc_mpi *serve_mpi; /* --mpi: ended after everything else */

/* serve --mpi on rank 0: the frame in hand waits for a rank that died, so the
 * requests waiting for it get an answer that says so, not a closed connection. */
#define MPI_ENDING "the MPI job is ending: a rank has died, hangs or was stopped (the log names it)"
static void answer_before_abort(void *ctx, const char *msg)
{
    (void)msg;
    lc_workers_abandon(((lc_server *)ctx)->workers, MPI_ENDING);
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
    if (cfg->mpi) {
        if (lc_mpi_init(&serve_mpi, &err) != 0) {
            LC_ERROR(MOD, "--mpi: %s", err.msg);
            return 1;
        }
        srv.mpi = serve_mpi;
    }
    srv.start_time = lc_now();
    /* The shutdown signals go to one watcher thread from here on, so that
     * they stop a start-up too (signals.h). */
    if (lc_signals_start(&err) != 0) {
        LC_ERROR(MOD, "%s", err.msg);
        return 1;
    }
    signal(SIGPIPE, SIG_IGN);

    lc_datasets_options dopts = {.demo_size = cfg->demo_size,
                                 .exact_positions = cfg->exact_positions,
                                 .max_memory = cfg->max_memory,
                                 .follow_symlinks = cfg->follow_symlinks,
                                 .workers = cfg->workers > 0 ? cfg->workers : 1};
    const char *mpi_read = getenv("LUCENT_MPI_READ");
    if (srv.mpi && !(mpi_read && strcmp(mpi_read, "whole") == 0)) { /* line files, point clouds: each rank reads its share */
        dopts.read_part = lc_serve_mpi_read_part;
        dopts.read_part_ctx = srv.mpi;
    }
    int rc = lc_datasets_load(cfg->data, cfg->data_count, &dopts, &srv.datasets, &err);
    if (rc == 0 && cfg->demo && cfg->data_count > 0)
        rc = lc_datasets_add_demos(srv.datasets, &err);
    if (rc == 0 && cfg->elements)
        rc = lc_datasets_set_element_budget(srv.datasets, cfg->elements, &err);
    if (srv.mpi)
        rc = lc_serve_mpi_start(&srv, rc, &err);
    if (rc == 0 && lc_cancelled())
        rc = lc_err_cancelled(&err, "start-up");
    if (rc != 0) {
        LC_ERROR(MOD, "%s", err.msg);
        lc_datasets_destroy(srv.datasets);
        return startup_failed();
    }

    /* The primary context: datasets are uploaded with it; worker 0 adopts it. */
    lc_gl *primary = NULL;
    lc_gl_desc gdesc = {.device = cfg->device};
    rc = lc_gl_create(&gdesc, &primary, &err);
    if (rc == 0)
        rc = lc_gl_make_current(primary, &err);
    if (rc == 0) {
        snprintf(srv.gl_renderer, sizeof srv.gl_renderer, "%s", lc_gl_renderer(primary));
        snprintf(srv.gl_version, sizeof srv.gl_version, "%s", lc_gl_version(primary));
        snprintf(srv.gl_platform, sizeof srv.gl_platform, "%s", lc_gl_platform(primary));
        LC_INFO(MOD, "GL: %s, %s (%s)", srv.gl_renderer, srv.gl_version, srv.gl_platform);
        rc = lc_datasets_upload(srv.datasets, &err);
        if (rc != 0)
            lc_datasets_release_gpu(srv.datasets);
        lc_gl_release_current(primary);
    }
    if (srv.mpi && (rc = lc_mpi_agree(srv.mpi, rc, &err)) == 0 && lc_mpi_rank(srv.mpi) > 0) {
        rc = lc_gl_make_current(primary, &err);
        if (rc == 0)
            rc = lc_serve_mpi_follow(&srv, primary, &err);
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
    int nworkers = cfg->workers > 0 ? cfg->workers : (lc_gl_is_software(primary) ? 1 : 2);
    if (srv.mpi)
        nworkers = 1; /* frames are collective: one at a time, in one order on every rank */
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
        rc = lc_http_start(&srv, &srv.http, &port, &err);
    if (rc == 0 && srv.mpi)
        lc_mpi_on_abort(srv.mpi, answer_before_abort, &srv);
    if (rc != 0) {
        LC_ERROR(MOD, "%s", err.msg);
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
    if (srv.mpi) {
        /* Under mpirun a signal also comes when another rank died: mpirun then
         * ends the job and names the rank. A frame waiting for that rank
         * would hold the shutdown, so it has 10 s. */
        LC_WARN(MOD, "--mpi: %s received: ending the service on every rank (if a rank died, mpirun names it)",
                lc_signals_name(sig));
        lc_mpi_exit_guard(srv.mpi, 10.0);
        /* mpirun follows its signal with SIGKILL about a second later: answer
         * the frames in hand and the queue now rather than let them finish. */
        lc_workers_abandon(srv.workers, MPI_ENDING);
    }
    atomic_store(&srv.stopping, 1);

    /* 1. no new connections; 2. frames in hand finish, are encoded and queued
     * (queued HTTP renders get 503); 3. WebSocket clients get those frames and
     * a close frame; 4. MHD answers the resumed requests and stops. */
    lc_http_quiesce(srv.http);
    lc_workers_stop(srv.workers);
    if (srv.mpi) {
        lc_serve_mpi_stop(&srv);
        lc_mpi_on_abort(srv.mpi, NULL, NULL); /* the pool and the WebSocket layer go next */
    }
    lc_ws_shutdown(srv.ws, 2.0);
    lc_http_stop(srv.http);
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
    lc_mpi_finalize(serve_mpi);
    serve_mpi = NULL;
    return rc;
}
