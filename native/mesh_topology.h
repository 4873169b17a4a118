#pragma once
// How thick the piece is that each triangle belongs to. The fine SDF takes
// its sign from how many rays meet back faces, which only means "inside" for
// a closed surface: behind a one-sided sheet it would mark a whole band as
// inside. And a closed piece thinner than a voxel has no inside on the grid
// at all, so shadow marches through it never see a negative value. Both are
// better read as thin slabs (see shaders/fine_trace.comp).
#include <cstdint>
#include <vector>

#include "scene.h"

namespace rtsdf {

// One value per triangle of `mesh`: the mean thickness 2 V / A of the
// triangle's connected piece (triangles joined through shared edges,
// vertices matched by position to a millionth of the mesh's size, so a
// triangle soup as STL stores it works too), in the mesh's units: a slab of
// thickness t gives t, a sphere of radius r gives 2r/3. 0 for an open piece
// (an edge used by only one triangle).
std::vector<float> piece_thickness(const Mesh& mesh);

}  // namespace rtsdf
