/* The rMCPD of DLS Eq. 3-4 and the bounds the pruned build tests pairs with,
 * as kernels over lines stored by coordinate (SoA: k x's, then k y's, ...),
 * which the compiler turns into vector code (CMakeLists.txt compiles this
 * file with -O3 -fno-math-errno: sqrt of a sum of squares never sets errno). */
#include "cluster_distance.h"

#define DIM KERNEL_DIM

#include <float.h>
#include <math.h>

void lc_cluster_transpose(const float *aos, int k, float *soa)
{
    for (int s = 0; s < k; s++)
        for (int j = 0; j < DIM; j++)
            soa[j * k + s] = aos[s * DIM + j];
}

/* Squared distances from sample i of a to every sample of b into d[k]; the
 * sum is formed in the order of the original AoS loop, so every kernel gives
 * the same floats. */
static inline void distances(const float *a, int i, const float *b, int k, float *d)
{
    float p0 = a[i], p1 = a[k + i], p2 = a[2 * k + i], p3 = a[3 * k + i], p4 = a[4 * k + i];
    for (int s = 0; s < k; s++) {
        float d0 = p0 - b[s], d1 = p1 - b[k + s], d2 = p2 - b[2 * k + s], d3 = p3 - b[3 * k + s],
              d4 = p4 - b[4 * k + s];
        d[s] = d0 * d0 + d1 * d1 + d2 * d2 + d3 * d3 + d4 * d4;
    }
}

/* The least of d[0..k) (overwrites d): halving while k is even, so that each
 * step is element-wise (vector) code; the value is the minimum whatever the
 * order (no NaN, no -0 among sums of squares). */
static inline float least(float *d, int k)
{
    int n = k;
    while (n > 1 && n % 2 == 0) {
        n /= 2;
        for (int s = 0; s < n; s++)
            d[s] = d[s + n] < d[s] ? d[s + n] : d[s];
    }
    float best = d[0];
    for (int s = 1; s < n; s++)
        best = d[s] < best ? d[s] : best;
    return best;
}

static inline float rmcpd_soa(const float *a, const float *b, int k)
{
    float d[KERNEL_MAX_K], col[KERNEL_MAX_K], row[KERNEL_MAX_K];
    for (int s = 0; s < k; s++)
        col[s] = FLT_MAX;
    for (int i = 0; i < k; i++) {
        distances(a, i, b, k, d);
        for (int s = 0; s < k; s++)
            col[s] = d[s] < col[s] ? d[s] : col[s];
        row[i] = least(d, k);
    }
    double ab = 0, ba = 0;
    for (int i = 0; i < k; i++) {
        ab += sqrt(row[i]);
        ba += sqrt(col[i]);
    }
    return (float)((ab < ba ? ab : ba) / k);
}

float lc_cluster_rmcpd_soa(const float *a, const float *b, int k)
{
    return k == KERNEL_FAST_K ? rmcpd_soa(a, b, KERNEL_FAST_K) : rmcpd_soa(a, b, k);
}

/* d'(a,b) of Eq. 4, or INFINITY as soon as it is known to reach r: the
 * partial sum of closest distances only grows. */
static inline float mean_closest_below(const float *a, const float *b, int k, float r)
{
    float d[KERNEL_MAX_K];
    double sum = 0, limit = (double)r * k;
    for (int i = 0; i < k; i++) {
        distances(a, i, b, k, d);
        sum += sqrt(least(d, k));
        if (sum >= limit)
            return INFINITY;
    }
    return (float)(sum / k);
}

static inline float rmcpd_below(const float *a, const float *b, int k, float r)
{
    float ab = mean_closest_below(a, b, k, r);
    float ba = mean_closest_below(b, a, k, ab < r ? ab : r);
    return ab < ba ? ab : ba;
}

float lc_cluster_rmcpd_below(const float *a, const float *b, int k, float r)
{
    return k == KERNEL_FAST_K ? rmcpd_below(a, b, KERNEL_FAST_K, r) : rmcpd_below(a, b, k, r);
}

/* Sum over the samples of a of their distances to box (lo, hi). */
static inline double box_sum(const float *a, const float *lo, const float *hi, int k)
{
    float t[KERNEL_MAX_K];
    for (int s = 0; s < k; s++)
        t[s] = 0;
    for (int j = 0; j < DIM; j++)
        for (int s = 0; s < k; s++) {
            float v = a[j * k + s], below = lo[j] - v, above = v - hi[j];
            float gap = below > above ? below : above;
            gap = gap > 0 ? gap : 0;
            t[s] += gap * gap;
        }
    for (int s = 0; s < k; s++)
        t[s] = sqrtf(t[s]);
    double sum = 0; /* in order, in double: the bound's value does not depend on the vector width */
    for (int s = 0; s < k; s++)
        sum += t[s];
    return sum;
}

/* min(s_ab, s_ba) / k with s_ab the sum over a's samples of the distance to
 * b's box; `r`: stop at the first direction that is already below it (the
 * caller only asks whether the bound reaches r). */
static inline float lower_bound(const float *a, const float *alo, const float *ahi, const float *b, const float *blo,
                                const float *bhi, int k, float r)
{
    double ab = box_sum(a, blo, bhi, k) / k;
    if (ab < r)
        return (float)ab;
    double ba = box_sum(b, alo, ahi, k) / k;
    return (float)(ab < ba ? ab : ba);
}

float lc_cluster_lower_bound(const float *a, const float *alo, const float *ahi, const float *b, const float *blo,
                             const float *bhi, int k, float r)
{
    return k == KERNEL_FAST_K ? lower_bound(a, alo, ahi, b, blo, bhi, KERNEL_FAST_K, r)
                              : lower_bound(a, alo, ahi, b, blo, bhi, k, r);
}
