// Exact reference, compositing: per output pixel, sort the list and blend
// front to back over the background, C = sum C_i a_i prod_{j<i}(1 - a_j) + T C_bg.
// A compute pass rather than a full-screen fragment pass: see exact.c.
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba8, binding = IMG_EXACT_OUTPUT) writeonly uniform image2D u_output;
uniform ivec2 u_size;
uniform vec3 u_background;
uniform int u_context; // layers: the opaque context's colour replaces the background (p6_resolve.frag.glsl)
layout(binding = TEX_CONTEXT_COLOR) uniform sampler2D u_context_color;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    uint list_length;
    int n = gather_list(p, list_length);
    sort_list(n);
    vec3 color = vec3(0.0);
    float transmittance = 1.0;
    for (int i = 0; i < n; i++) {
        uvec4 node = nodes[list[i].y];
        vec2 rg = unpackUnorm2x16(node.z);
        vec2 ba = unpackUnorm2x16(node.w);
        color += vec3(rg, ba.x) * (ba.y * transmittance);
        transmittance *= 1.0 - ba.y;
        // What remains is far below one 8-bit step of the output.
        if (transmittance < 1e-6)
            break;
    }
    vec3 bg = u_background;
    if (u_context != 0) {
        vec4 k = texelFetch(u_context_color, p, 0);
        bg = k.a > 0.0 ? k.rgb : bg;
    }
    imageStore(u_output, p, vec4(color + bg * transmittance, 1.0));
}
