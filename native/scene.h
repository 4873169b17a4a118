#pragma once
// The scene as the native side sees it: meshes in object space and instances
// placing them in the world. Units are world units throughout.
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace rtsdf {

struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;  // three per triangle
  // Optional per-vertex normals for smooth shading; empty: flat faces.
  std::vector<glm::vec3> normals;
  // Optional per-triangle material slot (an index into its instances'
  // `materials`); empty: slot 0 everywhere.
  std::vector<uint32_t> materials;
  // Optional per-vertex texture coordinates (Blender's: v up); empty: none.
  std::vector<glm::vec2> uvs;
  // Optional per-vertex colours (a colour attribute, linear RGB) that
  // materials with vertex_color multiply their base colour by; empty: white.
  std::vector<glm::vec3> colors;
  size_t triangle_count() const { return indices.size() / 3; }
};

// What the G-buffer takes of a material: its base colour, or an image
// (Scene::textures) sampled by the mesh's UVs.
struct Material {
  glm::vec3 base_color{0.8f};  // linear RGB
  int texture = -1;            // index into Scene::textures; -1: none
  bool vertex_color = false;   // the base colour times the mesh's colours (Mesh::colors), where there is no image
  bool operator==(const Material& other) const {
    return base_color == other.base_color && texture == other.texture && vertex_color == other.vertex_color;
  }
  bool operator!=(const Material& other) const { return !(*this == other); }
};

// An image as materials sample it: rows from the bottom (as Blender stores
// them), texels as RGBA8 with the colour sRGB-encoded (x = R in the low byte).
struct Texture {
  std::string name;
  int width = 0, height = 0;
  std::vector<uint32_t> texels;
  bool operator==(const Texture& other) const {
    return width == other.width && height == other.height && texels == other.texels;
  }
  bool operator!=(const Texture& other) const { return !(*this == other); }
};

struct Instance {
  uint32_t mesh = 0;
  glm::mat4 object_to_world{1.0f};
  glm::vec3 base_color{0.8f};  // linear RGB of the instance's material (where `materials` is empty)
  // Its material slots, which the mesh's per-triangle `materials` pick from
  // (clamped to the last); empty: base_color everywhere.
  std::vector<Material> materials;
  bool casts_shadow = true;    // off: seen and lit, but left out of the SDFs
  bool visible_to_camera = true;  // off: not seen, but still casts shadows (Blender's Ray Visibility > Camera)
  bool holdout = false;           // seen as a hole: transparent black that hides what is behind (Holdout)
};

struct Bounds {
  glm::vec3 lo{0.0f};
  glm::vec3 hi{0.0f};
  glm::vec3 extent() const { return hi - lo; }
  // Holds no point (lo above hi).
  static Bounds empty() { return {glm::vec3(1.0f), glm::vec3(-1.0f)}; }
  bool is_empty() const { return glm::any(glm::greaterThan(lo, hi)); }
};

class MeshExtent;  // mesh_extent.h

struct Scene {
  std::vector<Mesh> meshes;
  std::vector<Instance> instances;
  std::vector<Texture> textures;  // the materials' images

  // Triangles drawn, counting every instance.
  size_t triangle_count() const;
  // Throws rtsdf::Error for anything the pipeline cannot use: no triangles,
  // NaN or infinite coordinates or transforms, indices out of range.
  void validate() const;
  // The part of validate() about one mesh: coordinates, indices, normals, materials, UVs.
  static void validate_mesh(const Mesh& mesh);
  // The part about the whole: some triangles, and `bounds` (the world's)
  // finite and not flat to a point.
  void validate_extent(const Bounds& bounds) const;
  // World-space bounds of every instanced vertex; call validate() first.
  Bounds world_bounds() const;
  // The same over some instances only (by index).
  Bounds world_bounds(const std::vector<uint32_t>& instance_indices) const;
  // The same with the meshes' extents at hand (mesh_extents(*this)).
  Bounds world_bounds(const std::vector<uint32_t>& instance_indices, const std::vector<MeshExtent>& extents) const;
};

// A scene holding one mesh once, untransformed.
Scene single_mesh_scene(Mesh mesh);

// Every instance's triangles placed in world space, as one mesh (positions
// and indices only). A mirrored instance's corners are reordered, so that its
// faces still face the way they do in the scene.
Mesh placed_mesh(const Scene& scene);

}  // namespace rtsdf
