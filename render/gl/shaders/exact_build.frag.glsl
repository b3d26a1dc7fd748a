// Exact reference, list construction: every fragment of the geometry is
// appended to its pixel's linked list. Pass 0 (optimization resolution)
// stores importance and element, pass 1 (full resolution) opacity and colour.
// A full pool is counted, never written past.
// Pass 1 leaves out fragments below u_reduce_below opacity (Met.3D thesis
// §2.4.1) while the opacity its pixel left out stays within u_reduce_budget:
// removing fragments of opacities a_k changes no channel by more than
// sum a_k, so the image stays within that budget of the full one (exact.c).
#if EXACT_PASS == 1
layout(r32ui, binding = IMG_EXACT_REDUCED) coherent uniform uimage2D u_reduced;
uniform float u_reduce_below; // 0: keep every fragment
uniform uint u_reduce_budget; // in u_reduce_scale units of opacity
uniform float u_reduce_scale;

bool reduce(float alpha)
{
    if (alpha >= u_reduce_below)
        return false;
    ivec2 p = ivec2(gl_FragCoord.xy);
    uint units = uint(alpha * u_reduce_scale + 0.5);
    // Read first: a pixel past its budget stops adding (no wrap in dense pixels).
    if (imageLoad(u_reduced, p).r + units > u_reduce_budget)
        return false;
    uint before = imageAtomicAdd(u_reduced, p, units);
    if (before + units > u_reduce_budget)
        return false; // another fragment took the rest of the budget
    atomicAdd(counters[COUNTER_REDUCED + 1], 1u);
    return true;
}
#endif

void main()
{
    if (outside_primitive())
        discard;
#if EXACT_PASS == 1
    if (reduce(fragment_alpha()))
        return;
#endif
    uint idx = atomicAdd(counters[COUNTER_NODES + u_list_pass], 1u);
    if (idx >= u_pool_capacity) {
        atomicAdd(counters[COUNTER_DROP_POOL + u_list_pass], 1u);
        return;
    }
    uvec4 node;
    node.y = floatBitsToUint(fragment_zview()); // halos pushed back
#if EXACT_PASS == 0
    node.z = floatBitsToUint(fragment_importance());
    node.w = fragment_element();
#else
    // The opacity of P4/P5 (clamped, silhouettes) so that both methods see the same.
    float alpha = fragment_alpha();
    vec3 c = fragment_color();
#ifdef EXACT_EQUALIZE
    // color.equalize: the colour in 10 bits a channel (below the output's 8)
    // makes room for the fragment's colour bin, EXACT_NO_BIN for a halo.
    uvec3 q = uvec3(round(clamp(c, 0.0, 1.0) * 1023.0));
    node.z = q.r | (q.g << 10) | (q.b << 20);
    uint bin = halo_position() >= 0.0 ? EXACT_NO_BIN : uint(clamp(int(clamp(v_cscalar, 0.0, 1.0) * 256.0), 0, 255));
    node.w = (packUnorm2x16(vec2(alpha, 0.0)) & 0xFFFFu) | (bin << 16);
#else
    node.z = packUnorm2x16(c.rg);
    node.w = packUnorm2x16(vec2(c.b, alpha));
#endif
#endif
    node.x = imageAtomicExchange(u_heads, ivec2(gl_FragCoord.xy), idx);
    nodes[idx] = node;
}
