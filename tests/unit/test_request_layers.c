/* layers[] of a render request (protocol/request_layers.c): each layer's
 * fields land in lc_request, the normalized form parses back to the same
 * layers, and bad layer specifications are refused naming layers[i].key;
 * a layer's own sections (filter, time, lines, color.equalize) parse. The
 * layers are one shared snapshot: copies and patches reference it, a change
 * of layers makes a new one and leaves the old one as it was. */
#include <pthread.h>
#include <string.h>

#include "lc_test.h"
#include "request.h"
#include "request_patch.h"

static int refs(const lc_request_layers *l) { return l ? atomic_load(&((lc_request_layers *)l)->refs) : 0; }

/* Threads that copy and drop one request's layers at once (a session's
 * request, its frames on the workers, the encoder): every pair leaves the
 * count where it was, and the snapshot reads the same throughout. */
static void *copy_drop(void *arg)
{
    const lc_request *shared = arg;
    long bad = 0;
    for (int i = 0; i < 100000; i++) {
        lc_request mine;
        lc_request_copy(&mine, shared);
        bad += lc_request_layer_count(&mine) != 1 || mine.layers->p[0].style.point_size != 4;
        lc_request_release(&mine);
    }
    return (void *)bad;
}

static void check_threads(void)
{
    lc_request r;
    lc_proto_error e;
    const char *one = "{\"layers\": [{\"dataset\": \"demo:points\", \"style\": {\"pointSize\": 4}}]}";
    CHECK(lc_proto_parse_request(one, strlen(one), NULL, &r, &e) == 0, "one layer parses: %s", e.message);
    pthread_t t[4];
    for (int i = 0; i < 4; i++)
        pthread_create(&t[i], NULL, copy_drop, &r);
    long bad = 0;
    for (int i = 0; i < 4; i++) {
        void *b;
        pthread_join(t[i], &b);
        bad += (long)b;
    }
    CHECK(bad == 0 && refs(r.layers) == 1,
          "4 threads x 100000 copies and releases: the count is back to 1 (%d), %ld bad reads", refs(r.layers), bad);
    lc_request_release(&r);
}

/* Copies share the snapshot; an update of layers replaces it (copy on write). */
static void check_sharing(void)
{
    lc_request a, b;
    lc_proto_error e;
    const char *one = "{\"layers\": [{\"dataset\": \"demo:points\", \"style\": {\"pointSize\": 4}}]}";
    CHECK(lc_proto_parse_request(one, strlen(one), NULL, &a, &e) == 0 && refs(a.layers) == 1, "one layer parses: %s",
          e.message);
    const lc_request_layers *first = a.layers;
    lc_request_copy(&b, &a);
    CHECK(b.layers == first && refs(first) == 2, "a copy shares the snapshot (refs %d)", refs(first));
    json_t *q = json_loads("{\"params\": {\"q\": 7}}", 0, NULL);
    CHECK(lc_proto_apply_request(q, NULL, &b, &e) == 0 && b.layers == first && refs(first) == 2,
          "an update without layers keeps the snapshot (refs %d)", refs(first));
    json_decref(q);
    json_t *two = json_loads("{\"layers\": [{\"dataset\": \"x\"}, {\"dataset\": \"y\"}]}", 0, NULL);
    CHECK(lc_proto_apply_request(two, NULL, &b, &e) == 0 && b.layers != first && refs(first) == 1 &&
              lc_request_layer_count(&b) == 2 && lc_request_layer_count(&a) == 1 &&
              strcmp(first->dataset[0], "demo:points") == 0 && first->p[0].style.point_size == 4,
          "an update of layers makes a new snapshot and leaves the copy's as it was");
    /* A refused update leaves the request and its snapshot alone. */
    json_t *bad = json_loads("{\"layers\": [{\"dataset\": \"x\"}], \"params\": {\"q\": -1}}", 0, NULL);
    const lc_request_layers *kept = b.layers;
    CHECK(lc_proto_apply_request(bad, NULL, &b, &e) != 0 && b.layers == kept && refs(kept) == 1,
          "a refused update keeps the snapshot (refs %d)", refs(kept));
    json_decref(bad);
    /* A patch holds its layers once and every request it applies to shares them. */
    lc_request_patch *patch;
    CHECK(lc_proto_patch_parse(two, NULL, &patch, &e) == 0, "a patch of layers parses: %s", e.message);
    CHECK(lc_proto_patch_apply(patch, NULL, &a, &e) == 0 && lc_proto_patch_apply(patch, NULL, &b, &e) == 0 &&
              a.layers == b.layers && refs(a.layers) == 3,
          "a patch's layers are shared by the requests it applies to (refs %d)", refs(a.layers));
    lc_proto_patch_free(patch);
    json_decref(two);
    CHECK(refs(a.layers) == 2, "freeing the patch drops its reference (refs %d)", refs(a.layers));
    lc_request_assign(&a, &a);
    CHECK(refs(a.layers) == 2, "assigning a request to itself keeps the count (refs %d)", refs(a.layers));
    lc_request_release(&b);
    CHECK(b.layers == NULL && refs(a.layers) == 1, "a release drops one reference");
    lc_request_release(&a);
}

static int parse(const char *json, lc_request *r, lc_proto_error *e)
{
    memset(e, 0, sizeof *e);
    return lc_proto_parse_request(json, strlen(json), NULL, r, e);
}

static void refused(const char *json, const char *field)
{
    lc_request r;
    lc_proto_error e;
    int rc = parse(json, &r, &e);
    CHECK(rc != 0 && strcmp(e.field, field) == 0 && strncmp(e.message, field, strlen(field)) == 0 && !r.layers,
          "%s -> error naming %s (got %d, \"%s\": %s)", json, field, rc, e.field, e.message);
}

int main(void)
{
    lc_request req, copy, *r = &req, *back = &copy;
    lc_proto_error e;
    const char *two = "{\"dataset\": \"demo:points\", \"layers\": ["
                      "{\"dataset\": \"demo:points\", \"style\": {\"pointSize\": 3}, \"visible\": false},"
                      "{\"dataset\": \"demo:tornado\", \"role\": \"context\", \"importance\": {\"attribute\": "
                      "\"curvature\", \"range\": [0, 2]}, \"color\": {\"colormap\": \"coolwarm\"}}]}";
    CHECK(parse(two, r, &e) == 0, "two layers parse: %s", e.message);
    CHECK(lc_request_layer_count(r) == 2, "layer count %d", lc_request_layer_count(r));
    CHECK(strcmp(r->layers->dataset[0], "demo:points") == 0 && !r->layers->p[0].visible &&
              r->layers->p[0].style.point_size == 3 && r->layers->p[0].role == LC_LAYER_TRANSPARENT,
          "layer 0: dataset, visible false, pointSize 3, transparent");
    CHECK(strcmp(r->layers->dataset[1], "demo:tornado") == 0 && r->layers->p[1].visible &&
              r->layers->p[1].role == LC_LAYER_CONTEXT &&
              strcmp(r->layers->p[1].importance.attribute, "curvature") == 0 && r->layers->p[1].importance.has_range &&
              r->layers->p[1].importance.range[1] == 2 && strcmp(r->layers->p[1].color.colormap, "coolwarm") == 0,
          "layer 1: context, its importance and colour");
    CHECK(r->render.importance.attribute[0] == '\0' && strcmp(r->render.color.colormap, "viridis") == 0,
          "a layer's mapping leaves the request's own untouched");

    /* The normalized form gives back the same layers. */
    json_t *j = lc_proto_request_to_json(r);
    char *text = lc_proto_dump(j);
    CHECK(text && parse(text, back, &e) == 0, "the normalized form parses: %s", e.message);
    CHECK(lc_request_layer_count(back) == 2 && memcmp(back->layers->p, r->layers->p, 2 * sizeof r->layers->p[0]) == 0 &&
              memcmp(back->layers->dataset, r->layers->dataset, 2 * sizeof r->layers->dataset[0]) == 0,
          "the normalized form gives back equal layers: %s", text ? text : "(none)");
    free(text);
    json_decref(j);
    lc_request_release(back);

    /* [] goes back to the single dataset. */
    json_t *update = json_loads("{\"layers\": []}", 0, NULL);
    CHECK(lc_proto_apply_request(update, NULL, r, &e) == 0 && !r->layers, "layers [] -> no layers");
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
    CHECK(parse(sections, r, &e) == 0 && r->layers->p[0].color.equalize && r->layers->p[0].clusters.count == 7 &&
              r->layers->p[0].time.has_window && r->layers->p[0].time.window[1] == 2 &&
              r->layers->p[0].filter_count == 1 && r->layers->p[0].filters[0].lo == 0.5,
          "a layer's equalize, clusters, time window and filter parse: %s", e.message);
    lc_request_release(r);
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
    CHECK(lc_proto_apply_query(r, "layers", "[{\"dataset\": \"demo:points\"}]", NULL, &e) == 0 &&
              lc_request_layer_count(r) == 1,
          "query layers=[...]: %s", e.message);
    lc_request_release(r);
    check_sharing();
    check_threads();
    return lc_test_finish();
}
