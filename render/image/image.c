/* RGBA8 image encoding/decoding (PNG via libpng, JPEG via TurboJPEG), file I/O and the image metrics (RMSE,
 * windowed SSIM) used to compare renders against the exact path. Decoders treat their input as hostile. */
#include "image.h"
#include "lc_params.h" /* lc_image_format */

#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <turbojpeg.h>

/* Caps on decoded images: a few header bytes must not make us allocate gigabytes. 16384 per side covers every
 * render size we produce; 2^28 bytes (64 Mpixel RGBA) bounds one allocation. */
#define MAX_SIDE 16384
#define MAX_PIXELS (64u * 1024u * 1024u)
/* Files read by lc_image_read_file; larger ones cannot decode within MAX_PIXELS at any sane compression. */
#define MAX_FILE_BYTES (512L * 1024L * 1024L)

static int check_dimensions(int width, int height, lc_error *err)
{
    if (width <= 0 || height <= 0)
        return lc_err(err, LC_ERR_INVALID, "image size %dx%d is empty", width, height);
    if (width > MAX_SIDE || height > MAX_SIDE || (size_t)width * (size_t)height > MAX_PIXELS)
        return lc_err(err, LC_ERR_LIMIT, "image size %dx%d exceeds the limit (%d per side, %u pixels)", width, height,
                      MAX_SIDE, MAX_PIXELS);
    return LC_OK;
}

/* ---- PNG ---------------------------------------------------------------------------------------------- */

/* libpng reports errors through callbacks; the message lands here and png_longjmp returns to our setjmp. */
typedef struct png_context {
    lc_error *err;
    int code;          /* status for the setjmp branch, also when err is NULL */
    char warning[128]; /* libpng's last warning: often the reason behind a terse error */
    /* write: growing output buffer */
    uint8_t *out;
    size_t size, capacity;
    /* read: input cursor and output image (in the struct, not in locals, so longjmp cannot clobber them) */
    const uint8_t *in;
    size_t in_size, in_pos;
    uint8_t *pixels;
    png_bytep *rows;
} png_context;

static void png_error_fn(png_structp png, png_const_charp msg)
{
    png_context *ctx = png_get_error_ptr(png);
    if (ctx->warning[0])
        ctx->code = lc_err(ctx->err, LC_ERR_INVALID, "png: %s (%s)", msg, ctx->warning);
    else
        ctx->code = lc_err(ctx->err, LC_ERR_INVALID, "png: %s", msg);
    png_longjmp(png, 1);
}

static void png_warning_fn(png_structp png, png_const_charp msg)
{
    /* Kept for the error message only: warnings alone (e.g. unknown chunks) are not worth a log line. */
    png_context *ctx = png_get_error_ptr(png);
    snprintf(ctx->warning, sizeof ctx->warning, "%s", msg);
}

static void png_write_fn(png_structp png, png_bytep data, png_size_t length)
{
    png_context *ctx = png_get_io_ptr(png);
    if (length > ctx->capacity - ctx->size) {
        size_t capacity = ctx->capacity ? ctx->capacity : 65536;
        while (length > capacity - ctx->size)
            capacity *= 2;
        uint8_t *grown = realloc(ctx->out, capacity);
        if (!grown) {
            ctx->code = lc_err(ctx->err, LC_ERR_NOMEM, "png: out of memory");
            png_longjmp(png, 1);
        }
        ctx->out = grown;
        ctx->capacity = capacity;
    }
    memcpy(ctx->out + ctx->size, data, length);
    ctx->size += length;
}

static void png_flush_fn(png_structp png) { (void)png; }

/* Runs the libpng encoder. ctx lives in the caller's frame: libpng's longjmp lands in this function, and only
 * objects that are not locals of the setjmp caller are guaranteed intact afterwards (C11 7.13.2.1). */
static int encode_png_run(png_context *ctx, int width, int height)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, ctx, png_error_fn, png_warning_fn);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_write_struct(&png, NULL);
        return lc_err(ctx->err, LC_ERR_NOMEM, "png: cannot create the encoder");
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return ctx->code ? ctx->code : LC_ERR_INTERNAL;
    }
    png_set_write_fn(png, ctx, png_write_fn, png_flush_fn);
    /* Renders are mostly smooth: level 3 is much faster than the default 6 for a few % in size. */
    png_set_compression_level(png, 3);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, ctx->rows);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return LC_OK;
}

int lc_image_encode_png(const uint8_t *rgba, int width, int height, uint8_t **out, size_t *out_size, lc_error *err)
{
    *out = NULL;
    *out_size = 0;
    int rc = check_dimensions(width, height, err);
    if (rc)
        return rc;
    if (!rgba)
        return lc_err(err, LC_ERR_INVALID, "png: no pixels");

    png_context ctx = {.err = err};
    ctx.rows = malloc((size_t)height * sizeof *ctx.rows);
    if (!ctx.rows)
        return lc_err(err, LC_ERR_NOMEM, "png: out of memory");
    for (int y = 0; y < height; y++)
        ctx.rows[y] = (png_bytep)(rgba + (size_t)y * (size_t)width * 4);
    rc = encode_png_run(&ctx, width, height);
    free(ctx.rows);
    if (rc) {
        free(ctx.out);
        return rc;
    }
    *out = ctx.out;
    *out_size = ctx.size;
    return LC_OK;
}

static void png_read_fn(png_structp png, png_bytep data, png_size_t length)
{
    png_context *ctx = png_get_io_ptr(png);
    if (length > ctx->in_size - ctx->in_pos)
        png_error(png, "data truncated");
    memcpy(data, ctx->in + ctx->in_pos, length);
    ctx->in_pos += length;
}

/* Runs the libpng decoder into ctx->pixels (see encode_png_run for why ctx is the caller's). */
static int decode_png_run(png_context *ctx, int *out_width, int *out_height)
{
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, ctx, png_error_fn, png_warning_fn);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_read_struct(&png, NULL, NULL);
        return lc_err(ctx->err, LC_ERR_NOMEM, "png: cannot create the decoder");
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        return ctx->code ? ctx->code : LC_ERR_INTERNAL;
    }
    png_set_read_fn(png, ctx, png_read_fn);
    png_set_user_limits(png, MAX_SIDE, MAX_SIDE);
    png_set_chunk_malloc_max(png, 8u << 20); /* ancillary chunks (text, ICC) never need more */
    png_read_info(png, info);

    png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
    if ((ctx->code = check_dimensions((int)width, (int)height, ctx->err)) != 0) {
        lc_err_prefix(ctx->err, "png");
        png_longjmp(png, 1);
    }

    /* Normalize every PNG flavour to 8-bit RGBA. */
    int color_type = png_get_color_type(png, info);
    png_set_expand(png); /* palette -> RGB, gray < 8 bit -> 8 bit, tRNS -> alpha */
    png_set_strip_16(png);
    if (color_type == PNG_COLOR_TYPE_GRAY || color_type == PNG_COLOR_TYPE_GRAY_ALPHA)
        png_set_gray_to_rgb(png);
    png_set_add_alpha(png, 0xff, PNG_FILLER_AFTER); /* only where there is no alpha channel */
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    if (png_get_rowbytes(png, info) != (size_t)width * 4)
        png_error(png, "unexpected row layout after conversion to RGBA8");

    ctx->pixels = malloc((size_t)width * height * 4);
    ctx->rows = malloc((size_t)height * sizeof *ctx->rows);
    if (!ctx->pixels || !ctx->rows) {
        ctx->code = lc_err(ctx->err, LC_ERR_NOMEM, "png: out of memory for %ux%u", (unsigned)width, (unsigned)height);
        png_longjmp(png, 1);
    }
    for (png_uint_32 y = 0; y < height; y++)
        ctx->rows[y] = ctx->pixels + (size_t)y * width * 4;
    png_read_image(png, ctx->rows);
    png_read_end(png, NULL); /* checks the trailing chunks' CRCs: a truncated file fails here */
    png_destroy_read_struct(&png, &info, NULL);
    *out_width = (int)width;
    *out_height = (int)height;
    return LC_OK;
}

static int decode_png(const uint8_t *data, size_t size, lc_image *img, lc_error *err)
{
    png_context ctx = {.err = err, .in = data, .in_size = size};
    int width = 0, height = 0;
    int rc = decode_png_run(&ctx, &width, &height);
    free(ctx.rows);
    if (rc) {
        free(ctx.pixels);
        return rc;
    }
    img->width = width;
    img->height = height;
    img->rgba = ctx.pixels;
    return LC_OK;
}

/* ---- JPEG --------------------------------------------------------------------------------------------- */

int lc_image_encode_jpeg(const uint8_t *rgba, int width, int height, int quality, uint8_t **out, size_t *out_size,
                         lc_error *err)
{
    *out = NULL;
    *out_size = 0;
    int rc = check_dimensions(width, height, err);
    if (rc)
        return rc;
    if (!rgba)
        return lc_err(err, LC_ERR_INVALID, "jpeg: no pixels");
    if (quality < 1 || quality > 100)
        return lc_err(err, LC_ERR_INVALID, "jpeg: quality %d is outside 1..100", quality);

    /* Chroma subsampling blurs thin coloured lines; it is only worth it at interactive qualities. */
    int subsampling = quality < 90 ? TJSAMP_420 : TJSAMP_444;
    /* Our own malloc'd buffer of the worst-case size, so the caller frees with free(), not tjFree(). */
    unsigned long capacity = tjBufSize(width, height, subsampling);
    if (capacity == (unsigned long)-1)
        return lc_err(err, LC_ERR_INVALID, "jpeg: cannot size the output for %dx%d", width, height);
    unsigned char *buffer = malloc(capacity);
    if (!buffer)
        return lc_err(err, LC_ERR_NOMEM, "jpeg: out of memory");
    tjhandle tj = tjInitCompress();
    if (!tj) {
        free(buffer);
        return lc_err(err, LC_ERR_INTERNAL, "jpeg: %s", tjGetErrorStr2(NULL));
    }
    unsigned long size = capacity;
    if (tjCompress2(tj, rgba, width, width * 4, height, TJPF_RGBA, &buffer, &size, subsampling, quality,
                    TJFLAG_NOREALLOC) != 0) {
        rc = lc_err(err, LC_ERR_INTERNAL, "jpeg: %s", tjGetErrorStr2(tj));
        tjDestroy(tj);
        free(buffer);
        return rc;
    }
    tjDestroy(tj);
    *out = buffer;
    *out_size = size;
    return LC_OK;
}

static int decode_jpeg(const uint8_t *data, size_t size, lc_image *img, lc_error *err)
{
    if (size > (size_t)MAX_FILE_BYTES)
        return lc_err(err, LC_ERR_LIMIT, "jpeg: %zu bytes exceed the limit", size);
    tjhandle tj = tjInitDecompress();
    if (!tj)
        return lc_err(err, LC_ERR_INTERNAL, "jpeg: %s", tjGetErrorStr2(NULL));
    int width, height, subsampling, colorspace, rc;
    if (tjDecompressHeader3(tj, data, (unsigned long)size, &width, &height, &subsampling, &colorspace) != 0) {
        rc = lc_err(err, LC_ERR_INVALID, "jpeg: %s", tjGetErrorStr2(tj));
        tjDestroy(tj);
        return rc;
    }
    if ((rc = check_dimensions(width, height, err)) != 0) {
        lc_err_prefix(err, "jpeg");
        tjDestroy(tj);
        return rc;
    }
    uint8_t *pixels = malloc((size_t)width * (size_t)height * 4);
    if (!pixels) {
        tjDestroy(tj);
        return lc_err(err, LC_ERR_NOMEM, "jpeg: out of memory for %dx%d", width, height);
    }
    /* STOPONWARNING: a truncated or corrupt stream is an error, not a half-grey picture. LIMITSCANS stops
     * progressive files crafted with thousands of scans (a CPU exhaustion attack). */
    if (tjDecompress2(tj, data, (unsigned long)size, pixels, width, width * 4, height, TJPF_RGBA,
                      TJFLAG_STOPONWARNING | TJFLAG_LIMITSCANS) != 0) {
        rc = lc_err(err, LC_ERR_INVALID, "jpeg: %s", tjGetErrorStr2(tj));
        tjDestroy(tj);
        free(pixels);
        return rc;
    }
    tjDestroy(tj);
    img->width = width;
    img->height = height;
    img->rgba = pixels;
    return LC_OK;
}

/* ---- decode / files ----------------------------------------------------------------------------------- */

int lc_image_decode(const uint8_t *data, size_t size, lc_image *img, lc_error *err)
{
    static const uint8_t png_signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    img->width = img->height = 0;
    img->rgba = NULL;
    if (!data || size == 0)
        return lc_err(err, LC_ERR_INVALID, "image: no data");
    if (size >= 8 && memcmp(data, png_signature, 8) == 0)
        return decode_png(data, size, img, err);
    if (size >= 3 && data[0] == 0xff && data[1] == 0xd8 && data[2] == 0xff)
        return decode_jpeg(data, size, img, err);
    return lc_err(err, LC_ERR_INVALID, "image: neither PNG nor JPEG (unknown signature)");
}

/* Format from the extension, case-insensitively: 0 = PNG, 1 = JPEG, -1 = unknown. */
static int format_from_path(const char *path)
{
    const char *dot = strrchr(path, '.');
    if (!dot)
        return -1;
    if (strcasecmp(dot, ".png") == 0)
        return LC_FORMAT_PNG;
    if (strcasecmp(dot, ".jpg") == 0 || strcasecmp(dot, ".jpeg") == 0)
        return LC_FORMAT_JPEG;
    return -1;
}

int lc_image_write_file(const char *path, const uint8_t *rgba, int width, int height, int quality, lc_error *err)
{
    int format = format_from_path(path);
    if (format < 0)
        return lc_err(err, LC_ERR_INVALID, "%s: unknown image extension (use .png, .jpg or .jpeg)", path);
    uint8_t *encoded;
    size_t size;
    int rc = format == LC_FORMAT_PNG ? lc_image_encode_png(rgba, width, height, &encoded, &size, err)
                                     : lc_image_encode_jpeg(rgba, width, height, quality, &encoded, &size, err);
    if (rc) {
        lc_err_prefix(err, "%s", path);
        return rc;
    }
    FILE *f = fopen(path, "wb");
    if (!f) {
        free(encoded);
        return lc_err(err, LC_ERR_IO, "%s: cannot open for writing", path);
    }
    size_t written = fwrite(encoded, 1, size, f);
    free(encoded);
    if (fclose(f) != 0 || written != size)
        return lc_err(err, LC_ERR_IO, "%s: write failed", path);
    return LC_OK;
}

int lc_image_read_file(const char *path, lc_image *img, lc_error *err)
{
    /* The content's signature decides the format, so a misnamed file still reads. */
    img->width = img->height = 0;
    img->rgba = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        return lc_err(err, LC_ERR_IO, "%s: cannot open", path);
    long size = -1;
    if (fseek(f, 0, SEEK_END) == 0)
        size = ftell(f);
    if (size < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return lc_err(err, LC_ERR_IO, "%s: cannot determine the file size", path);
    }
    if (size > MAX_FILE_BYTES) {
        fclose(f);
        return lc_err(err, LC_ERR_LIMIT, "%s: %ld bytes exceed the image file limit", path, size);
    }
    uint8_t *data = malloc(size ? (size_t)size : 1);
    if (!data) {
        fclose(f);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", path);
    }
    size_t got = fread(data, 1, (size_t)size, f);
    fclose(f);
    if (got != (size_t)size) {
        free(data);
        return lc_err(err, LC_ERR_IO, "%s: short read", path);
    }
    int rc = lc_image_decode(data, got, img, err);
    free(data);
    if (rc)
        lc_err_prefix(err, "%s", path);
    return rc;
}

void lc_image_free(lc_image *img)
{
    if (!img)
        return;
    free(img->rgba);
    img->rgba = NULL;
    img->width = img->height = 0;
}

/* ---- metrics ------------------------------------------------------------------------------------------ */

double lc_image_rmse(const uint8_t *a, const uint8_t *b, int width, int height)
{
    if (width <= 0 || height <= 0)
        return 0;
    size_t pixels = (size_t)width * (size_t)height;
    double sum = 0;
    for (size_t i = 0; i < pixels; i++)
        for (int c = 0; c < 3; c++) {
            double d = ((double)a[4 * i + c] - (double)b[4 * i + c]) / 255.0;
            sum += d * d;
        }
    return sqrt(sum / (double)(pixels * 3));
}

#define SSIM_WINDOW 11
#define SSIM_SIGMA 1.5
#define SSIM_C1 (0.01 * 0.01)
#define SSIM_C2 (0.03 * 0.03)

static void luminance(const uint8_t *rgba, size_t pixels, double *y)
{
    for (size_t i = 0; i < pixels; i++)
        y[i] = (0.2126 * rgba[4 * i] + 0.7152 * rgba[4 * i + 1] + 0.0722 * rgba[4 * i + 2]) / 255.0;
}

static double ssim_formula(double mx, double my, double sxx, double syy, double sxy)
{
    return ((2 * mx * my + SSIM_C1) * (2 * sxy + SSIM_C2)) / ((mx * mx + my * my + SSIM_C1) * (sxx + syy + SSIM_C2));
}

/* Images smaller than the window in a dimension: one global window with uniform weights over all pixels. */
static double ssim_global(const double *x, const double *y, size_t pixels)
{
    double mx = 0, my = 0;
    for (size_t i = 0; i < pixels; i++)
        mx += x[i], my += y[i];
    mx /= (double)pixels, my /= (double)pixels;
    double sxx = 0, syy = 0, sxy = 0;
    for (size_t i = 0; i < pixels; i++) {
        sxx += (x[i] - mx) * (x[i] - mx);
        syy += (y[i] - my) * (y[i] - my);
        sxy += (x[i] - mx) * (y[i] - my);
    }
    return ssim_formula(mx, my, sxx / (double)pixels, syy / (double)pixels, sxy / (double)pixels);
}

double lc_image_ssim(const uint8_t *a, const uint8_t *b, int width, int height)
{
    /* Wang et al. 2004, Gaussian-windowed, mean over the valid window positions (no padding, like their
     * reference code's 'valid' filtering). The 2D window is the outer product of a normalized 1D Gaussian, so
     * filtering separably (rows, then columns) gives the same local moments at 2*11 instead of 121 taps. */
    if (width <= 0 || height <= 0)
        return 1.0; /* nothing differs */
    size_t pixels = (size_t)width * (size_t)height;
    double *x = malloc(pixels * sizeof *x), *y = malloc(pixels * sizeof *y);
    if (!x || !y) {
        free(x), free(y);
        return NAN;
    }
    luminance(a, pixels, x);
    luminance(b, pixels, y);
    if (width < SSIM_WINDOW || height < SSIM_WINDOW) {
        double s = ssim_global(x, y, pixels);
        free(x), free(y);
        return s;
    }

    double kernel[SSIM_WINDOW], ksum = 0;
    for (int i = 0; i < SSIM_WINDOW; i++) {
        double t = i - SSIM_WINDOW / 2;
        kernel[i] = exp(-t * t / (2 * SSIM_SIGMA * SSIM_SIGMA));
        ksum += kernel[i];
    }
    for (int i = 0; i < SSIM_WINDOW; i++)
        kernel[i] /= ksum;

    /* Horizontal pass: five moment images (x, y, x^2, y^2, xy) of width - 10 columns. */
    int vw = width - SSIM_WINDOW + 1, vh = height - SSIM_WINDOW + 1;
    size_t hsize = (size_t)vw * (size_t)height;
    double *h = malloc(5 * hsize * sizeof *h);
    if (!h) {
        free(x), free(y);
        return NAN;
    }
    double *hx = h, *hy = h + hsize, *hxx = h + 2 * hsize, *hyy = h + 3 * hsize, *hxy = h + 4 * hsize;
    for (int row = 0; row < height; row++) {
        const double *xr = x + (size_t)row * width, *yr = y + (size_t)row * width;
        for (int col = 0; col < vw; col++) {
            double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
            for (int k = 0; k < SSIM_WINDOW; k++) {
                double w = kernel[k], u = xr[col + k], v = yr[col + k];
                sx += w * u, sy += w * v;
                sxx += w * u * u, syy += w * v * v, sxy += w * u * v;
            }
            size_t o = (size_t)row * vw + col;
            hx[o] = sx, hy[o] = sy, hxx[o] = sxx, hyy[o] = syy, hxy[o] = sxy;
        }
    }
    free(x), free(y);

    /* Vertical pass straight into the SSIM mean. */
    double total = 0;
    for (int row = 0; row < vh; row++) {
        for (int col = 0; col < vw; col++) {
            double mx = 0, my = 0, exx = 0, eyy = 0, exy = 0;
            for (int k = 0; k < SSIM_WINDOW; k++) {
                size_t o = (size_t)(row + k) * vw + col;
                double w = kernel[k];
                mx += w * hx[o], my += w * hy[o];
                exx += w * hxx[o], eyy += w * hyy[o], exy += w * hxy[o];
            }
            total += ssim_formula(mx, my, exx - mx * mx, eyy - my * my, exy - mx * my);
        }
    }
    free(h);
    return total / ((double)vw * (double)vh);
}

uint8_t *lc_image_difference(const uint8_t *a, const uint8_t *b, int width, int height, double gain)
{
    if (width <= 0 || height <= 0 || !a || !b)
        return NULL;
    size_t pixels = (size_t)width * (size_t)height;
    uint8_t *diff = malloc(pixels * 4);
    if (!diff)
        return NULL;
    for (size_t i = 0; i < pixels; i++) {
        for (int c = 0; c < 3; c++) {
            double d = fabs((double)a[4 * i + c] - (double)b[4 * i + c]) * gain;
            diff[4 * i + c] = (uint8_t)(d > 255 ? 255 : d < 0 ? 0 : d + 0.5);
        }
        diff[4 * i + 3] = 255;
    }
    return diff;
}
