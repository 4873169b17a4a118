#pragma once
// Render output written as an OpenEXR file: linear float channels R, G, B, A
// (Combined), Z (Depth) and Shadow (visibility), as Blender's multilayer EXR
// and compositors read them.
#include <string>

#include "renderer.h"

namespace rtsdf {

// Throws rtsdf::Error when the file cannot be written or the output is empty.
void write_exr(const std::string& path, const RenderOutput& output);

}  // namespace rtsdf
