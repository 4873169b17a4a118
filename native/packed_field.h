#pragma once
// A distance field as the shadow march reads it: one device buffer, reached
// by its address, that holds the fine SDF's texels only in 8^3 bricks where
// the fine SDF was traced (its band around surfaces), and the coarse SDF
// everywhere as the far field (away from surfaces the fine SDF holds the
// coarse distance anyway), in half floats (see shaders/shared.h). Its memory
// follows the surfaces' area rather than the grid's volume, as Unreal's
// mesh distance fields and AMD's Brixelizer store theirs.
#include <cstdint>
#include <memory>
#include <vector>

#include "grid.h"
#include "passes/field_pack.h"
#include "shaders/shared.h"
#include "vk/resources.h"

namespace rtsdf {

class PackedField {
 public:
  // `pass` may be shared between fields; null: a pass of its own.
  explicit PackedField(const vk::Context& context, std::shared_ptr<const FieldPackPass> pass = nullptr);

  // Lays the field out on `grid` (the fine grid) with `far_grid` (the coarse
  // grid, same origin, voxels at least as large) as its far field. The march
  // reads it within `content` (in the grids' space) grown by `room` voxels
  // (< 0: the whole grid). A new layout reads as zero distance everywhere
  // until packed.
  void set_layout(const GridSpec& grid, const GridSpec& far_grid, const Bounds& content, float room = -1.0f);

  struct Source {
    const vk::Image* coarse;  // the far grid's distances (r32f, GENERAL layout)
    const vk::Image* fine;    // the grid's distances, or null: the field is its far field alone
    float band = 0.0f;        // texels whose coarse distance is at most this were traced (see FineTraceSettings)
    float far_offset = 0.0f;  // added to the coarse distances (the fine SDF's far field is c + beta)
  };
  // Records the packing of `source` into the field's words.
  void record_pack(VkCommandBuffer cmd, const Source& source) const;
  // After the commands record_pack recorded have run: false when the bricks
  // needed more room than the field had (always, the first time: a new
  // layout has none); it has the room now, `slack` x the bricks more for
  // later packs of a changing field (at another address), and the same
  // source must be packed again. The bricks stored depend only on the
  // coarse SDF: refining the same field needs no more.
  bool settle(float slack = 0.0f);

  // Frees the field's words (set_layout lays it out again).
  void release();

  // One field to pack, with the slack its room gets (see settle).
  struct Packing {
    PackedField* field;
    Source source;
    float slack = 0.0f;
  };
  // Packs every field in one submission, and again those that needed more
  // room (a second round always fits).
  static void pack(const vk::Context& context, const std::vector<Packing>& packings);

  // The record that places the field, less its transform and scale.
  gpu::FieldInstance instance_record() const;
  const GridSpec& grid() const { return grid_; }
  glm::vec3 box_lo() const { return box_lo_; }  // what the march reads, in the grid's voxels
  glm::vec3 box_hi() const { return box_hi_; }
  // Bumped whenever the words move to another address (placements must be redone).
  uint64_t generation() const { return generation_; }

  size_t bytes() const { return size_t(words_.size() + stored_bricks_.size()) + sizeof(uint32_t); }
  uint32_t stored_bricks() const { return stored_; }
  uint32_t brick_count() const { return uint32_t(bricks_.x) * bricks_.y * bricks_.z; }

  // Every texel of the fine grid as the march reads it (x fastest): from its
  // brick where one is stored, else from the far field. For tools and tests.
  std::vector<float> read_texels() const;

  // A packed field as host data, to be kept on disk (FieldStore) and laid
  // out again as it was, in another process: the words hold no addresses.
  struct Saved {
    GridSpec grid, far_grid;
    glm::vec3 box_lo{0.0f}, box_hi{0.0f};
    float margin = 0.0f;
    uint32_t capacity = 0, stored = 0;
    std::vector<uint32_t> words;
  };
  Saved save() const;
  // A field as `saved` was, ready to be marched (and never packed: a saved
  // field was refined). Throws Error where the words do not fit the layout.
  static std::shared_ptr<PackedField> load(const vk::Context& context, std::shared_ptr<const FieldPackPass> pass,
                                           const Saved& saved);

 private:
  void lay_out_grids(const GridSpec& grid, const GridSpec& far_grid);
  size_t word_count(uint32_t capacity) const;
  std::vector<uint32_t> read_words() const;
  void allocate(uint32_t capacity);

  const vk::Context& context_;
  std::shared_ptr<const FieldPackPass> pass_;
  GridSpec grid_, far_grid_;
  glm::ivec3 bricks_{0};
  glm::vec3 box_lo_{0.0f}, box_hi_{0.0f};
  float margin_ = 0.0f;
  int far_row_ = 0;  // texels in a row of the far field (even: two to a word)
  uint32_t far_first_ = 0, bricks_first_ = 0, capacity_ = 0, stored_ = 0;
  vk::Buffer words_;
  vk::Buffer count_;  // host-visible copy of word 0 after a pack
  vk::Buffer stored_bricks_;  // a pack's list of the bricks it stores (FieldPackPass)
  uint64_t generation_ = 0;
};

}  // namespace rtsdf
