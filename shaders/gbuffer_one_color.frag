#version 450
#extension GL_GOOGLE_include_directive : require
// G-buffer, fragment stage, for instances of one plain colour (see gbuffer_fragment.glsl.h).
#include "gbuffer_fragment.glsl.h"
