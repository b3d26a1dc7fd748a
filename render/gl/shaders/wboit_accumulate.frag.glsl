// Weighted blended OIT (McGuire & Bavoil 2013) with the optimized opacities:
// target 0 sums (C a w, a w) additively, target 1 multiplies revealage by (1 - a).
// Depth weight on normalized depth d (nearer counts more), cf. their Eq. 9 family.
layout(location = 0) out vec4 o_accum;
layout(location = 1) out vec4 o_reveal;

void main()
{
    if (outside_primitive())
        discard;
    FLOOR_RETURN
    float alpha = fragment_alpha();
    float d = normalized_depth(v_zview);
    float w = alpha * clamp(3e3 * pow(1.0 - d, 3.0), 1e-2, 3e3);
    o_accum = vec4(fragment_color() * alpha * w, alpha * w);
    o_reveal = vec4(alpha);
}
