#version 450
#extension GL_GOOGLE_include_directive : require
// After a still field's first update: which of the texels it traced may
// still improve (see RTSDF_PROBE in fine_trace.glsl.h).
#define RTSDF_PROBE
#include "fine_trace.glsl.h"
