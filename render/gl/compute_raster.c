/* The compute rasterizer of the additive passes P4 and P5 (docs/ALGORITHM.md
 * "Compute rasterization"): which path each pass takes on this device, the
 * programs, the per-pixel sums and the two dispatches of a pass. */
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gl_context.h"
#include "renderer_internal.h"

#define MODULE "render"

/* A quad of more pixel rows than this goes to the second dispatch, a work
 * group of its own (raster.comp.glsl): the thin ribbons of dense lines span a
 * few rows, a segment across the view hundreds. */
#define RASTER_LARGE_ROWS 32u
#define RASTER_LARGE_CAPACITY 65535u /* one dispatch's groups along x */
/* Primitives a dispatch: pre-emption (desc.preempted) may end a pass between
 * two, as between the batches of a draw (pipeline.c); llvmpipe runs a
 * dispatch before the call returns. */
#define RASTER_CHUNK (1u << 18)

static atomic_int raster_software = 0;  /* llvmpipe and the like: the fixed pipeline's set-up is serial */
static atomic_int raster_override = -1; /* LUCENT_COMPUTE_RASTER: -1 the rule, 0 drawn, 1 compute */

/* The sums are integer atomics on a storage buffer (fragment_common.glsl
 * raster_add), which every OpenGL 4.5 device has: the path is a choice of
 * speed, never of support. */
void lc_compute_raster_configure(const char *gl_renderer)
{
    int software = lc_gl_renderer_is_software(gl_renderer);
    atomic_store(&raster_software, software);
    const char *e = getenv("LUCENT_COMPUTE_RASTER"); /* 0 / 1: drawn / compute (comparisons, tests) */
    atomic_store(&raster_override, e && (e[0] == '0' || e[0] == '1') ? e[0] - '0' : -1);
}

/* The rule, per pass and primitive type: on a software rasterizer each
 * traversal's vertex shading, set-up and binning run on the calling thread,
 * while a dispatch spreads over the worker threads; there P5 of point splats
 * measured 1.4-3 times as fast computed and P4 as fast, while both of dense
 * thin lines were 1.2-14 times slower (about ten fragments a segment, each a
 * dozen atomic adds in P4, and four corners' vertex work a segment against
 * the strips' two; docs/EVALUATION.md, "The geometry path"). Where a frame's
 * P4 records its fragments (listable: fragment_list.c, frames of millions of
 * fragments), a drawn recording P4 and the walks over its list cost less
 * than both computed passes, points too (a million points at 972x761: 1.6-1.7
 * s a frame against 2.3-2.5). A GPU's hardware rasterizer keeps both until
 * one measures otherwise. Surfaces always draw. */
static int rule(int software, int override, lc_raster_pass pass, lc_prim_type prim, int listable)
{
    (void)pass;
    if (prim == LC_PRIM_TRIANGLES)
        return 0;
    return override >= 0 ? override : software && prim == LC_PRIM_POINTS && !listable;
}

static int rule_path(lc_raster_pass pass, lc_prim_type prim, int listable)
{
    return rule(atomic_load(&raster_software), atomic_load(&raster_override), pass, prim, listable);
}

const char *lc_raster_path_name(const char *gl_renderer, lc_raster_pass pass, lc_prim_type prim)
{
    int software = lc_gl_renderer_is_software(gl_renderer);
    const char *e = getenv("LUCENT_COMPUTE_RASTER");
    int override = e && (e[0] == '0' || e[0] == '1') ? e[0] - '0' : -1;
    return rule(software, override, pass, prim, 0) ? "compute" : "drawn";
}

void lc_renderer_set_raster_path(lc_renderer *r, int path) { r->raster_path = path < 0 ? -1 : path > 0; }

int lc_compute_raster_wanted(const lc_renderer *r, const lc_frame_setup *fs, lc_raster_pass pass, int listable)
{
    int want = r->floor == LC_FLOOR_COMPUTE ? 1
               : r->floor != LC_FLOOR_FULL  ? 0
               : r->raster_path >= 0        ? r->raster_path
                                            : rule_path(pass, fs->gs->scene->type, listable);
    if (!want)
        return 0;
    /* What the compute path does not cover draws as before: surfaces, layered
     * frames (a layer each of its own type), an opaque context's depth test,
     * and the lists of important points or lines that moving frames add to
     * a strided draw. */
    lc_prim_type prim = fs->gs->scene->type;
    if (prim == LC_PRIM_TRIANGLES || fs->layer_count || r->context_layers || fs->kept_points)
        return 0;
    if (prim == LC_PRIM_LINES && fs->kept_line_indices[0] + fs->kept_line_indices[1])
        return 0;
    return 1;
}

static const char *kind_file(lc_program_kind kind)
{
    return kind == PROG_P4 || kind == PROG_P4_DIRECT ? "p4_optical_depth.frag.glsl" : "p5_accumulate.frag.glsl";
}

GLuint lc_compute_raster_program(lc_renderer *r, lc_program_kind kind, lc_prim_type prim, int bands, lc_error *err)
{
    int k = kind == PROG_P4 ? 0 : kind == PROG_P5 ? 1 : kind == PROG_P4_DIRECT ? 2 : kind == PROG_P5_DIRECT ? 3 : -1;
    if (k < 0 || prim == LC_PRIM_TRIANGLES || bands < 1 || bands > LC_MAX_BANDS) {
        lc_err(err, LC_ERR_INTERNAL, "no compute rasterizer for this pass");
        return 0;
    }
    GLuint *slot = &r->raster_programs[k][prim][bands];
    if (*slot)
        return *slot;
    int p4 = k == 0 || k == 2;
    const char *files[] = {"common.glsl",
                           "geometry.vert.glsl",
                           "fragment_common.glsl",
                           p4 ? "coefficient_output.glsl" : "coefficients.glsl",
                           kind_file(kind),
                           "raster.comp.glsl",
                           NULL};
    /* The vertex stage runs as a function (geometry.vert.glsl's main renamed,
     * its built-ins as globals); lines always pull their segments. */
    char defines[640];
    snprintf(defines, sizeof defines,
             "#define PRIM %d\n#define BANDS %d\n"
             "#define READ_ALPHA 1\n%s%s#define RASTER_STAGE 1\n#define FRAGMENT_STAGE 1\n"
             "#define main raster_vertex_main\n#define gl_Position raster_position\n"
             "#define gl_VertexID raster_vertex_id\n#define gl_InstanceID raster_instance_id\n",
             (int)prim, bands, k >= 2 ? "#define DIRECT_ALPHA 1\n" : "",
             prim == LC_PRIM_LINES ? "#define PULL_PRIMITIVES 1\n" : "");
    char label[80];
    snprintf(label, sizeof label, "%s compute rasterizer (%s, m=%d)", p4 ? "P4" : "P5", lc_prim_type_name(prim), bands);
    *slot = lc_renderer_build_program(defines, NULL, NULL, files, label, err);
    return *slot;
}

int lc_compute_raster_begin(lc_renderer *r, int width, int height, int planes, lc_error *err)
{
    uint64_t bytes = (uint64_t)width * (uint64_t)height * (uint64_t)planes * 8u; /* 64-bit fixed point */
    if (bytes > r->raster_sums_bytes) {
        lc_scratch_discard(&r->raster_sums);
        r->bytes_targets -= r->raster_sums_bytes;
        r->raster_sums_bytes = 0;
        r->raster_sums = lc_scratch_buffer(bytes, 0);
        r->bytes_targets += bytes;
        if (!r->raster_sums)
            return lc_err(err, LC_ERR_NOMEM, "compute rasterizer: no buffer of %llu bytes", (unsigned long long)bytes);
        r->raster_sums_bytes = bytes;
    }
    if (!r->raster_large) {
        glCreateBuffers(1, &r->raster_large); /* its header is written before each dispatch */
        glNamedBufferStorage(r->raster_large, 16 + 4 * (GLsizeiptr)RASTER_LARGE_CAPACITY, NULL, GL_DYNAMIC_STORAGE_BIT);
        r->bytes_targets += 16 + 4 * (uint64_t)RASTER_LARGE_CAPACITY;
    }
    const uint32_t zero = 0;
    glClearNamedBufferSubData(r->raster_sums, GL_R32UI, 0, (GLsizeiptr)bytes, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    r->raster_width = width, r->raster_height = height, r->raster_planes = planes;
    return 0;
}

void lc_compute_raster_bind(lc_renderer *r, GLuint prog, const lc_frame_setup *fs, int subset)
{
    /* The quads of the instanced splats, never GL points: the viewport is then the draw's own. */
    lc_frame_setup quads = *fs;
    quads.point_sprites = 0;
    lc_renderer_bind_geometry(r, prog, &quads, r->raster_width, r->raster_height, subset);
    GLint vp[4];
    glGetIntegerv(GL_VIEWPORT, vp);
    glProgramUniform4f(prog, glGetUniformLocation(prog, "u_raster_viewport"), (float)vp[0], (float)vp[1], (float)vp[2],
                       (float)vp[3]);
    glProgramUniform2i(prog, glGetUniformLocation(prog, "u_raster_size"), r->raster_width, r->raster_height);
    lc_uniform_i(prog, "u_raster_planes", r->raster_planes);
    lc_uniform_u(prog, "u_first_primitive", 0);
    lc_uniform_i(prog, "u_raster_pulled", lc_pulls_primitives(fs->gs->scene->type, subset, fs->pull_lines));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_RASTER_SUMS, r->raster_sums);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_RASTER_LARGE, r->raster_large);
}

void lc_compute_raster_dispatch(lc_renderer *r, GLuint prog, const lc_frame_setup *fs, int subset)
{
    const lc_gpu_level *lv = &fs->gs->levels[fs->level];
    uint64_t n = lv->primitive_count;
    if (fs->gs->scene->type == LC_PRIM_LINES)
        n = lv->index_count >= 4 ? lv->index_count / 2 - 1 : 0; /* ribbon slots of the strip */
    uint64_t step = lc_renderer_subset(fs, subset);
    uint64_t count = (n + step - 1) / step, lo, hi;
    lc_progressive_range(fs, count, &lo, &hi); /* params.progressive: the batch's splats (points only, fourier.c) */
    if (lo >= hi || (r->yield_cut))
        return;
    const uint32_t header[4] = {0, 1, 1, 0}; /* the second dispatch's groups, and the entries taken */
    glNamedBufferSubData(r->raster_large, 0, sizeof header, header);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    lc_uniform_u(prog, "u_raster_large_px", RASTER_LARGE_ROWS);
    lc_uniform_u(prog, "u_raster_large_capacity", RASTER_LARGE_CAPACITY);
    lc_uniform_i(prog, "u_raster_large_pass", 0);
    for (uint64_t first = lo; first < hi; first += RASTER_CHUNK) {
        uint64_t end = hi - first < RASTER_CHUNK ? hi : first + RASTER_CHUNK;
        lc_uniform_u(prog, "u_raster_first", (unsigned)first);
        lc_uniform_u(prog, "u_raster_count", (unsigned)end);
        lc_dispatch_linear((GLuint)((end - first + 63) / 64));
        if (hi - lo > RASTER_CHUNK && lc_renderer_batch_yield(fs))
            return; /* the frame ends at the pass's yield point */
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    lc_uniform_i(prog, "u_raster_large_pass", 1);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, r->raster_large);
    glDispatchComputeIndirect(0);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

static int store(lc_renderer *r, const lc_targets *t, int add, lc_error *err)
{
    int half = t->format == GL_RGBA16F;
    GLuint *slot = add ? &r->raster_add_programs[half] : &r->raster_store_program;
    if (!*slot) {
        static const char *const files[] = {"raster_store.comp.glsl", NULL};
        const char *defines = !add ? "" : half ? "#define ADD_FORMAT rgba16f\n" : "#define ADD_FORMAT rgba32f\n";
        *slot = lc_renderer_build_program(defines, NULL, NULL, files, "compute rasterizer store", err);
        if (!*slot)
            return LC_ERR_GL;
    }
    glUseProgram(*slot);
    glProgramUniform2i(*slot, glGetUniformLocation(*slot, "u_raster_size"), r->raster_width, r->raster_height);
    lc_uniform_i(*slot, "u_planes", r->raster_planes);
    lc_uniform_i(*slot, "u_targets", t->count);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_RASTER_SUMS, r->raster_sums);
    for (int i = 0; i < LC_MAX_COEF_TARGETS; i++)
        glBindImageTexture(IMG_COEF_FIRST + i, t->tex[i < t->count ? i : 0], 0, GL_FALSE, 0,
                           add ? GL_READ_WRITE : GL_WRITE_ONLY, t->format);
    uint64_t pixels = (uint64_t)r->raster_width * (uint64_t)r->raster_height;
    lc_dispatch_linear((GLuint)((pixels + 63) / 64));
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    return 0;
}

int lc_compute_raster_end(lc_renderer *r, const lc_targets *t, lc_error *err) { return store(r, t, 0, err); }

int lc_compute_raster_end_add(lc_renderer *r, const lc_targets *t, lc_error *err)
{
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    return store(r, t, 1, err);
}

void lc_compute_raster_release_sums(lc_renderer *r)
{
    lc_scratch_discard(&r->raster_sums);
    r->bytes_targets -= r->raster_sums_bytes;
    r->raster_sums_bytes = 0;
}

void lc_compute_raster_release(lc_renderer *r)
{
    for (int k = 0; k < 4; k++)
        for (int p = 0; p < 2; p++)
            for (int b = 0; b <= LC_MAX_BANDS; b++)
                if (r->raster_programs[k][p][b])
                    glDeleteProgram(r->raster_programs[k][p][b]);
    if (r->raster_store_program)
        glDeleteProgram(r->raster_store_program);
    for (int k = 0; k < 2; k++)
        if (r->raster_add_programs[k])
            glDeleteProgram(r->raster_add_programs[k]);
    if (r->raster_sums)
        glDeleteBuffers(1, &r->raster_sums);
    if (r->raster_large)
        glDeleteBuffers(1, &r->raster_large);
}
