// Weighted average OIT resolve (weighted_average.glsl) over the background, or
// over the opaque context's colour where it covers the pixel.
layout(binding = TEX_RESOLVE_A) uniform sampler2D u_accum;
layout(binding = TEX_RESOLVE_B) uniform sampler2D u_count;
uniform vec3 u_background;
uniform int u_context;
layout(binding = TEX_CONTEXT_COLOR) uniform sampler2D u_context_color;
out vec4 o_color;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 acc = texelFetch(u_accum, p, 0);
    vec3 bg = u_background;
    if (u_context != 0) {
        vec4 k = texelFetch(u_context_color, p, 0);
        bg = k.a > 0.0 ? k.rgb : bg;
    }
    o_color = vec4(weighted_average_blend(acc.rgb, acc.a, texelFetch(u_count, p, 0).r, bg), 1.0);
}
