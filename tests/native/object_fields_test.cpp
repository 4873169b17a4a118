// The object-space fields (rtsdf): one field per mesh shared by its
// instances, rigid motion costs no SDF work, deformation rebuilds only the
// mesh that changed, non-uniform scale stays conservative, and the memory
// budget coarsens fields instead of failing; refined fields are kept for
// later renderers of the same device (FieldCache) and, on disk, for later
// processes (FieldStore).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>

#include "error.h"
#include "field_store.h"
#include "march_fields.h"
#include "mesh_detail.h"
#include "mesh_import.h"
#include "reference/shapes.h"
#include "renderer.h"
#include "vulkan_test.h"

namespace rtsdf {
namespace {

class ObjectFieldsTest : public testing::VulkanTest {};

Camera top_view(float half_size) {
  Camera camera;
  camera.world_to_view = glm::lookAt(glm::vec3(0, 0, 10), glm::vec3(0), glm::vec3(0, 1, 0));
  camera.projection = glm::orthoRH_NO(-half_size, half_size, -half_size, half_size, 0.1f, 20.0f);
  camera.orthographic = true;
  return camera;
}

Light overhead_sun() {
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f));
  sun.energy = 3.0f;
  sun.sun_angle = 0.1f;
  return sun;
}

// A unit sphere (mesh 0), a box (mesh 1) and a ground sheet (mesh 2, left out of the fields).
Scene sphere_box_ground() {
  Scene scene;
  scene.meshes = {reference::uv_sphere({0, 0, 0}, 0.5f, 32), reference::box({-0.3f, -0.3f, -0.3f}, {0.3f, 0.3f, 0.3f}),
                  reference::sheet({-6, -6}, {6, 6}, 0.0f)};
  scene.instances = {{0, glm::translate(glm::mat4(1.0f), {-1.0f, 0, 1.0f})},
                     {1, glm::translate(glm::mat4(1.0f), {1.0f, 0.5f, 0.8f})},
                     {2, glm::mat4(1.0f)}};
  return scene;
}

// The viewport's settings: fields keep their history and refine until converged.
RenderSettings viewport_settings() {
  RenderSettings settings;
  settings.keep_history = true;
  settings.fine.interleave = 4;
  settings.grid_slack = 0.5f;
  settings.samples = 64;
  return settings;
}

// A final render of `scene` (2 samples) from above under the overhead sun.
RenderOutput quick_render(const Scene& scene, float half_size, int size) {
  GpuScene gpu_scene(testing::VulkanTest::context(), scene);
  RenderSettings settings;
  settings.samples = 2;
  Renderer renderer(testing::VulkanTest::context());
  return renderer.render(gpu_scene, top_view(half_size), {overhead_sun()}, glm::vec3(0.1f), size, size, settings);
}

// Draws frames until the fields stop refining (at most `limit`).
void run_until_still(Renderer& renderer, int limit = 40) {
  for (int i = 0; i < limit; ++i) {
    renderer.add_frame();
    if (renderer.stats().last_frame_traced_texels == 0) return;
  }
}

TEST_F(ObjectFieldsTest, RigidMotionTracesNoTexelAndMatchesAFreshRender) {
  Scene scene = sphere_box_ground();
  GpuScene gpu_scene(context(), scene);
  const RenderSettings settings = viewport_settings();
  const Camera camera = top_view(3.0f);
  Renderer renderer(context());
  renderer.begin(gpu_scene, camera, {overhead_sun()}, glm::vec3(0.1f), 96, 96, settings, true);
  EXPECT_EQ(renderer.stats().fields, 2) << "the ground casts no shadow and holds no field";
  EXPECT_EQ(renderer.stats().fields_regenerated, 2);
  renderer.add_frame();
  EXPECT_GT(renderer.stats().last_frame_traced_texels, 0u);
  run_until_still(renderer);
  ASSERT_EQ(renderer.stats().last_frame_traced_texels, 0u) << "a still field stops refining";

  // Move, turn and scale the sphere: only transforms change.
  std::vector<glm::mat4> moved;
  for (const Instance& instance : scene.instances) moved.push_back(instance.object_to_world);
  moved[0] = glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), {-0.4f, -0.8f, 1.2f}), 0.7f, {0, 1, 1}),
                        glm::vec3(1.3f));
  gpu_scene.set_transforms(moved);
  renderer.begin(gpu_scene, camera, {overhead_sun()}, glm::vec3(0.1f), 96, 96, settings, true);
  EXPECT_EQ(renderer.stats().fields_regenerated, 0) << "a rigid motion voxelizes nothing";
  for (int i = 0; i < 8; ++i) {
    renderer.add_frame();
    EXPECT_EQ(renderer.stats().last_frame_traced_texels, 0u) << "a rigid motion traces nothing (frame " << i << ")";
  }
  const RenderOutput after_move = renderer.read();

  // The same scene, uploaded afresh with the sphere already there, its fields converged the same way.
  for (size_t i = 0; i < moved.size(); ++i) scene.instances[i].object_to_world = moved[i];
  GpuScene fresh_scene(context(), scene);
  Renderer fresh(context());
  fresh.begin(fresh_scene, camera, {overhead_sun()}, glm::vec3(0.1f), 96, 96, settings, true);
  run_until_still(fresh);
  fresh.begin(fresh_scene, camera, {overhead_sun()}, glm::vec3(0.1f), 96, 96, settings, true);
  for (int i = 0; i < 8; ++i) fresh.add_frame();
  const RenderOutput reference = fresh.read();
  ASSERT_EQ(after_move.shadow.size(), reference.shadow.size());
  double worst = 0.0, shadowed = 0.0;
  for (size_t i = 0; i < reference.shadow.size(); ++i) {
    worst = std::max(worst, double(std::abs(after_move.shadow[i] - reference.shadow[i])));
    shadowed += reference.shadow[i] < 0.5f;
  }
  EXPECT_GT(shadowed, 100) << "the moved sphere casts a shadow in view";
  EXPECT_LT(worst, 1e-3) << "the moved instance's shadow is where a fresh render puts it";
}

TEST_F(ObjectFieldsTest, InstancesShareOneField) {
  Scene scene;
  scene.meshes = {reference::uv_sphere({0, 0, 0}, 0.2f, 16), reference::sheet({-8, -8}, {8, 8}, 0.0f)};
  for (int i = 0; i < 100; ++i)
    scene.instances.push_back({0, glm::translate(glm::mat4(1.0f), {-5.0f + float(i % 10), -5.0f + float(i / 10), 0.5f})});
  scene.instances.push_back({1, glm::mat4(1.0f)});
  const RenderOutput out = quick_render(scene, 6.0f, 128);
  EXPECT_EQ(out.stats.fields, 1);
  EXPECT_EQ(out.stats.field_instances, 100);
  // Every sphere shadows the ground next to it: more than 100 small shadows' worth of pixels.
  int dark = 0;
  for (float v : out.shadow) dark += v < 0.2f;
  EXPECT_GT(dark, 100 * 3);
}

// Copies of one geometry as separate meshes (as Collada, FBX and OBJ
// importers give each copy of a part, and a duplicate that is not linked)
// share one field, and shade as instances of one mesh do; a copy changed in
// one vertex, or deformed, has its own.
TEST_F(ObjectFieldsTest, MeshesOfOneGeometryShareOneField) {
  Scene copies;
  copies.meshes = {reference::sheet({-8, -8}, {8, 8}, 0.0f)};
  Scene instanced = copies;
  instanced.meshes.push_back(reference::uv_sphere({0, 0, 0}, 0.2f, 16));
  for (int i = 0; i < 16; ++i) {
    const glm::mat4 place = glm::translate(glm::mat4(1.0f), {-3.0f + float(i % 4) * 2.0f, -3.0f + float(i / 4) * 2.0f, 0.5f});
    copies.meshes.push_back(reference::uv_sphere({0, 0, 0}, 0.2f, 16));
    copies.instances.push_back({uint32_t(i + 1), place});
    instanced.instances.push_back({1, place});
  }
  copies.instances.push_back({0, glm::mat4(1.0f)});
  instanced.instances.push_back({0, glm::mat4(1.0f)});
  const RenderOutput shared = quick_render(copies, 5.0f, 96);
  EXPECT_EQ(shared.stats.fields, 1);
  EXPECT_EQ(shared.stats.field_instances, 16);
  const RenderOutput one_mesh = quick_render(instanced, 5.0f, 96);
  float worst = 0.0f;
  for (size_t i = 0; i < shared.shadow.size(); ++i) worst = std::max(worst, std::abs(shared.shadow[i] - one_mesh.shadow[i]));
  EXPECT_LT(worst, 1e-4) << "the copies shade as instances of one mesh";

  // Copies whose vertices differ by rounding (a generator run twice) share
  // too: every vertex of two copies 2e-5 off (5e-5 of their size), a
  // thousandth of a fine voxel.
  Scene rounded = copies;
  for (int copy : {4, 9})
    for (size_t v = 0; v < rounded.meshes[copy].positions.size(); ++v)
      rounded.meshes[copy].positions[v] += glm::vec3(v % 2 ? 2e-5f : -2e-5f, 0.0f, v % 3 ? 1e-5f : 0.0f);
  const RenderOutput near = quick_render(rounded, 5.0f, 96);
  EXPECT_EQ(near.stats.fields, 1);
  EXPECT_EQ(near.stats.field_instances, 16);
  worst = 0.0f;
  for (size_t i = 0; i < near.shadow.size(); ++i) worst = std::max(worst, std::abs(near.shadow[i] - one_mesh.shadow[i]));
  EXPECT_LT(worst, 1e-4) << "near copies shade as instances of one mesh";
  {
    GpuScene near_scene(context(), rounded);
    Renderer near_renderer(context());
    near_renderer.begin(near_scene, top_view(5.0f), {overhead_sun()}, glm::vec3(0.1f), 32, 32, viewport_settings(),
                        true);
    near_renderer.add_frame();
    ASSERT_NE(near_renderer.mesh_field(1), nullptr);
    EXPECT_EQ(near_renderer.mesh_field(4), near_renderer.mesh_field(1)) << "a near copy reads the field it shares";
  }

  copies.meshes[5].positions[0] += glm::vec3(0.0f, 0.0f, 0.01f);  // (one vertex of one copy: 2.5% of its size)
  EXPECT_EQ(quick_render(copies, 5.0f, 96).stats.fields, 2);

  // A copy that deforms leaves the others' field; the same shape again joins it.
  GpuScene gpu_scene(context(), copies);
  Renderer renderer(context());
  RenderSettings settings = viewport_settings();
  auto restart = [&] {
    renderer.begin(gpu_scene, top_view(5.0f), {overhead_sun()}, glm::vec3(0.1f), 32, 32, settings, true);
  };
  restart();
  EXPECT_EQ(renderer.stats().fields, 2);
  gpu_scene.set_mesh_positions(5, copies.meshes[1].positions);
  restart();
  EXPECT_EQ(renderer.stats().fields, 1) << "the changed copy, put back, shares the field again";
  std::vector<glm::vec3> grown = copies.meshes[1].positions;
  for (glm::vec3& p : grown) p *= 1.2f;
  gpu_scene.set_mesh_positions(3, grown);
  restart();
  EXPECT_EQ(renderer.stats().fields, 2) << "a deformed copy has its own field";
  EXPECT_EQ(renderer.stats().fields_regenerated, 1) << "and only it is built";
}

// Importers that bake transforms into the vertices (OBJ has no instances)
// give each copy of a part its own turned and moved vertices: such a copy
// shares the part's field, placed where the copy lies. A mirrored or
// scaled copy is another shape, with a field of its own.
TEST_F(ObjectFieldsTest, TurnedAndMovedCopiesShareOneField) {
  const Mesh part = reference::box({-0.6f, -0.2f, -0.3f}, {0.6f, 0.2f, 0.3f});  // (long: a wrong turn shows)
  const glm::mat4 first = glm::translate(glm::mat4(1.0f), {-1.5f, -0.5f, 1.0f});
  const glm::mat4 turned = glm::translate(glm::mat4(1.0f), {1.0f, 0.8f, 0.9f}) *
                           glm::rotate(glm::mat4(1.0f), glm::radians(40.0f), glm::normalize(glm::vec3(1, 2, 3)));
  auto baked = [&](const glm::mat4& transform) {
    Mesh copy = part;
    for (glm::vec3& p : copy.positions) p = glm::vec3(transform * glm::vec4(p, 1.0f));
    return copy;
  };
  Scene instanced;
  instanced.meshes = {part, reference::sheet({-6, -6}, {6, 6}, 0.0f)};
  instanced.instances = {{0, first}, {0, turned}, {1, glm::mat4(1.0f)}};
  Scene imported;
  imported.meshes = {part, baked(turned), reference::sheet({-6, -6}, {6, 6}, 0.0f)};
  imported.instances = {{0, first}, {1, glm::mat4(1.0f)}, {2, glm::mat4(1.0f)}};

  const RenderOutput one_mesh = quick_render(instanced, 3.0f, 96);
  const RenderOutput copies = quick_render(imported, 3.0f, 96);
  EXPECT_EQ(one_mesh.stats.fields, 1);
  EXPECT_EQ(copies.stats.fields, 1) << "the baked copy shares the part's field";
  float worst = 0.0f, shadowed = 0.0f;
  for (size_t i = 0; i < copies.shadow.size(); ++i) {
    worst = std::max(worst, std::abs(copies.shadow[i] - one_mesh.shadow[i]));
    shadowed += one_mesh.shadow[i] < 0.5f ? 1.0f : 0.0f;
  }
  EXPECT_GT(shadowed, 100.0f) << "both parts cast shadows in view";
  EXPECT_LT(worst, 1e-4) << "the copy shades as the part placed where it lies";

  // The copy's vertices split otherwise (each triangle's own, as STL stores
  // them; an importer's per-corner normals split turned copies apart
  // differently): compared welded, it is still the part.
  Mesh soup = baked(turned);
  soup.positions.clear();
  soup.indices.clear();
  soup.normals.clear();
  for (uint32_t v : part.indices) {
    soup.indices.push_back(uint32_t(soup.positions.size()));
    soup.positions.push_back(glm::vec3(turned * glm::vec4(part.positions[v], 1.0f)));
  }
  ASSERT_NE(soup.positions.size(), part.positions.size());
  imported.meshes[1] = soup;
  const RenderOutput soup_copies = quick_render(imported, 3.0f, 96);
  EXPECT_EQ(soup_copies.stats.fields, 1) << "the copy split otherwise shares the part's field";
  worst = 0.0f;
  for (size_t i = 0; i < soup_copies.shadow.size(); ++i)
    worst = std::max(worst, std::abs(soup_copies.shadow[i] - one_mesh.shadow[i]));
  EXPECT_LT(worst, 1e-4) << "and shades as the part placed where it lies";

  imported.meshes[1] = baked(turned * glm::scale(glm::mat4(1.0f), {-1.0f, 1.0f, 1.0f}));  // (mirrored)
  EXPECT_EQ(quick_render(imported, 3.0f, 96).stats.fields, 2);
  imported.meshes[1] = baked(turned * glm::scale(glm::mat4(1.0f), glm::vec3(1.01f)));  // (1% larger)
  EXPECT_EQ(quick_render(imported, 3.0f, 96).stats.fields, 2);
}

// sphere_box_ground() in a viewport-like render from above, run until its
// fields are still.
struct StillViewport {
  Scene scene = sphere_box_ground();
  GpuScene gpu_scene;
  Renderer renderer;
  explicit StillViewport(const vk::Context& context) : gpu_scene(context, scene), renderer(context) {
    restart();
    run_until_still(renderer);
  }
  // Starts the render afresh after a change, as the viewport does.
  void restart() {
    renderer.begin(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 64, 64, viewport_settings(), true);
  }
};

TEST_F(ObjectFieldsTest, DeformationRebuildsOnlyThatMesh) {
  StillViewport view(context());
  // The same positions again (what Blender sends for an animated object on
  // every frame change) are no deformation.
  view.gpu_scene.set_mesh_positions(0, view.scene.meshes[0].positions);
  EXPECT_EQ(view.gpu_scene.mesh_version(0), 0u);
  view.restart();
  EXPECT_EQ(view.renderer.stats().fields_regenerated, 0);
  std::vector<glm::vec3> grown = view.scene.meshes[0].positions;
  for (glm::vec3& p : grown) p *= 1.2f;
  view.gpu_scene.set_mesh_positions(0, grown);
  view.restart();
  EXPECT_EQ(view.renderer.stats().fields_regenerated, 1) << "only the deformed mesh's field is rebuilt";
  view.renderer.add_frame();
  EXPECT_GT(view.renderer.stats().last_frame_traced_texels, 0u) << "and refined";
}

// A mesh's voxel comes from its size and its detail (mesh_detail.h): a
// plate thinner than its size's voxel gets kMaxDetailScale times the
// resolution that a cube of the same extent gets; once it deforms (traced
// anew every frame) it takes its size's alone.
TEST_F(ObjectFieldsTest, ThinPartsGetFinerVoxelsUnlessTheyDeform) {
  Scene scene;
  scene.meshes = {reference::box({-1, -1, 0}, {1, 1, 0.005f}), reference::box({-1, -1, -1}, {1, 1, 1}),
                  reference::sheet({-6, -6}, {6, 6}, 0.0f)};
  scene.instances = {{0, glm::translate(glm::mat4(1.0f), {-2.5f, 0, 1.0f})},
                     {1, glm::translate(glm::mat4(1.0f), {2.5f, 0, 1.5f})},
                     {2, glm::mat4(1.0f)}};
  GpuScene gpu_scene(context(), scene);
  Renderer renderer(context());
  auto restart = [&] {
    renderer.begin(gpu_scene, top_view(5.0f), {overhead_sun()}, glm::vec3(0.1f), 32, 32, viewport_settings(), true);
  };
  auto voxel = [&](uint32_t mesh) {
    for (const FieldMemory& f : renderer.stats().per_field)
      if (f.mesh == mesh) return f.voxel_size;
    return 0.0f;
  };
  restart();
  ASSERT_GT(voxel(1), 0.0f);
  // (within the grids' margins, a few voxels that depend on the resolution)
  EXPECT_NEAR(voxel(0), voxel(1) / kMaxDetailScale, 0.1f * voxel(1) / kMaxDetailScale)
      << "the plate: the cube's voxel over the factor's cap";
  std::vector<glm::vec3> bent = scene.meshes[0].positions;
  bent[0].z += 0.01f;
  gpu_scene.set_mesh_positions(0, bent);
  restart();
  EXPECT_GE(voxel(0), 0.999f * voxel(1)) << "a deforming plate: no finer than its size's voxel";
}

// Slats thinner than their size's voxel with gaps as wide as they are, high
// above the ground under a sun at an angle: the field alone (no exact rays)
// lets the light through the gaps onto the ground beside them as the exact
// rays do. Read as slabs a voxel thick on either side at their size's
// resolution, they narrowed the gaps.
TEST_F(ObjectFieldsTest, LightPassesBetweenSlatsThinnerThanAVoxel) {
  Scene scene;
  Mesh slats;
  for (int i = 0; i < 10; ++i) {
    const float x = -1.0f + 0.2f * float(i);
    reference::append(slats, reference::box({x, -1.0f, 3.0f}, {x + 0.1f, 1.0f, 3.003f}));
  }
  scene.meshes = {slats, reference::sheet({-6, -6}, {6, 6}, 0.0f)};
  scene.instances = {{0, glm::mat4(1.0f)}, {1, glm::mat4(1.0f)}};
  Light sun;
  sun.type = LightType::Sun;
  sun.direction = glm::normalize(glm::vec3(-0.75f, 0.0f, -1.0f));  // (the slats' shadow 2.25 along -x)
  sun.energy = 3.0f;
  sun.sun_angle = 0.005f;
  Camera camera;  // (over the ground in the slats' shadow, beside them)
  camera.world_to_view = glm::lookAt(glm::vec3(-2.3f, 0, 10), glm::vec3(-2.3f, 0, 0), glm::vec3(0, 1, 0));
  camera.projection = glm::orthoRH_NO(-0.7f, 0.7f, -0.7f, 0.7f, 0.1f, 20.0f);
  camera.orthographic = true;
  auto lit_share = [&](ShadowMethod method) {
    GpuScene gpu_scene(context(), scene);
    RenderSettings settings;
    settings.shadow_method = method;
    settings.exact_rays = 0;
    settings.coarse_resolution = 32;
    settings.fine_resolution = 48;
    settings.samples = 16;
    Renderer renderer(context());
    const RenderOutput out = renderer.render(gpu_scene, camera, {sun}, glm::vec3(0.0f), 96, 96, settings);
    double lit = 0.0;
    for (float v : out.shadow) lit += v;
    return lit / double(out.shadow.size());
  };
  const double exact = lit_share(ShadowMethod::RayTraced), field = lit_share(ShadowMethod::Rtsdf);
  EXPECT_GT(exact, 0.4);
  EXPECT_LT(exact, 0.6);
  EXPECT_NEAR(field, exact, 0.045) << "the ground's lit share in the slats' shadow";
}

// New geometry in place: the box's quads split along their other diagonals
// (as Blender retriangulates a bending quad) and new normals.
TEST_F(ObjectFieldsTest, NewTrianglesReplaceTheMeshInPlace) {
  StillViewport view(context());
  GpuScene& gpu_scene = view.gpu_scene;
  const uint64_t scene_id = gpu_scene.id();

  Mesh box = view.scene.meshes[1];
  box.normals.assign(box.positions.size(), glm::vec3(0, 0, 1));
  gpu_scene.set_mesh(1, box);
  EXPECT_EQ(gpu_scene.mesh_version(1), 0u) << "new normals alone are no new shape";

  // Each quad (two triangles a b c, a c d) split along b d instead.
  for (size_t t = 0; t + 5 < box.indices.size(); t += 6) {
    const uint32_t a = box.indices[t], b = box.indices[t + 1], c = box.indices[t + 2], d = box.indices[t + 5];
    box.indices[t] = a, box.indices[t + 1] = b, box.indices[t + 2] = d;
    box.indices[t + 3] = b, box.indices[t + 4] = c, box.indices[t + 5] = d;
  }
  box.indices.resize(box.indices.size() - 3);  // and one triangle fewer: any count goes
  gpu_scene.set_mesh(1, box);
  EXPECT_EQ(gpu_scene.mesh_version(1), 1u);
  EXPECT_EQ(gpu_scene.id(), scene_id);
  EXPECT_EQ(gpu_scene.scene().meshes[1].triangle_count(), box.triangle_count());
  view.restart();
  EXPECT_EQ(view.renderer.stats().fields_regenerated, 1) << "only the box's field is rebuilt";
  view.renderer.add_frame();
  EXPECT_GT(view.renderer.stats().last_frame_traced_texels, 0u);
}

// How far a mesh's surface moved since a version (what a deforming mesh's
// field is told at each update): the sum of the shape changes' largest
// vertex moves since then, and infinite across new triangles.
TEST_F(ObjectFieldsTest, AMeshsSurfaceMoveSinceAVersionSumsItsLargestVertexMoves) {
  StillViewport view(context());
  GpuScene& gpu_scene = view.gpu_scene;
  Mesh box = view.scene.meshes[1];
  double moved = -1.0;
  const double start = gpu_scene.mesh_move_since(1, 0, 0.0, moved);
  EXPECT_EQ(moved, 0.0);

  box.positions[0].x += 0.25f;  // (one corner: the largest move)
  for (size_t v = 1; v < box.positions.size(); ++v) box.positions[v].z += 0.1f;
  gpu_scene.set_mesh(1, box);
  box.positions[2].y -= 0.5f;
  gpu_scene.set_mesh(1, box);
  const uint64_t version = gpu_scene.mesh_version(1);
  const double travel = gpu_scene.mesh_move_since(1, 0, start, moved);
  EXPECT_NEAR(moved, 0.25 + 0.5, 1e-6);
  gpu_scene.mesh_move_since(1, version, travel, moved);
  EXPECT_EQ(moved, 0.0) << "nothing moved since";

  box.positions[3].x += 0.125f;
  gpu_scene.set_mesh(1, box);
  gpu_scene.mesh_move_since(1, version, travel, moved);
  EXPECT_NEAR(moved, 0.125, 1e-6);

  std::swap(box.indices[0], box.indices[1]);  // (a triangle turned round: new triangles)
  gpu_scene.set_mesh(1, box);
  gpu_scene.mesh_move_since(1, version, travel, moved);
  EXPECT_TRUE(std::isinf(moved));
}

// A still field retraces only its texels still improving (FineTraceSettings::
// skip_converged): about half the rays, and the shadows of a CAD part and of
// leaf cards (thin pieces, read as slabs) no further from raytraced's than
// with every texel retraced.
TEST_F(ObjectFieldsTest, SkippingConvergedTexelsKeepsTheShadowsForFewerRays) {
  Scene scene;
  Scene part = import_scene(testing::test_mesh_path());
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : part.meshes[0].positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const glm::vec3 extent = hi - lo;
  const float fit = 1.6f / std::max(extent.x, std::max(extent.y, extent.z));
  scene.meshes = {part.meshes[0], reference::sheet({-6, -6}, {6, 6}, 0.0f)};
  scene.instances = {{0, glm::translate(glm::mat4(1.0f), {-0.6f, 0, 0.4f}) * glm::scale(glm::mat4(1.0f), glm::vec3(fit)) *
                             glm::translate(glm::mat4(1.0f), -0.5f * (lo + hi))},
                     {1, glm::mat4(1.0f)}};
  for (int i = 0; i < 4; ++i) {
    scene.meshes.push_back(reference::sheet({-0.15f, -0.15f}, {0.15f, 0.15f}, 0.0f));
    const glm::mat4 place = glm::translate(glm::mat4(1.0f), glm::vec3(0.9f + 0.2f * (i % 2), -0.9f + 0.5f * i, 0.7f));
    scene.instances.push_back({uint32_t(i + 2), place * glm::rotate(glm::mat4(1.0f), 0.4f * float(i), glm::vec3(1, 0, 0))});
  }
  GpuScene gpu_scene(context(), scene);
  Light sun = overhead_sun();
  sun.sun_angle = 0.05f;
  auto render = [&](ShadowMethod method, int samples, bool skip_converged) {
    RenderSettings settings;
    settings.shadow_method = method;
    settings.samples = samples;
    settings.fine.skip_converged = skip_converged;
    Renderer renderer(context());
    return renderer.render(gpu_scene, top_view(2.0f), {sun}, glm::vec3(0.0f), 96, 96, settings);
  };
  const std::vector<float> exact = render(ShadowMethod::RayTraced, 64, false).shadow;
  auto error = [&](const std::vector<float>& shadow) {  // mean |shadow - exact| where either shows a shadow
    double sum = 0.0;
    int count = 0;
    for (size_t i = 0; i < exact.size(); ++i)
      if (std::min(exact[i], shadow[i]) < 0.9f) sum += std::abs(shadow[i] - exact[i]), ++count;
    EXPECT_GT(count, 400) << "shadows in view";
    return sum / std::max(count, 1);
  };
  const RenderOutput full = render(ShadowMethod::Rtsdf, 8, false), skipping = render(ShadowMethod::Rtsdf, 8, true);
  const double full_error = error(full.shadow), skipping_error = error(skipping.shadow);
  std::printf("mean |visibility - raytraced's| in the shadows: retracing every texel %.4f (%lu texels traced), "
              "skipping converged ones %.4f (%lu)\n",
              full_error, (unsigned long)full.stats.traced_texels, skipping_error,
              (unsigned long)skipping.stats.traced_texels);
  EXPECT_LE(skipping_error, full_error + 0.01);
  EXPECT_LE(double(skipping.stats.traced_texels), 0.6 * double(full.stats.traced_texels));
}

// A scaled sphere's shadow against the same ellipsoid baked into the mesh
// (exact distances): the conservative scale loses no shadow.
TEST_F(ObjectFieldsTest, NonUniformScaleLosesNoShadow) {
  const glm::vec3 stretch(2.0f, 0.6f, 0.35f);
  const glm::mat4 place = glm::translate(glm::mat4(1.0f), {0, 0, 1.0f});
  auto shadow_of = [&](bool baked) {
    Scene scene;
    Mesh sphere = reference::uv_sphere({0, 0, 0}, 0.5f, 48);
    if (baked)
      for (glm::vec3& p : sphere.positions) p *= stretch;
    scene.meshes = {sphere, reference::sheet({-6, -6}, {6, 6}, 0.0f)};
    scene.instances = {{0, baked ? place : glm::scale(place, stretch)}, {1, glm::mat4(1.0f)}};
    GpuScene gpu_scene(context(), scene);
    RenderSettings settings;
    settings.samples = 8;
    Renderer renderer(context());
    return renderer.render(gpu_scene, top_view(1.5f), {overhead_sun()}, glm::vec3(0.0f), 96, 96, settings).shadow;
  };
  const std::vector<float> scaled = shadow_of(false), baked = shadow_of(true);
  int umbra = 0, lost = 0;
  for (size_t i = 0; i < baked.size(); ++i) {
    if (baked[i] > 0.1f) continue;
    umbra++;
    lost += scaled[i] > 0.5f;
  }
  EXPECT_GT(umbra, 200);
  EXPECT_EQ(lost, 0) << "umbra pixels of the exact ellipsoid lit under the scaled sphere";
}

TEST_F(ObjectFieldsTest, RefinedRigidFieldsKeepOnlyTheirBricks) {
  GpuScene gpu_scene(context(), sphere_box_ground());
  RenderSettings settings;
  settings.samples = 6;  // past the fields' 4 updates
  Renderer renderer(context());
  const RenderOutput out = renderer.render(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 64, 64, settings);
  EXPECT_FALSE(renderer.refining());
  EXPECT_GT(out.stats.stored_bricks, 0u);
  EXPECT_LT(out.stats.stored_bricks, out.stats.brick_count) << "bricks only near the surfaces";
  EXPECT_GT(out.stats.field_peak_mb, 2.0 * out.stats.field_mb) << "the SDFs are freed once refined";
  EXPECT_LE(out.stats.field_mb, out.stats.field_dense_mb / 4.0);
  std::printf("fields: %.2f MB (peak %.2f, dense %.2f), %llu of %llu bricks stored\n", out.stats.field_mb,
              out.stats.field_peak_mb, out.stats.field_dense_mb, (unsigned long long)out.stats.stored_bricks,
              (unsigned long long)out.stats.brick_count);
}

TEST_F(ObjectFieldsTest, OverBudgetFieldsAreCoarsenedNotRefused) {
  GpuScene gpu_scene(context(), sphere_box_ground());
  RenderSettings settings;
  settings.samples = 2;
  Renderer renderer(context());
  const RenderOutput full = renderer.render(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 64, 64, settings);
  EXPECT_FLOAT_EQ(full.stats.resolution_scale, 1.0f);
  settings.field_budget_mb = 8.0;
  const RenderOutput small = renderer.render(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 64, 64, settings);
  EXPECT_LT(small.stats.resolution_scale, 1.0f);
  EXPECT_LE(small.stats.field_peak_mb, 8.0);
  EXPECT_GT(full.stats.field_peak_mb, 8.0);
  EXPECT_LE(small.stats.field_mb, small.stats.field_peak_mb);
  int dark = 0;
  for (float v : small.shadow) dark += v < 0.2f;
  EXPECT_GT(dark, 50) << "coarser fields still cast shadows";
  settings.field_budget_mb = 0.0;
  EXPECT_THROW(renderer.render(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 64, 64, settings), Error);
}

// A model in parts (a CAD assembly imported as its parts) gives each part a
// field at its own size's resolution: together they would hold many times
// the surface voxels of the model's field as one mesh, and cost as much more
// to trace. Their resolutions are lowered alike to the surface voxel
// budget, and the parts still shade as the model in one piece does.
TEST_F(ObjectFieldsTest, AModelInManyPartsIsTracedWithinTheSurfaceBudget) {
  Scene parts, one_piece;
  Mesh merged;
  for (int i = 0; i < 8; ++i) {  // (boxes side by side, each a little taller: eight meshes)
    const glm::vec3 lo(-0.6f + 0.3f * float(i % 4), -0.3f + 0.3f * float(i / 4), 1.0f);
    const Mesh part = reference::box(lo, lo + glm::vec3(0.3f, 0.3f, 0.3f + 0.02f * float(i)));
    parts.meshes.push_back(part);
    parts.instances.push_back({uint32_t(i), glm::mat4(1.0f)});
    for (uint32_t v : part.indices) merged.indices.push_back(v + uint32_t(merged.positions.size()));
    merged.positions.insert(merged.positions.end(), part.positions.begin(), part.positions.end());
  }
  one_piece.meshes = {merged};
  one_piece.instances = {{0, glm::mat4(1.0f)}};
  for (Scene* scene : {&parts, &one_piece}) {
    scene->meshes.push_back(reference::sheet({-6, -6}, {6, 6}, 0.0f));
    scene->instances.push_back({uint32_t(scene->meshes.size() - 1), glm::mat4(1.0f)});
  }
  const RenderOutput in_parts = quick_render(parts, 1.5f, 96);
  const RenderOutput whole = quick_render(one_piece, 1.5f, 96);
  EXPECT_EQ(in_parts.stats.fields, 8);
  EXPECT_LT(in_parts.stats.resolution_scale, 0.9f) << "eight boxes at a box's resolution each are over the budget";
  EXPECT_TRUE(in_parts.stats.surface_limited);
  EXPECT_FLOAT_EQ(whole.stats.resolution_scale, 1.0f) << "the same boxes as one mesh are within it";
  int shadowed = 0, apart = 0;
  for (size_t i = 0; i < whole.shadow.size(); ++i) {
    shadowed += whole.shadow[i] < 0.5f;
    apart += std::abs(in_parts.shadow[i] - whole.shadow[i]) > 0.5f;
  }
  std::printf("parts at %.0f%% of their resolution; %d of %d shadowed pixels apart\n",
              100.0 * in_parts.stats.resolution_scale, apart, shadowed);
  EXPECT_GT(shadowed, 300) << "the boxes' shadow is in view";
  EXPECT_LT(apart, shadowed / 50) << "the parts shade as the model in one piece";
}

TEST_F(ObjectFieldsTest, FlattenedInstanceIsCountedAndTheRestRenders) {
  Scene scene = sphere_box_ground();
  scene.instances[0].object_to_world = glm::scale(scene.instances[0].object_to_world, {1.0f, 1.0f, 0.0f});
  const RenderOutput out = quick_render(scene, 3.0f, 64);
  EXPECT_EQ(out.stats.skipped_degenerate, 1);
  EXPECT_EQ(out.stats.field_instances, 1) << "the box still casts its shadow";
}

// Small fields, and 6 samples: past the fields' 4 updates.
RenderSettings small_fields() {
  RenderSettings settings;
  settings.coarse_resolution = 32;
  settings.fine_resolution = 48;
  settings.samples = 6;
  return settings;
}

// Renders `scene` as F12 does, with a renderer of its own on `cache`.
RenderOutput render_with(const std::shared_ptr<FieldCache>& cache, const Scene& scene,
                         const RenderSettings& settings = small_fields()) {
  GpuScene gpu_scene(testing::VulkanTest::context(), scene);
  Renderer renderer(testing::VulkanTest::context(), cache);
  return renderer.render(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 48, 48, settings);
}

double largest_difference(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0.0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, double(std::abs(a[i] - b[i])));
  return a.size() == b.size() ? worst : 1e9;
}

// A mesh that deforms again and again keeps its place in the scene's buffers
// (its vertices, its BVH in the range reserved at its first deformation):
// each frame renders as a fresh upload of the deformed scene does, its
// shadow through the rebuilt BVH and its surface through the rewritten vertices.
TEST_F(ObjectFieldsTest, ADeformingMeshRewrittenInPlaceRendersAsAFreshUpload) {
  Scene scene = sphere_box_ground();
  GpuScene gpu_scene(context(), scene);
  RenderSettings settings;
  settings.samples = 2;
  settings.shadow_method = ShadowMethod::RayTraced;
  Renderer renderer(context());
  const glm::mat4 deformations[] = {glm::scale(glm::mat4(1.0f), {1.3f, 1.0f, 1.0f}),
                                    glm::scale(glm::mat4(1.0f), {0.7f, 1.4f, 0.9f}),
                                    glm::translate(glm::mat4(1.0f), {0.4f, -0.2f, 0.1f})};
  for (const glm::mat4& deformation : deformations) {
    for (glm::vec3& p : scene.meshes[0].positions) p = glm::vec3(deformation * glm::vec4(p, 1.0f));
    gpu_scene.set_mesh_positions(0, scene.meshes[0].positions);
    const RenderOutput in_place = renderer.render(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 64, 64, settings);
    GpuScene fresh_scene(context(), scene);
    Renderer fresh_renderer(context());
    const RenderOutput fresh = fresh_renderer.render(fresh_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 64, 64, settings);
    EXPECT_LT(largest_difference(in_place.combined, fresh.combined), 1e-4);
    EXPECT_LT(largest_difference(in_place.shadow, fresh.shadow), 1e-4);
  }
  EXPECT_EQ(gpu_scene.mesh_version(0), 3u);
}

TEST_F(ObjectFieldsTest, ANewRendererTakesRefinedFieldsAndTracesNothing) {
  auto cache = std::make_shared<FieldCache>(size_t(64) << 20);
  const RenderOutput first = render_with(cache, sphere_box_ground());
  EXPECT_EQ(first.stats.fields_regenerated, 2);
  EXPECT_EQ(first.stats.fields_reused, 0);
  EXPECT_EQ(cache->size(), 2u) << "both refined fields are kept";

  // The next frame of an animation render: the sphere moved, nothing deformed.
  Scene moved = sphere_box_ground();
  moved.instances[0].object_to_world = glm::rotate(glm::translate(glm::mat4(1.0f), {-0.5f, -0.7f, 1.1f}), 0.6f, {1, 0, 0});
  const RenderOutput next = render_with(cache, moved);
  EXPECT_EQ(next.stats.fields_reused, 2);
  EXPECT_EQ(next.stats.fields_regenerated, 0);
  EXPECT_EQ(next.stats.traced_texels, 0u) << "a taken field is traced no further";

  // What a renderer of its own shows once its fields are refined: its second render of the scene.
  GpuScene gpu_scene(context(), moved);
  Renderer own(context());
  own.render(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 48, 48, small_fields());
  const RenderOutput refined = own.render(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 48, 48, small_fields());
  EXPECT_EQ(refined.stats.fields_regenerated, 0);
  int shadowed = 0;
  for (float v : refined.shadow) shadowed += v < 0.5f;
  EXPECT_GT(shadowed, 30);
  EXPECT_LT(largest_difference(next.shadow, refined.shadow), 1e-3) << "a taken field is the field it would have built";
}

// A renderer that takes every field refined from the cache, and casts no
// exact ray, builds no BVH: the meshes' feature sizes, whose probe builds
// one, come from the cache too.
TEST_F(ObjectFieldsTest, ARendererThatTakesEveryFieldBuildsNoBvh) {
  auto cache = std::make_shared<FieldCache>(size_t(64) << 20);
  render_with(cache, sphere_box_ground());
  GpuScene gpu_scene(context(), sphere_box_ground());
  Renderer renderer(context(), cache);
  const RenderOutput next = renderer.render(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 48, 48, small_fields());
  EXPECT_EQ(next.stats.fields_reused, 2);
  EXPECT_EQ(gpu_scene.bvh_build_ms(), 0.0) << "no BVH built";
}

TEST_F(ObjectFieldsTest, OtherGeometryOrSettingsBuildTheirOwnField) {
  auto cache = std::make_shared<FieldCache>(size_t(64) << 20);
  render_with(cache, sphere_box_ground());
  RenderSettings fewer_rays = small_fields();
  fewer_rays.fine.rays_per_texel = 4;
  const RenderOutput other_settings = render_with(cache, sphere_box_ground(), fewer_rays);
  EXPECT_EQ(other_settings.stats.fields_reused, 0);
  EXPECT_EQ(other_settings.stats.fields_regenerated, 2);

  Scene grown = sphere_box_ground();
  for (glm::vec3& p : grown.meshes[0].positions) p *= 1.1f;
  const RenderOutput other_sphere = render_with(cache, grown);
  EXPECT_EQ(other_sphere.stats.fields_reused, 1) << "the box is the same";
  EXPECT_EQ(other_sphere.stats.fields_regenerated, 1) << "the sphere is another";
}

TEST_F(ObjectFieldsTest, AKeptFieldIsNeverWrittenByTheRendererThatTookIt) {
  auto cache = std::make_shared<FieldCache>(size_t(64) << 20);
  render_with(cache, sphere_box_ground());
  const RenderOutput taken = render_with(cache, sphere_box_ground());
  ASSERT_EQ(taken.stats.fields_reused, 2);

  // A viewport (keeping history, with room for deformation) takes the
  // fields, then the sphere deforms there and its field is rebuilt and refined.
  Scene scene = sphere_box_ground();
  GpuScene gpu_scene(context(), scene);
  Renderer viewport(context(), cache);
  RenderSettings settings = small_fields();
  settings.keep_history = true;
  settings.grid_slack = 0.5f;
  viewport.begin(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 48, 48, settings, true);
  EXPECT_EQ(viewport.stats().fields_reused, 2);
  std::vector<glm::vec3> squashed = scene.meshes[0].positions;
  for (glm::vec3& p : squashed) p.z *= 0.5f;
  gpu_scene.set_mesh_positions(0, squashed);
  viewport.begin(gpu_scene, top_view(3.0f), {overhead_sun()}, glm::vec3(0.1f), 48, 48, settings, true);
  EXPECT_EQ(viewport.stats().fields_regenerated, 1);
  run_until_still(viewport);

  const RenderOutput again = render_with(cache, sphere_box_ground());
  EXPECT_EQ(again.stats.fields_reused, 2);
  EXPECT_EQ(largest_difference(again.shadow, taken.shadow), 0.0) << "the kept sphere's field is unchanged";
}

TEST_F(ObjectFieldsTest, TheCacheKeepsNoMoreThanItsCapacity) {
  auto tiny = std::make_shared<FieldCache>(1024);
  render_with(tiny, sphere_box_ground());
  EXPECT_EQ(tiny->size(), 0u);
  EXPECT_EQ(render_with(tiny, sphere_box_ground()).stats.fields_reused, 0);

  // Room for the larger of the two fields only: the most recently refined stays.
  auto one = std::make_shared<FieldCache>(size_t(64) << 20);
  render_with(one, sphere_box_ground());
  const size_t both = one->bytes();
  auto small = std::make_shared<FieldCache>(both - 1);
  render_with(small, sphere_box_ground());
  EXPECT_EQ(small->size(), 1u);
  EXPECT_LE(small->bytes(), small->capacity());
  small->clear();
  EXPECT_EQ(small->size(), 0u);
  EXPECT_EQ(small->bytes(), 0u);
}

// A directory of its own for one test's field store, removed after it.
class StoreDirectory {
 public:
  explicit StoreDirectory(const std::string& name)
      : path_(std::filesystem::temp_directory_path() / ("rtsdf_" + name + "_" + std::to_string(getpid()))) {
    std::filesystem::remove_all(path_);
  }
  ~StoreDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }
  std::vector<std::filesystem::path> files() const {
    std::vector<std::filesystem::path> found;
    for (const auto& entry : std::filesystem::directory_iterator(path_)) found.push_back(entry.path());
    std::sort(found.begin(), found.end());
    return found;
  }

 private:
  std::filesystem::path path_;
};

// A cache as a new process has it: nothing in memory, the store on disk.
std::shared_ptr<FieldCache> cache_on(const std::filesystem::path& directory,
                                     uint64_t build = FieldStore::build_identity(), size_t capacity = size_t(64) << 20) {
  auto cache = std::make_shared<FieldCache>(size_t(64) << 20);
  cache->set_store(std::make_shared<FieldStore>(directory, capacity, build));
  return cache;
}

TEST_F(ObjectFieldsTest, AFieldKeptOnDiskIsTakenByALaterProcessAndTracesNothing) {
  StoreDirectory directory("store_later_process");
  auto first = cache_on(directory.path());
  const RenderOutput built = render_with(first, sphere_box_ground());
  EXPECT_EQ(built.stats.fields_regenerated, 2);
  EXPECT_GT(built.stats.traced_texels, 0u);
  EXPECT_EQ(first->store()->stats().saved, 2);
  EXPECT_EQ(directory.files().size(), 2u);
  // What the same process shows with the fields it kept in memory.
  const RenderOutput from_memory = render_with(first, sphere_box_ground());
  ASSERT_EQ(from_memory.stats.fields_reused, 2);
  EXPECT_EQ(from_memory.stats.fields_loaded, 0);

  auto later = cache_on(directory.path());
  const RenderOutput from_disk = render_with(later, sphere_box_ground());
  EXPECT_EQ(from_disk.stats.fields_regenerated, 0);
  EXPECT_EQ(from_disk.stats.fields_reused, 2);
  EXPECT_EQ(from_disk.stats.fields_loaded, 2);
  EXPECT_EQ(from_disk.stats.traced_texels, 0u);
  EXPECT_EQ(later->store()->stats().loaded, 2);
  EXPECT_EQ(later->size(), 2u) << "kept in memory too";
  EXPECT_EQ(largest_difference(from_disk.combined, from_memory.combined), 0.0);
  EXPECT_EQ(largest_difference(from_disk.shadow, from_memory.shadow), 0.0);
  EXPECT_EQ(context().validation_message_count(), 0);
}

// Files that cannot be read as this build's field of the key (another
// build's, torn, corrupt) are passed over: the field is built again and
// its file written anew.
TEST_F(ObjectFieldsTest, AFieldStoreReadsOnlyWholeFilesOfItsOwnBuild) {
  StoreDirectory directory("store_whole_files");
  const RenderOutput built = render_with(cache_on(directory.path()), sphere_box_ground());
  ASSERT_EQ(directory.files().size(), 2u);

  auto other_build = cache_on(directory.path(), FieldStore::build_identity() ^ 1u);
  EXPECT_EQ(render_with(other_build, sphere_box_ground()).stats.fields_loaded, 0) << "another build's files are not read";
  EXPECT_EQ(directory.files().size(), 4u) << "the other build's own";
  std::filesystem::remove_all(directory.path());
  render_with(cache_on(directory.path()), sphere_box_ground());

  const std::vector<std::filesystem::path> files = directory.files();
  ASSERT_EQ(files.size(), 2u);
  std::filesystem::resize_file(files[0], std::filesystem::file_size(files[0]) / 2);  // torn
  {
    std::fstream corrupt(files[1], std::ios::in | std::ios::out | std::ios::binary);
    corrupt.seekg(std::streamoff(std::filesystem::file_size(files[1]) / 2));
    const char byte = char(corrupt.get() ^ 0x10);
    corrupt.seekp(std::streamoff(std::filesystem::file_size(files[1]) / 2));
    corrupt.put(byte);
  }
  auto after_damage = cache_on(directory.path());
  const RenderOutput rebuilt = render_with(after_damage, sphere_box_ground());
  EXPECT_EQ(rebuilt.stats.fields_loaded, 0);
  EXPECT_EQ(rebuilt.stats.fields_regenerated, 2);
  EXPECT_EQ(after_damage->store()->stats().passed_over, 2);
  EXPECT_EQ(largest_difference(rebuilt.shadow, built.shadow), 0.0);
  EXPECT_EQ(render_with(cache_on(directory.path()), sphere_box_ground()).stats.fields_loaded, 2) << "written anew";

  // A header that claims more words than the file holds (four billion) is
  // passed over before anything is allocated for them.
  {
    std::fstream corrupt(directory.files()[0], std::ios::in | std::ios::out | std::ios::binary);
    corrupt.seekp(24);  // (the words' count: after the magic, format, key length and build)
    const uint64_t claimed = uint64_t(1) << 32;
    corrupt.write(reinterpret_cast<const char*>(&claimed), sizeof claimed);
  }
  auto after_claim = cache_on(directory.path());
  EXPECT_EQ(render_with(after_claim, sphere_box_ground()).stats.fields_loaded, 1);
  EXPECT_EQ(after_claim->store()->stats().passed_over, 1);
}

TEST_F(ObjectFieldsTest, AFieldStoreKeepsNoMoreThanItsCapacity) {
  StoreDirectory directory("store_capacity");
  render_with(cache_on(directory.path()), sphere_box_ground());
  std::vector<uintmax_t> sizes;
  for (const auto& file : directory.files()) sizes.push_back(std::filesystem::file_size(file));
  ASSERT_EQ(sizes.size(), 2u);
  std::filesystem::remove_all(directory.path());

  const size_t room = size_t(std::max(sizes[0], sizes[1]));
  auto cache = cache_on(directory.path(), FieldStore::build_identity(), room);
  render_with(cache, sphere_box_ground());
  EXPECT_EQ(cache->store()->stats().saved, 2);
  EXPECT_EQ(directory.files().size(), 1u) << "the least recently used went";
  EXPECT_LE(cache->store()->stats().bytes, room);
}

// A store that cannot write loses nothing: the render is as without one.
TEST_F(ObjectFieldsTest, AFieldStoreThatCannotWriteFailsNoRender) {
  StoreDirectory directory("store_unwritable");
  auto cache = cache_on(directory.path());
  const RenderOutput without_store = render_with(std::make_shared<FieldCache>(size_t(64) << 20), sphere_box_ground());
  std::filesystem::remove_all(directory.path());
  std::ofstream(directory.path()) << "a file where the directory was";
  const RenderOutput rendered = render_with(cache, sphere_box_ground());
  EXPECT_EQ(rendered.stats.fields_regenerated, 2);
  EXPECT_EQ(largest_difference(rendered.shadow, without_store.shadow), 0.0);
  const FieldStore::Stats stats = cache->store()->stats();
  EXPECT_EQ(stats.failed_saves, 2);
  EXPECT_NE(stats.last_error.find(directory.path().string()), std::string::npos) << stats.last_error;
  try {
    FieldStore store(directory.path(), 1 << 20);
    ADD_FAILURE() << "a file is no directory";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot use"), std::string::npos) << e.what();
  }
  std::filesystem::remove(directory.path());
}


TEST(SingularValues, OfScalesAndRotations) {
  const glm::mat3 m = glm::mat3(glm::rotate(glm::mat4(1.0f), 0.8f, glm::normalize(glm::vec3(1, 2, 3)))) *
                      glm::mat3(glm::scale(glm::mat4(1.0f), {3.0f, -0.5f, 1.5f}));
  const glm::vec2 range = singular_value_range(m);
  EXPECT_NEAR(range.x, 0.5f, 1e-4f);
  EXPECT_NEAR(range.y, 3.0f, 1e-4f);
  EXPECT_NEAR(singular_value_range(glm::mat3(2.0f)).x, 2.0f, 1e-5f);
  EXPECT_NEAR(singular_value_range(glm::mat3(0.0f)).y, 0.0f, 1e-6f);
}

}  // namespace
}  // namespace rtsdf
