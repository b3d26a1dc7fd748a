// Surface layers: every line fragment is appended to its pixel's list for
// this batch (no colour output); the merge pass sorts them into layers.
in float v_depth;
in vec3 v_normal;
flat in uint v_order;

uniform vec3 u_color;
uniform int u_width;

void main()
{
    uint i = atomicAdd(pixels[SURFACE_COUNTER_NODES], 1u);
    if (i >= u_pool_capacity) {
        atomicAdd(pixels[SURFACE_COUNTER_POOL_DROP], 1u);
        return;
    }
    ivec2 p = ivec2(gl_FragCoord.xy);
    uint pix = uint(p.y * u_width + p.x);
    frags[i].depth = v_depth;
    frags[i].color = packUnorm4x8(vec4(u_color, 1.0));
    frags[i].order = v_order;
    frags[i].normal = vec4(v_normal, 0.0);
    frags[i].next = atomicExchange(pixels[heads_at(pix)], i);
}
