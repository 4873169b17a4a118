#version 450
#extension GL_GOOGLE_include_directive : require
// After the temporal keep pass: the groups of quads the quad pass runs on,
// one invocation per group (kQuadGroup^2 quads). A quad's sample serves the
// 4 x 4 pixels around it (quad_share.glsl.h), so a group is listed where a
// pixel tile the keep pass listed (one holding a pixel it did not keep)
// overlaps the pixels around its quads: quads 8g to 8g + 7 share samples
// with pixels 16g - 1 to 16g + 16.
#include "shared.h"

layout(local_size_x = 64) in;
layout(push_constant) uniform Push { TemporalPush pc; };
layout(std430, binding = 0) buffer Tiles { uint tile_words[]; };
#define RTSDF_LISTS_TILES
#include "kept_tiles.glsl.h"

void main() {
  TileList groups = quad_groups(), tiles = pixel_tiles();
  uint index = gl_GlobalInvocationID.x;
  if (index >= uint(groups.tiles.x * groups.tiles.y)) return;
  ivec2 group = ivec2(int(index) % groups.tiles.x, int(index) / groups.tiles.x);
  int pixels = 2 * int(kQuadGroup);
  ivec2 lo = max(group * pixels - 1, ivec2(0)) / int(kTemporalTile);
  ivec2 hi = min(group * pixels + pixels, pc.image_size - 1) / int(kTemporalTile);
  bool listed = false;
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x)
      listed = listed || tile_words[tiles.first + 4u + uint(x + tiles.tiles.x * y)] != 0u;
  if (listed) list_tile(groups, group);
}
