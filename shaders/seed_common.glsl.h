// Packing of seed voxel indices (see kSeedBits in shared.h).
uint pack_seed(ivec3 v) { return uint(v.x) | (uint(v.y) << kSeedBits) | (uint(v.z) << (2u * kSeedBits)); }
ivec3 unpack_seed(uint s) { return ivec3(s & kSeedMask, (s >> kSeedBits) & kSeedMask, s >> (2u * kSeedBits)); }
