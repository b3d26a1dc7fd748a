// P4 over its own recorded fragments (fragment_list.glsl, COMPOSITE_LIST): a
// recording P4 writes no target; one invocation a pixel then walks the
// pixel's chain (last fragment first) and sums what p4_optical_depth.frag.glsl
// would have blended, f = -ln(1 - alpha) projected at the series depth, into
// the coefficient targets (cleared before P4), which P5 over the same chain
// (p5_list.comp.glsl) reads after they are summed over MPI ranks.
layout(local_size_x = 64) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x; }

void main()
{
    ivec2 xy;
    vec4 m;
    uint i = composite_pixel(linear_invocation(), xy, m);
    if (i == FRAGMENT_NONE)
        return; // no fragment: the targets keep their cleared 0
    float sum[NTARGETS * 4];
    for (int j = 0; j < NTARGETS * 4; j++)
        sum[j] = 0.0;
    while (i != FRAGMENT_NONE) {
        uvec4 f = composites[i];
        float c[NTARGETS * 4];
        fourier_project(composite_depth(m, f.y), -log(1.0 - unpack_opacity(f.z)), c);
        for (int j = 0; j < NTARGETS * 4; j++)
            sum[j] += c[j];
        i = f.x;
    }
    store_coefficients(xy, sum);
}
