#version 450
#extension GL_GOOGLE_include_directive : require
// G-buffer, vertex stage, for instances whose material slots are read (see gbuffer_vertex.glsl.h).
#define RTSDF_MATERIAL_INPUTS
#include "gbuffer_vertex.glsl.h"
