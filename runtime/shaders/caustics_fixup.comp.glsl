#version 450 core
// After culling: turn the list length into the indirect dispatch of the
// geometry pass and the vertex count of the draw (6 per primitive, clamped
// to capacity). One flat draw, not one instance per primitive: instancing
// thousands of tiny primitives costs per-instance overhead on some drivers.
layout(local_size_x = 1) in;
layout(std430, binding = 6) buffer Command { uint cmd[]; };
// cmd: [0..3] draw {6 n, 1, 0, 0}, [4] unused; [5..7] dispatch {x, 1, 1}; [8] list length; [9] overflow; [10] n.
uniform uint u_capacity;
void main() {
  uint n = min(cmd[8], u_capacity);
  cmd[0] = 6u * n;  // DrawArraysIndirect {count, instances, first, base instance}
  cmd[1] = 1u;
  cmd[2] = 0u;
  cmd[3] = 0u;
  cmd[4] = 0u;
  cmd[5] = (n + 63u) / 64u;
  cmd[6] = 1u;
  cmd[7] = 1u;
  cmd[10] = n;
}
