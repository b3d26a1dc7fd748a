/* Headless OpenGL 4.5 core contexts through EGL: the device platform
 * (EGL_EXT_platform_device, NVIDIA and Mesa) with selection by index, falling
 * back to Mesa's surfaceless platform (llvmpipe). No window, no display. */
#ifndef LC_GL_CONTEXT_H
#define LC_GL_CONTEXT_H

#include <stdint.h>

#include "lc_base.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_gl lc_gl;

typedef struct lc_gl_desc {
    /* EGL device index; -1 = LUCENT_EGL_DEVICE from the environment, else the
     * first device that gives a hardware context, else any (0 is a valid index,
     * so callers wanting "auto" must set -1 explicitly; a zeroed desc picks 0). */
    int device;
    /* Context whose objects (buffers, textures) the new one shares; must stay
     * alive longer than this one. NULL for the first context. */
    lc_gl *share;
    int debug; /* create a debug context and log GL debug messages */
} lc_gl_desc;

/* Creates a context (not current). Errors name the EGL error and what to
 * install, e.g. "eglInitialize failed (EGL_NOT_INITIALIZED): install
 * libegl-mesa0 and libgl1-mesa-dri". Thread: any. */
int lc_gl_create(const lc_gl_desc *desc, lc_gl **out, lc_error *err);
/* Destroys the context; it must not be current on another thread. */
void lc_gl_destroy(lc_gl *gl);
/* Binds the context to the calling thread (a context is current on at most one
 * thread at a time). */
int lc_gl_make_current(lc_gl *gl, lc_error *err);
void lc_gl_release_current(lc_gl *gl);
/* A number naming the context made current on this thread by
 * lc_gl_make_current (0 = none), never given to another context of the
 * process: for per-context caches of objects a share group does not share
 * safely (programs, whose compiled variants a driver may keep per context). */
uint64_t lc_gl_current_serial(void);

const char *lc_gl_renderer(const lc_gl *gl); /* GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" */
const char *lc_gl_version(const lc_gl *gl);  /* GL_VERSION */
const char *lc_gl_platform(const lc_gl *gl); /* "device 0 (EGL_EXT_platform_device)" or "surfaceless" */
int lc_gl_is_software(const lc_gl *gl);      /* llvmpipe / softpipe / swrast */
/* Whether a GL_RENDERER string names a software rasterizer (llvmpipe, softpipe,
 * swrast): the renderer's modules choose their paths by it. NULL: no. */
int lc_gl_renderer_is_software(const char *gl_renderer);

/* Name of an EGL error code ("EGL_BAD_ALLOC"). */
const char *lc_egl_error_name(int code);

#ifdef __cplusplus
}
#endif
#endif
