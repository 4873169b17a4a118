// Structs and constants seen by both C++ and GLSL. Keep layouts std430/std140
// compatible: vec4-sized members first, scalars padded to 16 bytes (or, in
// push constants, named scalars in groups of four).
#ifndef RTSDF_SHADERS_SHARED_H
#define RTSDF_SHADERS_SHARED_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
namespace rtsdf::gpu {
using uint = std::uint32_t;
using vec2 = glm::vec2;
using vec4 = glm::vec4;
using ivec2 = glm::ivec2;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
using mat3x4 = glm::mat3x4;
#endif

// A seed voxel index packed as x | y << 10 | z << 20: grids are at most 1024 per axis.
const uint kSeedBits = 10u;
const uint kSeedMask = 1023u;
const uint kNoSeed = 0xFFFFFFFFu;
const uint kMaxGridResolution = 1024u;

// Work-group shape of the 3D compute passes (64 invocations). x-major: lavapipe
// runs 8 invocations per SIMD step along x, the fastest-varying image axis, and
// 8x4x2 made a jump-flood pass 2.5x faster than 4x4x4.
#define RTSDF_GROUP_X 8
#define RTSDF_GROUP_Y 4
#define RTSDF_GROUP_Z 2
#ifdef __cplusplus
inline constexpr glm::ivec3 kGroupShape3D{RTSDF_GROUP_X, RTSDF_GROUP_Y, RTSDF_GROUP_Z};
#endif

// Voxelization draws one instance at a time; vertices are pulled from storage buffers.
struct VoxelizePush {
  mat4 object_to_voxel;  // object space -> voxel space (voxel i spans [i, i+1))
  ivec4 dims;            // grid dimensions; w = edge of each of the three projection squares
  uint first_index;      // first index of this mesh in the shared index buffer
  uint base_vertex;      // added to every index
  uint triangle_count;   // triangles of this mesh (the splat's thread count)
  uint pad0;
};

struct JumpFloodPush {
  ivec4 dims;  // grid dimensions, w = step in voxels
};

struct SeedDistancePush {
  ivec4 dims;
  vec4 scale;  // x = voxel size (world units), y = beta (world units)
};

// A BVH node (both levels). count > 0: leaf over primitives [first, first + count);
// count == 0: inner node with children first and first + 1.
struct BvhNode {
  vec4 lo;  // xyz = box minimum, w unused
  vec4 hi;  // xyz = box maximum, w unused
  uint first;
  uint count;
  uint pad0;
  uint pad1;
};

// What a bottom-level BVH node's triangles look like from afar, for fast
// winding numbers (Barill et al. 2018, to first order): their area-weighted
// normals summed, placed at their area-weighted centre. Only triangles of
// pieces that bound a volume count (see native/winding_number.h).
struct WindingDipole {
  vec4 centre;  // xyz = area-weighted centre; w = radius of the ball about it that holds the triangles
  vec4 normal;  // xyz = sum of the triangles' area vectors (half their edges' cross products); w = their area
};

// A placed mesh, as the ray tracer sees it.
struct RayInstance {
  mat4 world_to_object;
  mat4 object_to_world;
  uint blas_root;   // index of the mesh's root in the bottom-level node buffer
  uint mirrored;    // 1 if the transform flips winding (negative determinant)
  uint first_triangle;  // the mesh's triangles in triangle_corners (3 corners each):
  uint triangle_count;  // a triangle index kept from an earlier frame is checked against them
};

// One fine-SDF update (classify, then trace the band).
struct FinePush {
  vec4 rotation;      // unit quaternion turning this frame's ray set
  ivec4 fine_dims;    // w = rays per texel
  vec4 fine_grid;     // xyz = origin, w = voxel size (world)
  ivec4 coarse_dims;  // w = 1 on the first frame (no history)
  vec4 coarse_grid;   // xyz = origin, w = voxel size (world)
  vec4 params;        // x = alpha, y = trace band d (world), z = decay target bias (world), w = ray length (world)
  uvec4 schedule;     // x = interleave K (each band texel is traced every K-th frame), y = frame,
                      // z, w = first and last texel (packed like seeds) of the focus box, see kFineFocused
  vec4 state;         // x = beta (world): coarse value + beta = the distance between voxel and seed centres,
                      // y = this update's flags (kFine*), z = the most any point of the surfaces moved since
                      // the last update (world; kUnknownSurfaceMove where it is not known), w = 0
};
// FinePush::state.y's flags.
const uint kFineFocused = 1u;          // trace every band texel in the focus box and none elsewhere (after a local change)
const uint kFineStill = 2u;            // a still field, tracing only texels still improving
const uint kFineNearSurfaceOnly = 4u;  // only the bricks near the band are classified (fine_bricks_near.comp)
const float kUnknownSurfaceMove = 3.0e38;

#define RTSDF_TRACE_GROUP 64

// Lights, in the units of Cycles' direct light (see native/lights.cpp).
const uint kLightSun = 0u;
const uint kLightPoint = 1u;
const uint kLightSpot = 2u;
const uint kLightArea = 3u;

struct GpuLight {
  vec4 position;   // xyz = world position (not for suns), w = type
  vec4 direction;  // xyz = direction the light shines along, w = tan(angular radius) for suns, else radius (world)
  vec4 radiance;   // rgb = value of a white diffuse surface facing the light at distance 1 (sun: any distance)
  vec4 spot;       // x = cos(half cone angle), y = blend width in cosine, z = 1 for a one-sided emitter (area),
                   // w = 1 for a light that casts no shadow
};

// Per-frame camera data (a uniform buffer, so push constants stay small: on
// lavapipe a storage buffer's read costs every lane a gather, a uniform
// buffer's one load).
const uint kMaxSkyBlockers = 8u;

// The casters whose moved shadows the temporal passes follow, at most (FrameData::shadow_movers).
const uint kMaxShadowMovers = 8u;
const uint kShadowMoverWords = 5u;

struct FrameData {
  mat4 world_to_clip;   // jittered by a sub-pixel offset per accumulation frame
  vec4 camera_position; // xyz; w = 1 for orthographic cameras
  vec4 camera_forward;  // xyz = view direction (for the Depth pass)
  vec4 ambient;         // rgb = world colour (uniform environment light), w = sky blocker count
  // Flat receivers left out of the SDF that still hide the sky (see
  // sky_blockers in native/shadow_casters.h): lo, hi of each world box.
  vec4 sky_blockers[2 * kMaxSkyBlockers];
  // Temporal reuse (shaders/temporal_resolve.comp): this frame's projection
  // without the jitter, and the last frame's camera (its projection without
  // jitter, position and view direction), for the G-buffer's motion.
  mat4 steady_world_to_clip;
  mat4 previous_world_to_clip;
  vec4 previous_camera_position;
  vec4 previous_camera_forward;
  // World box of what moved or deformed among the shadow casters since the
  // last frame (the union of their old and new bounds; lo.w = 0: nothing).
  // Each of them alone is in changed_casters, where they are few.
  vec4 changed_lo, changed_hi;
  // The same over every instance, casting shadows or not (what the camera may
  // have seen move).
  vec4 moved_lo, moved_hi;
  // previous_world_to_clip times the inverse of steady_world_to_clip (the
  // background's motion), made in double precision: the identity where the
  // camera stayed.
  mat4 steady_clip_to_previous_clip;
  // The inverse of steady_world_to_clip, made in double precision (where the
  // temporal passes' background pixels look from).
  mat4 steady_clip_to_world;
  // The shadow casters placed elsewhere since the last frame (moved, turned
  // or scaled), kShadowMoverWords vec4s each: the world box each holds now
  // (lo, hi; lo.w = 1 where its mesh deformed too), then the three rows of
  // its world_to_previous_world (where a point of it now was). A shadow
  // they cast moved with them: its history is where their shadow was
  // (temporal_history.glsl.h, follow_shadow).
  // shadow_counts.x of them; 0 where none moved, or more than
  // kMaxShadowMovers did.
  vec4 shadow_movers[kShadowMoverWords * kMaxShadowMovers];
  // The world boxes (lo, hi) of the casters that stayed, shadow_counts.y of
  // them (one holding them all where they are more than kMaxShadowMovers):
  // a light path that meets none of them is shadowed by what moved alone.
  vec4 still_casters[2 * kMaxShadowMovers];
  // The shadow casters that moved or deformed since the last frame, each
  // one's own part of changed_lo, hi (lo, hi: the union of its old and new
  // bounds), boxes_apart.x of them; 0 where more than kMaxShadowMovers
  // changed, and changed_lo, hi stands for them all. Several objects moving
  // apart (a scene's animation) change little of the space between them,
  // where one box holding them all took in every shadow on the ground.
  vec4 changed_casters[2 * kMaxShadowMovers];
  // The same of moved_lo, hi: every instance that moved or deformed,
  // boxes_apart.y of them.
  vec4 moved_instances[2 * kMaxShadowMovers];
  // x: shadow movers, y: still casters (above); z: the history bits (kHistoryBits) of every
  // instance placed elsewhere since the last frame, casting shadows or not.
  uvec4 shadow_counts;
  // x: changed_casters, y: moved_instances (above).
  uvec4 boxes_apart;
};

// What a G-buffer pixel holds (its position's w, and GBufferPush.base_color.w).
const float kShadedSurface = 1.0;
const float kHoldoutSurface = 2.0;  // a holdout: shaded transparent black (0 where nothing is seen)

// The G-buffer's transforms are affine, each as the three rows of its 3x4
// matrix (the columns of a mat3x4: p' = vec4(p, 1) * rows), so that two of
// them fit the 128 bytes of push constants every Vulkan device has.
struct GBufferPush {
  mat3x4 object_to_world;
  mat3x4 world_to_previous_world;  // where a point of this instance now was in the last frame (its motion)
  vec4 base_color;      // w = kShadedSurface or kHoldoutSurface; rgb where the instance has no materials
  float field_voxel;    // world size of a voxel of the field holding this surface (0: only a receiver, in no field)
  uint first_material;  // its material slots in the scene's materials (the vertices give the slot)
  uint material_count;  // 0: base_color everywhere (and the pipeline without per-vertex material inputs)
  uint history_bit;     // the instance's bit among kHistoryBits (its index modulo them; see the G-buffer's normal.w)
};

// Each pixel's accumulation keeps which instances its samples saw, as bits
// (instance index modulo kHistoryBits) in its second moments' w (a float:
// exact up to 24 bits), and FrameData::shadow_counts.z holds the bits of the
// instances placed elsewhere since the last frame. A pixel whose history saw
// one of them, now showing something else, holds an object that has left it
// (temporal_history.glsl.h, front_moved): its depth alone cannot tell where
// the object lay closer in front of the surface than a pixel's spread of
// depths (ivy on its wall).
const uint kHistoryBits = 24u;

// A material slot as the G-buffer reads it (Material, Texture in scene.h).
struct GpuMaterial {
  vec4 base_color;   // linear RGB
  uint texel_first;  // its image's first texel in the scene's texels
  uint width;        // its image's size in texels; 0: no image
  uint height;
  uint vertex_color;  // 1: base_color times the vertex's colour (where there is no image)
};

// The temporal resolve: history reprojected into the first frame after a change.
struct TemporalPush {
  ivec2 image_size;            // pixels
  int light_count;
  int history_samples;         // the most samples history may stand for
  float clip;                  // history is clipped to the new frame's neighbourhood mean +- this many deviations
  float moved_shadow_clip;     // ... and this many where a moved caster's shadow may have moved (a still
                               // receiver whose shadow changed: the colour, not the surface, moved)
  float moved_shadow_samples;  // the most samples history stands for there
  float depth_tolerance;       // relative depth a reprojected surface may differ by
  float jitter_reach;          // the sub-pixel jitter's reach (whole pixels)
  uint same_lighting;          // 1: the lights and the world are as history saw them (pixels may settle)
  // The converged test (temporal_converged.comp): a pixel whose samples'
  // spread is below this share of its brightness takes no more.
  float noise_threshold;
  uint pad0;
};
// The keep pass lists the tiles of kTemporalTile^2 pixels and the groups of
// kQuadGroup^2 quads where pixels it did not keep lie (kept_tiles.glsl.h).
const uint kTemporalTile = 8u;
const uint kQuadGroup = 8u;
// The most samples history stands for where it matched a pixel's depth only
// within the jitter's reach (temporal_resolve.comp).
const float kNearbyHistorySamples = 3.0;
// accum_passes.z of a pixel whose history the temporal keep pass kept as
// this frame's sample (temporal_keep.comp): the shading passes skip it.
const float kKeptSample = -1.0;
// accum_passes.z of a pixel the keep pass did not keep and whose history may
// stand for one sample or none (history_may_be_short): the shown frame is
// then mostly this frame's sample, and its exact rays are
// ShadePush::short_history_rays times as many (shade_inputs.glsl.h,
// exact_rays_at). The keep pass counts them in the tile words'
// kShortHistoryCountWord (the pixel tiles' indirect dispatch's fourth
// word), for RenderStats::short_history_share.
const float kShortHistorySample = -2.0;
const uint kShortHistoryCountWord = 3u;
// Where a still pixel is in contact with the casters that moved (and is
// shaded anew): within this share of a changed box's diagonal of that box
// (temporal_history.glsl.h, in_contact_with_change).
const float kContactReach = 0.25;

// The depth pass where a pixel sees no surface (the world behind everything).
const float kNothingHitDepth = 1e10;

// What the shading's visibility reads (ShadePush::visibility.x).
const uint kVisibilitySignedSdf = 0u;    // march signed fields: fine SDFs (rtsdf, rtsdf_world, rt_only)
const uint kVisibilityUnsignedSdf = 1u;  // march an unsigned field: the coarse SDF (jfa_only)
const uint kVisibilityShadowMaps = 2u;   // look up EVSM shadow maps (csm_evsm, csm_jitter)
const uint kVisibilityRayTraced = 3u;    // trace rays through the BVH towards a point of each light (raytraced)
const uint kVisibilityHybrid = 4u;       // march signed fields, and where they cannot tell lit from shadowed with
                                         // epsilon to spare, trace rays (the SDF methods with exact_rays > 0)

// Which part of the shading a pipeline runs (its specialization constant 1; see ShadePass).
const uint kShadeFull = 0u;    // every pixel marches its own lights (the world light: from the quad pass)
const uint kShadeShared = 1u;  // every pixel takes all its light from the quad pass; lists those it cannot
const uint kShadeFill = 2u;    // the listed pixels, shaded as kShadeFull
const uint kShadeSkyList = 3u; // (the quad pass) the world light of the quads the quad pass listed

// A distance field as the shadow march reads it (native/packed_field.h,
// shaders/sdf_fields.glsl.h): one device buffer of 32-bit words reached by
// its address. Word 0 counts the stored bricks; words kBrickTableFirst on
// hold one entry per brick of the fine grid (its slot, or kNoBrick); then the
// far field (the coarse grid's distances, x fastest, rows of an even length);
// then the bricks. Distances are in voxels of the fine grid, as half floats,
// two to a word (the lower half first).
// A brick holds 8^3 fine texels, x fastest, and covers the 7^3 cells between
// them: neighbouring bricks share a face of texels, so a trilinear sample
// reads one brick. Bricks are stored where the fine SDF was traced (near
// surfaces); elsewhere the fine SDF holds the coarse distance, which the far
// field gives.
const uint kBrickTexels = 8u;
const uint kBrickCells = 7u;
const uint kBrickWords = 256u;
const uint kBrickTableFirst = 1u;
const uint kNoBrick = 0xFFFFFFFFu;
// Half floats reach 65504: distances are clamped within, in voxels.
const float kMaxPackedDistance = 60000.0;

// A field placed in the world. A transform that scales unevenly stretches
// distances, so they are scaled by the smallest singular value of the
// transform, which never overstates a distance.
struct FieldInstance {
  mat4 world_to_field;  // world -> the field's voxel space (voxel i spans [i, i+1))
  vec4 scale;           // x = world units per voxel (at least), y = world size of a voxel (at most: for
                        // clearances and step limits), z = voxels between the box's faces and what the field
                        // holds (its margin, on every side)
  uvec4 store;          // xy = device address of the field's words, z = first word of the far field,
                        // w = first word of the bricks
  ivec4 dims;           // xyz = the fine grid's texels, w = bricks the store has room for
  ivec4 far_dims;       // xyz = the far field's texels (its grid shares the fine grid's origin), w = its row length
  vec4 box_lo;          // xyz: the part of the field the march reads, in its voxel space: what it holds,
  vec4 box_hi;          // grown by the margin (a grid with room for motion has more, of far values only);
                        // box_lo.w = far-field voxels per fine voxel
};

// Packs a fine SDF and its coarse SDF into a field's words (passes/field_pack).
struct FieldPackPush {
  uvec4 store;        // as FieldInstance.store
  ivec4 dims;         // xyz = the fine grid's texels, w = bricks the store has room for
  ivec4 coarse_dims;  // the far field's (coarse grid's) texels, w = its row length (even)
  vec4 fine_grid;     // xyz = origin, w = voxel size (world)
  vec4 coarse_grid;   // xyz = origin, w = voxel size (world)
  vec4 params;        // x = the trace band (a texel whose coarse distance is at most this was traced),
                      // y = added to the coarse distances (the fine SDF's far field is c + beta)
};

struct ShadePush {
  ivec2 image_size;              // pixels
  int light_count;
  int accumulation_frame;        // 0: the first of an accumulation (no mean to read yet)
  uint visibility_mode;          // kVisibility*
  uint shadow_map_tile_texels;   // texels per side of a shadow-map tile
  uint field_instances;          // fields placed in the scene (0: nothing casts shadows)
  uint max_march_steps;          // shadow_max_steps
  // Distances along the march are in voxels of the field nearest each sample.
  float shadow_epsilon;          // a sample this near a surface blocks the ray
  float max_step;                // the longest step, in voxels
  float receiver_clearance;      // voxels of the receiver's own field a light's march starts along the ray
  float field_reach;             // world: the longest step the march can take anywhere (max_step voxels of the coarsest field)
  float caster_offset;           // a caster's march origin off its surface along the normal (voxels of its field)
  float shadow_map_offset;       // the shadow-map lookup's offset off the surface (texels)
  uint exact_rays;               // rays per light where the field is uncertain (kVisibilityHybrid)
  uint sequence;                 // this frame's index in the jitter sequences: the accumulation frame, counted on
                                 // across frame changes whose history is kept, so reused samples and new ones differ
  vec2 evsm_exponents;           // c+ and c- of the exponential warp
  float light_bleeding_reduction;
  float map_filter_texels;       // filter radius (texels; 0: from a blocker search, as wide as the penumbra)
  uint field_view;               // kDebug*: a view of the fields in place of the image
  float field_view_height;       // the distance slice's world z
  float sky_receiver_clearance;  // ... and the sky's cones
  uint listed_tiles;             // 1: shaded over the tiles a pass listed (kept_tiles.glsl.h): the temporal keep
                                 // pass (pixels marked kKeptSample are not shaded) or the converged test
  uint short_history_rays;       // pixels the keep pass marked kShortHistorySample take this many times exact_rays
  uint pad0;                     // (the block's size a multiple of its vec2's 8 bytes, as in GLSL)
};

// Views of the distance fields in place of the shaded image (ShadePush::field_view; field_views.glsl.h).
const uint kDebugNone = 0u;
const uint kDebugDistanceSlice = 1u;    // the fields' distance on the plane z = debug.y, as a heat map
const uint kDebugMarchSteps = 2u;       // the fields' zero level sphere-traced from the camera, by its steps
const uint kDebugFieldResolution = 3u;  // each surface by its field's voxel against the pixel's footprint
const uint kDebugExactRays = 4u;        // the shaded image, magenta where the hybrid traced rays

// Shadow maps (csm_evsm, csm_jitter). Every view (a sun's cascade, a spot
// light's view, a face of a point or area light's cube) is one square tile of one atlas.
struct ShadowTile {
  mat4 world_to_clip;  // Vulkan clip space of the view (x, y in [-1, 1] across the tile, z in [0, 1])
  vec4 depth_axis;     // view depth (world units) = dot(xyz, p) + w
  vec4 depth_range;    // x = near, y = 1 / (far - near) (view depth), z = world size of a texel at view depth 0, w = its growth per unit depth
  vec4 light;          // the light's size as the penumbra's width follows it: x = tan of a sun's angular radius
                       // (penumbra = x * (receiver - blocker depth)), or a local light's radius (penumbra =
                       // x * (receiver - blocker) / blocker); y = 1 for a local light's view, 0 for a sun's
  ivec4 atlas;         // xy = the tile's first texel in the atlas, z = texels kept clear of its border when picking
                       // it: the filter's widest reach
};

// A light's tiles: [first, first + count), finest first.
struct ShadowLightTiles {
  uint first;
  uint count;
  uint pad0;
  uint pad1;
};

struct ShadowMapPush {
  mat4 object_to_world;
  vec4 evsm;  // x = c+, y = c-
  uint first_index;
  uint base_vertex;
  uint tile;  // index into the tile buffer
  uint pad0;
};

#ifdef __cplusplus
static_assert(sizeof(BvhNode) == 48, "BvhNode layout");
static_assert(sizeof(WindingDipole) == 32, "WindingDipole layout");
static_assert(sizeof(GpuLight) == 64, "GpuLight layout");
static_assert(sizeof(FrameData) == 112 + 32 * kMaxSkyBlockers + 4 * 64 + 6 * 16 + 16 * kShadowMoverWords * kMaxShadowMovers +
                                       3 * 32 * kMaxShadowMovers + 2 * 16,
              "FrameData layout");
static_assert(sizeof(GBufferPush) == 128, "GBufferPush layout");
static_assert(sizeof(GpuMaterial) == 32, "GpuMaterial layout");
static_assert(sizeof(ShadePush) == 104, "ShadePush layout");
// (a vec2 sits on 8 bytes in GLSL's push-constant layout: its offset must agree)
static_assert(offsetof(ShadePush, evsm_exponents) == 64 && offsetof(ShadePush, field_view) == 80, "ShadePush offsets");
static_assert(sizeof(TemporalPush) == 48, "TemporalPush layout");
static_assert(sizeof(FieldInstance) == 160, "FieldInstance layout");
static_assert(sizeof(FieldPackPush) == 96, "FieldPackPush layout");
static_assert(sizeof(ShadowTile) == 128, "ShadowTile layout");
static_assert(sizeof(ShadowLightTiles) == 16, "ShadowLightTiles layout");
static_assert(sizeof(ShadowMapPush) == 96, "ShadowMapPush layout");
static_assert(sizeof(RayInstance) == 144, "RayInstance layout");
static_assert(sizeof(FinePush) == 128, "FinePush layout");
static_assert(sizeof(VoxelizePush) == 96, "VoxelizePush layout");
static_assert(sizeof(JumpFloodPush) == 16, "JumpFloodPush layout");
static_assert(sizeof(SeedDistancePush) == 32, "SeedDistancePush layout");
}  // namespace rtsdf::gpu
#endif

#endif
