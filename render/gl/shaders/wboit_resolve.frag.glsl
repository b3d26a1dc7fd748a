// Weighted blended OIT resolve: average colour times coverage over the background.
layout(binding = TEX_RESOLVE_A) uniform sampler2D u_accum;
layout(binding = TEX_RESOLVE_B) uniform sampler2D u_reveal;
uniform vec3 u_background;
out vec4 o_color;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 acc = texelFetch(u_accum, p, 0);
    float reveal = texelFetch(u_reveal, p, 0).r;
    vec3 avg = acc.rgb / max(acc.a, 1e-5);
    o_color = vec4(avg * (1.0 - reveal) + u_background * reveal, 1.0);
}
