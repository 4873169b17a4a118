#pragma once
// Which instances can shadow anything. Only those go into the SDFs, and the
// grids are fitted to them: a large ground under the objects would otherwise
// set the voxel size, and the objects whose shadows matter would get few voxels.
#include <cstdint>
#include <vector>

#include "lights.h"
#include "mesh_extent.h"
#include "scene.h"

namespace rtsdf {

// One flag per instance of `scene`: 0 for an instance that cannot occlude any
// light from any surface, 1 otherwise. An instance is left out when
// - its `casts_shadow` is off (Blender's object visibility "Shadow"), or
// - it is flat (a plane, a disc, a thin slab: thickness along some direction
//   at most 1% of its size), every light lies on the far side of its outer
//   face, and so does every other shadow caster, or stands on that face (what
//   sinks behind it lies within the flat instance's extent across: a foot
//   through the floor is hidden under it). A segment from a surface to a
//   light then stays in that half-space and cannot pass through it: a ground
//   under objects lit from above is such a receiver, a wall between the sun
//   and a room is not, nor a ground with something wholly under it.
// Call scene.validate() first.
std::vector<uint8_t> find_shadow_casters(const Scene& scene, const std::vector<Light>& lights);
// The same with the scene's mesh extents at hand (mesh_extents(scene)).
std::vector<uint8_t> find_shadow_casters(const Scene& scene, const std::vector<MeshExtent>& extents,
                                         const std::vector<Light>& lights);

// The world boxes of the instances left out for being flat (casts_shadow on,
// not among `casters`), which still hide the sky behind them: the world
// light's cone marches stop at them (a ground left out of the SDF would
// otherwise show the sky below it to every wall and object above). Only
// boxes thin along a world axis count (a tilted sheet's box would hide far
// too much); at most `max_count`, the largest first.
// `casters` ascending.
std::vector<Bounds> sky_blockers(const Scene& scene, const std::vector<MeshExtent>& extents,
                                 const std::vector<uint32_t>& casters, size_t max_count);

}  // namespace rtsdf
