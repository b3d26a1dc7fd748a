/* Internals shared by the renderer's method implementations (renderer.c for
 * Fourier and baselines, exact.c for the linked-list reference). Not public. */
#ifndef LC_RENDERER_INTERNAL_H
#define LC_RENDERER_INTERNAL_H

#include <epoxy/gl.h>

#include "camera.h"
#include "renderer.h"

#define LC_MAX_COEF_TARGETS 5 /* (2 * 8 + 1 + 3) / 4 */

/* SSBO binding points (must match shaders/common.glsl and the pass shaders). */
enum {
    BIND_POSITIONS = 0,
    BIND_FRAMES = 1,
    BIND_ATTRIBUTES = 2,
    BIND_COLORS = 3,
    BIND_VERTEX_ELEMENTS = 4,
    BIND_VERTEX_WEIGHTS = 5,
    BIND_INDICES = 6,
    BIND_ELEMENT_ALPHA_MIN = 7,
    BIND_ELEMENT_ALPHA = 8,
    BIND_SMOOTH_SRC = 9,
    BIND_SMOOTH_DST = 10,
    BIND_ADJ_OFFSETS = 11,
    BIND_ADJ = 12,
    BIND_STATS = 13,
    BIND_EXACT_FIRST = 14 /* exact.c uses 14.. */
};

struct lc_gpu_scene {
    const lc_scene *scene;
    GLuint positions, frames, attributes, colors, vertex_elements, vertex_weights, indices;
    GLuint adj_offsets, adj;
    GLuint draw_indices;      /* element buffer of indexed draws: ribbon quads (lines) or the triangles */
    uint64_t primitive_count; /* points, segments or triangles */
    uint64_t bytes;
};

/* A colour target set at one resolution. */
typedef struct lc_targets {
    int width, height, count;
    GLuint fbo;
    GLuint tex[LC_MAX_COEF_TARGETS];
    GLenum format;
} lc_targets;

typedef enum {
    PROG_P1 = 0,
    PROG_P2,
    PROG_P4,
    PROG_P5,
    PROG_P4_DIRECT,
    PROG_P5_DIRECT,
    PROG_OPAQUE,
    PROG_WBOIT,
    PROG_DEPTH_RANGE,
    PROG_GEOMETRY_KINDS, /* per primitive type and band count */
    PROG_P3 = PROG_GEOMETRY_KINDS,
    PROG_RESOLVE,
    PROG_WBOIT_RESOLVE,
    PROG_FIXED_KINDS
} lc_program_kind;

struct lc_renderer {
    lc_renderer_desc desc;
    GLuint vao;
    GLuint colormap_tex[16];
    int colormap_count;
    /* [kind][primitive][bands][pulled]: pulled = unindexed subset variant */
    GLuint geometry_programs[PROG_GEOMETRY_KINDS][3][LC_MAX_BANDS + 1][2];
    GLuint fixed_programs[PROG_FIXED_KINDS];
    lc_targets coef_low;   /* P1 at optimization resolution */
    lc_targets coef_full;  /* P4 */
    lc_targets accum;      /* P5 (and WBOIT accum + revealage) */
    lc_targets output;     /* RGBA8 + depth */
    lc_targets range_full; /* P0 per-pixel depth ranges (RG32F), output resolution */
    lc_targets range_low;  /* the same at the optimization resolution */
    GLuint output_depth;   /* opaque baseline only */
    int depth_width, depth_height;
    GLuint nofb; /* framebuffer without attachments for P2 */
    int nofb_w, nofb_h;
    /* per-element buffers, grown to the largest scene */
    GLuint element_alpha_min, element_alpha, smooth_a, smooth_b, stats;
    uint32_t element_capacity;
    GLuint timer_queries[LC_PASS_COUNT + 1];
    GLuint dummy_buffer;
    void *exact; /* exact.c's state */
    uint64_t bytes_targets, bytes_elements;
};

/* Everything a geometry pass needs from the frame's parameters. */
typedef struct lc_frame_setup {
    const lc_render_params *params;
    const lc_gpu_scene *gs;
    lc_view view;
    int importance_attr, color_mode, color_attr, colormap;
    double importance_range[2], color_range[2], importance_exponent;
    double line_half_width; /* world */
    int width, height;      /* output */
    int low_width, low_height;
    int pixel_depth_range; /* P0 ran: geometry passes normalize by range_full / range_low */
} lc_frame_setup;

/* Returns the program for (kind, primitive, bands) that lc_renderer_draw_geometry
 * draws with the given subset stride, compiling on first use; 0 on error. Lines
 * and triangles draw indexed (shared vertices shaded once) unless subset > 1,
 * which pulls every n-th primitive unindexed (#define PULL_PRIMITIVES); points
 * always draw instanced. Programs built elsewhere from geometry.vert.glsl
 * without PULL_PRIMITIVES match subset 1. */
GLuint lc_renderer_geometry_program(lc_renderer *r, lc_program_kind kind, lc_prim_type prim, int bands, int subset,
                                    lc_error *err);
/* Compiles a program from embedded shader files; defines is a "#define ..\n" block. */
GLuint lc_renderer_build_program(const char *defines, const char *const *vertex_files,
                                 const char *const *fragment_files, const char *const *compute_files, const char *label,
                                 lc_error *err);
/* Binds the scene's buffers and sets the shared uniforms of a geometry program
 * for a pass rendered at (w, h). */
void lc_renderer_bind_geometry(lc_renderer *r, GLuint prog, const lc_frame_setup *fs, int w, int h, int subset);
/* Issues the draw of every (subset-th) primitive. */
void lc_renderer_draw_geometry(const lc_frame_setup *fs, int subset);
/* (Re)allocates a target set; format GL_RGBA32F, GL_RGBA16F or GL_RGBA8. */
void lc_targets_ensure(lc_targets *t, int w, int h, int count, GLenum format, uint64_t *bytes);
void lc_targets_free(lc_targets *t, uint64_t *bytes);
/* Records a timestamp after pass `pass` (index LC_PASS_COUNT = frame start). */
void lc_renderer_timestamp(lc_renderer *r, int slot);
/* Runs P3 on element_alpha_min → element_alpha (uploads state first). */
int lc_renderer_smooth_and_fade(lc_renderer *r, const lc_frame_setup *fs, lc_frame_state *state, double dt,
                                lc_frame_info *info, lc_error *err);
/* Resolve helpers and readback into rgba (top-down). */
void lc_renderer_readback(lc_renderer *r, const lc_frame_setup *fs, uint8_t *rgba);

/* exact.c */
int lc_render_exact(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, uint8_t *rgba,
                    lc_frame_info *info, lc_error *err);
void lc_exact_destroy(lc_renderer *r);

#endif
