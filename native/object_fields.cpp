#include "object_fields.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>

#include "error.h"
#include "mesh_detail.h"
#include "mesh_topology.h"
#include "vk/context.h"

namespace rtsdf {

namespace {

// Device bytes of one mesh's field at these resolutions while it refines:
// the coarse SDF, the fine SDF's images and lists, and 4 bytes per fine
// texel for the packed field (at worst every brick stored: 3 bytes, and the
// far field).
size_t field_bytes(const Bounds& bounds, int coarse_resolution, int fine_resolution) {
  const GridSpec coarse = fit_grid(bounds, coarse_resolution);
  const GridSpec fine = FineSdf::fit(coarse, fine_resolution);
  return coarse_sdf_bytes(coarse) + fine.voxel_count() * (FineSdf::kBytesPerTexel + sizeof(float));
}

// Room for a quarter more bricks in a deforming mesh's field, so that it
// seldom packs twice in a frame.
constexpr float kDeformingSlack = 0.25f;

// The trace settings of a field's next update: one rebuilt every frame
// keeps its history, so its texels' convergence is never final, and traces
// kDeformingRaysPerTexel rays (at most): each texel measures its own and its
// neighbours' kept nearest triangles again in the new shape
// (fine_trace.comp), and the rays mostly check its sign.
FineTraceSettings trace_settings(const FineTraceSettings& settings, bool rebuilt_every_frame) {
  FineTraceSettings trace = settings;
  trace.skip_converged = settings.skip_converged && !rebuilt_every_frame;
  if (rebuilt_every_frame) trace.rays_per_texel = std::min(settings.rays_per_texel, kDeformingRaysPerTexel);
  return trace;
}

// Whether a field built before was made for another shape of its mesh
// than the scene holds now: the mesh deformed since.
template <class Field>
bool shape_changed(const Field& field, const GpuScene& scene) {
  return field.coarse && field.version != scene.mesh_version(field.mesh);
}

// How far, as a share of a mesh's size (its bounds' largest side), the
// vertices of a near copy may lie from the mesh's own, each from its own:
// every point of its surface then lies as near the mesh's (the same
// triangles between the vertices), an eighth of a voxel at the default
// fine resolution with its detail's factor of 2 (1/256 of the size).
constexpr float kNearCopyShare = 5e-4f;

// The meshes of one topology a mesh is compared with: the last ones found
// with a field of their own. Near copies come in runs (a generator run
// again, a part copied); a scene of thousands of boxes of one topology and
// as many sizes would otherwise compare each with all the others.
constexpr size_t kNearCopyCandidates = 32;

// How many copy_of verdicts are kept before they are let go: a
// deforming mesh brings new digests every frame, and the verdicts of the
// shapes gone would pile up.
constexpr size_t kNearCopyVerdicts = 4096;

// How far a near copy's vertices may lie from those of a mesh of bounds lo, hi.
float near_copy_tolerance(glm::vec3 lo, glm::vec3 hi) {
  const glm::vec3 e = hi - lo;
  return kNearCopyShare * std::max(e.x, std::max(e.y, e.z));
}

// The root mean square of the vertices' distances from their centroid: the
// same for a copy however it was turned and moved (within twice the
// tolerance for a near copy), so most meshes of one topology that are not
// copies are told apart without comparing their vertices.
float vertex_spread(const std::vector<glm::vec3>& positions) {
  if (positions.empty()) return 0.0f;
  glm::dvec3 sum(0.0);
  for (const glm::vec3& p : positions) sum += glm::dvec3(p);
  const glm::dvec3 centroid = sum / double(positions.size());
  double squares = 0.0;
  for (const glm::vec3& p : positions) {
    const glm::dvec3 d = glm::dvec3(p) - centroid;
    squares += glm::dot(d, d);
  }
  return float(std::sqrt(squares / double(positions.size())));
}

// Where b lies as a copy of a: the rigid motion (a turn and a shift, no
// mirror or scale) taking each of a's vertices to within `tolerance` of
// b's, or none. The identity for a copy in place. Importers that bake
// transforms into the vertices (OBJ has no instances) give each copy of a
// part its own turned and moved vertices; it shares a's field, placed by
// this motion.
// (p and q: the two meshes' vertices, their triangles the same)
std::optional<glm::mat4> copy_placement(const std::vector<glm::vec3>& p, const std::vector<glm::vec3>& q,
                                        float tolerance) {
  if (p.size() != q.size() || p.empty()) return std::nullopt;
  auto within = [&](const glm::mat3& turn, glm::vec3 shift) {
    for (size_t i = 0; i < p.size(); ++i)
      if (!(glm::distance(turn * p[i] + shift, q[i]) <= tolerance)) return false;
    return true;
  };
  if (within(glm::mat3(1.0f), glm::vec3(0.0f))) return glm::mat4(1.0f);
  // Frames on three vertices far apart (the first, the farthest from it,
  // the farthest from the line through both), the same three in each.
  size_t far = 0, off = 0;
  for (size_t i = 0; i < p.size(); ++i)
    if (glm::distance(p[i], p[0]) > glm::distance(p[far], p[0])) far = i;
  const glm::vec3 axis = p[far] - p[0];
  auto off_line = [&](size_t i) { return glm::length(glm::cross(p[i] - p[0], axis)); };
  for (size_t i = 0; i < p.size(); ++i)
    if (off_line(i) > off_line(off)) off = i;
  // (too close or too straight to fix a turn within the tolerance: no copy)
  const float length = glm::length(axis);
  if (!(length > 100.0f * tolerance) || !(off_line(off) / length > 100.0f * tolerance)) return std::nullopt;
  auto frame = [&](const std::vector<glm::vec3>& v) {
    const glm::vec3 u = glm::normalize(v[far] - v[0]);
    const glm::vec3 w = glm::normalize(glm::cross(u, v[off] - v[0]));
    return glm::mat3(u, glm::cross(w, u), w);
  };
  const glm::mat3 turn = frame(q) * glm::transpose(frame(p));
  const glm::vec3 shift = q[0] - turn * p[0];
  if (!within(turn, shift)) return std::nullopt;
  glm::mat4 placement(turn);
  placement[3] = glm::vec4(shift, 1.0f);
  return placement;
}

bool has_volume_to_fit(const Bounds& bounds) {
  const glm::vec3 e = bounds.extent();
  return !bounds.is_empty() && std::max(e.x, std::max(e.y, e.z)) > 0.0f;
}

}  // namespace

ObjectFields::ObjectFields(const vk::Context& context, std::shared_ptr<FieldCache> cache)
    : context_(context),
      cache_(std::move(cache)),
      coarse_passes_(std::make_shared<CoarsePasses>(context)),
      fine_pass_(std::make_shared<const FineTracePass>(context)),
      pack_pass_(std::make_shared<const FieldPackPass>(context)) {}

int ObjectFields::update_limit() const {
  return settings_.updates > 0 ? settings_.updates : 4 * std::max(settings_.fine.interleave, 1);
}

bool ObjectFields::refining() const {
  return std::any_of(fields_.begin(), fields_.end(), [&](const Field& f) { return due(f); });
}

void ObjectFields::rebuild(GpuScene& scene, Field& field, const Bounds& bounds, int coarse_resolution,
                           int fine_resolution) {
  const bool same_resolution = field.coarse && field.coarse_resolution == coarse_resolution &&
                               field.fine_resolution == fine_resolution && field.beta == settings_.beta;
  const GridSpec* current = settings_.keep_history && same_resolution ? &field.coarse_grid : nullptr;
  // Room around the mesh only once it deforms: a rigid mesh never outgrows its grid.
  const bool deformed = shape_changed(field, scene);
  const GridSpec coarse_grid =
      keep_or_fit_grid(current, bounds, coarse_resolution, deformed ? settings_.grid_slack : 0.0f);
  const bool same_grid = current && coarse_grid.origin == field.coarse_grid.origin &&
                         coarse_grid.voxel_size == field.coarse_grid.voxel_size && coarse_grid.dims == field.coarse_grid.dims;
  if (!field.coarse) field.coarse = std::make_unique<CoarseSdf>(context_, coarse_passes_);
  if (!field.fine) field.fine = std::make_unique<FineSdf>(context_, fine_pass_);
  if (!field.packed || field.borrowed) field.packed = std::make_shared<PackedField>(context_, pack_pass_);
  field.borrowed = false;
  field.deforms = field.deforms || deformed;
  field.coarse_grid = coarse_grid;
  field.fine_grid = FineSdf::fit(coarse_grid, fine_resolution);
  field.coarse->build_mesh(scene, field.mesh, coarse_grid, settings_.beta);
  // A kept grid keeps the fine SDF's history (the decay forgets what the
  // deformation moved); anything else starts afresh.
  if (!same_grid) field.fine->release();
  field.coarse_resolution = coarse_resolution;
  field.fine_resolution = fine_resolution;
  field.beta = settings_.beta;
  field.version = scene.mesh_version(field.mesh);
  field.updates = 0;
  field.quiet_updates = 0;
  stats_.regenerated++;
}

bool ObjectFields::reuse(GpuScene& scene, Field& field, const FieldKey& key) {
  if (!cache_ || (settings_.keep_history && field.deforms)) return false;
  std::optional<CachedField> cached = cache_->find(key);
  if (!cached && (cached = cache_->load(key, context_, pack_pass_))) stats_.loaded++;
  if (!cached) return false;
  // (empty SDFs: a later deformation rebuilds them)
  if (!field.coarse) field.coarse = std::make_unique<CoarseSdf>(context_, coarse_passes_);
  if (!field.fine) field.fine = std::make_unique<FineSdf>(context_, fine_pass_);
  field.coarse->release();
  field.fine->release();
  field.packed = cached->packed;
  field.borrowed = true;
  field.coarse_grid = cached->coarse_grid;
  field.fine_grid = cached->fine_grid;
  field.coarse_resolution = key.coarse_resolution;
  field.fine_resolution = key.fine_resolution;
  field.beta = key.beta;
  field.version = scene.mesh_version(field.mesh);
  field.updates = key.updates;
  stats_.reused++;
  return true;
}

void ObjectFields::sync(GpuScene& scene, const ObjectFieldSettings& settings, MarchFields& march) {
  if (!(settings.budget_mb > 0.0)) throw Error("the field memory budget must be positive");
  settings_ = settings;
  if (scene.id() != scene_id_) {
    fields_.clear();
    digests_.clear();
    features_.clear();
    scene_id_ = scene.id();
  }
  stats_ = {};

  // The meshes that need a field: those of the shadow casters (with
  // triangles and some extent), each once however many instances it has.
  const std::vector<Instance>& instances = scene.instances();
  std::vector<uint32_t> meshes;
  for (uint32_t i : scene.shadow_casters()) meshes.push_back(instances[i].mesh);
  std::sort(meshes.begin(), meshes.end());
  meshes.erase(std::unique(meshes.begin(), meshes.end()), meshes.end());
  std::vector<Bounds> bounds;
  std::vector<uint32_t> kept;
  for (uint32_t m : meshes) {
    const Bounds b = scene.mesh_bounds(m);
    if (scene.meshes()[m].triangle_count == 0 || !has_volume_to_fit(b)) continue;
    kept.push_back(m);
    bounds.push_back(b);
  }
  meshes = kept;

  // Meshes of one geometry share one field, the first one's: importers
  // (Collada, FBX, OBJ) give each copy of a part its own mesh, as does a
  // duplicate that is not linked, and a field for each made a scene of 64
  // copies of one 12-triangle box take two minutes (assimp's
  // anims_with_full_rotations_between_keys.DAE).
  // Told apart by their digests, as the FieldCache tells fields apart (the
  // arrays compared on every sync cost a frame of a playback as much as
  // reading every copy's vertices).
  std::vector<size_t> twin(meshes.size());  // per mesh: the index (in meshes) of the mesh whose field it reads
  // Per mesh: where it lies as a copy of its twin (the identity for the twin itself and copies in place).
  std::vector<glm::mat4> placed_as(meshes.size(), glm::mat4(1.0f));
  {
    std::unordered_map<uint64_t, size_t> firsts;  // digest -> the first mesh of that geometry
    for (size_t k = 0; k < meshes.size(); ++k) twin[k] = firsts.try_emplace(digest(scene, meshes[k]), k).first->second;
    // Near copies share too: generators and importers give copies of one
    // part whose vertices differ by rounding (Bolt Factory's nuts, made twice
    // with the same options: 0.005 mm apart on 21 mm, a field each), or
    // turned and moved (copy_placement).
    // Compared as stored (copies whose vertices were split alike), then
    // welded (copies whose importer split them apart differently).
    // Per form: topology -> the meshes with a field of their own so far.
    std::unordered_map<uint64_t, std::vector<size_t>> shapes[2];
    for (size_t k = 0; k < meshes.size(); ++k) {
      if (twin[k] != k) {
        // (the first of its geometry may have joined a near copy)
        placed_as[k] = placed_as[twin[k]];
        twin[k] = twin[twin[k]];
        continue;
      }
      for (const Form form : {Form::Stored, Form::Welded}) {
        const std::vector<size_t>& alike = shapes[int(form)][topology(scene, meshes[k], form)];
        for (size_t n = alike.size(); twin[k] == k && n > 0 && n + kNearCopyCandidates > alike.size(); --n)
          if (const std::optional<glm::mat4> placement =
                  copy_of(scene, meshes[alike[n - 1]], bounds[alike[n - 1]], meshes[k], form))
            twin[k] = alike[n - 1], placed_as[k] = *placement;
      }
      if (twin[k] == k)
        for (const Form form : {Form::Stored, Form::Welded}) shapes[int(form)][topology(scene, meshes[k], form)].push_back(k);
    }
  }
  std::vector<uint32_t> owners;  // the meshes with a field, in mesh order
  std::vector<Bounds> owner_bounds;
  std::vector<size_t> field_index(meshes.size());  // per mesh: its field in fields_
  readers_.clear();
  for (size_t k = 0; k < meshes.size(); ++k) {
    // (a copy turned or moved reads its twin's field in the twin's space, not its own)
    if (placed_as[k] == glm::mat4(1.0f)) readers_[meshes[k]] = meshes[twin[k]];
    if (twin[k] != k) {
      field_index[k] = field_index[twin[k]];
      continue;
    }
    field_index[k] = owners.size();
    owners.push_back(meshes[k]);
    owner_bounds.push_back(bounds[k]);
  }

  // Resolutions: each mesh's own, times its detail's factor (mesh_detail.h),
  // lowered alike until all fit the budget.
  // A mesh that deforms keeps its size's resolution: its field is traced
  // anew every frame, and the trace's cost grows with the square of the
  // resolution. A rigid mesh's is traced once.
  std::vector<std::vector<Field>::iterator> olds(owners.size());  // each owner's field from before, if any
  std::vector<float> details(owners.size(), 1.0f);
  for (size_t k = 0; k < owners.size(); ++k) {
    auto old = olds[k] =
        std::find_if(fields_.begin(), fields_.end(), [&](const Field& f) { return f.mesh == owners[k]; });
    const bool deforms = old != fields_.end() && (old->deforms || shape_changed(*old, scene));
    const glm::vec3 e = owner_bounds[k].extent();
    if (!deforms)
      details[k] = detail_scale(feature_size(scene, owners[k]), std::max(e.x, std::max(e.y, e.z)),
                                settings.fine_resolution);
  }
  const double budget = settings.budget_mb * 1024.0 * 1024.0;
  const double surface_budget = settings.surface_voxel_budget > 0.0 ? settings.surface_voxel_budget : kSurfaceVoxelBudget;
  float scale = 1.0f;
  stats_.surface_limited = false;
  auto resolutions = [&](float s) {
    const int coarse = std::max(8, int(std::lround(settings.coarse_resolution * s)));
    const int fine = std::min(int(gpu::kMaxGridResolution), int(std::lround(settings.fine_resolution * s)));
    return std::pair{coarse, std::max(coarse, fine)};
  };
  for (int attempt = 0;; ++attempt) {
    double total = 0.0, surface = 0.0;
    int coarse = 0;
    for (size_t k = 0; k < owners.size(); ++k) {
      const auto [c, f] = resolutions(scale * details[k]);
      total += double(field_bytes(owner_bounds[k], c, f));
      coarse = std::max(coarse, c);
      const glm::vec3 e = owner_bounds[k].extent();
      const double voxel = double(std::max(e.x, std::max(e.y, e.z))) / double(f);
      if (voxel > 0.0) surface += surface_area(scene, owners[k]) / (voxel * voxel);
    }
    if (owners.empty() || coarse == 8) {
      if (total <= budget || owners.empty()) break;  // (the surface budget is a cost, not a limit: at the coarsest, go on)
    } else if (total <= budget && surface <= surface_budget) {
      break;
    }
    if (coarse == 8 || attempt == 32)
      throw Error("the distance fields of " + std::to_string(owners.size()) + " meshes need " +
                  std::to_string(int(total / (1 << 20))) + " MiB even at the coarsest resolution, over the budget of " +
                  std::to_string(int(settings.budget_mb)) + " MiB");
    // (memory goes with the cube of the resolution, the surface voxels with its square)
    const double by_memory = std::cbrt(budget / total), by_surface = std::sqrt(surface_budget / surface);
    stats_.surface_limited = by_surface < by_memory;
    scale *= std::min(0.95f, float(std::min(by_memory, by_surface)));
  }
  stats_.resolution_scale = scale;

  // Keep the fields of meshes still casting, in mesh order; (re)build what is stale.
  std::vector<Field> fields;
  for (size_t k = 0; k < owners.size(); ++k) {
    Field field;
    if (olds[k] != fields_.end()) field = std::move(*olds[k]);
    field.mesh = owners[k];
    field.detail = details[k];
    const auto [coarse_resolution, fine_resolution] = resolutions(scale * details[k]);
    FieldKey key{digest(scene, field.mesh), coarse_resolution, fine_resolution, settings.beta, settings.fine,
                 update_limit()};
    if (!field.coarse || field.version != scene.mesh_version(field.mesh) || !(key == field.key)) {
      if (!reuse(scene, field, key)) rebuild(scene, field, owner_bounds[k], coarse_resolution, fine_resolution);
      field.key = key;
    }
    fields.push_back(std::move(field));
  }
  fields_ = std::move(fields);
  for (auto it = digests_.begin(); it != digests_.end();)  // (those of meshes gone from the casters)
    it = std::binary_search(meshes.begin(), meshes.end(), it->first) ? std::next(it) : digests_.erase(it);
  for (auto it = features_.begin(); it != features_.end();)
    it = std::binary_search(owners.begin(), owners.end(), it->first) ? std::next(it) : features_.erase(it);

  // The march reads each field within the margin a tight grid would have
  // around its mesh: a deforming mesh's room holds only far values.
  for (size_t k = 0; k < fields_.size(); ++k) {
    const Field& f = fields_[k];
    if (f.borrowed) continue;  // (laid out so by the renderer that refined it)
    const int coarse_longest = std::max(f.coarse_grid.dims.x, std::max(f.coarse_grid.dims.y, f.coarse_grid.dims.z));
    const float room = float(margin_voxels(coarse_longest)) * f.coarse_grid.voxel_size / f.fine_grid.voxel_size;
    f.packed->set_layout(f.fine_grid, f.coarse_grid, owner_bounds[k], room);
  }

  // Place every caster instance of a mesh with a field.
  placements_.clear();
  instance_voxels_.assign(instances.size(), 0.0f);
  for (uint32_t i : scene.shadow_casters()) {
    auto it = std::lower_bound(meshes.begin(), meshes.end(), instances[i].mesh);
    if (it == meshes.end() || *it != instances[i].mesh) continue;
    const size_t index = size_t(it - meshes.begin());
    const PackedField& field = *fields_[field_index[index]].packed;
    const glm::mat4 field_to_world = instances[i].object_to_world * placed_as[index];
    placements_.push_back({&field, field_to_world});
    const glm::vec2 stretch = singular_value_range(glm::mat3(field_to_world));
    if (stretch.x > kDegenerateScale * stretch.y) instance_voxels_[i] = MarchFields::world_voxel(field, field_to_world);
  }
  march.place(placements_);
  for (Field& f : fields_) f.placed_generation = f.packed->generation();

  stats_.fields = int(fields_.size());
  stats_.placed = int(march.instance_count());
  stats_.skipped_degenerate = int(march.skipped_degenerate());
  update_memory_stats();
}

void ObjectFields::update_memory_stats() {
  stats_.bytes = stats_.dense_bytes = 0;
  stats_.stored_bricks = stats_.brick_count = 0;
  stats_.per_field.clear();
  for (const Field& f : fields_) {
    const size_t bytes = f.packed->bytes() + f.coarse->bytes() + f.fine->bytes();
    stats_.per_field.push_back(
        {f.mesh, bytes, f.packed->stored_bricks(), f.packed->brick_count(), f.fine_grid.voxel_size, f.detail});
    stats_.bytes += bytes;
    stats_.dense_bytes += coarse_sdf_bytes(f.coarse_grid) + f.fine_grid.voxel_count() * (FineSdf::kBytesPerTexel + sizeof(float));
    stats_.stored_bricks += f.packed->stored_bricks();
    stats_.brick_count += f.packed->brick_count();
  }
  stats_.peak_bytes = std::max(stats_.peak_bytes, stats_.bytes);
}

const PackedField* ObjectFields::packed_field(uint32_t mesh) const {
  auto owner = readers_.find(mesh);  // (a mesh that shares a copy's field reads that one)
  if (owner == readers_.end()) return nullptr;
  for (const Field& f : fields_)
    if (f.mesh == owner->second && f.updates > 0) return f.packed.get();
  return nullptr;
}

float ObjectFields::feature_size(GpuScene& scene, uint32_t mesh) {
  const Mesh& geometry = scene.scene().meshes[mesh];
  auto it = features_.find(mesh);
  if (it == features_.end() || it->second.triangles != geometry.triangle_count()) {
    // (measured once per geometry for the device's renderers: FieldCache::feature_size)
    const uint64_t key = digest(scene, mesh);
    const std::optional<float> known = cache_ ? cache_->feature_size(key) : std::nullopt;
    const float size = known ? *known : mesh_feature_size(geometry, scene.mesh_bvh(mesh));
    if (cache_ && !known) cache_->remember_feature_size(key, size);
    it = features_.insert_or_assign(mesh, Feature{geometry.triangle_count(), size}).first;
  }
  return it->second.size;
}

uint64_t ObjectFields::digest(const GpuScene& scene, uint32_t mesh) {
  const uint64_t version = scene.mesh_version(mesh);
  auto it = digests_.find(mesh);
  if (it == digests_.end() || it->second.version != version) {
    const Mesh& geometry = scene.scene().meshes[mesh];
    const uint64_t stored_topology = topology_digest(geometry);
    Digest d{version, geometry_digest(geometry, stored_topology)};
    d.topology[int(Form::Stored)] = stored_topology;
    // The weld is kept while the triangles are the same ones and the
    // vertices it joined still meet (a deforming mesh's, every frame).
    std::optional<std::vector<glm::vec3>> welded;
    if (it != digests_.end() && it->second.topology[int(Form::Stored)] == stored_topology && it->second.weld) {
      welded = welded_positions(geometry, *it->second.weld);
      d.weld = it->second.weld;
      d.topology[int(Form::Welded)] = it->second.topology[int(Form::Welded)];
    }
    if (!welded) {
      d.weld = std::make_shared<const WeldedTriangles>(weld_by_position(geometry));
      welded = welded_positions(geometry, *d.weld);
      d.topology[int(Form::Welded)] = topology_digest(welded->size(), d.weld->indices);
    }
    d.spread[int(Form::Stored)] = vertex_spread(geometry.positions);
    d.spread[int(Form::Welded)] = vertex_spread(*welded);
    for (size_t t = 0; t < geometry.triangle_count(); ++t) d.area += triangle_area(geometry, t);
    it = digests_.insert_or_assign(mesh, std::move(d)).first;
  }
  return it->second.digest;
}

double ObjectFields::surface_area(const GpuScene& scene, uint32_t mesh) {
  digest(scene, mesh);
  return digests_[mesh].area;
}

uint64_t ObjectFields::topology(const GpuScene& scene, uint32_t mesh, Form form) {
  digest(scene, mesh);
  return digests_[mesh].topology[int(form)];
}

std::optional<glm::mat4> ObjectFields::copy_of(const GpuScene& scene, uint32_t a, const Bounds& bounds, uint32_t b,
                                               Form form) {
  // (spreads further apart than twice the tolerance rule it out without the vertices)
  const float tolerance = near_copy_tolerance(bounds.lo, bounds.hi);
  digest(scene, a);
  digest(scene, b);
  const Digest &first = digests_[a], &second = digests_[b];
  if (!(std::abs(first.spread[int(form)] - second.spread[int(form)]) <= 2.0f * tolerance)) return std::nullopt;
  const std::tuple<uint64_t, uint64_t, Form> key{first.digest, second.digest, form};
  auto it = copies_.find(key);
  if (it != copies_.end()) return it->second;
  if (copies_.size() >= kNearCopyVerdicts) copies_.clear();
  const Mesh &mesh_a = scene.scene().meshes[a], &mesh_b = scene.scene().meshes[b];
  if (form == Form::Stored)
    return copies_[key] = mesh_a.indices == mesh_b.indices
                              ? copy_placement(mesh_a.positions, mesh_b.positions, tolerance)
                              : std::nullopt;
  // (welded again from the kept welds: digest found they hold)
  const std::optional<std::vector<glm::vec3>> welded_a = welded_positions(mesh_a, *first.weld),
                                               welded_b = welded_positions(mesh_b, *second.weld);
  return copies_[key] = welded_a && welded_b && first.weld->indices == second.weld->indices
                            ? copy_placement(*welded_a, *welded_b, tolerance)
                            : std::nullopt;
}

void ObjectFields::pack(const std::vector<Field*>& fields) {
  std::vector<PackedField::Packing> packings;
  for (Field* f : fields)
    packings.push_back({f->packed.get(),
                        {&f->coarse->distance(), &f->fine->distance(),
                         settings_.fine.band_world(f->coarse_grid.voxel_size), f->coarse->beta_world()},
                        f->deforms ? kDeformingSlack : 0.0f});
  PackedField::pack(context_, packings);
}

void ObjectFields::refine(GpuScene& scene, MarchFields& march) {
  stats_.refined = 0;
  stats_.traced_texels = 0;
  std::vector<Field*> updated;
  for (Field& f : fields_) {
    if (!due(f)) continue;
    const FineTraceSettings trace = trace_settings(settings_.fine, settings_.keep_history && f.deforms);
    double moved;
    f.traced_travel = scene.mesh_move_since(f.mesh, f.traced_version, f.traced_travel, moved);
    f.traced_version = scene.mesh_version(f.mesh);
    const float surface_move = moved < double(gpu::kUnknownSurfaceMove) ? float(moved) : gpu::kUnknownSurfaceMove;
    f.fine->update(scene.mesh_rays(f.mesh), *f.coarse, f.fine_grid, trace, nullptr, surface_move);
    const uint32_t traced = f.fine->read_traced_texels(), improved = f.fine->read_improved_texels();
    stats_.traced_texels += traced;
    stats_.refined++;
    f.updates++;
    // Converged: once every texel was traced twice, a whole round of turns
    // (interleave updates) in which no texel's rays found anything closer.
    f.quiet_updates = improved == 0 ? f.quiet_updates + 1 : 0;
    if (trace.skip_converged && f.updates > trace.interleave && f.quiet_updates >= trace.interleave)
      f.updates = update_limit();
    updated.push_back(&f);
  }
  if (updated.empty()) return;
  pack(updated);
  update_memory_stats();
  // A refined field needs its SDFs no more, unless the mesh deforms and the
  // next rebuild is to keep their history.
  for (Field* f : updated) {
    if (due(*f)) continue;
    if (!(settings_.keep_history && f->deforms)) {
      f->coarse->release();
      f->fine->release();
    }
    if (cache_ && !f->deforms) {
      cache_->insert(f->key, {f->packed, f->coarse_grid, f->fine_grid});
      f->borrowed = true;
    }
  }
  const bool moved = std::any_of(fields_.begin(), fields_.end(),
                                 [](const Field& f) { return f.placed_generation != f.packed->generation(); });
  if (moved) {
    march.place(placements_);
    for (Field& f : fields_) f.placed_generation = f.packed->generation();
  }
  update_memory_stats();
}

}  // namespace rtsdf
