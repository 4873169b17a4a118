// Structs and constants seen by both C++ and GLSL. Keep layouts std430/std140
// compatible: vec4-sized members first, scalars padded to 16 bytes.
#ifndef RTSDF_SHADERS_SHARED_H
#define RTSDF_SHADERS_SHARED_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace rtsdf::gpu {
using uint = std::uint32_t;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
#endif

// A seed voxel index packed as x | y << 10 | z << 20: grids are at most 1024 per axis.
const uint kSeedBits = 10u;
const uint kSeedMask = 1023u;
const uint kNoSeed = 0xFFFFFFFFu;
const uint kMaxGridResolution = 1024u;

// Work-group edge of the 3D compute passes (4x4x4 = 64 invocations).
#define RTSDF_GROUP_EDGE 4

// Voxelization draws one instance at a time; vertices are pulled from storage buffers.
struct VoxelizePush {
  mat4 object_to_voxel;  // object space -> voxel space (voxel i spans [i, i+1))
  ivec4 dims;            // grid dimensions; w = edge of each of the three projection squares
  uint first_index;      // first index of this mesh in the shared index buffer
  uint base_vertex;      // added to every index
  uint pad0;
  uint pad1;
};

struct JumpFloodPush {
  ivec4 dims;  // grid dimensions, w = step in voxels
};

struct SeedDistancePush {
  ivec4 dims;
  vec4 scale;  // x = voxel size (world units), y = beta (world units)
};

#ifdef __cplusplus
static_assert(sizeof(VoxelizePush) == 96, "VoxelizePush layout");
static_assert(sizeof(JumpFloodPush) == 16, "JumpFloodPush layout");
static_assert(sizeof(SeedDistancePush) == 32, "SeedDistancePush layout");
}  // namespace rtsdf::gpu
#endif

#endif
