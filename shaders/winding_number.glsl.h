// Generalized winding numbers through the bottom-level BVHs (see
// native/winding_number.h): exact solid angles for the triangles of nearby
// leaves, one dipole per node far enough away. Needs ray_trace.glsl.h's
// buffers, and the dipoles at binding RTSDF_WINDING_BINDING.
layout(std430, binding = RTSDF_WINDING_BINDING) readonly buffer WindingDipoles { WindingDipole winding_dipoles[]; };

// A node's dipole stands in for its triangles beyond this many radii (Barill
// et al.'s beta: about 1% of a node's own contribution off, at first order).
const float kDipoleReach = 2.0;
const float kInvFourPi = 0.0795774715;

// The winding number of one mesh (its BVH's root) at p, in the mesh's space.
float mesh_winding_number(uint root, vec3 p) {
  float w = 0.0;
  uint stack[RTSDF_STACK];
  int top = 0;
  stack[top++] = root;
  while (top > 0) {
    uint index = stack[--top];
    WindingDipole dipole = winding_dipoles[index];
    if (dipole.normal.w <= 0.0) continue;  // no triangle of a volume below
    vec3 offset = dipole.centre.xyz - p;
    float distance = length(offset);
    if (distance > kDipoleReach * dipole.centre.w) {
      w += kInvFourPi * dot(dipole.normal.xyz, offset) / (distance * distance * distance);
      continue;
    }
    BvhNode node = bottom_nodes[index];
    if (node.count == 0u) {
      if (top + 2 <= RTSDF_STACK) { stack[top++] = node.first; stack[top++] = node.first + 1u; }
      continue;
    }
    for (uint i = node.first; i < node.first + node.count; ++i) {
      if (!(triangle_corners[3u * i].w > 0.0)) continue;  // a sheet's triangle
      // Van Oosterom and Strackee: the triangle's signed solid angle (turned to face out).
      vec3 a = triangle_corners[3u * i].xyz - p, b = triangle_corners[3u * i + 1u].xyz - p;
      vec3 c = triangle_corners[3u * i + 2u].xyz - p;
      float la = length(a), lb = length(b), lc = length(c);
      w += 2.0 * kInvFourPi * triangle_corners[3u * i + 1u].w *
           atan(dot(a, cross(b, c)), la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb);
    }
  }
  return w;
}

// Whether p lies inside some placed mesh: |w| > 1/2 for one of the instances
// whose bounds hold it (outside its bounds a mesh's volumes have w = 0).
// Instances are taken one by one, so that a mirrored one still counts.
bool inside_scene(vec3 p) {
  uint stack[RTSDF_STACK];
  int top = 0;
  stack[top++] = 0u;
  while (top > 0) {
    BvhNode node = top_nodes[stack[--top]];
    if (any(lessThan(p, node.lo.xyz)) || any(greaterThan(p, node.hi.xyz))) continue;
    if (node.count == 0u) {
      if (top + 2 <= RTSDF_STACK) { stack[top++] = node.first; stack[top++] = node.first + 1u; }
      continue;
    }
    for (uint i = node.first; i < node.first + node.count; ++i) {
      RayInstance inst = instances[i];
      if (abs(mesh_winding_number(inst.blas_root, (inst.world_to_object * vec4(p, 1.0)).xyz)) > 0.5) return true;
    }
  }
  return false;
}
