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

bool MarchFields::set_layout(const std::vector<GridSpec>& grids, const std::vector<Bounds>& contents,
                             const std::vector<float>& rooms) {
  if (contents.size() != grids.size() || (!rooms.empty() && rooms.size() != grids.size()))
    throw Error("MarchFields: one content box (and room) per field");
  margins_.clear();
  box_lo_.clear();
  box_hi_.clear();
  for (size_t i = 0; i < grids.size(); ++i) {
    const glm::vec3 dims(grids[i].dims);
    const glm::vec3 content_lo = (contents[i].lo - grids[i].origin) / grids[i].voxel_size;
    const glm::vec3 content_hi = (contents[i].hi - grids[i].origin) / grids[i].voxel_size;
    const glm::vec3 lo = rooms.empty() ? glm::vec3(0.0f) : glm::clamp(content_lo - rooms[i], glm::vec3(0.0f), dims);
    const glm::vec3 hi = rooms.empty() ? dims : glm::clamp(content_hi + rooms[i], glm::vec3(0.0f), dims);
    const glm::vec3 room = glm::min(content_lo - lo, hi - content_hi);
    margins_.push_back(std::max(0.0f, std::min(room.x, std::min(room.y, room.z))));
    box_lo_.push_back(lo);
    box_hi_.push_back(hi);
  }
  bool same = grids.size() == grids_.size() && texels_;
  for (size_t i = 0; same && i < grids.size(); ++i) same = grids[i].dims == grids_[i].dims;
  grids_ = grids;
  if (same) return false;
  first_texel_.clear();
  size_t total = 0;
  for (const GridSpec& grid : grids) {
    first_texel_.push_back(uint32_t(total));
    total += grid.voxel_count();
  }
  if (total > size_t(UINT32_MAX)) throw Error("the distance fields hold more than 2^32 texels: lower the resolution");
  const size_t bytes = std::max<size_t>(total, 1) * sizeof(float);
  if (bytes > context_.device_local_heap_bytes() / 2)
    throw Error("the distance fields need " + std::to_string(bytes >> 20) + " MiB: lower the resolution");
  texels_ = vk::Buffer(context_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       vk::Buffer::Access::DeviceOnly);
  return true;
}

void MarchFields::record_copy(VkCommandBuffer cmd, uint32_t field, const vk::Image& distance) const {
  if (field >= grids_.size() || distance.dims() != grids_[field].dims)
    throw Error("MarchFields: a field's image does not match its layout");
  vk::image_barrier(cmd, distance.handle(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                    VK_PIPELINE_STAGE_TRANSFER_BIT);
  VkBufferImageCopy region{};
  region.bufferOffset = VkDeviceSize(first_texel_[field]) * sizeof(float);
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {uint32_t(distance.dims().x), uint32_t(distance.dims().y), uint32_t(distance.dims().z)};
  vkCmdCopyImageToBuffer(cmd, distance.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, texels_.handle(), 1, &region);
  vk::image_barrier(cmd, distance.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                    VK_ACCESS_TRANSFER_READ_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
}

void MarchFields::record_copies_done(VkCommandBuffer cmd) {
  vk::memory_barrier(cmd, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
}

float MarchFields::world_voxel(uint32_t field, const glm::mat4& object_to_world) const {
  return grids_.at(field).voxel_size * singular_value_range(glm::mat3(object_to_world)).y;
}

void MarchFields::place(const std::vector<Placement>& placements) {
  std::vector<gpu::FieldInstance> records;
  std::vector<Aabb> boxes;
  largest_voxel_ = 0.0f;
  skipped_degenerate_ = 0;
  for (const Placement& placement : placements) {
    const GridSpec& grid = grids_.at(placement.field);
    const glm::vec2 stretch = singular_value_range(glm::mat3(placement.object_to_world));
    if (!(stretch.x > kDegenerateScale * stretch.y)) {
      skipped_degenerate_++;
      continue;
    }
    gpu::FieldInstance record{};
    record.world_to_field = grid.world_to_voxel() * glm::inverse(placement.object_to_world);
    record.scale = glm::vec4(stretch.x, stretch.x * grid.voxel_size, stretch.y * grid.voxel_size,
                             margins_[placement.field]);
    record.texels = glm::uvec4(first_texel_[placement.field], glm::uvec3(grid.dims));
    record.box_lo = glm::vec4(box_lo_[placement.field], 0.0f);
    record.box_hi = glm::vec4(box_hi_[placement.field], 0.0f);
    records.push_back(record);
    largest_voxel_ = std::max(largest_voxel_, record.scale.z);
    Aabb box;
    const glm::vec3 lo = grid.origin + box_lo_[placement.field] * grid.voxel_size;
    const glm::vec3 hi = grid.origin + box_hi_[placement.field] * grid.voxel_size;
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
