#include "mesh_import.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <fstream>

#include "error.h"

namespace rtsdf {

namespace {

glm::mat4 to_glm(const aiMatrix4x4& m) {
  // Assimp is row-major with column vectors; glm is column-major.
  return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4, m.b4, m.c4, m.d4);
}

Mesh convert(const aiMesh& source) {
  Mesh mesh;
  mesh.name = source.mName.length > 0 ? source.mName.C_Str() : "mesh";
  mesh.positions.reserve(source.mNumVertices);
  for (unsigned i = 0; i < source.mNumVertices; ++i)
    mesh.positions.emplace_back(source.mVertices[i].x, source.mVertices[i].y, source.mVertices[i].z);
  mesh.indices.reserve(size_t(source.mNumFaces) * 3);
  for (unsigned f = 0; f < source.mNumFaces; ++f) {
    const aiFace& face = source.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines have no surface
    mesh.indices.insert(mesh.indices.end(), face.mIndices, face.mIndices + 3);
  }
  return mesh;
}

void add_instances(const aiNode& node, const glm::mat4& parent, Scene& scene) {
  glm::mat4 transform = parent * to_glm(node.mTransformation);
  for (unsigned i = 0; i < node.mNumMeshes; ++i) scene.instances.push_back(Instance{node.mMeshes[i], transform});
  for (unsigned i = 0; i < node.mNumChildren; ++i) add_instances(*node.mChildren[i], transform, scene);
}

}  // namespace

Scene import_scene(const std::string& path) {
  if (!std::ifstream(path).good()) throw Error("cannot open mesh file '" + path + "'");
  Assimp::Importer importer;
  const aiScene* source = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_SortByPType);
  if (!source || !source->mRootNode || (source->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw Error("cannot read mesh file '" + path + "': " + importer.GetErrorString());
  Scene scene;
  for (unsigned i = 0; i < source->mNumMeshes; ++i) scene.meshes.push_back(convert(*source->mMeshes[i]));
  add_instances(*source->mRootNode, glm::mat4(1.0f), scene);
  if (scene.triangle_count() == 0) throw Error("mesh file '" + path + "' has no triangles");
  return scene;
}

}  // namespace rtsdf
