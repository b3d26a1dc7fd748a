// P4 over its own recorded fragments (fragment_list.glsl, COMPOSITE_LIST): a
// recording P4 writes no target; one invocation a pixel then walks the
// pixel's chain (last fragment first) and sums what p4_optical_depth.frag.glsl
// would have blended (composite_sums) into the coefficient targets (cleared
// before P4), which P5 over the same chain (p5_list.comp.glsl) reads after
// they are summed over MPI ranks. With one process P5's walk makes the sums
// itself (SUMS_IN_WALK there) and this pass does not run.
layout(local_size_x = 64) in;
uint linear_invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x; }

void main()
{
    ivec2 xy;
    vec3 w;
    uint i = composite_pixel(linear_invocation(), xy, w);
    if (i == FRAGMENT_NONE)
        return; // no fragment: the targets keep their cleared 0
    float sum[NTARGETS * 4];
    composite_sums(i, w, sum);
    store_coefficients(xy, sum);
}
