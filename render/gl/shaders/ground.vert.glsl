// The ground plane (shadow.c): a square of four world corners, drawn into the
// opaque context like a context layer.
uniform vec3 u_corners[4];
uniform mat4 u_view_proj;

void main() { gl_Position = u_view_proj * vec4(u_corners[gl_VertexID], 1.0); }
