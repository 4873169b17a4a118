// The tiles the temporal keep pass (temporal_keep.comp) lists: where pixels
// it did not keep lie, so that the shading and the resolve run there alone
// (lavapipe runs a shader's whole body, masked, for lanes that returned
// early). Two lists in one buffer of words `tile_words` (declared by the
// shader including this, after the TemporalPush or ShadePush `pc`): the
// pixel tiles (kTemporalTile^2 pixels, a work group of the pixel passes and
// the resolve each) holding such a pixel, and the quad groups (kQuadGroup^2
// quads, a work group of the quad pass) whose quads share a sample with one
// (quad_share.glsl.h: a quad's sample serves the 4 x 4 pixels around it).
// Each list: its indirect dispatch (4 words), a flag per tile (listed), the
// tile indices (x + tiles across * y).

struct TileList {
  ivec2 tiles;  // across, down
  uint first;   // its first word
};

ivec2 tiles_over(ivec2 size, int tile) { return (size + tile - 1) / tile; }

TileList pixel_tiles() { return TileList(tiles_over(pc.image_size, int(kTemporalTile)), 0u); }

TileList quad_groups() {
  ivec2 pixel_tiles = tiles_over(pc.image_size, int(kTemporalTile));
  return TileList(tiles_over((pc.image_size + 1) / 2, int(kQuadGroup)), 4u + 2u * uint(pixel_tiles.x * pixel_tiles.y));
}

// The tile this work group takes in a pass over `list`.
ivec2 listed_tile(TileList list) {
  uint count = uint(list.tiles.x * list.tiles.y);
  uint index = tile_words[list.first + 4u + count + gl_WorkGroupID.x];
  return ivec2(index % uint(list.tiles.x), index / uint(list.tiles.x));
}

// Whether `tile` of `list` is listed.
bool tile_listed(TileList list, ivec2 tile) {
  return tile_words[list.first + 4u + uint(tile.x + list.tiles.x * tile.y)] != 0u;
}

#ifdef RTSDF_LISTS_TILES
// Lists `tile` of `list`, once: true for the call that listed it.
bool list_tile(TileList list, ivec2 tile) {
  uint count = uint(list.tiles.x * list.tiles.y), index = uint(tile.x + list.tiles.x * tile.y);
  if (atomicExchange(tile_words[list.first + 4u + index], 1u) != 0u) return false;
  tile_words[list.first + 4u + count + atomicAdd(tile_words[list.first], 1u)] = index;
  return true;
}
#endif
