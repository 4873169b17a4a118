#version 450
#extension GL_GOOGLE_include_directive : require
// G-buffer, vertex stage, for instances of one plain colour (see gbuffer_vertex.glsl.h).
#include "gbuffer_vertex.glsl.h"
