/* The moving frames' quality and size from the link's throughput (stream_fit.h). */
#include "stream_fit.h"

#include <math.h>

/* Bytes over quality 70's, libjpeg-turbo with 4:2:0 chroma below 90 and 4:4:4
 * from 90 (render/image/image.c), hence the step at 90: the mean of the
 * tornado and points demos at 340x266 and 486x380 (docs/ALGORITHM.md). */
static const struct {
    int q;
    double share;
} table[] = {{1, 0.29},  {10, 0.37}, {20, 0.50}, {30, 0.61}, {40, 0.70}, {50, 0.78}, {60, 0.87},
             {70, 1.00}, {80, 1.21}, {85, 1.38}, {89, 1.62}, {90, 2.35}, {95, 3.35}, {100, 7.0}};

double lc_fit_jpeg_share(int q)
{
    int n = (int)(sizeof table / sizeof table[0]);
    if (q <= table[0].q)
        return table[0].share;
    for (int i = 1; i < n; i++)
        if (q <= table[i].q) {
            double t = (double)(q - table[i - 1].q) / (table[i].q - table[i - 1].q);
            return table[i - 1].share + t * (table[i].share - table[i - 1].share);
        }
    return table[n - 1].share;
}

void lc_stream_fit(double rate, double bound, double budget_s, const lc_fit_ref *ref, double pixels, int ceiling,
                   lc_fit *out)
{
    out->quality = ceiling;
    out->scale = 1.0;
    out->target = 0;
    if (!ref || ref->bytes <= 0 || ref->pixels <= 0 || ref->quality < 1 || pixels <= 0)
        return;
    /* The probe grows bytes per pixel: a larger rung of the ladder is no
     * probe, nor is a smaller one a leap in quality (the frame after a
     * gesture's first, larger one would take the ceiling). */
    double sure = bound * budget_s * LC_FIT_SHARE, probe = ref->bytes * LC_FIT_PROBE * pixels / ref->pixels;
    if (ref->still && rate <= 0 && sure <= 0)
        return; /* nothing known of the link: the ceiling */
    out->target = rate > 0 ? rate * budget_s * LC_FIT_SHARE : ref->still ? sure : probe > sure ? probe : sure;
    double per_share = ref->bytes / lc_fit_jpeg_share(ref->quality) * pixels / ref->pixels;
    int floor = ceiling < LC_FIT_MIN_QUALITY ? ceiling : LC_FIT_MIN_QUALITY;
    for (int q = ceiling; q >= floor; q--)
        if (per_share * lc_fit_jpeg_share(q) <= out->target) {
            out->quality = q;
            return;
        }
    out->quality = floor;
    double scale = sqrt(out->target / (per_share * lc_fit_jpeg_share(floor)));
    out->scale = scale < LC_FIT_MIN_SCALE ? LC_FIT_MIN_SCALE : scale;
}
