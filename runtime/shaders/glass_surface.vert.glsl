// The glass seen by the camera (prefixed with #version and transport.glsl).
// Iwasaki et al. §3 computes the transmitted viewing rays with the light-transport
// table: per vertex, the direction to the eye is the "incident" direction,
// and the table gives where and in which direction the view ray leaves the
// object, with its transmittance and path length (for absorption).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_model;
uniform mat3 u_rotation;
uniform float u_scale;
uniform mat4 u_view_proj;
uniform vec3 u_eye;
uniform vec3 u_glass_absorption;
uniform vec3 u_glass_transmit = vec3(1.0);  // the surface's tint at the two crossings (Material::tint^2)
// Where the pass draws into a window of the frame (the glass view draws
// into a target that covers only the glass's rectangle): NDC x, y scaled
// and offset (identity by default).
uniform vec4 u_ndc_window = vec4(1.0, 1.0, 0.0, 0.0);

out vec3 v_world;
out vec3 v_normal;
out vec3 v_exit;
out vec3 v_exit_dir;
out vec3 v_transmitted;  // T e^(-K path) of the view path

void main() {
  vec3 w = (u_model * vec4(a_position, 1.0)).xyz;
  v_world = w;
  v_normal = u_rotation * a_normal;
  Transport t = ltt_lookup(uint(gl_VertexID), normalize(a_normal), transpose(u_rotation) * normalize(u_eye - w));
  v_exit = t.leaves ? (u_model * vec4(t.exit, 1.0)).xyz : w;
  v_exit_dir = t.leaves ? u_rotation * t.dir : normalize(w - u_eye);
  v_transmitted = t.leaves ? t.transmittance * exp(-u_glass_absorption * t.path * u_scale) * u_glass_transmit : vec3(0.0);
  gl_Position = u_view_proj * vec4(w, 1.0);
  gl_Position.xy = gl_Position.xy * u_ndc_window.xy + u_ndc_window.zw * gl_Position.w;
}
