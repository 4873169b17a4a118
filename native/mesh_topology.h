#pragma once
// How thick the piece is that each triangle belongs to. The fine SDF takes
// its sign from which faces rays meet, or from the winding number, and both
// only mean "inside" for a surface that bounds a volume: behind a one-sided
// sheet they would mark a whole band as inside. And a closed piece thinner than a voxel has no inside on the grid
// at all, so shadow marches through it never see a negative value. Both are
// better read as thin slabs (see shaders/fine_trace.comp).
#include <cstdint>
#include <optional>
#include <vector>

#include "scene.h"

namespace rtsdf {

// Two values per triangle of `mesh`. The mean thickness 2 V / A of the
// triangle's connected piece (triangles joined through shared edges,
// vertices matched by position to a millionth of the mesh's size, so a
// triangle soup as STL stores it works too), in the mesh's units: a slab of
// thickness t gives t, a sphere of radius r gives 2r/3. 0 for an open piece:
// a sheet, or a surface with a hole larger than 2% of its area (edges used by
// only one triangle along cracks and T-junctions make no hole: the piece's
// vector area tells, see mesh_topology.cpp).
//
// And whether the triangle faces into its piece: the piece is turned
// inside out (a negative volume, as a part mirrored in a CAD export can be),
// or the triangle is turned against its neighbours (orientation is made
// coherent across edges that two triangles share, see mesh_topology.cpp).
// Such a triangle counts as if its corners ran the other way round.
struct Pieces {
  std::vector<float> thickness;
  std::vector<uint8_t> faces_in;
};
Pieces mesh_pieces(const Mesh& mesh);

// What mesh_pieces finds from the triangles and which vertices share a
// position, not from where they are: each triangle's piece (the index of
// one of its triangles), the way it is turned to run coherently with its
// piece (+1 as stored, -1 reversed), and whether the piece has edges that
// one triangle alone uses (at its piece's index). A mesh that deforms keeps
// its triangles and, as skinning and shape keys move them, which vertices
// meet: its topology is found once and only the thicknesses measured anew
// (finding it was three quarters of a refitted deformed mesh's bottom level).
struct PieceTopology {
  std::vector<uint32_t> piece;
  std::vector<int8_t> turn;
  std::vector<uint8_t> has_boundary;
};
PieceTopology piece_topology(const Mesh& mesh);

// The area of triangle t of `mesh` (in double: the huge coordinates a scene
// may hold do not overflow it).
double triangle_area(const Mesh& mesh, size_t t);

// A mesh's vertices joined where they lie at exactly one position: the
// surface as its field sees it, whatever split its vertices (sharp edges,
// UV seams, the per-corner normals an importer brings). Welded vertices are
// numbered in the order the triangles first use them, so two copies of one
// part with the same triangles weld alike however their split vertices
// were ordered or counted. `vertex_of` maps the mesh's vertices to them.
struct WeldedTriangles {
  std::vector<uint32_t> vertex_of;
  std::vector<uint32_t> indices;  // three welded vertices per triangle
  uint32_t vertex_count = 0;
};
WeldedTriangles weld_by_position(const Mesh& mesh);
// The welded vertices' positions in `mesh` as it is now, from a weld found
// for it before (a deformed mesh keeps its triangles, and skinning and shape
// keys move the vertices that meet alike): none where the vertices joined
// no longer meet, and the weld is to be found again.
std::optional<std::vector<glm::vec3>> welded_positions(const Mesh& mesh, const WeldedTriangles& welded);
// mesh_pieces of `mesh` in the shape it has now, with the topology found before.
Pieces mesh_pieces(const Mesh& mesh, const PieceTopology& topology);

}  // namespace rtsdf
