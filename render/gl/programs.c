/* Shader programs: embedded GLSL sources joined with #defines (band count,
 * primitive, binding points), compiled once per variant and cached. */
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "embedded.h"
#include "foo_math.h"
#include "gl_context.h"
#include "renderer_internal.h"

#define MODULE "render"

/* The shader sources, embedded by cmake/embed.cmake. */
extern const lc_embedded_file lc_shader_files[];

#define LC_GL_BINDING_DEFINE(name, value) "#define " #name " " #value "\n"
/* One more level, so that a value given as a macro expands before it is stringized. */
#define LC_GL_FLOAT_DEFINE(name, value) LC_GL_BINDING_DEFINE(name, value)
/* Every program sees the binding points of renderer_internal.h by name, and
 * the float constants it shares with the CPU reference (foo_math.h). */
static const char binding_defines[] = LC_GL_BINDINGS(LC_GL_BINDING_DEFINE) LC_GL_CONSTANTS(LC_GL_BINDING_DEFINE)
    LC_GL_FLOAT_DEFINE(MOMENT_MIN_SPREAD, LC_MOMENT_MIN_SPREAD);
#undef LC_GL_FLOAT_DEFINE
#undef LC_GL_BINDING_DEFINE

/* What every program of this device compiles with: SOFTWARE_GL on llvmpipe
 * (common.glsl's turn_cos_sin). Every worker's renderer sets the same value. */
static atomic_int software_gl;
#define DEVICE_DEFINES (atomic_load(&software_gl) ? "#define SOFTWARE_GL 1\n" : "")

static char *concat_sources(const char *defines, const char *const *files, lc_error *err)
{
    size_t total = sizeof binding_defines + strlen(DEVICE_DEFINES) + strlen(defines) + 64;
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
    size_t off = (size_t)sprintf(src, "#version 450 core\n%s%s%s", binding_defines, DEVICE_DEFINES, defines);
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
    char stage_defines[1280];
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

/* Specialized programs (docs/ALGORITHM.md "Specialized programs"): llvmpipe
 * runs both sides of a branch on a uniform under masks, so the frame's and the
 * scene's values that the shaders branch on are compiled in as macros named
 * like the uniforms they replace (the declarations step aside, common.glsl). The
 * values come from the frame setup the program is bound with, so that
 * lc_renderer_bind_geometry's uniforms and the macros agree (checked there). */
enum {
    SPEC_ON = 1u << 0,
    SPEC_MIDPOINT = 1u << 1,
    SPEC_ORTHO = 1u << 2,
    SPEC_UNSHADED = 1u << 3,
    SPEC_NO_HALO = 1u << 4,
    SPEC_NO_SILHOUETTE = 1u << 5,
    SPEC_PIXEL_RANGE = 1u << 6,
    SPEC_MOMENTS = 1u << 7,
    SPEC_COMPACT = 1u << 8,
    SPEC_BLEND_SHIFT = 9, /* 2 bits: the scene's element blend (lc_gpu_scene.blend) */
    SPEC_FILTERED = 1u << 11,
    SPEC_LINE_MASK = 1u << 12,
    SPEC_COLOR_SHIFT = 13, /* 2 bits: the colour mode */
    SPEC_NO_TERMS = 1u << 15,
    SPEC_NO_CURVES = 1u << 16,
    SPEC_BITS = 17
};

static atomic_int specialize_override = -1; /* LUCENT_SPECIALIZE: 0 off (comparisons); else on */

void lc_programs_configure(const char *gl_renderer)
{
    int software = lc_gl_renderer_is_software(gl_renderer);
    atomic_store(&software_gl, software);
    const char *e = getenv("LUCENT_SPECIALIZE");
    atomic_store(&specialize_override, e && e[0] == '0' ? 0 : -1);
}

void lc_renderer_set_specialize(lc_renderer *r, int on) { r->specialize = on ? 1 : 0; }

/* The spec bits of kind bound with fs; 0: the kind keeps its uniforms (the
 * shadow passes set their own camera and shading after the geometry's). */
static unsigned program_spec(const lc_renderer *r, lc_program_kind kind, const lc_frame_setup *fs)
{
    if (!fs || !r->specialize || atomic_load(&specialize_override) == 0 || kind == PROG_SHADOW ||
        kind == PROG_SHADOW_DIRECT)
        return 0;
    const lc_render_params *p = fs->params;
    return SPEC_ON | (p->foo.estimator == LC_ESTIMATOR_MIDPOINT ? SPEC_MIDPOINT : 0) |
           (p->camera.parallel_projection ? SPEC_ORTHO : 0) |
           (p->style.shading == LC_SHADING_NONE ? SPEC_UNSHADED : 0) | (p->style.halo_width > 0 ? 0 : SPEC_NO_HALO) |
           (p->style.silhouette_exponent > 1 ? 0 : SPEC_NO_SILHOUETTE) |
           (fs->pixel_depth_range ? SPEC_PIXEL_RANGE : 0) | (fs->depth_moments ? SPEC_MOMENTS : 0) |
           (fs->gs->exact ? 0 : SPEC_COMPACT) | ((unsigned)fs->gs->blend & 3u) << SPEC_BLEND_SHIFT |
           (fs->filtered ? SPEC_FILTERED : 0) | (fs->line_mask ? SPEC_LINE_MASK : 0) |
           ((unsigned)fs->color_mode & 3u) << SPEC_COLOR_SHIFT | (fs->terms.count > 0 ? 0 : SPEC_NO_TERMS) |
           (fs->terms.curve_count == 0 && p->color.curve.count == 0 ? SPEC_NO_CURVES : 0);
}

static void spec_defines(unsigned spec, char *out, size_t n)
{
    out[0] = '\0';
    if (!spec)
        return;
    snprintf(out, n,
             "#define u_estimator %d\n#define u_ortho %d\n#define u_shading %d\n#define u_pixel_depth_range %d\n"
             "#define u_depth_moments %d\n#define u_compact %d\n#define u_blend %u\n#define u_filtered %d\n"
             "#define u_line_mask %d\n#define u_color_mode %u\n%s%s%s%s",
             !!(spec & SPEC_MIDPOINT), !!(spec & SPEC_ORTHO), !!(spec & SPEC_UNSHADED), !!(spec & SPEC_PIXEL_RANGE),
             !!(spec & SPEC_MOMENTS), !!(spec & SPEC_COMPACT), spec >> SPEC_BLEND_SHIFT & 3u, !!(spec & SPEC_FILTERED),
             !!(spec & SPEC_LINE_MASK), spec >> SPEC_COLOR_SHIFT & 3u,
             spec & SPEC_NO_HALO ? "#define u_halo_px 0.0\n" : "",
             spec & SPEC_NO_SILHOUETTE ? "#define u_silhouette_exponent 1.0\n" : "",
             spec & SPEC_NO_TERMS ? "#define u_importance_terms 0\n" : "",
             spec & SPEC_NO_CURVES ? "#define u_curve_n ivec2(0, 0)\n" : "");
}

/* The slot of a specialized program: the least recently used one is
 * replaced (a frame binds a handful; sessions change few of the values). */
static lc_spec_program *spec_slot(lc_renderer *r, uint64_t key)
{
    lc_spec_program *oldest = &r->spec_programs[0];
    for (int i = 0; i < LC_SPEC_PROGRAMS; i++) {
        lc_spec_program *e = &r->spec_programs[i];
        if (e->prog && e->key == key) {
            e->used = ++r->spec_clock;
            return e;
        }
        if (!e->prog || (oldest->prog && e->used < oldest->used))
            oldest = e;
    }
    if (oldest->prog)
        glDeleteProgram(oldest->prog);
    *oldest = (lc_spec_program){.key = key, .prog = 0, .used = ++r->spec_clock};
    return oldest;
}

void lc_renderer_check_spec(const lc_renderer *r, GLuint prog, const lc_frame_setup *fs)
{
    for (int i = 0; i < LC_SPEC_PROGRAMS; i++)
        if (r->spec_programs[i].prog == prog) {
            unsigned want = program_spec(r, r->spec_programs[i].kind, fs);
            unsigned built = (unsigned)(r->spec_programs[i].key & ((1u << SPEC_BITS) - 1));
            if (want != built) /* a caller chose the program with another frame setup: fix the caller */
                LC_ERROR(MODULE, "a specialized program (spec %#x) bound with a frame of spec %#x", built, want);
            return;
        }
}

GLuint lc_renderer_geometry_program(lc_renderer *r, const lc_frame_setup *fs, lc_program_kind kind, lc_prim_type prim,
                                    int bands, int subset, lc_error *err)
{
    int pulled = lc_pulls_primitives(prim, subset, r->pull_lines);
    int sprites = prim == LC_PRIM_POINTS && r->point_sprites; /* points never pull: the variant slots share */
    int context = r->context_layers != 0;
    /* lc_renderer_set_floor's empty shaders: a variant of their own, never
     * with a context layer (the floor is measured on plain frames). */
    int floor = r->floor == LC_FLOOR_EMPTY_SHADER && !context;
    int lines = prim == LC_PRIM_LINES && r->line_primitive && !pulled; /* wide line strips (line_primitive.c) */
    int variant = lines ? 2 : pulled | sprites;
    unsigned spec = program_spec(r, kind, fs);
    GLuint *slot = NULL;
    if (spec) {
        uint64_t config = ((((uint64_t)kind * 3 + prim) * (LC_MAX_BANDS + 1) + (uint64_t)bands) * 3 + variant) * 2;
        uint64_t key = ((config + context) * 2 + floor) << SPEC_BITS | spec;
        lc_spec_program *e = spec_slot(r, key);
        e->kind = kind;
        slot = &e->prog;
    } else
        slot = floor ? &r->floor_programs[kind][prim][bands][variant]
                     : &r->geometry_programs[kind][prim][bands][variant][context];
    if (*slot)
        return *slot;
    static const char *const vs[] = {"common.glsl", "geometry.vert.glsl", NULL};
    static const char *const fs_p1[] = {"common.glsl", "fragment_common.glsl", "coefficient_output.glsl",
                                        "p1_importance.frag.glsl", NULL};
    static const char *const fs_p1_list[] = {"common.glsl",        "fragment_common.glsl",    "coefficient_output.glsl",
                                             "fragment_list.glsl", "p1_importance.frag.glsl", NULL};
    static const char *const fs_p2[] = {"common.glsl",
                                        "fragment_common.glsl",
                                        "coefficients.glsl",
                                        "occluders.glsl",
                                        "opacity_common.glsl",
                                        "p2_opacity.frag.glsl",
                                        NULL};
    static const char *const fs_p4[] = {"common.glsl", "fragment_common.glsl", "coefficient_output.glsl",
                                        "p4_optical_depth.frag.glsl", NULL};
    static const char *const fs_p5[] = {"common.glsl", "fragment_common.glsl", "coefficients.glsl",
                                        "p5_accumulate.frag.glsl", NULL};
    static const char *const fs_opaque[] = {"common.glsl", "fragment_common.glsl", "opaque.frag.glsl", NULL};
    static const char *const fs_wboit[] = {"common.glsl", "fragment_common.glsl", "wboit_accumulate.frag.glsl", NULL};
    static const char *const fs_range[] = {"common.glsl", "fragment_common.glsl", "depth_range.frag.glsl", NULL};
    static const char *const fs_moments[] = {"common.glsl", "fragment_common.glsl", "depth_moments.frag.glsl", NULL};
    static const char *const fs_moments_list[] = {"common.glsl", "fragment_common.glsl", "fragment_list.glsl",
                                                  "depth_moments.frag.glsl", NULL};
    static const char *const fs_p4_list[] = {
        "common.glsl",        "fragment_common.glsl",       "coefficient_output.glsl",
        "fragment_list.glsl", "p4_optical_depth.frag.glsl", NULL};
    static const char *const fs_hist[] = {"common.glsl", "fragment_common.glsl", "coefficients.glsl",
                                          "color_histogram.frag.glsl", NULL};
    static const char *const fs_wavg[] = {"common.glsl", "fragment_common.glsl",
                                          "weighted_average_accumulate.frag.glsl", NULL};
    static const char *const fs_kanzler[] = {"common.glsl", "fragment_common.glsl", "kanzler_maps.frag.glsl", NULL};
    static const char *const fs_p4_kanzler[] = {
        "common.glsl",    "fragment_common.glsl",       "coefficient_output.glsl",
        "occluders.glsl", "p4_optical_depth.frag.glsl", NULL};
    static const char *const *fs_by_kind[PROG_GEOMETRY_KINDS] = {
        fs_p1,    fs_p2,      fs_p4,      fs_p5,         fs_p4,      fs_p5,           fs_opaque,  fs_wboit,
        fs_range, fs_moments, fs_hist,    fs_hist,       fs_p1_list, fs_moments_list, fs_p4_list, fs_p4,
        fs_p5,    fs_wavg,    fs_kanzler, fs_p4_kanzler, fs_p5,      fs_p4,           fs_p4};
    static const char *kind_names[PROG_GEOMETRY_KINDS] = {"P1",
                                                          "P2",
                                                          "P4",
                                                          "P5",
                                                          "P4-direct",
                                                          "P5-direct",
                                                          "opaque",
                                                          "wboit",
                                                          "depth range",
                                                          "depth moments",
                                                          "colour histogram",
                                                          "colour histogram (direct)",
                                                          "P1 (recording)",
                                                          "depth moments (recording)",
                                                          "P4 (recording)",
                                                          "P4-binning",
                                                          "P5-binning",
                                                          "weighted average",
                                                          "kanzler maps",
                                                          "P4-kanzler",
                                                          "P5-kanzler",
                                                          "shadow map",
                                                          "shadow map (direct)"};
    int bins = kind == PROG_P4_BINS || kind == PROG_P5_BINS;
    int reads_alpha = kind == PROG_P4 || kind == PROG_P4_LIST || kind == PROG_P5 || kind == PROG_WBOIT ||
                      kind == PROG_COLOR_HISTOGRAM || bins || kind == PROG_WEIGHTED_AVERAGE || kind == PROG_SHADOW;
    int kanzler = kind == PROG_P4_KANZLER || kind == PROG_P5_KANZLER;
    int direct = kind == PROG_P4_DIRECT || kind == PROG_P5_DIRECT || kind == PROG_COLOR_HISTOGRAM_DIRECT || kanzler ||
                 kind == PROG_SHADOW_DIRECT;
    /* The recording passes' chain heads through framebuffer fetch (fragment_list.glsl). */
    int fetch = r->heads_fetch && (kind == PROG_P4_LIST || kind == PROG_DEPTH_MOMENTS_LIST);
    char specialized[512], defines[1000];
    spec_defines(spec, specialized, sizeof specialized);
    snprintf(defines, sizeof defines, "#define PRIM %d\n#define BANDS %d\n%s%s%s%s%s%s%s%s%s%s%s", (int)prim, bands,
             fetch ? "#extension GL_EXT_shader_framebuffer_fetch : enable\n#define HEADS_FETCH 1\n" : "",
             bins ? "#define TAU_BINS " LC_TAU_BINS_TEXT "\n" : "", reads_alpha ? "#define READ_ALPHA 1\n" : "",
             direct ? "#define DIRECT_ALPHA 1\n" : "", pulled ? "#define PULL_PRIMITIVES 1\n" : "",
             sprites ? "#define POINT_SPRITES 1\n" : "", lines ? "#define LINE_PRIMITIVE 1\n" : "",
             context ? "#define CONTEXT_DEPTH 1\n" : "", floor ? "#define FLOOR_EMPTY 1\n" : "",
             kind == PROG_P1_LIST              ? "#define RECORD_FRAGMENTS 1\n"
             : kind == PROG_DEPTH_MOMENTS_LIST ? "#define RECORD_FRAGMENTS 1\n#define FRAGMENT_CHAINS 1\n"
             : kind == PROG_P4_LIST            ? "#define COMPOSITE_LIST 1\n"
             : kind == PROG_KANZLER_MAPS       ? "#define KANZLER_MAPS 1\n"
             : kanzler                         ? "#define KANZLER_PENALTY 1\n"
             : kind == PROG_SHADOW || kind == PROG_SHADOW_DIRECT ? "#define SHADOW_MAP 1\n"
                                                                 : "",
             specialized);
    char label[80];
    snprintf(label, sizeof label, "%s program (%s, m=%d%s%s)", kind_names[kind], lc_prim_type_name(prim), bands,
             lines     ? ", lines"
             : pulled  ? ", subset"
             : sprites ? ", sprites"
                       : "",
             context ? ", context" : "");
    *slot = lc_renderer_build_program(defines, vs, fs_by_kind[kind], NULL, label, err);
    return *slot;
}

void lc_renderer_set_floor(lc_renderer *r, lc_floor_mode mode)
{
    r->floor = mode >= LC_FLOOR_FULL && mode < LC_FLOOR_COUNT ? mode : LC_FLOOR_FULL;
}

const char *lc_floor_mode_name(lc_floor_mode mode)
{
    static const char *names[LC_FLOOR_COUNT] = {"shaded", "empty shader", "no raster", "compute"};
    return mode >= LC_FLOOR_FULL && mode < LC_FLOOR_COUNT ? names[mode] : "unknown";
}

GLuint lc_renderer_fixed_program(lc_renderer *r, lc_program_kind kind, lc_error *err)
{
    GLuint *slot = &r->fixed_programs[kind - PROG_GEOMETRY_KINDS];
    if (*slot)
        return *slot;
    static const char *const cs_p3[] = {"p3_smooth.comp.glsl", NULL};
    static const char *const vs_full[] = {"fullscreen.vert.glsl", NULL};
    static const char *const fs_resolve[] = {"p6_resolve.frag.glsl", NULL};
    static const char *const fs_wboit[] = {"wboit_resolve.frag.glsl", NULL};
    static const char *const fs_wavg[] = {"weighted_average.glsl", "weighted_average_resolve.frag.glsl", NULL};
    static const char *const cs_mass[] = {"mass_common.glsl", "mass_histogram.comp.glsl", NULL};
    static const char *const cs_importance[] = {"common.glsl", "element_importance.comp.glsl", NULL};
    static const char *const cs_points[] = {"common.glsl", "point_select.comp.glsl", NULL};
    static const char *const cs_lines[] = {"common.glsl", "line_select.comp.glsl", NULL};
    static const char *const cs_filter[] = {"common.glsl", "filter_mask.comp.glsl", NULL};
    static const char *const cs_kanzler[] = {"kanzler_blur.comp.glsl", NULL};
    static const char *const cs_reach[] = {"reach_reduce.comp.glsl", NULL};
    if (kind == PROG_P3)
        *slot = lc_renderer_build_program("", NULL, NULL, cs_p3, "P3 smoothing", err);
    else if (kind == PROG_MASS_HISTOGRAM)
        *slot = lc_renderer_build_program("", NULL, NULL, cs_mass, "mass histogram", err);
    else if (kind == PROG_ELEMENT_IMPORTANCE)
        *slot = lc_renderer_build_program("", NULL, NULL, cs_importance, "element importance", err);
    else if (kind == PROG_POINT_SELECT)
        *slot = lc_renderer_build_program("", NULL, NULL, cs_points, "point subset", err);
    else if (kind == PROG_LINE_SELECT)
        *slot = lc_renderer_build_program("", NULL, NULL, cs_lines, "line subset", err);
    else if (kind == PROG_FILTER_MASK)
        *slot = lc_renderer_build_program("", NULL, NULL, cs_filter, "filter mask", err);
    else if (kind == PROG_KANZLER_BLUR)
        *slot = lc_renderer_build_program("", NULL, NULL, cs_kanzler, "kanzler maps blur", err);
    else if (kind == PROG_REACH_REDUCE)
        *slot = lc_renderer_build_program("", NULL, NULL, cs_reach, "topDecileReach sums", err);
    else if (kind == PROG_RESOLVE)
        *slot = lc_renderer_build_program("", vs_full, fs_resolve, NULL, "P6 resolve", err);
    else if (kind == PROG_WEIGHTED_AVERAGE_RESOLVE)
        *slot = lc_renderer_build_program("", vs_full, fs_wavg, NULL, "weighted average resolve", err);
    else
        *slot = lc_renderer_build_program("", vs_full, fs_wboit, NULL, "WBOIT resolve", err);
    return *slot;
}
