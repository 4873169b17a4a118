#pragma once
// Inside and outside for meshes as they come: open along seams, cracked,
// overlapping, some parts turned inside out. The generalized winding number
// (Jacobson et al. 2013) is the solid angle a surface subtends at a point
// over 4 pi: 1 inside a closed surface (-1 inside one turned inside out), 0
// outside, and it degrades gracefully at cracks and small holes. Summed over
// interpenetrating parts it counts how many hold the point. The fine SDF is
// negative where |w| > 1/2 (shaders/fine_trace.comp, winding_number.glsl.h). Far from a node of the
// mesh's BVH its triangles act as one dipole (Barill et al. 2018), so a
// point costs a tree walk, not a pass over every triangle.
//
// Sheets (pieces whose thickness is 0, see mesh_topology.h) have no inside
// and are left out: near a sheet w is about 1/2 and says nothing; the fine
// SDF reads such pieces as slabs instead.
#include <vector>

#include "bvh.h"
#include "mesh_topology.h"
#include "scene.h"
#include "shaders/shared.h"

namespace rtsdf {

// One dipole per node of `bvh` (build_mesh_bvh(mesh)), over the triangles
// of pieces with a thickness (mesh_pieces(mesh)), each turned to face out.
std::vector<gpu::WindingDipole> winding_dipoles(const Bvh& bvh, const Mesh& mesh, const Pieces& pieces);

// The winding number at p of the same triangles, summed exactly (the
// reference the dipoles approximate): about 1 inside a piece, whichever way
// its triangles were stored.
double winding_number(const Mesh& mesh, const Pieces& pieces, glm::vec3 p);

}  // namespace rtsdf
