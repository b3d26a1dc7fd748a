/* Colour equalization: the equalizing transfer with fixed ranges, its decay
 * over time and the equalized colormap table (DLS Eq. 6-10). */
#include "equalize.h"

#include <math.h>

static int clampi(int v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : v; }

int lc_equalize_target(const double *hist, int bins, const double (*fixed)[2], int fixed_count, float *knots)
{
    if (bins < 1 || fixed_count < 0 || fixed_count > LC_EQUALIZE_MAX_FIXED)
        return -1;
    /* Bin knots that are pinned to the identity: every knot of a fixed range. */
    unsigned char pinned[4 * LC_EQUALIZE_BINS + 1];
    if (bins > 4 * LC_EQUALIZE_BINS)
        return -1;
    for (int b = 0; b <= bins; b++)
        pinned[b] = b == 0 || b == bins;
    for (int i = 0; i < fixed_count; i++) {
        double lo = fixed[i][0], hi = fixed[i][1];
        if (!(lo >= 0 && hi <= 1 && lo <= hi))
            return -1;
        int a = clampi((int)floor(lo * bins), 0, bins), z = clampi((int)ceil(hi * bins), 0, bins);
        for (int b = a; b <= z; b++)
            pinned[b] = 1;
    }
    /* Between consecutive pinned knots p < q the stretch [p, q] is equalized
     * by its bins' weights (a fixed range's stretches are single bins, whose
     * ends stay put: the identity). */
    int p = 0;
    knots[0] = 0.0f;
    for (int q = 1; q <= bins; q++) {
        if (!pinned[q])
            continue;
        double total = 0;
        for (int b = p; b < q; b++)
            total += hist[b] > 0 ? hist[b] : 0;
        double acc = 0;
        for (int b = p + 1; b <= q; b++) {
            acc += hist[b - 1] > 0 ? hist[b - 1] : 0;
            double share = total > 0 ? acc / total : (double)(b - p) / (q - p);
            knots[b] = (float)(((double)p + share * (q - p)) / bins);
        }
        p = q;
    }
    knots[bins] = 1.0f;
    return 0;
}

void lc_equalize_approach(float *knots, const float *target, int bins, double dt, double half_life)
{
    double alpha = half_life > 0 ? 1.0 - exp2(-dt / half_life) : 1.0;
    for (int b = 0; b <= bins; b++)
        knots[b] = (float)(knots[b] * (1.0 - alpha) + target[b] * alpha);
}

float lc_equalize_map(const float *knots, int bins, float c)
{
    if (!(c > 0))
        return knots[0];
    if (c >= 1)
        return knots[bins];
    float x = c * bins;
    int b = (int)x;
    if (b >= bins)
        b = bins - 1;
    float t = x - (float)b;
    return knots[b] * (1 - t) + knots[b + 1] * t;
}

float lc_equalize_inverse(const float *knots, int bins, float x)
{
    if (!(x > knots[0]))
        return 0.0f;
    for (int b = 0; b < bins; b++)
        if (x <= knots[b + 1]) {
            float span = knots[b + 1] - knots[b];
            float t = span > 0 ? (x - knots[b]) / span : 0.0f;
            return ((float)b + t) / (float)bins;
        }
    return 1.0f;
}

void lc_equalize_table(const float *table, int table_size, const float *knots, int bins, float *out, int size)
{
    for (int k = 0; k < size; k++) {
        float f = lc_equalize_map(knots, bins, size > 1 ? (float)k / (float)(size - 1) : 0.0f);
        float x = f * (float)(table_size - 1);
        int i = (int)x;
        if (i >= table_size - 1)
            i = table_size - 2;
        if (i < 0)
            i = 0;
        float t = x - (float)i;
        for (int c = 0; c < 3; c++)
            out[3 * k + c] = table[3 * i + c] * (1 - t) + table[3 * (i + 1) + c] * t;
    }
}
