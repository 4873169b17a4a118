#include "bvh.h"

#include <algorithm>
#include <array>

namespace rtsdf {

namespace {

constexpr int kBins = 16;

struct Builder {
  const std::vector<Aabb>& boxes;
  std::vector<glm::vec3> centers;
  uint32_t max_leaf;
  Bvh bvh;

  // Splits node `index` (covering order[first, first + count)) until leaves are small.
  void subdivide(uint32_t index) {
    BvhBuildNode& node = bvh.nodes[index];
    const uint32_t first = node.first, count = node.count;
    Aabb centroid_box;
    for (uint32_t i = first; i < first + count; ++i) centroid_box.grow(centers[bvh.order[i]]);

    float best_cost = node.box.area() * float(count);  // cost of keeping a leaf
    int best_axis = -1, best_split = 0;
    for (int axis = 0; axis < 3; ++axis) {
      float lo = centroid_box.lo[axis], extent = centroid_box.hi[axis] - lo;
      if (extent <= 0.0f) continue;
      std::array<Aabb, kBins> bins;
      std::array<uint32_t, kBins> bin_counts{};
      const float scale = float(kBins) / extent;
      for (uint32_t i = first; i < first + count; ++i) {
        uint32_t p = bvh.order[i];
        int b = std::min(kBins - 1, int((centers[p][axis] - lo) * scale));
        bins[b].grow(boxes[p]);
        bin_counts[b]++;
      }
      // Sweep from the right to get the cost of every split plane.
      std::array<float, kBins> right_cost{};
      Aabb right;
      uint32_t right_count = 0;
      for (int b = kBins - 1; b > 0; --b) {
        right.grow(bins[b]);
        right_count += bin_counts[b];
        right_cost[b] = right_count ? right.area() * float(right_count) : 0.0f;
      }
      Aabb left;
      uint32_t left_count = 0;
      for (int b = 0; b < kBins - 1; ++b) {
        left.grow(bins[b]);
        left_count += bin_counts[b];
        if (left_count == 0 || left_count == count) continue;
        float cost = left.area() * float(left_count) + right_cost[b + 1] + node.box.area() * 0.5f;
        if (cost < best_cost) best_cost = cost, best_axis = axis, best_split = b;
      }
    }
    if (best_axis < 0) {
      if (count <= max_leaf) return;
      // All centroids coincide (or no split pays): halve by order to keep leaves small.
      best_axis = -2;
    }

    uint32_t middle;
    if (best_axis == -2) {
      middle = first + count / 2;
    } else {
      const float lo = centroid_box.lo[best_axis];
      const float scale = float(kBins) / (centroid_box.hi[best_axis] - lo);
      auto it = std::partition(bvh.order.begin() + first, bvh.order.begin() + first + count, [&](uint32_t p) {
        return std::min(kBins - 1, int((centers[p][best_axis] - lo) * scale)) <= best_split;
      });
      middle = uint32_t(it - bvh.order.begin());
    }
    const uint32_t left_index = uint32_t(bvh.nodes.size());
    for (auto [from, n] : {std::pair{first, middle - first}, std::pair{middle, first + count - middle}}) {
      BvhBuildNode child;
      child.first = from;
      child.count = n;
      for (uint32_t i = from; i < from + n; ++i) child.box.grow(boxes[bvh.order[i]]);
      bvh.nodes.push_back(child);
    }
    bvh.nodes[index].first = left_index;  // `node` may dangle after push_back
    bvh.nodes[index].count = 0;
    subdivide(left_index);
    subdivide(left_index + 1);
  }
};

}  // namespace

Bvh build_bvh(const std::vector<Aabb>& boxes, uint32_t max_leaf) {
  Builder builder{boxes, {}, std::max(1u, max_leaf), {}};
  builder.centers.reserve(boxes.size());
  for (const Aabb& b : boxes) builder.centers.push_back(0.5f * (b.lo + b.hi));
  builder.bvh.order.resize(boxes.size());
  for (uint32_t i = 0; i < boxes.size(); ++i) builder.bvh.order[i] = i;
  BvhBuildNode root;
  root.count = uint32_t(boxes.size());
  for (const Aabb& b : boxes) root.box.grow(b);
  builder.bvh.nodes.reserve(2 * boxes.size() / std::max(1u, max_leaf) + 1);
  builder.bvh.nodes.push_back(root);
  if (!boxes.empty()) builder.subdivide(0);
  return std::move(builder.bvh);
}

Bvh build_mesh_bvh(const Mesh& mesh) {
  std::vector<Aabb> boxes(mesh.triangle_count());
  for (size_t t = 0; t < boxes.size(); ++t)
    for (int k = 0; k < 3; ++k) boxes[t].grow(mesh.positions[mesh.indices[3 * t + k]]);
  return build_bvh(boxes);
}

void refit_mesh_bvh(Bvh& bvh, const Mesh& mesh) {
  // (children come after their parent: from the last node back, they are made first)
  for (size_t n = bvh.nodes.size(); n-- > 0;) {
    BvhBuildNode& node = bvh.nodes[n];
    Aabb box;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i)
        for (int k = 0; k < 3; ++k) box.grow(mesh.positions[mesh.indices[3 * size_t(bvh.order[i]) + k]]);
    } else {
      box.grow(bvh.nodes[node.first].box);
      box.grow(bvh.nodes[node.first + 1].box);
    }
    node.box = box;
  }
}

float bvh_cost(const Bvh& bvh) {
  if (bvh.nodes.empty() || !(bvh.nodes[0].box.area() > 0.0f)) return 0.0f;
  double areas = 0.0;
  for (const BvhBuildNode& node : bvh.nodes) areas += node.box.area();
  return float(areas / bvh.nodes[0].box.area());
}

std::vector<gpu::BvhNode> gpu_nodes(const Bvh& bvh, uint32_t node_offset, uint32_t primitive_offset) {
  std::vector<gpu::BvhNode> nodes;
  nodes.reserve(bvh.nodes.size());
  for (const BvhBuildNode& n : bvh.nodes) {
    gpu::BvhNode node{};
    node.lo = glm::vec4(n.box.lo, 0.0f);
    node.hi = glm::vec4(n.box.hi, 0.0f);
    node.count = n.count;
    node.first = n.count > 0 ? n.first + primitive_offset : n.first + node_offset;
    nodes.push_back(node);
  }
  return nodes;
}

}  // namespace rtsdf
