#include "march_fields.h"

#include <algorithm>
#include <cmath>

#include "bvh.h"
#include "error.h"
#include "vk/context.h"

namespace rtsdf {

namespace {

template <typename T>
vk::Buffer storage(const vk::Context& context, const std::vector<T>& data) {
  return vk::upload_buffer(context, data.data(), data.size() * sizeof(T), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
}

}  // namespace

glm::vec2 singular_value_range(const glm::mat3& m) {
  // Eigenvalues of the symmetric M^T M (Smith's closed form), then square roots.
  const glm::mat3 a = glm::transpose(m) * m;
  const double p1 = double(a[0][1]) * a[0][1] + double(a[0][2]) * a[0][2] + double(a[1][2]) * a[1][2];
  const double q = (double(a[0][0]) + a[1][1] + a[2][2]) / 3.0;
  double lo, hi;
  if (p1 <= 1e-30 * (q * q + 1e-300)) {
    lo = std::min({double(a[0][0]), double(a[1][1]), double(a[2][2])});
    hi = std::max({double(a[0][0]), double(a[1][1]), double(a[2][2])});
  } else {
    const double p2 = (a[0][0] - q) * (a[0][0] - q) + (a[1][1] - q) * (a[1][1] - q) + (a[2][2] - q) * (a[2][2] - q) +
                      2.0 * p1;
    const double p = std::sqrt(p2 / 6.0);
    glm::dmat3 b = (glm::dmat3(a) - q * glm::dmat3(1.0)) * (1.0 / p);
    const double r = std::clamp(glm::determinant(b) / 2.0, -1.0, 1.0);
    const double phi = std::acos(r) / 3.0;
    hi = q + 2.0 * p * std::cos(phi);
    lo = q + 2.0 * p * std::cos(phi + 2.0 * M_PI / 3.0);
  }
  return {float(std::sqrt(std::max(lo, 0.0))), float(std::sqrt(std::max(hi, 0.0)))};
}

MarchFields::MarchFields(const vk::Context& context) : context_(context) {}

float MarchFields::world_voxel(const PackedField& field, const glm::mat4& object_to_world) {
  return field.grid().voxel_size * singular_value_range(glm::mat3(object_to_world)).y;
}

void MarchFields::place(const std::vector<Placement>& placements) {
  std::vector<gpu::FieldInstance> records;
  std::vector<Aabb> boxes;
  largest_voxel_ = 0.0f;
  skipped_degenerate_ = 0;
  for (const Placement& placement : placements) {
    const PackedField& field = *placement.field;
    const GridSpec& grid = field.grid();
    const glm::vec2 stretch = singular_value_range(glm::mat3(placement.object_to_world));
    if (!(stretch.x > kDegenerateScale * stretch.y)) {
      skipped_degenerate_++;
      continue;
    }
    gpu::FieldInstance record = field.instance_record();
    record.world_to_field = grid.world_to_voxel() * glm::inverse(placement.object_to_world);
    record.scale = glm::vec4(stretch.x * grid.voxel_size, stretch.y * grid.voxel_size, record.scale.z, 0.0f);
    records.push_back(record);
    largest_voxel_ = std::max(largest_voxel_, record.scale.y);
    Aabb box;
    const glm::vec3 lo = grid.origin + field.box_lo() * grid.voxel_size;
    const glm::vec3 hi = grid.origin + field.box_hi() * grid.voxel_size;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p(corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z);
      box.grow(glm::vec3(placement.object_to_world * glm::vec4(p, 1.0f)));
    }
    boxes.push_back(box);
  }
  instance_count_ = uint32_t(records.size());
  if (records.empty()) {
    // Placeholders: the shading binds these buffers whatever it reads.
    records.emplace_back();
    boxes.emplace_back();
  }
  const Bvh bvh = build_bvh(boxes, 2);
  std::vector<gpu::FieldInstance> ordered;
  for (uint32_t i : bvh.order) ordered.push_back(records[i]);
  instances_ = storage(context_, ordered);
  nodes_ = storage(context_, gpu_nodes(bvh));
}

}  // namespace rtsdf
