#version 450
#extension GL_GOOGLE_include_directive : require
// G-buffer, fragment stage, for instances whose mesh deformed since the last
// frame (see gbuffer_fragment.glsl.h).
#define RTSDF_MATERIAL_INPUTS
#define RTSDF_DEFORMATION
#include "gbuffer_fragment.glsl.h"
