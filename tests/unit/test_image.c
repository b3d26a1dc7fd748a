/* Unit tests of render/image.c: PNG/JPEG round trips, hostile input, files, and the RMSE/SSIM metrics (SSIM
 * cross-checked against a direct 2D-window computation written here). */
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#include "image.h"
#include "lc_test.h"

static uint64_t rng_state = 0x1234567ULL;

static uint32_t random_u32(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (uint32_t)(rng_state >> 16);
}

static uint8_t *make_image(int w, int h)
{
    uint8_t *p = malloc((size_t)w * h * 4);
    if (!p) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    return p;
}

static uint8_t *noise_image(int w, int h)
{
    uint8_t *p = make_image(w, h);
    for (size_t i = 0; i < (size_t)w * h * 4; i++)
        p[i] = (uint8_t)random_u32();
    return p;
}

/* Smooth colour ramps: what a JPEG encoder handles well. */
static uint8_t *gradient_image(int w, int h)
{
    uint8_t *p = make_image(w, h);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint8_t *px = p + ((size_t)y * w + x) * 4;
            px[0] = (uint8_t)(255 * x / (w - 1));
            px[1] = (uint8_t)(255 * y / (h - 1));
            px[2] = (uint8_t)(128 + 100 * sin(0.05 * (x + y)));
            px[3] = 255;
        }
    return p;
}

/* Adds uniform noise of +-amplitude to RGB. */
static uint8_t *noisy_copy(const uint8_t *src, int w, int h, int amplitude)
{
    uint8_t *p = make_image(w, h);
    memcpy(p, src, (size_t)w * h * 4);
    for (size_t i = 0; i < (size_t)w * h; i++)
        for (int c = 0; c < 3; c++) {
            int v = p[4 * i + c] + (int)(random_u32() % (uint32_t)(2 * amplitude + 1)) - amplitude;
            p[4 * i + c] = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
        }
    return p;
}

static void test_png_roundtrip(void)
{
    const int w = 37, h = 23; /* odd sizes catch row-stride mistakes */
    uint8_t *src = noise_image(w, h), *png;
    size_t size;
    lc_error err = {0};
    CHECK(lc_image_encode_png(src, w, h, &png, &size, &err) == LC_OK, "encode png: %s", err.msg);
    CHECK(size > 8 && png[0] == 0x89 && png[1] == 'P', "png signature");
    lc_image img;
    CHECK(lc_image_decode(png, size, &img, &err) == LC_OK, "decode png: %s", err.msg);
    CHECK(img.width == w && img.height == h, "png size %dx%d", img.width, img.height);
    CHECK(img.rgba && memcmp(img.rgba, src, (size_t)w * h * 4) == 0, "png round trip is exact (RGBA)");
    lc_image_free(&img);
    CHECK(img.rgba == NULL && img.width == 0, "free resets the image");

    /* Truncations at every interesting length, and a flipped byte inside the compressed data (CRC error). */
    const size_t cuts[] = {0, 1, 7, 8, 16, 33, size / 2, size - 12, size - 1};
    for (size_t i = 0; i < sizeof cuts / sizeof cuts[0]; i++) {
        memset(&err, 0, sizeof err);
        int rc = lc_image_decode(png, cuts[i], &img, &err);
        CHECK(rc < 0 && img.rgba == NULL, "truncated png (%zu of %zu bytes) decoded: rc %d", cuts[i], size, rc);
        CHECK(rc == 0 || err.msg[0] != '\0', "truncated png has a message");
    }
    uint8_t *corrupt = malloc(size);
    memcpy(corrupt, png, size);
    corrupt[size / 2] ^= 0x5a;
    CHECK(lc_image_decode(corrupt, size, &img, &err) < 0, "corrupt png decoded");
    free(corrupt);
    free(png);
    free(src);
}

static uint32_t crc32_of(const uint8_t *p, size_t n)
{
    uint32_t crc = 0xffffffffu;
    for (size_t i = 0; i < n; i++) {
        crc ^= p[i];
        for (int k = 0; k < 8; k++)
            crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1)));
    }
    return ~crc;
}

static void put_be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24), p[1] = (uint8_t)(v >> 16), p[2] = (uint8_t)(v >> 8), p[3] = (uint8_t)v;
}

/* A valid PNG header (correct CRC) announcing a huge image: must be refused before any allocation. */
static void test_png_absurd_size(void)
{
    const uint32_t sizes[][2] = {{100000, 100000}, {16385, 1}, {16384, 16384}, {9000, 9000}, {0, 10}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        uint8_t file[8 + 25 + 12 + 12] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
        uint8_t *ihdr = file + 8;
        put_be32(ihdr, 13);
        memcpy(ihdr + 4, "IHDR", 4);
        put_be32(ihdr + 8, sizes[s][0]);
        put_be32(ihdr + 12, sizes[s][1]);
        ihdr[16] = 8, ihdr[17] = 6, ihdr[18] = 0, ihdr[19] = 0, ihdr[20] = 0; /* 8-bit RGBA */
        put_be32(ihdr + 21, crc32_of(ihdr + 4, 17));
        uint8_t *idat = file + 33; /* empty IDAT: png_read_info stops here, so the size checks get to run */
        put_be32(idat, 0);
        memcpy(idat + 4, "IDAT", 4);
        put_be32(idat + 8, crc32_of(idat + 4, 4));
        uint8_t *iend = file + 45;
        put_be32(iend, 0);
        memcpy(iend + 4, "IEND", 4);
        put_be32(iend + 8, crc32_of(iend + 4, 4));
        lc_image img;
        lc_error err = {0};
        int rc = lc_image_decode(file, sizeof file, &img, &err);
        CHECK(rc < 0 && img.rgba == NULL, "png header %ux%u accepted", sizes[s][0], sizes[s][1]);
        printf("  png %ux%u header: %s (%s)\n", sizes[s][0], sizes[s][1], err.msg, lc_status_name(rc));
    }
}

static void test_jpeg(void)
{
    const int w = 128, h = 96;
    uint8_t *src = gradient_image(w, h);
    lc_error err = {0};
    size_t size95 = 0, size75 = 0;
    const int qualities[] = {95, 75};
    for (int qi = 0; qi < 2; qi++) {
        uint8_t *jpg;
        size_t size;
        CHECK(lc_image_encode_jpeg(src, w, h, qualities[qi], &jpg, &size, &err) == LC_OK, "encode jpeg: %s", err.msg);
        *(qi ? &size75 : &size95) = size;
        lc_image img;
        CHECK(lc_image_decode(jpg, size, &img, &err) == LC_OK, "decode jpeg: %s", err.msg);
        CHECK(img.width == w && img.height == h, "jpeg size %dx%d", img.width, img.height);
        double rmse = img.rgba ? lc_image_rmse(src, img.rgba, w, h) : 1;
        printf("  jpeg quality %d: %zu bytes, RMSE %.4f\n", qualities[qi], size, rmse);
        CHECK(rmse < (qi ? 0.03 : 0.02), "jpeg quality %d RMSE %.4f", qualities[qi], rmse);
        int opaque = 1;
        for (size_t i = 0; img.rgba && i < (size_t)w * h; i++)
            opaque &= img.rgba[4 * i + 3] == 255;
        CHECK(opaque, "jpeg decodes with alpha 255");
        lc_image_free(&img);

        if (qi == 0) {
            const size_t cuts[] = {0, 2, 3, 10, 100, size / 2, size - 2};
            for (size_t i = 0; i < sizeof cuts / sizeof cuts[0]; i++) {
                int rc = lc_image_decode(jpg, cuts[i], &img, &err);
                CHECK(rc < 0 && img.rgba == NULL, "truncated jpeg (%zu of %zu bytes) decoded", cuts[i], size);
            }
            /* SOI marker followed by noise. */
            uint8_t garbage[512];
            for (size_t i = 0; i < sizeof garbage; i++)
                garbage[i] = (uint8_t)random_u32();
            garbage[0] = 0xff, garbage[1] = 0xd8, garbage[2] = 0xff;
            CHECK(lc_image_decode(garbage, sizeof garbage, &img, &err) < 0, "jpeg garbage decoded");

            /* The frame header (SOF) rewritten to 60000x60000: refused before allocating 14 GB. */
            uint8_t *huge = malloc(size);
            memcpy(huge, jpg, size);
            int patched = 0;
            for (size_t i = 2; i + 9 < size && !patched; i++)
                if (huge[i] == 0xff && (huge[i + 1] == 0xc0 || huge[i + 1] == 0xc1 || huge[i + 1] == 0xc2)) {
                    huge[i + 5] = 0xea, huge[i + 6] = 0x60, huge[i + 7] = 0xea, huge[i + 8] = 0x60;
                    patched = 1;
                }
            int rc = lc_image_decode(huge, size, &img, &err);
            CHECK(patched && rc == LC_ERR_LIMIT && img.rgba == NULL, "60000^2 jpeg: rc %d", rc);
            printf("  jpeg 60000x60000 header: %s\n", err.msg);
            free(huge);
        }
        free(jpg);
    }
    CHECK(size75 < size95, "quality 75 (%zu bytes) smaller than 95 (%zu)", size75, size95);

    uint8_t *out;
    size_t size;
    CHECK(lc_image_encode_jpeg(src, w, h, 0, &out, &size, &err) == LC_ERR_INVALID && out == NULL, "quality 0");
    CHECK(lc_image_encode_jpeg(src, w, h, 101, &out, &size, &err) == LC_ERR_INVALID, "quality 101");
    CHECK(lc_image_encode_jpeg(src, 0, h, 90, &out, &size, &err) < 0, "width 0");
    CHECK(lc_image_encode_png(src, w, -1, &out, &size, &err) < 0, "height -1");
    free(src);
}

static void test_garbage(void)
{
    lc_image img;
    lc_error err = {0};
    uint8_t noise[4096];
    for (int trial = 0; trial < 200; trial++) {
        for (size_t i = 0; i < sizeof noise; i++)
            noise[i] = (uint8_t)random_u32();
        size_t n = 1 + random_u32() % sizeof noise;
        if (trial % 2) /* half of them get a PNG signature to reach the decoder proper */
            memcpy(noise, "\x89PNG\r\n\x1a\n", n < 8 ? n : 8);
        CHECK(lc_image_decode(noise, n, &img, &err) < 0 && img.rgba == NULL, "garbage %d decoded", trial);
    }
    CHECK(lc_image_decode(NULL, 0, &img, &err) == LC_ERR_INVALID, "NULL data");
    CHECK(lc_image_decode((const uint8_t *)"GIF89a", 6, &img, &err) == LC_ERR_INVALID, "GIF rejected");
    printf("  unknown format: %s\n", err.msg);
}

static void test_files(void)
{
    char dir[] = "/tmp/lucent-test-image-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(0, "mkdtemp failed");
        return;
    }
    const int w = 40, h = 30;
    uint8_t *src = gradient_image(w, h);
    char path[256];
    lc_error err = {0};
    lc_image img;

    snprintf(path, sizeof path, "%s/a.PNG", dir);
    CHECK(lc_image_write_file(path, src, w, h, 0, &err) == LC_OK, "write png: %s", err.msg);
    CHECK(lc_image_read_file(path, &img, &err) == LC_OK, "read png: %s", err.msg);
    CHECK(img.rgba && img.width == w && memcmp(img.rgba, src, (size_t)w * h * 4) == 0, "png file exact");
    lc_image_free(&img);
    unlink(path);

    snprintf(path, sizeof path, "%s/a.jpeg", dir);
    CHECK(lc_image_write_file(path, src, w, h, 92, &err) == LC_OK, "write jpeg: %s", err.msg);
    CHECK(lc_image_read_file(path, &img, &err) == LC_OK, "read jpeg: %s", err.msg);
    CHECK(img.rgba && lc_image_rmse(src, img.rgba, w, h) < 0.02, "jpeg file close");
    lc_image_free(&img);
    unlink(path);

    snprintf(path, sizeof path, "%s/a.bmp", dir);
    CHECK(lc_image_write_file(path, src, w, h, 90, &err) == LC_ERR_INVALID, "unknown extension written");
    printf("  %s\n", err.msg);
    snprintf(path, sizeof path, "%s/missing.png", dir);
    CHECK(lc_image_read_file(path, &img, &err) == LC_ERR_IO, "missing file read");
    snprintf(path, sizeof path, "%s/nodir/a.png", dir);
    CHECK(lc_image_write_file(path, src, w, h, 90, &err) == LC_ERR_IO, "unwritable path");
    rmdir(dir);
    free(src);
}

static void test_rmse_and_difference(void)
{
    const int w = 8, h = 5;
    uint8_t *black = make_image(w, h), *white = make_image(w, h), *grey = make_image(w, h);
    for (size_t i = 0; i < (size_t)w * h; i++) {
        for (int c = 0; c < 3; c++)
            black[4 * i + c] = 0, white[4 * i + c] = 255, grey[4 * i + c] = 51;
        black[4 * i + 3] = 0, white[4 * i + 3] = 255, grey[4 * i + 3] = 7; /* alpha is ignored */
    }
    CHECK_NEAR(lc_image_rmse(black, white, w, h), 1.0, 1e-12, "black vs white");
    CHECK_NEAR(lc_image_rmse(black, grey, w, h), 0.2, 1e-12, "black vs 51");
    CHECK_NEAR(lc_image_rmse(grey, grey, w, h), 0.0, 0.0, "identical");
    /* Only the red channel of one pixel differs by 255: sqrt(1 / (40 * 3)). */
    memcpy(grey, black, (size_t)w * h * 4);
    grey[0] = 255;
    CHECK_NEAR(lc_image_rmse(black, grey, w, h), sqrt(1.0 / 120.0), 1e-12, "one channel");

    uint8_t *diff = lc_image_difference(black, grey, w, h, 4.0);
    CHECK(diff && diff[0] == 255 && diff[1] == 0 && diff[3] == 255 && diff[7] == 255, "difference image");
    free(diff);
    grey[0] = 10;
    diff = lc_image_difference(grey, black, w, h, 4.0);
    CHECK(diff && diff[0] == 40, "difference amplified: %d", diff ? diff[0] : -1);
    free(diff);
    CHECK(lc_image_difference(black, grey, 0, h, 1.0) == NULL, "empty difference");
    free(black), free(white), free(grey);
}

/* SSIM the slow, obvious way: the full 11x11 window at every valid position. */
static double ssim_direct(const uint8_t *a, const uint8_t *b, int w, int h)
{
    double g[11][11], gsum = 0;
    for (int i = 0; i < 11; i++)
        for (int j = 0; j < 11; j++)
            gsum += g[i][j] = exp(-((i - 5) * (i - 5) + (j - 5) * (j - 5)) / (2 * 1.5 * 1.5));
    double total = 0;
    for (int y0 = 0; y0 + 11 <= h; y0++)
        for (int x0 = 0; x0 + 11 <= w; x0++) {
            double mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
            for (int i = 0; i < 11; i++)
                for (int j = 0; j < 11; j++) {
                    const uint8_t *pa = a + ((size_t)(y0 + i) * w + x0 + j) * 4;
                    const uint8_t *pb = b + ((size_t)(y0 + i) * w + x0 + j) * 4;
                    double u = (0.2126 * pa[0] + 0.7152 * pa[1] + 0.0722 * pa[2]) / 255;
                    double v = (0.2126 * pb[0] + 0.7152 * pb[1] + 0.0722 * pb[2]) / 255;
                    double wt = g[i][j] / gsum;
                    mx += wt * u, my += wt * v;
                    xx += wt * u * u, yy += wt * v * v, xy += wt * u * v;
                }
            double sx = xx - mx * mx, sy = yy - my * my, sxy = xy - mx * my;
            const double c1 = 1e-4, c2 = 9e-4;
            total += (2 * mx * my + c1) * (2 * sxy + c2) / ((mx * mx + my * my + c1) * (sx + sy + c2));
        }
    return total / ((double)(w - 10) * (h - 10));
}

static void test_ssim(void)
{
    const int w = 64, h = 48;
    uint8_t *a = gradient_image(w, h);
    CHECK_NEAR(lc_image_ssim(a, a, w, h), 1.0, 1e-12, "SSIM(a, a)");

    double previous = 1.0;
    const int amplitudes[] = {4, 16, 48, 120};
    for (int i = 0; i < 4; i++) {
        uint8_t *b = noisy_copy(a, w, h, amplitudes[i]);
        double s = lc_image_ssim(a, b, w, h);
        printf("  SSIM with noise +-%d: %.4f\n", amplitudes[i], s);
        CHECK(s < previous && s > -1, "SSIM falls with noise: %.4f after %.4f", s, previous);
        previous = s;
        if (i == 1) {
            double direct = ssim_direct(a, b, w, h);
            CHECK_NEAR(s, direct, 1e-9, "separable SSIM vs direct 2D window");
            /* Symmetric in its arguments. */
            CHECK_NEAR(lc_image_ssim(b, a, w, h), s, 1e-12, "SSIM symmetric");
        }
        free(b);
    }

    /* Smaller than the window: one global window; identical images still give 1. */
    uint8_t *small = noise_image(7, 20), *small2 = noisy_copy(small, 7, 20, 30);
    CHECK_NEAR(lc_image_ssim(small, small, 7, 20), 1.0, 1e-12, "small image SSIM(a, a)");
    double s_small = lc_image_ssim(small, small2, 7, 20);
    CHECK(s_small < 1.0 && s_small > -1.0, "small image SSIM %.4f", s_small);
    CHECK_NEAR(lc_image_ssim(a, a, 11, 11), 1.0, 1e-12, "exactly one window");
    free(small), free(small2);

    /* Scoring every test render needs SSIM to stay linear in the pixels (about
     * 0.1 s at 1024^2 optimized). Speed is a benchmark's business, not a
     * test's: the bound only catches a blow-up by orders of magnitude, never a
     * loaded or sanitized machine (it failed at 2 s on a busy 2-core host). */
    const int big = 1024;
    uint8_t *x = gradient_image(big, big), *y = noisy_copy(x, big, big, 10);
    double t0 = lc_now();
    double s_big = lc_image_ssim(x, y, big, big);
    double seconds = lc_now() - t0;
    printf("  SSIM 1024x1024: %.4f in %.3f s\n", s_big, seconds);
    CHECK(seconds < 60.0, "SSIM 1024^2 took %.3f s", seconds);
    free(x), free(y), free(a);
}

int main(void)
{
    test_png_roundtrip();
    test_png_absurd_size();
    test_jpeg();
    test_garbage();
    test_files();
    test_rmse_and_difference();
    test_ssim();
    return lc_test_finish();
}
