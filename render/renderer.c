/* Frame renderer: Fourier opacity optimization passes P1..P6 and the opaque,
 * direct and WBOIT baselines on one GL context (DESIGN §3). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "colormap.h"
#include "embedded.h"
#include "foo_math.h"
#include "renderer_internal.h"

#define MODULE "render"

/* ------------------------------------------------------------------ names */

const char *lc_pass_name(int pass)
{
    static const char *names[LC_PASS_COUNT] = {"importance", "opacity", "smooth",   "opticalDepth",
                                               "accumulate", "resolve", "readback", "depthRange"};
    return pass >= 0 && pass < LC_PASS_COUNT ? names[pass] : "unknown";
}

/* ---------------------------------------------------------------- shaders */

static char *concat_sources(const char *defines, const char *const *files, lc_error *err)
{
    size_t total = strlen(defines) + 64;
    for (int i = 0; files[i]; i++) {
        const lc_embedded_file *f = lc_embedded_find(lc_shader_files, files[i]);
        if (!f) {
            lc_err(err, LC_ERR_INTERNAL, "shader file %s is not embedded", files[i]);
            return NULL;
        }
        total += f->size + 32;
    }
    char *src = malloc(total);
    if (!src) {
        lc_err(err, LC_ERR_NOMEM, "out of memory");
        return NULL;
    }
    size_t off = (size_t)sprintf(src, "#version 450 core\n%s", defines);
    for (int i = 0; files[i]; i++) {
        const lc_embedded_file *f = lc_embedded_find(lc_shader_files, files[i]);
        off += (size_t)sprintf(src + off, "#line 1 %d\n", i + 1);
        memcpy(src + off, f->data, f->size);
        off += f->size;
        src[off++] = '\n';
    }
    src[off] = '\0';
    return src;
}

static GLuint compile_stage(GLenum type, const char *defines, const char *const *files, const char *label,
                            lc_error *err)
{
    /* normalized_depth() reads the per-pixel range only where gl_FragCoord exists. */
    char stage_defines[512];
    snprintf(stage_defines, sizeof stage_defines, "%s%s", defines,
             type == GL_FRAGMENT_SHADER ? "#define FRAGMENT_STAGE 1\n" : "");
    char *src = concat_sources(stage_defines, files, err);
    if (!src)
        return 0;
    GLuint sh = glCreateShader(type);
    const char *srcs[1] = {src};
    glShaderSource(sh, 1, srcs, NULL);
    glCompileShader(sh);
    free(src);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[LC_ERROR_MSG_LEN];
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        /* "#line 1 N": file N of the list, so the log names the file index. */
        lc_err(err, LC_ERR_GL, "compiling %s (%s): %s", label, files[0], log);
        LC_ERROR(MODULE, "%s", err ? err->msg : log);
        glDeleteShader(sh);
        return 0;
    }
    return sh;
}

GLuint lc_renderer_build_program(const char *defines, const char *const *vertex_files,
                                 const char *const *fragment_files, const char *const *compute_files, const char *label,
                                 lc_error *err)
{
    GLuint prog = glCreateProgram();
    GLuint stages[2] = {0, 0};
    int n = 0;
    if (compute_files) {
        if (!(stages[n++] = compile_stage(GL_COMPUTE_SHADER, defines, compute_files, label, err)))
            goto fail;
    } else {
        if (!(stages[n++] = compile_stage(GL_VERTEX_SHADER, defines, vertex_files, label, err)))
            goto fail;
        if (!(stages[n++] = compile_stage(GL_FRAGMENT_SHADER, defines, fragment_files, label, err)))
            goto fail;
    }
    for (int i = 0; i < n; i++)
        glAttachShader(prog, stages[i]);
    glLinkProgram(prog);
    for (int i = 0; i < n; i++)
        glDeleteShader(stages[i]);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[LC_ERROR_MSG_LEN];
        glGetProgramInfoLog(prog, sizeof log, NULL, log);
        lc_err(err, LC_ERR_GL, "linking %s: %s", label, log);
        LC_ERROR(MODULE, "linking %s: %s", label, log);
        glDeleteProgram(prog);
        return 0;
    }
    return prog;
fail:
    for (int i = 0; i < n; i++)
        if (stages[i])
            glDeleteShader(stages[i]);
    glDeleteProgram(prog);
    return 0;
}

static int pulls_primitives(lc_prim_type prim, int subset) { return prim != LC_PRIM_POINTS && subset > 1; }

GLuint lc_renderer_geometry_program(lc_renderer *r, lc_program_kind kind, lc_prim_type prim, int bands, int subset,
                                    lc_error *err)
{
    int pulled = pulls_primitives(prim, subset);
    GLuint *slot = &r->geometry_programs[kind][prim][bands][pulled];
    if (*slot)
        return *slot;
    static const char *const vs[] = {"common.glsl", "geometry.vert.glsl", NULL};
    static const char *const fs_p1[] = {"common.glsl", "fragment_common.glsl", "coefficient_output.glsl",
                                        "p1_importance.frag.glsl", NULL};
    static const char *const fs_p2[] = {"common.glsl", "fragment_common.glsl", "coefficients.glsl",
                                        "p2_opacity.frag.glsl", NULL};
    static const char *const fs_p4[] = {"common.glsl", "fragment_common.glsl", "coefficient_output.glsl",
                                        "p4_optical_depth.frag.glsl", NULL};
    static const char *const fs_p5[] = {"common.glsl", "fragment_common.glsl", "coefficients.glsl",
                                        "p5_accumulate.frag.glsl", NULL};
    static const char *const fs_opaque[] = {"common.glsl", "fragment_common.glsl", "opaque.frag.glsl", NULL};
    static const char *const fs_wboit[] = {"common.glsl", "fragment_common.glsl", "wboit_accumulate.frag.glsl", NULL};
    static const char *const fs_range[] = {"common.glsl", "fragment_common.glsl", "depth_range.frag.glsl", NULL};
    static const char *const *fs_by_kind[PROG_GEOMETRY_KINDS] = {fs_p1, fs_p2,     fs_p4,    fs_p5,   fs_p4,
                                                                 fs_p5, fs_opaque, fs_wboit, fs_range};
    static const char *kind_names[PROG_GEOMETRY_KINDS] = {"P1",        "P2",     "P4",    "P5",         "P4-direct",
                                                          "P5-direct", "opaque", "wboit", "depth range"};
    int reads_alpha = kind == PROG_P4 || kind == PROG_P5 || kind == PROG_WBOIT;
    int direct = kind == PROG_P4_DIRECT || kind == PROG_P5_DIRECT;
    char defines[256];
    snprintf(defines, sizeof defines, "#define PRIM %d\n#define BANDS %d\n%s%s%s", (int)prim, bands,
             reads_alpha ? "#define READ_ALPHA 1\n" : "", direct ? "#define DIRECT_ALPHA 1\n" : "",
             pulled ? "#define PULL_PRIMITIVES 1\n" : "");
    char label[80];
    snprintf(label, sizeof label, "%s program (%s, m=%d%s)", kind_names[kind], lc_prim_type_name(prim), bands,
             pulled ? ", subset" : "");
    *slot = lc_renderer_build_program(defines, vs, fs_by_kind[kind], NULL, label, err);
    return *slot;
}

static GLuint fixed_program(lc_renderer *r, lc_program_kind kind, lc_error *err)
{
    GLuint *slot = &r->fixed_programs[kind - PROG_GEOMETRY_KINDS];
    if (*slot)
        return *slot;
    static const char *const cs_p3[] = {"p3_smooth.comp.glsl", NULL};
    static const char *const vs_full[] = {"fullscreen.vert.glsl", NULL};
    static const char *const fs_resolve[] = {"p6_resolve.frag.glsl", NULL};
    static const char *const fs_wboit[] = {"wboit_resolve.frag.glsl", NULL};
    if (kind == PROG_P3)
        *slot = lc_renderer_build_program("", NULL, NULL, cs_p3, "P3 smoothing", err);
    else if (kind == PROG_RESOLVE)
        *slot = lc_renderer_build_program("", vs_full, fs_resolve, NULL, "P6 resolve", err);
    else
        *slot = lc_renderer_build_program("", vs_full, fs_wboit, NULL, "WBOIT resolve", err);
    return *slot;
}

/* ------------------------------------------------------------- GPU scene */

static GLuint make_buffer(const void *data, size_t size, uint64_t *bytes)
{
    GLuint b;
    glCreateBuffers(1, &b);
    /* Zero-size storage is invalid; keep one vec4 so a binding is always valid. */
    glNamedBufferStorage(b, size ? (GLsizeiptr)size : 16, size ? data : NULL, 0);
    *bytes += size ? size : 16;
    return b;
}

int lc_gpu_scene_create(const lc_scene *s, lc_gpu_scene **out, lc_error *err)
{
    *out = NULL;
    if (!s->finalized)
        return lc_err(err, LC_ERR_INVALID, "%s: scene is not finalized", s->name);
    lc_gpu_scene *gs = calloc(1, sizeof *gs);
    if (!gs)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    gs->scene = s;
    size_t n = s->vertex_count;
    float *tmp = malloc((n ? n : 1) * 4 * sizeof(float));
    if (!tmp) {
        free(gs);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %zu vertices", s->name, n);
    }
    for (size_t i = 0; i < n; i++) {
        memcpy(tmp + 4 * i, s->positions + 3 * i, 3 * sizeof(float));
        tmp[4 * i + 3] = 1.0f;
    }
    gs->positions = make_buffer(tmp, n * 4 * sizeof(float), &gs->bytes);
    const float *frame = s->type == LC_PRIM_LINES ? s->tangents : s->type == LC_PRIM_TRIANGLES ? s->normals : NULL;
    if (frame) {
        for (size_t i = 0; i < n; i++) {
            memcpy(tmp + 4 * i, frame + 3 * i, 3 * sizeof(float));
            tmp[4 * i + 3] = 0.0f;
        }
        gs->frames = make_buffer(tmp, n * 4 * sizeof(float), &gs->bytes);
    } else {
        gs->frames = make_buffer(NULL, 0, &gs->bytes);
    }
    free(tmp);

    /* Attributes back to back: attribute a of vertex v at a * n + v. */
    size_t na = (size_t)s->attribute_count;
    glCreateBuffers(1, &gs->attributes);
    size_t attr_bytes = na * n * sizeof(float);
    glNamedBufferStorage(gs->attributes, attr_bytes ? (GLsizeiptr)attr_bytes : 16, NULL, GL_DYNAMIC_STORAGE_BIT);
    for (size_t a = 0; a < na; a++)
        glNamedBufferSubData(gs->attributes, (GLintptr)(a * n * sizeof(float)), (GLsizeiptr)(n * sizeof(float)),
                             s->attributes[a].values);
    gs->bytes += attr_bytes ? attr_bytes : 16;
    gs->colors = make_buffer(s->rgb, s->rgb ? n * 3 * sizeof(float) : 0, &gs->bytes);
    gs->vertex_elements = make_buffer(s->elements.vertex_elements, n * 4 * sizeof(uint32_t), &gs->bytes);
    gs->vertex_weights = make_buffer(s->elements.vertex_weights, n * 4 * sizeof(float), &gs->bytes);

    if (s->type == LC_PRIM_LINES) {
        uint64_t segs = lc_scene_primitive_count(s);
        uint32_t *idx = malloc((segs ? segs : 1) * 2 * sizeof(uint32_t));
        if (!idx) {
            lc_gpu_scene_destroy(gs);
            return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for segments", s->name);
        }
        uint64_t k = 0;
        for (uint32_t l = 0; l < s->line_count; l++)
            for (uint32_t v = s->line_offsets[l]; v + 1 < s->line_offsets[l + 1]; v++) {
                idx[2 * k] = v;
                idx[2 * k + 1] = v + 1;
                k++;
            }
        gs->indices = make_buffer(idx, k * 2 * sizeof(uint32_t), &gs->bytes);
        gs->primitive_count = k;
        /* Indexed ribbons: vertex 2v / 2v+1 are the two sides at line vertex v. */
        uint32_t *quads = realloc(idx, (k ? k : 1) * 6 * sizeof(uint32_t));
        if (!quads) {
            free(idx);
            lc_gpu_scene_destroy(gs);
            return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for segments", s->name);
        }
        for (uint64_t j = k; j-- > 0;) { /* backwards: pairs live in the first 2k slots */
            uint32_t a = 2 * quads[2 * j], b = 2 * quads[2 * j + 1];
            uint32_t q[6] = {a, a + 1, b, a + 1, b + 1, b};
            memcpy(quads + 6 * j, q, sizeof q);
        }
        gs->draw_indices = make_buffer(quads, k * 6 * sizeof(uint32_t), &gs->bytes);
        free(quads);
    } else if (s->type == LC_PRIM_TRIANGLES) {
        gs->indices = make_buffer(s->triangles, (size_t)s->triangle_count * 3 * sizeof(uint32_t), &gs->bytes);
        gs->draw_indices = gs->indices; /* the same buffer serves both bindings */
        gs->primitive_count = s->triangle_count;
    } else {
        gs->indices = make_buffer(NULL, 0, &gs->bytes);
        gs->primitive_count = n;
    }
    uint32_t ne = s->elements.count;
    gs->adj_offsets = make_buffer(s->elements.adjacency_offsets, ((size_t)ne + 1) * sizeof(uint32_t), &gs->bytes);
    gs->adj = make_buffer(s->elements.adjacency, (size_t)s->elements.adjacency_count * sizeof(uint32_t), &gs->bytes);
    /* Other contexts of the share group may use the buffers right away. */
    glFinish();
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        lc_gpu_scene_destroy(gs);
        return lc_err(err, LC_ERR_GL, "%s: uploading the scene failed (GL error 0x%04x; out of GPU memory?)", s->name,
                      e);
    }
    *out = gs;
    return 0;
}

void lc_gpu_scene_destroy(lc_gpu_scene *gs)
{
    if (!gs)
        return;
    GLuint bufs[] = {gs->positions,
                     gs->frames,
                     gs->attributes,
                     gs->colors,
                     gs->vertex_elements,
                     gs->vertex_weights,
                     gs->indices,
                     gs->adj_offsets,
                     gs->adj,
                     gs->draw_indices != gs->indices ? gs->draw_indices : 0};
    glDeleteBuffers(sizeof bufs / sizeof bufs[0], bufs);
    free(gs);
}

const lc_scene *lc_gpu_scene_source(const lc_gpu_scene *gs) { return gs->scene; }
uint64_t lc_gpu_scene_bytes(const lc_gpu_scene *gs) { return gs->bytes; }

/* ------------------------------------------------------------ frame state */

struct lc_frame_state {
    uint32_t count;
    int fresh;
    float *alpha;
};

lc_frame_state *lc_frame_state_create(uint32_t element_count)
{
    lc_frame_state *st = calloc(1, sizeof *st);
    if (!st)
        return NULL;
    st->count = element_count;
    st->alpha = malloc((element_count ? element_count : 1) * sizeof(float));
    if (!st->alpha) {
        free(st);
        return NULL;
    }
    lc_frame_state_reset(st);
    return st;
}

void lc_frame_state_destroy(lc_frame_state *st)
{
    if (st) {
        free(st->alpha);
        free(st);
    }
}

void lc_frame_state_reset(lc_frame_state *st)
{
    st->fresh = 1;
    for (uint32_t i = 0; i < st->count; i++)
        st->alpha[i] = 1.0f;
}

uint64_t lc_frame_state_bytes(const lc_frame_state *st) { return sizeof *st + (uint64_t)st->count * sizeof(float); }
const float *lc_frame_state_alphas(const lc_frame_state *st) { return st->alpha; }

/* --------------------------------------------------------------- targets */

static uint64_t texel_bytes(GLenum format)
{
    return format == GL_RGBA32F ? 16u : format == GL_RGBA16F || format == GL_RG32F ? 8u : 4u;
}

void lc_targets_free(lc_targets *t, uint64_t *bytes)
{
    if (t->fbo)
        glDeleteFramebuffers(1, &t->fbo);
    if (t->count)
        glDeleteTextures(t->count, t->tex);
    uint64_t px = (uint64_t)t->width * (uint64_t)t->height;
    *bytes -= px * (uint64_t)t->count * texel_bytes(t->format);
    memset(t, 0, sizeof *t);
}

void lc_targets_ensure(lc_targets *t, int w, int h, int count, GLenum format, uint64_t *bytes)
{
    if (t->fbo && t->width == w && t->height == h && t->count == count && t->format == format)
        return;
    lc_targets_free(t, bytes);
    t->width = w, t->height = h, t->count = count, t->format = format;
    glCreateFramebuffers(1, &t->fbo);
    glCreateTextures(GL_TEXTURE_2D, count, t->tex);
    GLenum draw[LC_MAX_COEF_TARGETS];
    for (int i = 0; i < count; i++) {
        glTextureStorage2D(t->tex[i], 1, format, w, h);
        glTextureParameteri(t->tex[i], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(t->tex[i], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glNamedFramebufferTexture(t->fbo, GL_COLOR_ATTACHMENT0 + i, t->tex[i], 0);
        draw[i] = GL_COLOR_ATTACHMENT0 + i;
    }
    glNamedFramebufferDrawBuffers(t->fbo, count, draw);
    *bytes += (uint64_t)w * (uint64_t)h * (uint64_t)count * texel_bytes(format);
}

static void clear_targets(const lc_targets *t, const float *value)
{
    static const float zero[4] = {0, 0, 0, 0};
    for (int i = 0; i < t->count; i++)
        glClearNamedFramebufferfv(t->fbo, GL_COLOR, i, value ? value : zero);
}

/* -------------------------------------------------------------- renderer */

int lc_renderer_create(const lc_renderer_desc *desc, lc_renderer **out, lc_error *err)
{
    *out = NULL;
    lc_renderer *r = calloc(1, sizeof *r);
    if (!r)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    if (desc)
        r->desc = *desc;
    glCreateVertexArrays(1, &r->vao);
    glGenQueries(LC_PASS_COUNT + 1, r->timer_queries);
    r->dummy_buffer = make_buffer(NULL, 0, &(uint64_t){0});

    r->colormap_count = lc_colormap_count() < 16 ? lc_colormap_count() : 16;
    glCreateTextures(GL_TEXTURE_2D, r->colormap_count, r->colormap_tex);
    for (int i = 0; i < r->colormap_count; i++) {
        const float *table = lc_colormap_table(i);
        uint8_t rgba[256 * 4];
        for (int k = 0; k < 256; k++) {
            for (int c = 0; c < 3; c++) {
                float v = table[3 * k + c];
                rgba[4 * k + c] = (uint8_t)lrintf(255.0f * (v < 0 ? 0 : v > 1 ? 1 : v));
            }
            rgba[4 * k + 3] = 255;
        }
        glTextureStorage2D(r->colormap_tex[i], 1, GL_RGBA8, 256, 1);
        glTextureSubImage2D(r->colormap_tex[i], 0, 0, 0, 256, 1, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
        glTextureParameteri(r->colormap_tex[i], GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(r->colormap_tex[i], GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(r->colormap_tex[i], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(r->colormap_tex[i], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glCreateFramebuffers(1, &r->nofb);
    /* Compile the programs every frame needs now, so shader errors surface at start-up. */
    if (!fixed_program(r, PROG_P3, err) || !fixed_program(r, PROG_RESOLVE, err)) {
        lc_renderer_destroy(r);
        return err ? err->code : LC_ERR_GL;
    }
    *out = r;
    return 0;
}

void lc_renderer_destroy(lc_renderer *r)
{
    if (!r)
        return;
    lc_exact_destroy(r);
    for (int k = 0; k < PROG_GEOMETRY_KINDS; k++)
        for (int p = 0; p < 3; p++)
            for (int b = 0; b <= LC_MAX_BANDS; b++)
                for (int v = 0; v < 2; v++)
                    if (r->geometry_programs[k][p][b][v])
                        glDeleteProgram(r->geometry_programs[k][p][b][v]);
    for (int k = 0; k < PROG_FIXED_KINDS - PROG_GEOMETRY_KINDS; k++)
        if (r->fixed_programs[k])
            glDeleteProgram(r->fixed_programs[k]);
    uint64_t b = 0;
    lc_targets_free(&r->coef_low, &b);
    lc_targets_free(&r->coef_full, &b);
    lc_targets_free(&r->accum, &b);
    lc_targets_free(&r->output, &b);
    lc_targets_free(&r->range_full, &b);
    lc_targets_free(&r->range_low, &b);
    if (r->output_depth)
        glDeleteRenderbuffers(1, &r->output_depth);
    glDeleteFramebuffers(1, &r->nofb);
    GLuint bufs[] = {r->element_alpha_min, r->element_alpha, r->smooth_a, r->smooth_b, r->stats, r->dummy_buffer};
    for (size_t i = 0; i < sizeof bufs / sizeof bufs[0]; i++)
        if (bufs[i])
            glDeleteBuffers(1, &bufs[i]);
    glDeleteTextures(r->colormap_count, r->colormap_tex);
    glDeleteQueries(LC_PASS_COUNT + 1, r->timer_queries);
    glDeleteVertexArrays(1, &r->vao);
    free(r);
}

uint64_t lc_renderer_bytes(const lc_renderer *r) { return r->bytes_targets + r->bytes_elements; }

static void ensure_element_buffers(lc_renderer *r, uint32_t count)
{
    if (count <= r->element_capacity && r->element_alpha)
        return;
    GLuint *bufs[] = {&r->element_alpha_min, &r->element_alpha, &r->smooth_a, &r->smooth_b};
    for (int i = 0; i < 4; i++) {
        if (*bufs[i])
            glDeleteBuffers(1, bufs[i]);
        glCreateBuffers(1, bufs[i]);
        glNamedBufferStorage(*bufs[i], (GLsizeiptr)(count ? count : 1) * 4, NULL, GL_DYNAMIC_STORAGE_BIT);
    }
    if (!r->stats) {
        glCreateBuffers(1, &r->stats);
        glNamedBufferStorage(r->stats, 16, NULL, GL_DYNAMIC_STORAGE_BIT);
    }
    r->element_capacity = count;
    r->bytes_elements = (uint64_t)(count ? count : 1) * 16 + 16;
}

void lc_renderer_timestamp(lc_renderer *r, int slot)
{
    if (!r->desc.no_timer_queries)
        glQueryCounter(r->timer_queries[slot], GL_TIMESTAMP);
}

/* ------------------------------------------------------------ frame setup */

static int resolve_mapping(lc_frame_setup *fs, lc_error *err)
{
    const lc_render_params *p = fs->params;
    const lc_scene *s = fs->gs->scene;
    const char *imp = p->importance.attribute[0] ? p->importance.attribute : s->default_importance;
    fs->importance_attr = -1;
    fs->importance_range[0] = 0, fs->importance_range[1] = 1;
    if (imp[0]) {
        fs->importance_attr = lc_scene_find_attribute(s, imp);
        if (fs->importance_attr < 0)
            return lc_err(err, LC_ERR_INVALID, "importance.attribute: %s has no attribute \"%s\"", s->name, imp);
        const lc_attribute *a = &s->attributes[fs->importance_attr];
        fs->importance_range[0] = p->importance.has_range ? p->importance.range[0] : a->min;
        fs->importance_range[1] = p->importance.has_range ? p->importance.range[1] : a->max;
    }
    fs->importance_exponent = p->importance.exponent > 0 ? p->importance.exponent : 1.0;

    const char *col = p->color.attribute[0] ? p->color.attribute : s->default_color;
    if (!col[0])
        col = "importance";
    fs->color_attr = -1;
    fs->color_range[0] = 0, fs->color_range[1] = 1;
    if (strcmp(col, "rgb") == 0) {
        if (!s->rgb)
            return lc_err(err, LC_ERR_INVALID, "color.attribute: %s has no per-vertex RGB", s->name);
        fs->color_mode = 2;
    } else if (strcmp(col, "importance") == 0) {
        fs->color_mode = 1;
    } else {
        fs->color_attr = lc_scene_find_attribute(s, col);
        if (fs->color_attr < 0)
            return lc_err(err, LC_ERR_INVALID, "color.attribute: %s has no attribute \"%s\"", s->name, col);
        fs->color_mode = 0;
        fs->color_range[0] = s->attributes[fs->color_attr].min;
        fs->color_range[1] = s->attributes[fs->color_attr].max;
    }
    if (p->color.has_range)
        fs->color_range[0] = p->color.range[0], fs->color_range[1] = p->color.range[1];
    fs->colormap = lc_colormap_find(p->color.colormap[0] ? p->color.colormap : "viridis");
    if (fs->colormap < 0)
        return lc_err(err, LC_ERR_INVALID, "color.colormap: unknown colormap \"%s\"", p->color.colormap);
    return 0;
}

static void set_f(GLuint prog, const char *name, double v)
{
    glProgramUniform1f(prog, glGetUniformLocation(prog, name), (float)v);
}
static void set_i(GLuint prog, const char *name, int v)
{
    glProgramUniform1i(prog, glGetUniformLocation(prog, name), v);
}
static void set_u(GLuint prog, const char *name, unsigned v)
{
    glProgramUniform1ui(prog, glGetUniformLocation(prog, name), v);
}
static void set_v2(GLuint prog, const char *name, double a, double b)
{
    glProgramUniform2f(prog, glGetUniformLocation(prog, name), (float)a, (float)b);
}
static void set_v3(GLuint prog, const char *name, const double *v)
{
    glProgramUniform3f(prog, glGetUniformLocation(prog, name), (float)v[0], (float)v[1], (float)v[2]);
}

void lc_renderer_bind_geometry(lc_renderer *r, GLuint prog, const lc_frame_setup *fs, int w, int h, int subset)
{
    const lc_gpu_scene *gs = fs->gs;
    const lc_view *v = &fs->view;
    const lc_render_params *p = fs->params;
    glUseProgram(prog);
    glBindVertexArray(r->vao);
    glVertexArrayElementBuffer(r->vao, gs->draw_indices);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_POSITIONS, gs->positions);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAMES, gs->frames);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ATTRIBUTES, gs->attributes);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_COLORS, gs->colors);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_VERTEX_ELEMENTS, gs->vertex_elements);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_VERTEX_WEIGHTS, gs->vertex_weights);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_INDICES, gs->indices);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_ALPHA_MIN, r->element_alpha_min);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_ALPHA, r->element_alpha);
    glBindTextureUnit(0, r->colormap_tex[fs->colormap < r->colormap_count ? fs->colormap : 0]);

    glProgramUniformMatrix4fv(prog, glGetUniformLocation(prog, "u_view"), 1, GL_FALSE, v->view);
    glProgramUniformMatrix4fv(prog, glGetUniformLocation(prog, "u_view_proj"), 1, GL_FALSE, v->view_proj);
    set_v3(prog, "u_eye", v->eye);
    set_v3(prog, "u_view_dir", v->dir);
    set_i(prog, "u_ortho", p->camera.parallel_projection ? 1 : 0);
    set_v2(prog, "u_viewport", w, h);
    /* Pixel size scales with this pass's resolution relative to the output. */
    set_f(prog, "u_pixel_world", v->pixel_world * (double)fs->height / h);
    double focal = 0;
    for (int i = 0; i < 3; i++)
        focal += (fs->params->camera.focal_point[i] - v->eye[i]) * v->dir[i];
    set_f(prog, "u_focal_dist", focal > 0 ? focal : 1);
    set_f(prog, "u_line_half_width", fs->line_half_width);
    set_f(prog, "u_min_half_pixels", 0.5 * (p->style.min_line_pixels > 0 ? p->style.min_line_pixels : 1.0));
    /* A disc of radius >= sqrt(2)/2 px always covers a pixel centre, so every
     * point reaches P2 even at the reduced optimization resolution. */
    double radius = 0.5 * p->style.point_size * (double)h / fs->height;
    set_f(prog, "u_point_radius_px", radius > 0.75 ? radius : 0.75);
    set_u(prog, "u_vertex_count", gs->scene->vertex_count);
    set_u(prog, "u_subset", (unsigned)(subset > 0 ? subset : 1));
    set_i(prog, "u_importance_attr", fs->importance_attr);
    set_v2(prog, "u_importance_range", fs->importance_range[0], fs->importance_range[1]);
    set_f(prog, "u_importance_exp", fs->importance_exponent);
    set_i(prog, "u_color_mode", fs->color_mode);
    set_i(prog, "u_color_attr", fs->color_attr);
    set_v2(prog, "u_color_range", fs->color_range[0], fs->color_range[1]);
    set_i(prog, "u_shading", p->style.shading == LC_SHADING_NONE ? 1 : 0);
    set_v2(prog, "u_depth_range", v->depth_min, v->depth_max);
    /* Per pixel, the nearest and farthest fragment sit at d = 1/4 and 3/4: half a
     * period apart both ways, where the truncated series of one step is exact at
     * the other for every m (its error sum_{k>m} sin(2 pi k x)/(pi k) vanishes at
     * x = 1/2), so the ends of a pixel's stack cannot disturb each other. */
    set_f(prog, "u_depth_margin", fs->pixel_depth_range ? LC_PIXEL_DEPTH_MARGIN : p->foo.depth_margin);
    set_i(prog, "u_pixel_depth_range", fs->pixel_depth_range);
    if (fs->pixel_depth_range)
        glBindTextureUnit(6, w == fs->width && h == fs->height ? r->range_full.tex[0] : r->range_low.tex[0]);
    glViewport(0, 0, w, h);
}

void lc_renderer_draw_geometry(const lc_frame_setup *fs, int subset)
{
    const lc_gpu_scene *gs = fs->gs;
    lc_prim_type prim = gs->scene->type;
    uint64_t n = gs->primitive_count;
    uint64_t step = subset > 0 ? (uint64_t)subset : 1;
    uint64_t drawn = (n + step - 1) / step;
    if (!drawn)
        return;
    if (prim == LC_PRIM_POINTS)
        glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)drawn);
    else if (pulls_primitives(prim, subset))
        glDrawArrays(GL_TRIANGLES, 0, (GLsizei)(drawn * (prim == LC_PRIM_TRIANGLES ? 3u : 6u)));
    else
        glDrawElements(GL_TRIANGLES, (GLsizei)(n * (prim == LC_PRIM_TRIANGLES ? 3u : 6u)), GL_UNSIGNED_INT, NULL);
}

static void bind_coefficients(const lc_targets *t)
{
    for (int i = 0; i < LC_MAX_COEF_TARGETS; i++)
        glBindTextureUnit(1 + i, t->tex[i < t->count ? i : 0]);
}

/* Additive float blending for the accumulation passes. */
static void additive_blending(void)
{
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE);
}

int lc_renderer_smooth_and_fade(lc_renderer *r, const lc_frame_setup *fs, lc_frame_state *state, double dt,
                                lc_frame_info *info, lc_error *err)
{
    const lc_scene *s = fs->gs->scene;
    uint32_t count = s->elements.count;
    GLuint prog = fixed_program(r, PROG_P3, err);
    if (!prog)
        return LC_ERR_GL;
    int one_shot = !state || state->fresh;
    double fade = one_shot ? 1.0 : lc_foo_fade_factor(dt, fs->params->foo.fade_half_life);
    if (state && !state->fresh)
        glNamedBufferSubData(r->element_alpha, 0, (GLsizeiptr)count * 4, state->alpha);
    else {
        const float one = 1.0f;
        glClearNamedBufferData(r->element_alpha, GL_R32F, GL_RED, GL_FLOAT, &one);
    }
    const uint32_t zero = 0;
    glClearNamedBufferData(r->stats, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

    glUseProgram(prog);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_ALPHA_MIN, r->element_alpha_min);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_ALPHA, r->element_alpha);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ADJ_OFFSETS, fs->gs->adj_offsets);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ADJ, fs->gs->adj);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_STATS, r->stats);
    set_u(prog, "u_count", count);
    set_f(prog, "u_omega", fs->params->foo.smoothing_weight);
    set_f(prog, "u_fade", fade);
    GLuint groups = (count + 255) / 256;
    GLuint src = r->smooth_a, dst = r->smooth_b;
    /* Stage 0 writes the targets into dst; then ping-pong. */
    set_i(prog, "u_stage", 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SMOOTH_SRC, dst);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SMOOTH_DST, src);
    if (groups)
        glDispatchCompute(groups, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    set_i(prog, "u_stage", 1);
    int iterations = fs->params->foo.smoothing > 0 ? fs->params->foo.smoothing : 0;
    for (int i = 0; i < iterations && s->elements.adjacency_count > 0; i++) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SMOOTH_SRC, src);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SMOOTH_DST, dst);
        if (groups)
            glDispatchCompute(groups, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        GLuint t = src;
        src = dst, dst = t;
    }
    set_i(prog, "u_stage", 2);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SMOOTH_SRC, src);
    if (groups)
        glDispatchCompute(groups, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

    if (state) {
        glGetNamedBufferSubData(r->element_alpha, 0, (GLsizeiptr)count * 4, state->alpha);
        state->fresh = 0;
    }
    uint32_t bits = 0;
    glGetNamedBufferSubData(r->stats, 0, 4, &bits);
    float change;
    memcpy(&change, &bits, 4);
    if (info) {
        info->max_alpha_change = one_shot ? 0.0 : change;
        info->converged = info->max_alpha_change < LC_CONVERGED_EPSILON;
    }
    return 0;
}

void lc_renderer_readback(lc_renderer *r, const lc_frame_setup *fs, uint8_t *rgba)
{
    int w = fs->width, h = fs->height;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->output.fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    /* GL rows run bottom-up; images top-down. */
    size_t row = (size_t)w * 4;
    uint8_t *tmp = malloc(row);
    if (tmp) {
        for (int y = 0; y < h / 2; y++) {
            memcpy(tmp, rgba + (size_t)y * row, row);
            memcpy(rgba + (size_t)y * row, rgba + (size_t)(h - 1 - y) * row, row);
            memcpy(rgba + (size_t)(h - 1 - y) * row, tmp, row);
        }
        free(tmp);
    }
}

/* The RGBA8 image every method ends in; a depth buffer only for the opaque
 * baseline (the order-independent methods never depth-test). */
static void ensure_output(lc_renderer *r, int w, int h, int with_depth)
{
    lc_targets_ensure(&r->output, w, h, 1, GL_RGBA8, &r->bytes_targets);
    if (!with_depth || (r->output_depth && r->depth_width == w && r->depth_height == h))
        return;
    if (r->output_depth) {
        glDeleteRenderbuffers(1, &r->output_depth);
        r->bytes_targets -= (uint64_t)r->depth_width * r->depth_height * 4;
    }
    glCreateRenderbuffers(1, &r->output_depth);
    glNamedRenderbufferStorage(r->output_depth, GL_DEPTH_COMPONENT24, w, h);
    glNamedFramebufferRenderbuffer(r->output.fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->output_depth);
    r->depth_width = w, r->depth_height = h;
    r->bytes_targets += (uint64_t)w * h * 4;
}

static void resolve_pass(lc_renderer *r, const lc_frame_setup *fs, lc_program_kind kind, const lc_targets *a,
                         GLuint second_tex, lc_error *err)
{
    GLuint prog = fixed_program(r, kind, err);
    if (!prog)
        return;
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->output.fbo);
    glViewport(0, 0, fs->width, fs->height);
    glUseProgram(prog);
    glBindVertexArray(r->vao);
    glBindTextureUnit(0, a->tex[0]);
    glBindTextureUnit(1, second_tex);
    set_v3(prog, "u_background", fs->params->style.background);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

/* Draws the (z, -z) GL_MIN pass of P0 into one range target. */
static void draw_depth_range(lc_renderer *r, lc_frame_setup *fs, GLuint prog, lc_targets *t, int w, int h)
{
    lc_targets_ensure(t, w, h, 1, GL_RG32F, &r->bytes_targets);
    const float empty[4] = {1e30f, 1e30f, 0, 0};
    clear_targets(t, empty);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->fbo);
    lc_renderer_bind_geometry(r, prog, fs, w, h, 1);
    lc_renderer_draw_geometry(fs, 1);
}

/* P0: per-pixel depth ranges, drawn at both resolutions so that each pass sees
 * exactly the fragments its own rasterization produces (a range reduced from
 * full resolution misses thin geometry that is wider at the optimization
 * resolution, and a fragment outside its range would wrap to the periodic
 * ends). Afterwards every geometry pass normalizes depth by its pixel's range. */
static int depth_range_pass(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    GLuint prog = lc_renderer_geometry_program(r, PROG_DEPTH_RANGE, fs->gs->scene->type, 1, 1, err);
    if (!prog)
        return LC_ERR_GL;
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_MIN);
    fs->pixel_depth_range = 0; /* this pass itself uses nothing per pixel */
    draw_depth_range(r, fs, prog, &r->range_full, fs->width, fs->height);
    draw_depth_range(r, fs, prog, &r->range_low, fs->low_width, fs->low_height);
    glBlendEquation(GL_FUNC_ADD);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    fs->pixel_depth_range = 1;
    lc_renderer_timestamp(r, LC_PASS_DEPTH_RANGE);
    return 0;
}

/* P1 + P2 (+ P3): element opacities for the frame. */
static int optimize_opacities(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, lc_frame_info *info,
                              lc_error *err)
{
    const lc_render_params *p = fs->params;
    lc_prim_type prim = fs->gs->scene->type;
    int bands = p->foo.bands, ntargets = (2 * bands + 1 + 3) / 4;
    int lw = fs->low_width, lh = fs->low_height;
    GLuint p1 = lc_renderer_geometry_program(r, PROG_P1, prim, bands, p->foo.subset, err);
    GLuint p2 = p1 ? lc_renderer_geometry_program(r, PROG_P2, prim, bands, 1, err) : 0;
    if (!p2)
        return LC_ERR_GL;
    lc_targets_ensure(&r->coef_low, lw, lh, ntargets, GL_RGBA32F, &r->bytes_targets);
    clear_targets(&r->coef_low, NULL);

    /* P1 importance projection. */
    additive_blending();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->coef_low.fbo);
    lc_renderer_bind_geometry(r, p1, fs, lw, lh, p->foo.subset);
    set_f(p1, "u_weight", p->foo.subset > 0 ? p->foo.subset : 1);
    lc_renderer_draw_geometry(fs, p->foo.subset);
    lc_renderer_timestamp(r, LC_PASS_IMPORTANCE);

    /* P2 optimal opacity into the element minimum buffer. */
    const float sentinel = 2.0f; /* > 1: "no fragment this frame" */
    glClearNamedBufferData(r->element_alpha_min, GL_R32F, GL_RED, GL_FLOAT, &sentinel);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glDisable(GL_BLEND);
    if (r->nofb_w != lw || r->nofb_h != lh) {
        glNamedFramebufferParameteri(r->nofb, GL_FRAMEBUFFER_DEFAULT_WIDTH, lw);
        glNamedFramebufferParameteri(r->nofb, GL_FRAMEBUFFER_DEFAULT_HEIGHT, lh);
        r->nofb_w = lw, r->nofb_h = lh;
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->nofb);
    lc_renderer_bind_geometry(r, p2, fs, lw, lh, 1);
    bind_coefficients(&r->coef_low);
    set_f(p2, "u_q", p->foo.q);
    set_f(p2, "u_r", p->foo.r);
    set_f(p2, "u_lambda", p->foo.lambda);
    set_i(p2, "u_estimator", p->foo.estimator == LC_ESTIMATOR_MIDPOINT ? 1 : 0);
    lc_renderer_draw_geometry(fs, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    lc_renderer_timestamp(r, LC_PASS_OPACITY);

    /* P3 smoothing and fading. */
    int rc = lc_renderer_smooth_and_fade(r, fs, state, dt, info, err);
    lc_renderer_timestamp(r, LC_PASS_SMOOTH);
    return rc;
}

/* P4..P6 with the element opacities (or alpha = g^k when direct). */
static int composite_fourier(lc_renderer *r, lc_frame_setup *fs, int direct, lc_error *err)
{
    const lc_render_params *p = fs->params;
    lc_prim_type prim = fs->gs->scene->type;
    int bands = p->foo.bands, ntargets = (2 * bands + 1 + 3) / 4;
    GLuint p4 = lc_renderer_geometry_program(r, direct ? PROG_P4_DIRECT : PROG_P4, prim, bands, p->foo.subset, err);
    GLuint p5 = p4 ? lc_renderer_geometry_program(r, direct ? PROG_P5_DIRECT : PROG_P5, prim, bands, 1, err) : 0;
    if (!p5)
        return LC_ERR_GL;
    lc_targets_ensure(&r->coef_full, fs->width, fs->height, ntargets, GL_RGBA32F, &r->bytes_targets);
    /* Half floats suffice for the weighted sums: the image is their ratio. */
    lc_targets_ensure(&r->accum, fs->width, fs->height, 1, GL_RGBA16F, &r->bytes_targets);
    clear_targets(&r->coef_full, NULL);
    clear_targets(&r->accum, NULL);

    additive_blending();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->coef_full.fbo);
    lc_renderer_bind_geometry(r, p4, fs, fs->width, fs->height, p->foo.subset);
    set_f(p4, "u_weight", p->foo.subset > 0 ? p->foo.subset : 1);
    set_f(p4, "u_direct_exponent", p->foo.direct_exponent);
    lc_renderer_draw_geometry(fs, p->foo.subset);
    lc_renderer_timestamp(r, LC_PASS_OPTICAL_DEPTH);

    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->accum.fbo);
    lc_renderer_bind_geometry(r, p5, fs, fs->width, fs->height, 1);
    bind_coefficients(&r->coef_full);
    set_i(p5, "u_estimator", p->foo.estimator == LC_ESTIMATOR_MIDPOINT ? 1 : 0);
    set_f(p5, "u_direct_exponent", p->foo.direct_exponent);
    lc_renderer_draw_geometry(fs, 1);
    lc_renderer_timestamp(r, LC_PASS_ACCUMULATE);

    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    resolve_pass(r, fs, PROG_RESOLVE, &r->accum, r->coef_full.tex[0], err);
    lc_renderer_timestamp(r, LC_PASS_RESOLVE);
    return 0;
}

static int render_opaque(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    GLuint prog = lc_renderer_geometry_program(r, PROG_OPAQUE, fs->gs->scene->type, 1, 1, err);
    if (!prog)
        return LC_ERR_GL;
    const double *bg = fs->params->style.background;
    const float clear[4] = {(float)bg[0], (float)bg[1], (float)bg[2], 1.0f};
    glClearNamedFramebufferfv(r->output.fbo, GL_COLOR, 0, clear);
    glClearNamedFramebufferfi(r->output.fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->output.fbo);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    lc_renderer_bind_geometry(r, prog, fs, fs->width, fs->height, 1);
    lc_renderer_draw_geometry(fs, 1);
    glDisable(GL_DEPTH_TEST);
    lc_renderer_timestamp(r, LC_PASS_ACCUMULATE);
    return 0;
}

static int render_wboit(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    GLuint prog = lc_renderer_geometry_program(r, PROG_WBOIT, fs->gs->scene->type, 1, 1, err);
    if (!prog)
        return LC_ERR_GL;
    lc_targets_ensure(&r->accum, fs->width, fs->height, 2, GL_RGBA16F, &r->bytes_targets);
    static const float zero[4] = {0, 0, 0, 0}, one[4] = {1, 1, 1, 1};
    glClearNamedFramebufferfv(r->accum.fbo, GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(r->accum.fbo, GL_COLOR, 1, one);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->accum.fbo);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunci(0, GL_ONE, GL_ONE);
    glBlendFunci(1, GL_ZERO, GL_ONE_MINUS_SRC_COLOR);
    lc_renderer_bind_geometry(r, prog, fs, fs->width, fs->height, 1);
    lc_renderer_draw_geometry(fs, 1);
    glBlendFunc(GL_ONE, GL_ONE);
    lc_renderer_timestamp(r, LC_PASS_ACCUMULATE);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    resolve_pass(r, fs, PROG_WBOIT_RESOLVE, &r->accum, r->accum.tex[1], err);
    lc_renderer_timestamp(r, LC_PASS_RESOLVE);
    return 0;
}

static int validate_params(const lc_render_params *p, lc_error *err)
{
    if (p->width < 1 || p->height < 1 || p->width > 16384 || p->height > 16384)
        return lc_err(err, LC_ERR_INVALID, "image size %dx%d is out of range", p->width, p->height);
    if (p->foo.bands < LC_MIN_BANDS || p->foo.bands > LC_MAX_BANDS)
        return lc_err(err, LC_ERR_INVALID, "params.bands: %d is outside 1..8", p->foo.bands);
    if (!(p->foo.resolution_scale > 0 && p->foo.resolution_scale <= 1))
        return lc_err(err, LC_ERR_INVALID, "params.resolutionScale: %g is outside (0, 1]", p->foo.resolution_scale);
    if ((unsigned)p->method >= LC_METHOD_COUNT)
        return lc_err(err, LC_ERR_INVALID, "method: unknown method %d", (int)p->method);
    if (p->has_camera && lc_camera_validate(&p->camera) != 0)
        return lc_err(err, LC_ERR_INVALID, "camera: position, focalPoint and viewUp do not define a view");
    return 0;
}

int lc_render_frame(lc_renderer *r, const lc_gpu_scene *gs, const lc_render_params *params, lc_frame_state *state,
                    double dt, uint8_t *rgba, lc_frame_info *info, lc_error *err)
{
    double t0 = lc_now();
    lc_frame_info local;
    if (!info)
        info = &local;
    memset(info, 0, sizeof *info);
    for (int i = 0; i < LC_PASS_COUNT; i++)
        info->pass_ms[i] = -1;
    int rc = validate_params(params, err);
    if (rc)
        return rc;
    const lc_scene *s = gs->scene;
    if (state && state->count != s->elements.count)
        return lc_err(err, LC_ERR_INVALID, "frame state has %u elements, scene %s has %u", state->count, s->name,
                      s->elements.count);

    lc_render_params p = *params;
    lc_frame_setup fs = {.params = &p, .gs = gs, .width = p.width, .height = p.height};
    if (!p.has_camera) {
        /* The dataset's suggested view, else ParaView's default (-Z, +Y up), fitted to the bounds. */
        p.camera.view_angle = p.camera.view_angle > 0 ? p.camera.view_angle : 30;
        lc_camera_fit(&p.camera, s->bounds, s->has_view ? s->view_direction : NULL, s->has_view ? s->view_up : NULL);
    }
    rc = resolve_mapping(&fs, err);
    if (rc)
        return rc;
    lc_camera_view(&p.camera, s->bounds, (double)p.width / p.height, p.height, &fs.view);
    double diag = 0;
    for (int i = 0; i < 3; i++)
        diag += (s->bounds[i + 3] - s->bounds[i]) * (s->bounds[i + 3] - s->bounds[i]);
    diag = sqrt(diag);
    fs.line_half_width = 0.5 * (p.style.line_width > 0 ? p.style.line_width : 0.004 * diag);
    fs.low_width = (int)ceil(p.width * p.foo.resolution_scale);
    fs.low_height = (int)ceil(p.height * p.foo.resolution_scale);
    if (fs.low_width < 1)
        fs.low_width = 1;
    if (fs.low_height < 1)
        fs.low_height = 1;

    ensure_element_buffers(r, s->elements.count);
    ensure_output(r, p.width, p.height, p.method == LC_METHOD_OPAQUE);
    lc_renderer_timestamp(r, LC_PASS_COUNT);
    info->converged = 1;
    /* The per-pixel depth range serves every method that normalizes depth. */
    int pixel_range = p.foo.depth_range == LC_DEPTH_RANGE_PIXEL &&
                      (p.method == LC_METHOD_FOURIER || p.method == LC_METHOD_DIRECT || p.method == LC_METHOD_WBOIT);
    if (pixel_range && (rc = depth_range_pass(r, &fs, err)) != 0)
        return rc;
    switch (p.method) {
    case LC_METHOD_FOURIER:
        rc = optimize_opacities(r, &fs, state, dt, info, err);
        if (!rc)
            rc = composite_fourier(r, &fs, 0, err);
        break;
    case LC_METHOD_DIRECT: rc = composite_fourier(r, &fs, 1, err); break;
    case LC_METHOD_OPAQUE: rc = render_opaque(r, &fs, err); break;
    case LC_METHOD_WBOIT:
        rc = optimize_opacities(r, &fs, state, dt, info, err);
        if (!rc)
            rc = render_wboit(r, &fs, err);
        break;
    case LC_METHOD_EXACT: rc = lc_render_exact(r, &fs, state, dt, rgba, info, err); break;
    default: rc = lc_err(err, LC_ERR_INVALID, "unknown method");
    }
    if (rc)
        return rc;
    lc_renderer_readback(r, &fs, rgba);
    lc_renderer_timestamp(r, LC_PASS_READBACK);

    /* Timestamps of passes that ran are strictly after the previous slot. */
    if (!r->desc.no_timer_queries) {
        GLuint64 start = 0, prev;
        glGetQueryObjectui64v(r->timer_queries[LC_PASS_COUNT], GL_QUERY_RESULT, &start);
        prev = start;
        static const int order[] = {LC_PASS_DEPTH_RANGE,   LC_PASS_IMPORTANCE, LC_PASS_OPACITY, LC_PASS_SMOOTH,
                                    LC_PASS_OPTICAL_DEPTH, LC_PASS_ACCUMULATE, LC_PASS_RESOLVE, LC_PASS_READBACK};
        int ran[LC_PASS_COUNT] = {0};
        int fourier = p.method == LC_METHOD_FOURIER || p.method == LC_METHOD_WBOIT || p.method == LC_METHOD_EXACT;
        ran[LC_PASS_IMPORTANCE] = ran[LC_PASS_OPACITY] = ran[LC_PASS_SMOOTH] = fourier;
        ran[LC_PASS_OPTICAL_DEPTH] =
            p.method == LC_METHOD_FOURIER || p.method == LC_METHOD_DIRECT || p.method == LC_METHOD_EXACT;
        ran[LC_PASS_ACCUMULATE] = 1;
        ran[LC_PASS_RESOLVE] = p.method != LC_METHOD_OPAQUE;
        ran[LC_PASS_READBACK] = 1;
        ran[LC_PASS_DEPTH_RANGE] = pixel_range;
        for (int i = 0; i < LC_PASS_COUNT; i++) {
            int pass = order[i];
            if (!ran[pass])
                continue;
            GLuint64 t = 0;
            glGetQueryObjectui64v(r->timer_queries[pass], GL_QUERY_RESULT, &t);
            info->pass_ms[pass] = t >= prev ? (double)(t - prev) * 1e-6 : 0.0;
            info->gpu_ms += info->pass_ms[pass];
            prev = t;
        }
    }
    info->width = p.width, info->height = p.height;
    info->camera = p.camera;
    info->element_count = s->elements.count;
    info->pipeline_bytes = lc_renderer_bytes(r);
    info->wall_ms = (lc_now() - t0) * 1e3;
    GLenum e = glGetError();
    if (e != GL_NO_ERROR)
        return lc_err(err, LC_ERR_GL, "OpenGL error 0x%04x during the frame (out of GPU memory?)", e);
    return 0;
}
