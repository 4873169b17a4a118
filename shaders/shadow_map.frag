#version 450
#extension GL_GOOGLE_include_directive : require
// Shadow map (csm_evsm), fragment stage: the EVSM moments of the nearest
// caster (the depth test keeps it).
#include "shared.h"
#include "evsm.glsl.h"

layout(push_constant) uniform Push { ShadowMapPush pc; };
layout(location = 0) in float v_depth;
layout(location = 0) out vec4 out_moments;  // e^(c+ x), its square, -e^(-c- x), its square

void main() {
  vec2 warped = evsm_warp(v_depth, pc.evsm.xy);
  out_moments = vec4(warped.x, warped.x * warped.x, warped.y, warped.y * warped.y);
}
