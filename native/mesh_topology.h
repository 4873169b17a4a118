#pragma once
// Which triangles belong to open surfaces. The fine SDF takes its sign from
// how many rays meet back faces, which only means "inside" for a closed
// surface: behind a one-sided sheet it would mark a whole band as inside.
#include <cstdint>
#include <vector>

#include "scene.h"

namespace rtsdf {

// One flag per triangle of `mesh`: 1 when the triangle's connected piece
// (triangles joined through shared edges, vertices matched by position to a
// millionth of the mesh's size, so a triangle soup as STL stores it works
// too) has an edge used by only one triangle, 0 when the piece is closed.
std::vector<uint8_t> open_triangles(const Mesh& mesh);

}  // namespace rtsdf
