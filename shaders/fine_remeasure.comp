#version 450
#extension GL_GOOGLE_include_directive : require
// Fine SDF, step 3, in a field whose geometry changes between updates: the
// band texels off their turn, which cast no ray (fine_trace.glsl.h).
#define RTSDF_REMEASURE
#include "fine_trace.glsl.h"
