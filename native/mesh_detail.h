#pragma once
// How finely a mesh's field must resolve it. A field's voxel comes from the
// mesh's own size (its longest side over the resolution setting), which
// leaves the parts of a detailed mesh thinner than a voxel: leaf cards,
// fence slats, branches, a window frame. A field reads such a part as a
// slab a voxel thick on either side, and its shadow leaks or swells. The
// mesh's feature size says how thin its parts and the gaps between them
// are: at sample points spread over its surface by area, the distance
// along the normal, either way, to where the mesh is met again (the shape
// diameter function's probe, both ways, so that open meshes and sheets
// count as well as solids).
#include "bvh.h"
#include "scene.h"

namespace rtsdf {

// The lower quartile of the probes' distances over the mesh's surface, in
// object units; +infinity where fewer than a quarter meet the mesh again
// (a ground plane, a lone card). `bvh`: the mesh's (build_mesh_bvh).
float mesh_feature_size(const Mesh& mesh, const Bvh& bvh);

// The factor on a mesh's resolutions for its detail: its voxel at
// `resolution` voxels on its longest side `longest` set against its feature
// size, so that its thin parts are kVoxelsAcrossFeature voxels across, at
// most kMaxDetailScale times as many voxels as its size alone gives.
float detail_scale(float feature_size, float longest, int resolution);

constexpr float kVoxelsAcrossFeature = 1.0f;
// (2 took the third-party engine's Final row from 0.0254 to 0.0242, but
// its rigid fields' first trace, and so a whole F12 of the ivy sample, to
// 1.2x EEVEE's, and the Archimesh room's Preview row from 0.0057 to 0.0067:
// its window frame, finer, darkened the cones through the window)
constexpr float kMaxDetailScale = 1.5f;

}  // namespace rtsdf
