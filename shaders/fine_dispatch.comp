#version 450
#extension GL_GOOGLE_include_directive : require
// Fine SDF, step 2: turns the trace-list length into indirect dispatch sizes,
// one for the texels on their turn and one for those measured again off it
// (fine_classify.comp), so that only listed texels get a thread, and zeroes
// the count of texels the trace improves.
#include "shared.h"

layout(local_size_x = 1) in;
layout(std430, binding = 0) readonly buffer TraceList { uint trace_count; uint remeasure_count; };
layout(std430, binding = 1) writeonly buffer Dispatch { uvec4 groups; uint improved; uint remeasure_groups[3]; };

void main() {
  groups = uvec4((trace_count + RTSDF_TRACE_GROUP - 1u) / RTSDF_TRACE_GROUP, 1u, 1u, trace_count);
  improved = 0u;
  remeasure_groups = uint[3]((remeasure_count + RTSDF_TRACE_GROUP - 1u) / RTSDF_TRACE_GROUP, 1u, 1u);
}
