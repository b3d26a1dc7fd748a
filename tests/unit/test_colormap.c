/* Colormaps: names, clamping, endpoints and published reference values. */
#include <math.h>
#include <string.h>

#include "colormap.h"
#include "lc_params.h"
#include "lc_test.h"

static void check_rgb(int map, float t, double r, double g, double b, double tol, const char *what)
{
    float c[3];
    lc_colormap_sample(map, t, c);
    CHECK(fabs(c[0] - r) <= tol && fabs(c[1] - g) <= tol && fabs(c[2] - b) <= tol,
          "%s at t=%g: (%.6f %.6f %.6f) vs (%.6f %.6f %.6f)", what, t, c[0], c[1], c[2], r, g, b);
}

int main(void)
{
    int n = lc_colormap_count();
    CHECK(n >= 3, "at least three maps, got %d", n);
    const char *required[] = {"viridis", "coolwarm", "grayscale", "inferno", "plasma"};
    for (size_t i = 0; i < sizeof required / sizeof *required; i++) {
        int k = lc_colormap_find(required[i]);
        CHECK(k >= 0, "%s exists", required[i]);
        CHECK(k >= 0 && strcmp(lc_colormap_name(k), required[i]) == 0, "name round trip");
    }
    /* One order everywhere: table i is the i-th name of lc_params.h. */
    CHECK(lc_colormap_count() == LC_COLORMAP_COUNT, "%d tables, %d names", lc_colormap_count(), LC_COLORMAP_COUNT);
    for (int i = 0; i < LC_COLORMAP_COUNT; i++)
        CHECK(lc_colormap_name(i) && strcmp(lc_colormap_name(i), lc_colormap_names[i]) == 0, "colormap %d is %s", i,
              lc_colormap_names[i]);
    CHECK(lc_colormap_find("Viridis") == -1 && lc_colormap_find("jet") == -1, "unknown names");
    CHECK(lc_colormap_find(NULL) == -1, "NULL name");
    CHECK(lc_colormap_name(-1) == NULL && lc_colormap_name(n) == NULL, "name out of range");
    CHECK(lc_colormap_table(n) == NULL, "table out of range");
    float c[3] = {1, 1, 1};
    lc_colormap_sample(n, 0.5f, c);
    CHECK(c[0] == 0 && c[1] == 0 && c[2] == 0, "unknown map samples black");

    int v = lc_colormap_find("viridis");
    /* matplotlib _viridis_data entries 0, 128, 255 (control points, exact) */
    check_rgb(v, 0.0f, 0.267004, 0.004874, 0.329415, 1e-6, "viridis start");
    check_rgb(v, 128.0f / 255, 0.127568, 0.566949, 0.550556, 1e-5, "viridis 128");
    check_rgb(v, 1.0f, 0.993248, 0.906157, 0.143936, 1e-6, "viridis end");
    /* entries between control points: within one 8-bit step */
    check_rgb(v, 42.0f / 255, 0.267968, 0.223549, 0.512008, 1.0 / 255, "viridis 42");
    check_rgb(v, 201.0f / 255, 0.449368, 0.813768, 0.335384, 1.0 / 255, "viridis 201");
    /* clamping and NaN */
    check_rgb(v, -3.0f, 0.267004, 0.004874, 0.329415, 1e-6, "clamp low");
    check_rgb(v, 7.0f, 0.993248, 0.906157, 0.143936, 1e-6, "clamp high");
    check_rgb(v, NAN, 0.267004, 0.004874, 0.329415, 1e-6, "NaN maps to 0");
    /* viridis is monotone in luminance */
    const float *tab = lc_colormap_table(v);
    int monotone = 1;
    for (int k = 1; k < LC_COLORMAP_SIZE; k++) {
        double y0 = 0.2126 * tab[3 * k - 3] + 0.7152 * tab[3 * k - 2] + 0.0722 * tab[3 * k - 1];
        double y1 = 0.2126 * tab[3 * k] + 0.7152 * tab[3 * k + 1] + 0.0722 * tab[3 * k + 2];
        monotone &= y1 > y0;
    }
    CHECK(monotone, "viridis luminance increases");
    /* sample interpolates the table linearly */
    float a[3], b[3], m[3];
    lc_colormap_sample(v, 10.0f / 255, a);
    lc_colormap_sample(v, 11.0f / 255, b);
    lc_colormap_sample(v, 10.5f / 255, m);
    CHECK_NEAR(m[1], 0.5 * (a[1] + b[1]), 1e-6, "linear between entries");

    int cw = lc_colormap_find("coolwarm");
    check_rgb(cw, 0.0f, 0.2298057, 0.298717966, 0.753683153, 1e-6, "coolwarm start");
    check_rgb(cw, 0.5f, 0.865395197, 0.86541021, 0.865395561, 2e-3, "coolwarm mid (grey)");
    check_rgb(cw, 1.0f, 0.705673158, 0.01555616, 0.150232812, 1e-6, "coolwarm end");
    int g = lc_colormap_find("grayscale");
    check_rgb(g, 0.0f, 0, 0, 0, 1e-7, "grayscale black");
    check_rgb(g, 0.25f, 0.25, 0.25, 0.25, 1e-6, "grayscale linear");
    check_rgb(g, 1.0f, 1, 1, 1, 1e-7, "grayscale white");
    check_rgb(lc_colormap_find("inferno"), 0.0f, 0.001462, 0.000466, 0.013866, 1e-6, "inferno start");
    check_rgb(lc_colormap_find("inferno"), 1.0f, 0.988362, 0.998364, 0.644924, 1e-6, "inferno end");
    check_rgb(lc_colormap_find("plasma"), 0.0f, 0.050383, 0.029803, 0.527975, 1e-6, "plasma start");
    check_rgb(lc_colormap_find("plasma"), 1.0f, 0.940015, 0.975158, 0.131326, 1e-6, "plasma end");
    /* every table stays inside [0,1] */
    int inside = 1;
    for (int i = 0; i < n; i++) {
        const float *t = lc_colormap_table(i);
        for (int k = 0; k < 3 * LC_COLORMAP_SIZE; k++)
            inside &= t[k] >= 0.0f && t[k] <= 1.0f;
    }
    CHECK(inside, "tables in [0,1]");
    return lc_test_finish();
}
