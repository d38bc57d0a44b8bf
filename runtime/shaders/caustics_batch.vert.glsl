// A full-screen triangle in the layer of each map of a batch from
// u_map_base on, an instance a map (prefixed with #version,
// GL_ARB_shader_viewport_layer_array and caustics_batch.glsl): the
// windows and presence passes of a run of the batch's maps in one draw.
uniform uint u_map_base;  // the first map of this draw
flat out uint v_map;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  v_map = u_map_base + uint(gl_InstanceID);
  gl_Layer = int(batch_maps[v_map].ints.x);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
