#pragma once
// Triangle meshes of simple shapes with known distance fields, for tests and benchmarks.
#include <glm/glm.hpp>

#include "scene.h"

namespace rtsdf::reference {

Mesh uv_sphere(glm::vec3 center, float radius, int segments);
Mesh box(glm::vec3 lo, glm::vec3 hi);
// A closed box as CAD exports often leave one: its top face meets a side face
// in a T-junction (a vertex halfway along the side's edge), so two edges are
// used by one triangle each although the surface has no hole.
Mesh cracked_box(glm::vec3 lo, glm::vec3 hi);
// The same surface with every triangle's winding reversed (normals inward).
Mesh inside_out(Mesh mesh);
// One-sided rectangle in the plane z = `z`, split into two triangles.
Mesh sheet(glm::vec2 lo, glm::vec2 hi, float z);
Mesh single_triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c);
// Appends `other` to `mesh` (one mesh, several parts).
void append(Mesh& mesh, const Mesh& other);

// Exact distance from p to the box [lo, hi] (negative inside).
float box_distance(glm::vec3 p, glm::vec3 lo, glm::vec3 hi);

}  // namespace rtsdf::reference
