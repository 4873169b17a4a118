#pragma once
#include <string>

#include "scene.h"

namespace rtsdf {

// Reads any file Assimp reads (OBJ, PLY, glTF/GLB, STL, FBX, ...) into a scene:
// one Mesh per file mesh and one Instance per node that places it, with the
// node transforms applied. Throws rtsdf::Error with Assimp's reason on failure.
Scene import_scene(const std::string& path);

}  // namespace rtsdf
