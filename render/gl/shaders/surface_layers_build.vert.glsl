// Surface layers: a traced curve's vertex to clip space, with its view depth
// and its ghost-particle normal in view space.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_view;
uniform mat4 u_projection;

out float v_depth;
out vec3 v_normal;
flat out uint v_order; // the provoking (last) vertex of a segment: batch vertices run curve by curve

void main()
{
    vec4 pv = u_view * vec4(a_position, 1.0);
    v_depth = -pv.z;
    v_normal = mat3(u_view) * a_normal; // the view is a rigid motion
    v_order = uint(gl_VertexID);
    gl_Position = u_projection * pv;
}
