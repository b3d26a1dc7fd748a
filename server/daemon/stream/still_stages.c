/* The preview stage's stride (still_stages.h). */
#include "still_stages.h"

int lc_still_preview_stride(double full_ms, double budget_ms, int moving_stride)
{
    if (moving_stride <= 1 || full_ms <= 0 || full_ms <= budget_ms)
        return 1;
    int n = 2;
    while (n < moving_stride && full_ms * LC_STILL_THINNED_SHARE(n) > budget_ms)
        n *= 2;
    return n < moving_stride ? n : moving_stride;
}
