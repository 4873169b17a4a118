#include "mesh_topology.h"

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>
#include <unordered_map>

namespace rtsdf {

namespace {

using Cell = glm::i64vec3;
struct CellHash {
  size_t operator()(const Cell& c) const {
    return size_t(c.x) * 0x9E3779B97F4A7C15ull ^ size_t(c.y) * 0xC2B2AE3D27D4EB4Full ^ size_t(c.z) * 0x165667B19E3779F9ull;
  }
};

struct DisjointSets {
  std::vector<uint32_t> parent;
  explicit DisjointSets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

// Whether a piece bounds a volume. Boundary edges alone do not say: CAD
// exports leave cracks and T-junctions along seams (edges that no other
// triangle shares although the surface closes), and such a piece has no hole
// at all. A hole shows in the vector area instead: it vanishes for every
// closed surface, cracked or not, and for a sheet it is the sheet's area. A
// hole up to 2% of the area (a missing face, say) still leaves an inside.
bool encloses_volume(bool has_boundary, glm::dvec3 vector_area, double area) {
  constexpr double kLargestHole = 0.02;
  return area > 0.0 && (!has_boundary || glm::length(vector_area) <= kLargestHole * area);
}

glm::vec3 lowest_corner(const Mesh& mesh) {
  glm::vec3 lo(std::numeric_limits<float>::max());
  for (const glm::vec3& p : mesh.positions) lo = glm::min(lo, p);
  return lo;
}

}  // namespace

double triangle_area(const Mesh& mesh, size_t t) {
  const glm::dvec3 a(mesh.positions[mesh.indices[3 * t]]), b(mesh.positions[mesh.indices[3 * t + 1]]);
  const glm::dvec3 c(mesh.positions[mesh.indices[3 * t + 2]]);
  return 0.5 * glm::length(glm::cross(b - a, c - a));
}

PieceTopology piece_topology(const Mesh& mesh) {
  const size_t triangles = mesh.triangle_count();
  // Vertices at the same position (to a millionth of the mesh's size, as
  // rounding leaves seams and poles) are one vertex.
  glm::vec3 lo = lowest_corner(mesh), hi(-std::numeric_limits<float>::max());
  for (const glm::vec3& p : mesh.positions) hi = glm::max(hi, p);
  const glm::vec3 extent = hi - lo;
  const double cell = std::max(1e-30, 1e-6 * double(std::max(extent.x, std::max(extent.y, extent.z))));
  std::unordered_map<Cell, uint32_t, CellHash> welded;
  std::vector<uint32_t> vertex_id(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::dvec3 q = glm::round(glm::dvec3(mesh.positions[v] - lo) / cell);
    vertex_id[v] = welded.emplace(Cell(q), uint32_t(welded.size())).first->second;
  }

  // Each undirected edge: how many triangles use it, and the first two of
  // them with the way each runs along it (from the lower vertex id or not).
  struct EdgeUse {
    uint32_t count = 0;
    uint32_t triangle[2] = {0, 0};
    bool forward[2] = {false, false};
  };
  std::unordered_map<uint64_t, EdgeUse> edges;
  edges.reserve(3 * triangles);
  DisjointSets pieces(triangles);
  for (uint32_t t = 0; t < triangles; ++t)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = vertex_id[mesh.indices[3 * t + k]], b = vertex_id[mesh.indices[3 * t + (k + 1) % 3]];
      if (a == b) continue;  // a degenerate edge joins nothing
      const bool forward = a < b;
      if (!forward) std::swap(a, b);
      EdgeUse& use = edges[(uint64_t(a) << 32) | b];
      if (use.count < 2) use.triangle[use.count] = t, use.forward[use.count] = forward;
      if (use.count++ > 0) pieces.join(t, use.triangle[0]);
    }

  // Orientation, made coherent: across an edge two triangles share (and only
  // two), a coherent surface runs the edge once each way. Exports mix the
  // two (a mirrored part merged, faces flipped by hand), and a box with half
  // its triangles turned has no volume and no inside. Coherent patches grow
  // across such edges from a seed; each keeps the way most of its area
  // already faces, so a coherent mesh keeps every triangle as it is.
  constexpr uint32_t kNone = ~0u;
  struct Neighbour {
    uint32_t triangle = kNone;
    bool same_way = false;  // coherent as stored
  };
  std::vector<std::array<Neighbour, 3>> neighbours(triangles);
  for (const auto& [key, use] : edges) {
    if (use.count != 2) continue;
    const bool same_way = use.forward[0] != use.forward[1];
    for (int side = 0; side < 2; ++side)
      for (Neighbour& n : neighbours[use.triangle[side]])
        if (n.triangle == kNone) {
          n = {use.triangle[1 - side], same_way};
          break;
        }
  }
  std::vector<int8_t> turn(triangles, 0);  // +1: as stored, -1: reversed (0: not reached yet)
  std::vector<uint32_t> patch;
  for (uint32_t seed = 0; seed < triangles; ++seed) {
    if (turn[seed] != 0) continue;
    turn[seed] = 1;
    patch.assign(1, seed);
    double kept = 0.0, reversed = 0.0;
    for (size_t i = 0; i < patch.size(); ++i) {
      const uint32_t t = patch[i];
      (turn[t] > 0 ? kept : reversed) += triangle_area(mesh, t);
      for (const Neighbour& n : neighbours[t])
        if (n.triangle != kNone && turn[n.triangle] == 0) {
          turn[n.triangle] = int8_t(n.same_way ? turn[t] : -turn[t]);
          patch.push_back(n.triangle);
        }
    }
    if (reversed > kept)
      for (uint32_t t : patch) turn[t] = int8_t(-turn[t]);
  }

  PieceTopology topology{std::vector<uint32_t>(triangles), std::move(turn), std::vector<uint8_t>(triangles, 0)};
  for (uint32_t t = 0; t < triangles; ++t) topology.piece[t] = pieces.find(t);
  for (const auto& [key, use] : edges)
    if (use.count == 1) topology.has_boundary[topology.piece[use.triangle[0]]] = 1;
  return topology;
}

Pieces mesh_pieces(const Mesh& mesh, const PieceTopology& topology) {
  const size_t triangles = mesh.triangle_count();
  // Volume (divergence theorem, about the mesh's corner for precision), area
  // and vector area (the sum of area-weighted normals) per piece, oriented coherently.
  const glm::vec3 lo = lowest_corner(mesh);
  std::vector<double> volume(triangles, 0.0), area(triangles, 0.0);
  std::vector<glm::dvec3> vector_area(triangles, glm::dvec3(0.0));
  for (uint32_t t = 0; t < triangles; ++t) {
    const glm::dvec3 a = glm::dvec3(mesh.positions[mesh.indices[3 * t]] - lo);
    const glm::dvec3 b = glm::dvec3(mesh.positions[mesh.indices[3 * t + 1]] - lo);
    const glm::dvec3 c = glm::dvec3(mesh.positions[mesh.indices[3 * t + 2]] - lo);
    const uint32_t piece = topology.piece[t];
    const glm::dvec3 normal = 0.5 * glm::cross(b - a, c - a);
    volume[piece] += double(topology.turn[t]) * glm::dot(a, glm::cross(b, c)) / 6.0;
    area[piece] += glm::length(normal);
    vector_area[piece] += double(topology.turn[t]) * normal;
  }
  Pieces result{std::vector<float>(triangles), std::vector<uint8_t>(triangles)};
  for (uint32_t t = 0; t < triangles; ++t) {
    const uint32_t piece = topology.piece[t];
    result.thickness[t] = encloses_volume(topology.has_boundary[piece] != 0, vector_area[piece], area[piece])
                              ? float(2.0 * std::abs(volume[piece]) / area[piece])
                              : 0.0f;
    // (a piece with negative volume is turned inside out as a whole)
    result.faces_in[t] = (topology.turn[t] < 0) != (volume[piece] < 0.0) ? 1 : 0;
  }
  return result;
}

Pieces mesh_pieces(const Mesh& mesh) { return mesh_pieces(mesh, piece_topology(mesh)); }

WeldedTriangles weld_by_position(const Mesh& mesh) {
  struct PositionHash {
    size_t operator()(const glm::vec3& p) const {
      // (+ 0: -0 and 0 are one position, and hash as one)
      return std::hash<float>()(p.x + 0.0f) * 0x9E3779B97F4A7C15ull ^
             std::hash<float>()(p.y + 0.0f) * 0xC2B2AE3D27D4EB4Full ^ std::hash<float>()(p.z + 0.0f);
    }
  };
  WeldedTriangles welded;
  constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();
  welded.vertex_of.assign(mesh.positions.size(), kUnused);
  welded.indices.reserve(mesh.indices.size());
  std::unordered_map<glm::vec3, uint32_t, PositionHash> at;
  for (uint32_t v : mesh.indices) {
    uint32_t& id = welded.vertex_of[v];
    if (id == kUnused) id = at.emplace(mesh.positions[v], uint32_t(at.size())).first->second;
    welded.indices.push_back(id);
  }
  // (vertices no triangle uses are not part of the surface: each its own, after the rest)
  for (size_t v = 0; v < mesh.positions.size(); ++v)
    if (welded.vertex_of[v] == kUnused) welded.vertex_of[v] = uint32_t(at.size() + v);
  welded.vertex_count = uint32_t(at.size());
  return welded;
}

std::optional<std::vector<glm::vec3>> welded_positions(const Mesh& mesh, const WeldedTriangles& welded) {
  if (welded.vertex_of.size() != mesh.positions.size()) return std::nullopt;
  std::vector<glm::vec3> positions(welded.vertex_count);
  std::vector<uint8_t> placed(welded.vertex_count, 0);
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const uint32_t w = welded.vertex_of[v];
    if (w >= welded.vertex_count) continue;
    if (placed[w] && !(positions[w] == mesh.positions[v])) return std::nullopt;
    positions[w] = mesh.positions[v];
    placed[w] = 1;
  }
  return positions;
}

}  // namespace rtsdf
