// The ground plane's colour, unlit: the shadow alone modulates it (shadow_apply.frag.glsl).
uniform vec3 u_ground_color;
out vec4 o_color;

void main() { o_color = vec4(u_ground_color, 1.0); }
