// Weighted average OIT (Bavoil & Myers 2008) with the optimized opacities:
// target 0 sums (a c, a), target 1 counts the fragments, both additively.
layout(location = 0) out vec4 o_accum;
layout(location = 1) out vec4 o_count;

void main()
{
    if (outside_primitive())
        discard;
    FLOOR_RETURN
    float alpha = fragment_alpha();
    o_accum = vec4(fragment_color() * alpha, alpha);
    o_count = vec4(1.0, 0.0, 0.0, 0.0);
}
