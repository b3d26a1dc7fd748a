// Ground shadows (docs/ALGORITHM.md §29; OOS §6, a Fourier opacity map): every
// context pixel finds its world position from the context depth, its place in
// the light's map and its depth along the light, and takes the transmittance
// T = exp(-F(d)) of the transparent layers in front of it from the map's
// optical-depth series (blurred 7x7 by shadow_blur.comp.glsl). Its colour becomes
// C (1 - s (1 - T) (1 - K)): s = style.shadow, K the occluders' colour (their
// optical-depth-weighted mean) with style.shadowColored, else black.
layout(binding = TEX_CONTEXT_DEPTH) uniform sampler2D u_receiver_depth;
layout(binding = TEX_CONTEXT_COLOR) uniform sampler2D u_receiver_color;
layout(binding = TEX_SHADOW_COLOR) uniform sampler2D u_shadow_color;
uniform mat4 u_inv_view_proj;   // the camera's clip space to world
uniform mat4 u_light_view;
uniform mat4 u_light_view_proj;
uniform vec2 u_light_depth;     // the bounds' depth range along the light
uniform float u_margin;         // params.depthMargin, as the light pass projected
uniform vec2 u_target_size;
uniform int u_map_size;
uniform float u_shadow;
uniform int u_colored;
out vec4 o_color;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 k = texelFetch(u_receiver_color, p, 0);
    o_color = k;
    if (k.a <= 0.0)
        return;
    float z = texelFetch(u_receiver_depth, p, 0).r;
    vec4 w = u_inv_view_proj * vec4(gl_FragCoord.xy / u_target_size * 2.0 - 1.0, z * 2.0 - 1.0, 1.0);
    vec4 world = vec4(w.xyz / w.w, 1.0);
    vec4 lc = u_light_view_proj * world;
    ivec2 t = ivec2(floor((lc.xy / lc.w * 0.5 + 0.5) * float(u_map_size)));
    float s = (-(u_light_view * world).z - u_light_depth.x) / max(u_light_depth.y - u_light_depth.x, 1e-20);
    float c[NTARGETS * 4];
    for (int j = 0; j < NTARGETS * 4; j++)
        c[j] = 0.0;
    vec4 col = vec4(0.0);
    if (all(greaterThanEqual(t, ivec2(0))) && all(lessThan(t, ivec2(u_map_size)))) {
        read_coefficients(t, c);
        col = texelFetch(u_shadow_color, t, 0);
    }
    // Behind the data's far end along the light every caster is in front: F = A0
    // exactly, where the truncated series would ring; in front of its near end none is.
    float tau = s >= 1.0 ? c[0] : s <= 0.0 ? 0.0 : fourier_eval(c, u_margin + (1.0 - 2.0 * u_margin) * s);
    float T = exp(-max(tau, 0.0));
    vec3 tint = u_colored != 0 && col.a > 0.0 ? col.rgb / col.a : vec3(0.0);
    o_color = vec4(k.rgb * (1.0 - u_shadow * (1.0 - T) * (1.0 - tint)), k.a);
}
