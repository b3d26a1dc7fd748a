/* Image encoding and decoding: PNG (libpng) and JPEG (TurboJPEG), in memory and
 * to files. Pixels are RGBA8, rows top to bottom. */
#ifndef LC_IMAGE_H
#define LC_IMAGE_H

#include <stddef.h>
#include <stdint.h>

#include "lc_base.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_image {
    int width, height;
    uint8_t *rgba; /* width * height * 4, owned */
} lc_image;

/* Encoders return a malloc'd buffer in *out (caller frees) and its size. */
int lc_image_encode_png(const uint8_t *rgba, int width, int height, uint8_t **out, size_t *out_size, lc_error *err);
/* quality 1..100, 4:2:0 subsampling below 90, 4:4:4 from 90 up. */
int lc_image_encode_jpeg(const uint8_t *rgba, int width, int height, int quality, uint8_t **out, size_t *out_size,
                         lc_error *err);
/* Decodes PNG or JPEG (by signature) into img (caller frees img->rgba). */
int lc_image_decode(const uint8_t *data, size_t size, lc_image *img, lc_error *err);
/* Write/read files; the format follows the extension (.png, .jpg/.jpeg). */
int lc_image_write_file(const char *path, const uint8_t *rgba, int width, int height, int quality, lc_error *err);
int lc_image_read_file(const char *path, lc_image *img, lc_error *err);
void lc_image_free(lc_image *img);

/* Image comparison on RGBA8 of equal size. RMSE over RGB in [0,1]. */
double lc_image_rmse(const uint8_t *a, const uint8_t *b, int width, int height);
/* Mean windowed SSIM (Wang et al. 2004) on luminance (Rec. 709 weights) in
 * [0,1], 11x11 Gaussian window with sigma 1.5, K1 = 0.01, K2 = 0.03, L = 1,
 * valid windows only. */
double lc_image_ssim(const uint8_t *a, const uint8_t *b, int width, int height);
/* Absolute difference image, amplified by gain, alpha 255 (caller frees). */
uint8_t *lc_image_difference(const uint8_t *a, const uint8_t *b, int width, int height, double gain);

#ifdef __cplusplus
}
#endif
#endif
