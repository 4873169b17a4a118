#version 450
#extension GL_GOOGLE_include_directive : require
// Fine SDF, step 3: the texels on their turn (fine_trace.glsl.h).
#include "fine_trace.glsl.h"
