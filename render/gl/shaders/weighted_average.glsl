// Weighted average OIT (Bavoil & Myers 2008), shared by the datasets' method
// "weighted-average" and the surface layers' count-based baseline: every
// fragment takes the mean opacity and the alpha-weighted mean colour, so
// C = (sum a c / sum a) (1 - (1 - a_mean)^n) + (1 - a_mean)^n C_bg, a_mean = sum a / n.
vec3 weighted_average_blend(vec3 sum_color_alpha, float sum_alpha, float count, vec3 background)
{
    if (!(count > 0.0) || !(sum_alpha > 0.0))
        return background;
    float t = pow(max(1.0 - sum_alpha / count, 0.0), count);
    return sum_color_alpha / sum_alpha * (1.0 - t) + background * t;
}
