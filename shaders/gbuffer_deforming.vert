#version 450
#extension GL_GOOGLE_include_directive : require
// G-buffer, vertex stage, for instances whose mesh deformed since the last
// frame: material slots read, and each vertex's last position (see
// gbuffer_vertex.glsl.h).
#define RTSDF_MATERIAL_INPUTS
#define RTSDF_DEFORMATION
#include "gbuffer_vertex.glsl.h"
