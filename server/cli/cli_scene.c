/* The scene a command renders: one dataset, or the datasets of the request's
 * layers[] (docs/ALGORITHM.md §24) drawn in one frame as POST /api/v1/render
 * draws them (lc_render_layers over the layers' uploaded scenes). */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "frame_check.h"
#include "memory.h"
#include "request_check.h"

/* Loads layer i's dataset spec (demo:NAME[?count=N&seed=S] or a file) with
 * --elements applied; errors name layers[i].dataset, as the daemon's 404. */
static int open_layer(const lc_request *req, const lc_cli_common *common, int i, lc_scene **out, lc_error *err)
{
    const char *spec = req->layers->dataset[i];
    lc_error e = {0};
    int rc = lc_cli_open_dataset(spec, out, &e);
    if (rc == 0 && common->elements)
        rc = lc_scene_set_element_budget(*out, (uint32_t)common->elements, &e);
    if (rc == 0)
        return 0;
    char field[32];
    snprintf(field, sizeof field, "layers[%d].dataset", i);
    return lc_err_field(err, rc, field, "cannot open \"%.300s\": %.400s", spec, e.msg);
}

/* --max-memory over every layer's dataset together (the daemon's budget
 * counts every dataset it serves). */
static int check_memory(const lc_cli_scene *s, const lc_cli_common *common, lc_error *err)
{
    if (!common->max_memory)
        return 0;
    lc_gpu_scene_desc desc = {.exact_positions = common->exact_positions};
    uint64_t need = 0;
    for (int i = 0; i < s->count; i++)
        need += lc_memory_estimate(s->scenes[i], &desc, 1, 1);
    if (need <= common->max_memory)
        return 0;
    return lc_err_field(err, LC_ERR_LIMIT, "layers",
                        "the %d datasets need an estimated %.1f MB resident, over --max-memory %.1f MB", s->count,
                        need / 1e6, common->max_memory / 1e6);
}

/* What the daemon refuses of a request when it arrives (admit.h), refused
 * here before the first frame: a field where it does not apply, what the
 * renderer refuses of it on these scenes. */
static int admit(const char *cmd, const lc_request *req, const lc_cli_scene *s)
{
    unsigned prims = 0;
    for (int i = 0; i < s->count; i++)
        prims |= 1u << s->scenes[i]->type;
    lc_proto_error pe;
    if (lc_proto_check_scope(NULL, req, prims, &pe) != 0) {
        fprintf(stderr, "lucent %s: %s\n", cmd, pe.message);
        return 1;
    }
    lc_error err = {0};
    if (lc_render_check((const lc_scene *const *)s->scenes, s->layer_count ? s->layers : NULL,
                        s->layer_count ? s->layer_count : 1, &req->render, 0, &err) != 0) {
        fprintf(stderr, "lucent %s: %s\n", cmd, err.msg);
        return 1;
    }
    return 0;
}

int lc_cli_scene_open(const char *cmd, const lc_request *req, const lc_cli_common *common, lc_cli_scene *out,
                      lc_cli_gl *g)
{
    memset(out, 0, sizeof *out);
    memset(g, 0, sizeof *g);
    if (lc_request_layer_count(req) == 0) { /* one dataset: --input, the request's, or demo:tornado */
        if (lc_cli_open(cmd, req, common, &out->scenes[0], g) != 0)
            return 1;
        out->count = 1;
        if (admit(cmd, req, out) == 0 && lc_cli_upload(cmd, common, out->scenes[0], &out->gpu[0]) == 0)
            return 0;
        lc_cli_scene_close(out, g);
        return 1;
    }
    lc_error err = {0};
    int rc = 0;
    if (common->input || common->dataset_set) /* every flag used or refused */
        rc = lc_err_field(&err, LC_ERR_INVALID, "layers", "%s names one dataset; the request's layers name theirs",
                          common->input ? "--input" : "--dataset");
    out->layer_count = lc_request_layer_count(req);
    out->layers = req->layers ? req->layers->p : NULL;
    for (int i = 0; rc == 0 && i < lc_request_layer_count(req); i++) {
        rc = open_layer(req, common, i, &out->scenes[i], &err);
        out->count += rc == 0;
    }
    if (rc == 0)
        rc = check_memory(out, common, &err);
    if (rc == 0 && admit(cmd, req, out) != 0) {
        lc_cli_scene_close(out, g);
        return 1;
    }
    if (rc == 0)
        rc = lc_cli_gl_open(common->device, g, &err);
    if (rc != 0) {
        fprintf(stderr, "lucent %s: %s\n", cmd, err.msg);
        lc_cli_scene_close(out, g);
        return 1;
    }
    lc_gpu_scene_desc desc = {.exact_positions = common->exact_positions};
    for (int i = 0; i < out->count; i++) {
        /* The layers' scenes are uploaded as the daemon uploads a dataset; the
         * CPU vertex arrays go once their GPU copy holds them. */
        if (lc_gpu_scene_create_ex(out->scenes[i], &desc, &out->gpu[i], &err) != 0) {
            fprintf(stderr, "lucent %s: layers[%d].dataset: %s\n", cmd, i, err.msg);
            lc_cli_scene_close(out, g);
            return 1;
        }
        lc_scene_release_vertex_arrays(out->scenes[i]);
    }
    lc_memory_trim();
    return 0;
}

int lc_cli_scene_render(lc_renderer *r, const lc_cli_scene *s, const lc_render_params *p, lc_frame_state *state,
                        double dt, uint8_t *rgba, lc_frame_info *info, lc_error *err)
{
    if (s->layer_count == 0)
        return lc_render_frame(r, s->gpu[0], p, state, dt, rgba, info, err);
    return lc_render_layers(r, (const lc_gpu_scene *const *)s->gpu, s->layers, s->layer_count, p, state, dt, rgba, info,
                            err);
}

uint64_t lc_cli_scene_elements(const lc_cli_scene *s)
{
    uint64_t n = 0;
    for (int i = 0; i < s->count; i++)
        n += s->scenes[i]->elements.count;
    return n;
}

uint64_t lc_cli_scene_primitives(const lc_cli_scene *s)
{
    uint64_t n = 0;
    for (int i = 0; i < s->count; i++)
        n += lc_scene_primitive_count(s->scenes[i]);
    return n;
}

const char *lc_cli_scene_name(const lc_cli_scene *s, char *buf, size_t cap)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < s->count && used < cap; i++) {
        int k = snprintf(buf + used, cap - used, "%s%s", i ? " + " : "", s->scenes[i]->name);
        used += k > 0 ? (size_t)k : 0;
    }
    return buf;
}

void lc_cli_scene_camera(const lc_cli_scene *s, lc_camera *cam)
{
    lc_render_fit_camera((const lc_gpu_scene *const *)s->gpu, s->count, cam);
}

void lc_cli_scene_close(lc_cli_scene *s, lc_cli_gl *g)
{
    for (int i = 0; i < s->count; i++)
        lc_gpu_scene_destroy(s->gpu[i]);
    lc_cli_gl_close(g);
    for (int i = 0; i < LC_MAX_LAYERS; i++)
        lc_scene_destroy(s->scenes[i]);
    memset(s, 0, sizeof *s);
}
