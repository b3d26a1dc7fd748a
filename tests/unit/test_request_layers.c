/* layers[] of a render request (protocol/request_layers.c): each layer's
 * fields land in lc_request, the normalized form parses back to the same
 * layers, and bad layer specifications are refused naming layers[i].key;
 * a layer's own sections (filter, time, lines, color.equalize) parse. */
#include <string.h>

#include "lc_test.h"
#include "request.h"

static int parse(const char *json, lc_request *r, lc_proto_error *e)
{
    memset(e, 0, sizeof *e);
    return lc_proto_parse_request(json, strlen(json), NULL, r, e);
}

static void refused(const char *json, const char *field)
{
    lc_request *r = malloc(sizeof *r);
    lc_proto_error e;
    int rc = parse(json, r, &e);
    CHECK(rc != 0 && strcmp(e.field, field) == 0 && strncmp(e.message, field, strlen(field)) == 0,
          "%s -> error naming %s (got %d, \"%s\": %s)", json, field, rc, e.field, e.message);
    free(r);
}

int main(void)
{
    lc_request *r = malloc(sizeof *r), *back = malloc(sizeof *back);
    lc_proto_error e;
    const char *two = "{\"dataset\": \"demo:points\", \"layers\": ["
                      "{\"dataset\": \"demo:points\", \"style\": {\"pointSize\": 3}, \"visible\": false},"
                      "{\"dataset\": \"demo:tornado\", \"role\": \"context\", \"importance\": {\"attribute\": "
                      "\"curvature\", \"range\": [0, 2]}, \"color\": {\"colormap\": \"coolwarm\"}}]}";
    CHECK(parse(two, r, &e) == 0, "two layers parse: %s", e.message);
    CHECK(r->layer_count == 2, "layer_count %d", r->layer_count);
    CHECK(strcmp(r->layers[0].dataset, "demo:points") == 0 && !r->layers[0].p.visible &&
              r->layers[0].p.style.point_size == 3 && r->layers[0].p.role == LC_LAYER_TRANSPARENT,
          "layer 0: dataset, visible false, pointSize 3, transparent");
    CHECK(strcmp(r->layers[1].dataset, "demo:tornado") == 0 && r->layers[1].p.visible &&
              r->layers[1].p.role == LC_LAYER_CONTEXT &&
              strcmp(r->layers[1].p.importance.attribute, "curvature") == 0 && r->layers[1].p.importance.has_range &&
              r->layers[1].p.importance.range[1] == 2 && strcmp(r->layers[1].p.color.colormap, "coolwarm") == 0,
          "layer 1: context, its importance and colour");
    CHECK(r->render.importance.attribute[0] == '\0' && strcmp(r->render.color.colormap, "viridis") == 0,
          "a layer's mapping leaves the request's own untouched");

    /* The normalized form gives back the same layers. */
    json_t *j = lc_proto_request_to_json(r);
    char *text = lc_proto_dump(j);
    CHECK(text && parse(text, back, &e) == 0, "the normalized form parses: %s", e.message);
    CHECK(back->layer_count == 2 && memcmp(back->layers, r->layers, 2 * sizeof r->layers[0]) == 0,
          "the normalized form gives back equal layers: %s", text ? text : "(none)");
    free(text);
    json_decref(j);

    /* [] goes back to the single dataset. */
    json_t *update = json_loads("{\"layers\": []}", 0, NULL);
    CHECK(lc_proto_apply_request(update, NULL, r, &e) == 0 && r->layer_count == 0, "layers [] -> no layers");
    json_decref(update);

    refused("{\"layers\": {}}", "layers");
    refused("{\"layers\": [{\"style\": {\"pointSize\": 2}}]}", "layers[0].dataset");
    refused("{\"layers\": [{\"dataset\": \"a\"}, {\"dataset\": \"b\", \"opacity\": 1}]}", "layers[1].opacity");
    refused("{\"layers\": [{\"dataset\": \"a\", \"role\": \"ghost\"}]}", "layers[0].role");
    refused("{\"layers\": [{\"dataset\": \"a\", \"visible\": 1}]}", "layers[0].visible");
    refused("{\"layers\": [{\"dataset\": \"a\", \"style\": {\"background\": [0, 0, 0]}}]}",
            "layers[0].style.background");
    refused("{\"layers\": [{\"dataset\": \"a\", \"style\": {\"pointSize\": 0}}]}", "layers[0].style.pointSize");
    refused("{\"layers\": [{\"dataset\": \"a\", \"importance\": {\"exponent\": \"x\"}}]}",
            "layers[0].importance.exponent");
    /* A layer's own sections: filter, time window, clustering, equalized colour. */
    const char *sections =
        "{\"layers\": [{\"dataset\": \"a\", \"color\": {\"equalize\": true}, \"lines\": {\"clusters\": 7}, "
        "\"time\": {\"window\": [1, 2]}, \"filter\": [{\"attribute\": \"g\", \"over\": \"max\", \"gt\": 0.5}]}]}";
    CHECK(parse(sections, r, &e) == 0 && r->layers[0].p.color.equalize && r->layers[0].p.clusters.count == 7 &&
              r->layers[0].p.time.has_window && r->layers[0].p.time.window[1] == 2 &&
              r->layers[0].p.filter_count == 1 && r->layers[0].p.filters[0].lo == 0.5,
          "a layer's equalize, clusters, time window and filter parse: %s", e.message);
    refused("{\"layers\": [{\"dataset\": \"a\", \"lines\": {\"clusters\": -1}}]}", "layers[0].lines.clusters");
    refused("{\"layers\": [{\"dataset\": \"a\", \"time\": {\"window\": [1]}}]}", "layers[0].time.window");
    refused("{\"layers\": [{\"dataset\": \"a\", \"color\": {\"colormap\": \"nope\"}}]}", "layers[0].color.colormap");
    refused("{\"layers\": [{\"dataset\": \"\"}]}", "layers[0].dataset");
    char many[1024] = "{\"layers\": [";
    for (int i = 0; i <= LC_MAX_LAYERS; i++)
        strcat(many, i ? ", {\"dataset\": \"a\"}" : "{\"dataset\": \"a\"}");
    strcat(many, "]}");
    refused(many, "layers");

    /* The query form takes the array as JSON text. */
    lc_request_default(r);
    CHECK(lc_proto_apply_query(r, "layers", "[{\"dataset\": \"demo:points\"}]", NULL, &e) == 0 && r->layer_count == 1,
          "query layers=[...]: %s", e.message);
    free(r);
    free(back);
    return lc_test_finish();
}
