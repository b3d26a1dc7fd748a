/* Headless EGL context creation: device platform first, surfaceless fallback. */
#include "gl_context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MODULE "egl"
#define MAX_DEVICES 16

struct lc_gl {
    EGLDisplay display;
    EGLConfig config;
    EGLContext context;
    char renderer[256];
    char version[256];
    char platform[128];
    int software;
    uint64_t serial; /* lc_gl_current_serial: never reused within the process */
};

static _Atomic uint64_t next_serial;
static _Thread_local uint64_t current_serial; /* of the lc_gl current on this thread, 0 = none */

/* eglInitialize/eglTerminate are not reference counted per display, and every
 * context of one device shares one display handle: count users ourselves. */
static pthread_mutex_t display_lock = PTHREAD_MUTEX_INITIALIZER;
static struct {
    EGLDisplay display;
    int users;
} displays[MAX_DEVICES + 1];

static const char *install_hint = "install libegl1 libegl-mesa0 libgl1-mesa-dri (Mesa) or NVIDIA's EGL driver";

const char *lc_egl_error_name(int code)
{
    switch (code) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: return "EGL_UNKNOWN_ERROR";
    }
}

static int has_ext(const char *list, const char *ext)
{
    if (!list)
        return 0;
    size_t n = strlen(ext);
    for (const char *p = list; (p = strstr(p, ext)) != NULL; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return 1;
    return 0;
}

/* Initializes (or reuses) a display; slot identifies it in `displays`. */
static int acquire_display(EGLDisplay dpy, lc_error *err, const char *what)
{
    pthread_mutex_lock(&display_lock);
    int free_slot = -1;
    for (int i = 0; i <= MAX_DEVICES; i++) {
        if (displays[i].users > 0 && displays[i].display == dpy) {
            displays[i].users++;
            pthread_mutex_unlock(&display_lock);
            return 0;
        }
        if (displays[i].users == 0 && free_slot < 0)
            free_slot = i;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor)) {
        EGLint e = eglGetError();
        pthread_mutex_unlock(&display_lock);
        return lc_err(err, LC_ERR_GL, "eglInitialize on %s failed (%s)", what, lc_egl_error_name(e));
    }
    if (free_slot >= 0) {
        displays[free_slot].display = dpy;
        displays[free_slot].users = 1;
    }
    pthread_mutex_unlock(&display_lock);
    LC_DEBUG(MODULE, "initialized EGL %d.%d on %s", major, minor, what);
    return 0;
}

static void release_display(EGLDisplay dpy)
{
    pthread_mutex_lock(&display_lock);
    for (int i = 0; i <= MAX_DEVICES; i++) {
        if (displays[i].users > 0 && displays[i].display == dpy) {
            if (--displays[i].users == 0)
                eglTerminate(dpy);
            break;
        }
    }
    pthread_mutex_unlock(&display_lock);
}

/* Creates a 4.5 core context on an initialized display. */
static int create_context(lc_gl *gl, EGLContext share, int debug, lc_error *err)
{
    if (!eglBindAPI(EGL_OPENGL_API))
        return lc_err(err, LC_ERR_GL, "eglBindAPI(EGL_OPENGL_API) failed (%s): the EGL driver has no desktop OpenGL",
                      lc_egl_error_name(eglGetError()));
    const EGLint config_attribs[] = {EGL_SURFACE_TYPE,
                                     EGL_PBUFFER_BIT,
                                     EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_BIT,
                                     EGL_RED_SIZE,
                                     8,
                                     EGL_GREEN_SIZE,
                                     8,
                                     EGL_BLUE_SIZE,
                                     8,
                                     EGL_NONE};
    EGLint count = 0;
    if (!eglChooseConfig(gl->display, config_attribs, &gl->config, 1, &count) || count < 1)
        return lc_err(err, LC_ERR_GL, "eglChooseConfig found no OpenGL config (%s)", lc_egl_error_name(eglGetError()));
    const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                  4,
                                  EGL_CONTEXT_MINOR_VERSION,
                                  5,
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                  EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                  EGL_CONTEXT_OPENGL_DEBUG,
                                  debug ? EGL_TRUE : EGL_FALSE,
                                  EGL_NONE};
    gl->context = eglCreateContext(gl->display, gl->config, share ? share : EGL_NO_CONTEXT, ctx_attribs);
    if (gl->context == EGL_NO_CONTEXT)
        return lc_err(err, LC_ERR_GL, "eglCreateContext for OpenGL 4.5 core failed (%s): the driver lacks GL 4.5; %s",
                      lc_egl_error_name(eglGetError()), install_hint);
    return 0;
}

static int device_is_software(EGLDeviceEXT dev)
{
    const char *exts = eglQueryDeviceStringEXT(dev, EGL_EXTENSIONS);
    return has_ext(exts, "EGL_MESA_device_software");
}

/* Tries the device platform; returns 0 with gl->display set, or an error. */
static int open_device(lc_gl *gl, int index, lc_error *err)
{
    const char *client_exts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client_exts) /* no EGL client extensions at all: typically no vendor library */
        return lc_err(err, LC_ERR_UNSUPPORTED, "eglQueryString failed (%s)", lc_egl_error_name(eglGetError()));
    if (!has_ext(client_exts, "EGL_EXT_device_enumeration") && !has_ext(client_exts, "EGL_EXT_device_base"))
        return lc_err(err, LC_ERR_UNSUPPORTED, "no EGL_EXT_device_enumeration");
    if (!has_ext(client_exts, "EGL_EXT_platform_device"))
        return lc_err(err, LC_ERR_UNSUPPORTED, "no EGL_EXT_platform_device");
    EGLDeviceEXT devices[MAX_DEVICES];
    EGLint n = 0;
    if (!eglQueryDevicesEXT(MAX_DEVICES, devices, &n) || n <= 0)
        return lc_err(err, LC_ERR_UNSUPPORTED, "eglQueryDevicesEXT found no device (%s)",
                      lc_egl_error_name(eglGetError()));
    int pick = index;
    if (pick < 0) { /* auto: the first hardware device, else the first one */
        pick = 0;
        for (int i = 0; i < n; i++)
            if (!device_is_software(devices[i])) {
                pick = i;
                break;
            }
    }
    if (pick >= n)
        return lc_err(err, LC_ERR_NOT_FOUND, "EGL device %d does not exist (%d device%s found)", pick, n,
                      n == 1 ? "" : "s");
    gl->display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[pick], NULL);
    if (gl->display == EGL_NO_DISPLAY)
        return lc_err(err, LC_ERR_GL, "eglGetPlatformDisplayEXT(device %d) failed (%s)", pick,
                      lc_egl_error_name(eglGetError()));
    char what[64];
    snprintf(what, sizeof what, "EGL device %d", pick);
    int rc = acquire_display(gl->display, err, what);
    if (rc)
        return rc;
    snprintf(gl->platform, sizeof gl->platform, "device %d of %d (EGL_EXT_platform_device%s)", pick, n,
             device_is_software(devices[pick]) ? ", software" : "");
    return 0;
}

static int open_surfaceless(lc_gl *gl, lc_error *err)
{
    const char *client_exts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_ext(client_exts, "EGL_MESA_platform_surfaceless"))
        return lc_err(err, LC_ERR_UNSUPPORTED, "no EGL_MESA_platform_surfaceless");
    gl->display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    if (gl->display == EGL_NO_DISPLAY)
        return lc_err(err, LC_ERR_GL, "eglGetPlatformDisplayEXT(surfaceless) failed (%s)",
                      lc_egl_error_name(eglGetError()));
    int rc = acquire_display(gl->display, err, "the surfaceless platform");
    if (rc)
        return rc;
    snprintf(gl->platform, sizeof gl->platform, "surfaceless (EGL_MESA_platform_surfaceless)");
    return 0;
}

static int pick_device_index(const lc_gl_desc *desc)
{
    if (desc && desc->device >= 0)
        return desc->device;
    const char *env = getenv("LUCENT_EGL_DEVICE");
    if (env && *env) {
        char *end;
        long v = strtol(env, &end, 10);
        if (*end == '\0' && v >= 0 && v < MAX_DEVICES)
            return (int)v;
        LC_WARN(MODULE, "ignoring LUCENT_EGL_DEVICE=%s (expected 0..%d)", env, MAX_DEVICES - 1);
    }
    return -1;
}

static void APIENTRY debug_callback(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                                    const GLchar *message, const void *user)
{
    (void)source, (void)type, (void)id, (void)length, (void)user;
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION)
        return;
    LC_WARN("gl", "%s", message);
}

int lc_gl_create(const lc_gl_desc *desc, lc_gl **out, lc_error *err)
{
    *out = NULL;
    lc_gl *gl = calloc(1, sizeof *gl);
    if (!gl)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    gl->serial = atomic_fetch_add(&next_serial, 1) + 1;
    int debug = desc && desc->debug;
    int rc;
    if (desc && desc->share) {
        /* Shared contexts must live on the same display. */
        gl->display = desc->share->display;
        snprintf(gl->platform, sizeof gl->platform, "%s", desc->share->platform);
        rc = acquire_display(gl->display, err, "the shared display");
    } else {
        int index = pick_device_index(desc);
        lc_error dev_err = {0};
        rc = open_device(gl, index, &dev_err);
        if (rc == 0) {
            rc = create_context(gl, EGL_NO_CONTEXT, debug, &dev_err);
            if (rc) {
                release_display(gl->display);
                gl->display = EGL_NO_DISPLAY;
            }
        }
        if (rc && index >= 0) { /* an explicit device must not silently become another */
            free(gl);
            return lc_err(err, rc, "%s", dev_err.msg);
        }
        if (rc) {
            LC_INFO(MODULE, "device platform unavailable (%s); trying surfaceless", dev_err.msg);
            lc_error surf_err = {0};
            rc = open_surfaceless(gl, &surf_err);
            if (rc) {
                free(gl);
                return lc_err(err, rc, "no usable EGL display (device platform: %s; surfaceless: %s); %s", dev_err.msg,
                              surf_err.msg, install_hint);
            }
        } else {
            goto created;
        }
    }
    if (rc == 0)
        rc = create_context(gl, desc && desc->share ? desc->share->context : EGL_NO_CONTEXT, debug, err);
    if (rc) {
        if (gl->display != EGL_NO_DISPLAY)
            release_display(gl->display);
        free(gl);
        return rc;
    }
created:
    if (!eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl->context)) {
        lc_err(err, LC_ERR_GL, "eglMakeCurrent without a surface failed (%s): EGL_KHR_surfaceless_context missing",
               lc_egl_error_name(eglGetError()));
        lc_gl_destroy(gl);
        return LC_ERR_GL;
    }
    snprintf(gl->renderer, sizeof gl->renderer, "%s", (const char *)glGetString(GL_RENDERER));
    snprintf(gl->version, sizeof gl->version, "%s", (const char *)glGetString(GL_VERSION));
    int major = epoxy_gl_version();
    if (major < 45) {
        lc_err(err, LC_ERR_GL, "OpenGL %s on %s is older than 4.5; %s", gl->version, gl->renderer, install_hint);
        eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        lc_gl_destroy(gl);
        return LC_ERR_GL;
    }
    gl->software = lc_gl_renderer_is_software(gl->renderer);
    if (debug) {
        glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        glDebugMessageCallback(debug_callback, NULL);
    }
    eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (!(desc && desc->share))
        LC_INFO(MODULE, "OpenGL %s on %s, %s", gl->version, gl->renderer, gl->platform);
    *out = gl;
    return 0;
}

void lc_gl_destroy(lc_gl *gl)
{
    if (!gl)
        return;
    if (gl->serial == current_serial) /* its objects go with it: no cache may find them under its number */
        current_serial = 0;
    if (gl->context != EGL_NO_CONTEXT)
        eglDestroyContext(gl->display, gl->context);
    if (gl->display != EGL_NO_DISPLAY)
        release_display(gl->display);
    free(gl);
}

int lc_gl_make_current(lc_gl *gl, lc_error *err)
{
    if (!eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl->context))
        return lc_err(err, LC_ERR_GL, "eglMakeCurrent failed (%s)", lc_egl_error_name(eglGetError()));
    current_serial = gl->serial;
    return 0;
}

void lc_gl_release_current(lc_gl *gl)
{
    eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    current_serial = 0;
}

uint64_t lc_gl_current_serial(void) { return current_serial; }

const char *lc_gl_renderer(const lc_gl *gl) { return gl->renderer; }
const char *lc_gl_version(const lc_gl *gl) { return gl->version; }
const char *lc_gl_platform(const lc_gl *gl) { return gl->platform; }
int lc_gl_is_software(const lc_gl *gl) { return gl->software; }

int lc_gl_renderer_is_software(const char *gl_renderer)
{
    return gl_renderer &&
           (strstr(gl_renderer, "llvmpipe") || strstr(gl_renderer, "softpipe") || strstr(gl_renderer, "swrast"));
}
