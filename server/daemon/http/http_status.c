/* The daemon's status routes: health, datasets and Prometheus metrics (http_status.h). */
#include "http_status.h"

#include <stdatomic.h>

#include "conn_limits.h"
#include "datasets.h"
#include "held.h"
#include "memory.h"
#include "messages.h"
#include "metrics.h"
#include "session.h"
#include "workers.h"
#include "ws.h"

/* The one memory budget (--max-memory): the datasets' and fields' estimate,
 * and what requests hold beside them (streamline sets, surfaces' curves). */
static json_t *memory_json(lc_server *srv)
{
    json_t *o = lc_datasets_memory_json(srv->datasets);
    uint64_t estimated = 0, limit = 0, sets = lc_held(LC_HELD_STREAMLINE_SETS), curves = lc_held(LC_HELD_SURFACES);
    lc_datasets_budget(srv->datasets, &estimated, &limit);
    json_object_set_new(o, "datasets", json_integer((json_int_t)estimated));
    json_object_set_new(o, "held",
                        json_pack("{s:I, s:I}", "streamlineSets", (json_int_t)sets, "surfaces", (json_int_t)curves));
    json_object_set_new(o, "estimated", json_integer((json_int_t)(estimated + sets + curves)));
    return o;
}

enum MHD_Result lc_http_health(lc_server *srv, struct MHD_Connection *c)
{
    int http = 0, ws = 0;
    lc_sessions_count(srv->sessions, &http, &ws);
    json_t *o = json_object();
    json_object_set_new(o, "status", json_string(atomic_load(&srv->stopping) ? "stopping" : "ok"));
    json_object_set_new(o, "renderer", json_string(srv->gl_renderer));
    json_object_set_new(o, "glVersion", json_string(srv->gl_version));
    json_object_set_new(o, "platform", json_string(srv->gl_platform));
    /* Which path P4 and P5 take per primitive type on this device (compute_raster.c). */
    json_t *paths = json_object();
    static const lc_prim_type prims[] = {LC_PRIM_POINTS, LC_PRIM_LINES, LC_PRIM_TRIANGLES};
    for (int i = 0; i < 3; i++) {
        json_t *path =
            json_pack("{s:s, s:s}", "opticalDepth", lc_raster_path_name(srv->gl_renderer, LC_RASTER_P4, prims[i]),
                      "accumulate", lc_raster_path_name(srv->gl_renderer, LC_RASTER_P5, prims[i]));
        /* and the form drawn segments take (line_primitive.c) */
        if (prims[i] == LC_PRIM_LINES)
            json_object_set_new(path, "primitive", json_string(lc_line_path_name()));
        json_object_set_new(paths, lc_prim_type_name(prims[i]), path);
    }
    json_object_set_new(o, "rasterPaths", paths);
    json_object_set_new(o, "uptime", json_real(lc_now() - srv->start_time));
    json_object_set_new(o, "datasets", json_integer(lc_datasets_count(srv->datasets)));
    json_object_set_new(o, "workers", json_integer(lc_workers_count(srv->workers)));
    json_object_set_new(o, "sessions", json_pack("{s:i, s:i}", "http", http, "ws", ws));
    json_object_set_new(o, "memory", memory_json(srv));
    json_object_set_new(o, "protocolVersion", json_integer(LC_PROTO_VERSION));
    return lc_http_json(srv, c, 200, o);
}

enum MHD_Result lc_http_datasets(lc_server *srv, struct MHD_Connection *c, const char *name)
{
    if (name) {
        const lc_dataset *ds = lc_datasets_find(srv->datasets, name);
        const lc_field_entry *fe = ds || !name[0] ? NULL : lc_fields_find(lc_datasets_fields(srv->datasets), name);
        if (fe)
            return lc_http_json(srv, c, 200, lc_field_info(fe));
        if (!ds || !name[0])
            return lc_http_error(srv, c, 404, "not_found", "dataset", "unknown dataset \"%.300s\"", name);
        return lc_http_json(srv, c, 200, lc_dataset_info(ds));
    }
    json_t *arr = json_array();
    for (int i = 0; i < lc_datasets_count(srv->datasets); i++)
        json_array_append_new(arr, lc_dataset_info(lc_datasets_at(srv->datasets, i)));
    json_t *o = json_object();
    json_object_set_new(o, "datasets", arr);
    json_object_set_new(o, "fields", lc_fields_json(lc_datasets_fields(srv->datasets)));
    json_object_set_new(o, "memory", memory_json(srv));
    return lc_http_json(srv, c, 200, o);
}

enum MHD_Result lc_http_metrics(lc_server *srv, struct MHD_Connection *c)
{
    lc_metrics_gauges g = {0};
    lc_sessions_count(srv->sessions, &g.sessions_http, &g.sessions_ws);
    lc_workers_depths(srv->workers, &g.queue_depth, &g.encode_depth);
    g.ws_connections = lc_ws_connections(srv->ws);
    g.datasets = lc_datasets_count(srv->datasets);
    g.workers = lc_workers_count(srv->workers);
    g.queue_clients = lc_workers_clients(srv->workers);
    lc_datasets_budget(srv->datasets, &g.memory_estimated, &g.memory_budget);
    g.memory_estimated += lc_held_total(); /* the one budget's whole estimate */
    g.resident = lc_memory_resident_bytes();
    lc_conn_limits_counts(&g.unfinished_deadline, &g.unfinished_evicted);
    return lc_http_text(srv, c, 200, lc_metrics_render(srv->metrics, &g), "text/plain; version=0.0.4; charset=utf-8");
}
