// Entity lifetime and the FxEntity handle. Creation validates the definition and appends to every
// packed array; removal compacts them in one pass, preserving creation order, and remaps every
// index stored elsewhere (contacts, proxies, sleeping islands), so other handles stay valid.
#include <algorithm>
#include <cmath>
#include <string>

#include "world/world.h"

namespace fx2d {

struct FxEntity::Snapshot : detail::Snapshot {};

FxEntity::FxEntity(detail::World* world, std::uint32_t packed_index) : world_(world), packed_index_(packed_index) {}

FxEntity::~FxEntity() = default;

namespace detail {
namespace {

void require(bool condition, const char* field, const char* expected) {
  if (!condition) throw FxInvalidArgument(std::string("FxEntityDef: ") + field + ": expected " + expected);
}

void validate(const FxEntityDef& def, const FxSceneSettings& settings) {
  const bool bounded = is_finite(def.position) && std::fabs(def.position.x) <= max_coordinate &&
                       std::fabs(def.position.y) <= max_coordinate;
  require(bounded, "position", "finite coordinates within +-1e7 m");
  require(std::isfinite(def.angle), "angle", "a finite number");
  require(is_finite(def.linear_velocity) && length(def.linear_velocity) <= settings.max_linear_speed, "linear_velocity",
          "finite components, speed <= FxSceneSettings::max_linear_speed");
  require(std::isfinite(def.angular_velocity) && std::fabs(def.angular_velocity) <= max_angular_speed(settings),
          "angular_velocity", "a finite number, |w| <= a quarter turn per substep");
  require(std::isfinite(def.linear_damping) && def.linear_damping >= 0.0f, "linear_damping", "a finite number >= 0");
  require(std::isfinite(def.angular_damping) && def.angular_damping >= 0.0f, "angular_damping", "a finite number >= 0");
  const FxMaterial& m = def.material;
  if (def.type == FxBodyType::dynamic) {
    require(std::isfinite(m.density) && m.density > 0.0f, "material.density", "a finite number > 0 for a dynamic body");
  }
  require(std::isfinite(m.static_friction) && m.static_friction >= 0.0f, "material.static_friction", "a finite number >= 0");
  require(std::isfinite(m.dynamic_friction) && m.dynamic_friction >= 0.0f, "material.dynamic_friction", "a finite number >= 0");
  require(std::isfinite(m.restitution) && m.restitution >= 0.0f && m.restitution <= 1.0f, "material.restitution",
          "a number in [0, 1]");
}

}  // namespace

// Mass properties of a dynamic body; checked before anything is stored, so a rejected definition
// leaves no trace.
FxMassData checked_mass(const FxEntityDef& def) {
  const FxMassData mass = def.shape.mass_data(def.material.density);
  // Within these bounds every product the solver forms (effective masses, impulses, impulse times
  // inverse mass or inertia times lever arm) stays finite in float for any shape up to
  // FxShape::max_extent; a mass of 1e-38 kg or 1e38 kg, though finite, would overflow one of them.
  const auto within = [](float value, float low, float high) { return value >= low && value <= high; };
  require(within(mass.mass, fx_min_mass, fx_max_mass), "material.density",
          "a density that gives a mass in [1e-9, 1e20] kg");
  require(within(mass.rotational_inertia, fx_min_rotational_inertia, fx_max_rotational_inertia), "material.density",
          "a density that gives a rotational inertia in [1e-18, 1e32] kg m^2");
  return mass;
}

std::shared_ptr<FxEntity> World::create_entity(const FxEntityDef& def) {
  if (bodies_.count() >= fx_max_entities) {
    throw FxInvalidArgument("FxScene::create_entity: expected a scene of at most " +
                            std::to_string(fx_max_entities) + " entities");
  }
  validate(def, settings_);
  const FxMassData mass = def.type == FxBodyType::dynamic ? checked_mass(def) : FxMassData{0.0f, def.shape.centroid(), 0.0f};
  reserve_scratch();
  const std::uint32_t index = bodies_.count();
  std::shared_ptr<FxEntity> handle(new FxEntity(this, index));

  BodyRecord& record = bodies_.records.emplace_back();
  record.handle = handle;
  record.shape = def.shape;
  record.material = def.material;
  record.type = def.type;
  record.can_sleep = def.can_sleep;
  record.bullet = def.bullet;
  record.awake = def.type != FxBodyType::static_body;
  if (record.awake) ++bodies_.awake_count;
  record.linear_damping = def.linear_damping;
  record.angular_damping = def.angular_damping;

  BodySim& sim = bodies_.sims.emplace_back();
  sim.origin = def.position;
  sim.rotation = FxRot::from_angle(def.angle);
  sim.local_center = mass.center;
  record.mass = mass.mass;
  record.rotational_inertia = mass.rotational_inertia;
  if (def.type == FxBodyType::dynamic) {
    sim.inv_mass = 1.0f / mass.mass;
    sim.inv_inertia = mass.rotational_inertia > 0.0f ? 1.0f / mass.rotational_inertia : 0.0f;
  }
  if (def.type != FxBodyType::static_body) {
    // The definition gives the origin's velocity; the solver works with the centre of mass's.
    sim.angular_velocity = def.angular_velocity;
    sim.linear_velocity = def.linear_velocity + cross(def.angular_velocity, rotate(sim.rotation, sim.local_center));
  }
  def.shape.compute_aabb(FxTransform{sim.origin, sim.rotation}, sim.aabb);
  set_continuous_extents(sim, def.type, def.shape);
  sim.enclosing_radius = def.shape.extent() + distance(def.shape.centroid(), sim.local_center);

  broad_phase_.add_body(record, sim.aabb, index);
  record.moved = true;
  broad_phase_.may_have_moved = true;
  return handle;
}

// Per-step scratch grows with the body count here, at creation, not inside a step as a scene's
// contacts build up. Four pair records per body (reserved for twice the bodies present, so the
// growth is geometric) covers piles and heaps, which settle at about three.
void World::reserve_scratch() {
  if (bodies_.records.size() < reserved_bodies_) return;
  reserved_bodies_ = std::max<std::size_t>(64, 2 * bodies_.records.size());
  const std::size_t n = reserved_bodies_;
  bodies_.records.reserve(n);
  bodies_.sims.reserve(n);
  solver_.reserve(n);
  broad_phase_.reserve(n);
  sleep_.reserve(n);
  continuous_.reserve(n);
  contacts_.slots.reserve(4 * n);
  narrow_phase_.reserve(n, 4 * n);
}

std::uint32_t World::index_of(const FxEntity& entity) const {
  if (entity.world_ != this) throw FxInvalidArgument("FxScene: entity: expected an entity of this scene");
  return entity.packed_index_;
}

void World::remove_entity(std::uint32_t index) {
  if (stepping_) throw FxInvalidArgument("FxScene::remove_entity: expected a call outside step()");
  std::vector<BodyRecord>& records = bodies_.records;
  // What rested on it must notice it is gone.
  wake_body(index);
  for (int edge = records[index].contact_head; edge >= 0;) {
    const int next_edge = contacts_.next(edge);
    const int id = ContactCache::contact_of(edge);
    const std::uint32_t other = contacts_.other_body(edge);
    wake_body(other);
    CachedContact& contact = contacts_.slots[id];
    contacts_.destroy(id, records[contact.body_a].contact_head, records[contact.body_b].contact_head);
    edge = next_edge;
  }
  FxEntity& entity = *records[index].handle;
  std::erase_if(constraints_, [&](const std::shared_ptr<FxConstraint>& c) {
    return c->entity_a().get() == &entity || c->entity_b().get() == &entity;
  });
  broad_phase_.jointed_pairs_dirty = true;
  broad_phase_.remove_body(records[index]);

  if (records[index].awake) --bodies_.awake_count;
  auto snapshot = std::make_unique<FxEntity::Snapshot>();
  snapshot->record = std::move(records[index]);
  snapshot->sim = bodies_.sims[index];
  std::shared_ptr<FxEntity> keep_alive = std::move(snapshot->record.handle);
  entity.detached_ = std::move(snapshot);
  entity.world_ = nullptr;

  records.erase(records.begin() + index);
  bodies_.sims.erase(bodies_.sims.begin() + index);
  auto shifted = [index](std::uint32_t i) { return i > index ? i - 1 : i; };
  for (std::uint32_t i = index; i < records.size(); ++i) {
    records[i].handle->packed_index_ = i;
    broad_phase_.renumber(records[i], i);
  }
  for (CachedContact& contact : contacts_.slots) {
    contact.body_a = shifted(contact.body_a);
    contact.body_b = shifted(contact.body_b);
  }
  for (BodyRecord& record : records) {
    if (record.sleep_island > static_cast<int>(index)) --record.sleep_island;
  }
}

void World::refresh_aabb(std::uint32_t index) {
  BodySim& sim = bodies_.sims[index];
  BodyRecord& record = bodies_.records[index];
  record.shape.compute_aabb(FxTransform{sim.origin, sim.rotation}, sim.aabb);
  broad_phase_.refresh(record, sim, settings_.dt);
  broad_phase_.may_have_moved = true;
}

void World::add_constraint(std::shared_ptr<FxConstraint> constraint) {
  if (!constraint) throw FxInvalidArgument("FxScene::add_constraint: constraint: expected a constraint, got null");
  const std::uint32_t a = index_of(*constraint->entity_a());
  const std::uint32_t b = index_of(*constraint->entity_b());
  // Jointed bodies do not collide: drop a contact they may already have.
  for (int edge = bodies_.records[a].contact_head; edge >= 0; edge = contacts_.next(edge)) {
    if (contacts_.other_body(edge) != b) continue;
    const CachedContact& contact = contacts_.slots[ContactCache::contact_of(edge)];
    contacts_.destroy(ContactCache::contact_of(edge), bodies_.records[contact.body_a].contact_head,
                      bodies_.records[contact.body_b].contact_head);
    break;
  }
  constraints_.push_back(std::move(constraint));
  broad_phase_.jointed_pairs_dirty = true;
}

void World::remove_constraint(const FxConstraint& constraint) {
  std::erase_if(constraints_, [&](const std::shared_ptr<FxConstraint>& c) { return c.get() == &constraint; });
  broad_phase_.jointed_pairs_dirty = true;
}

World::~World() {
  // Handles outlive the scene: leave each one a snapshot of its last state.
  for (std::size_t i = 0; i < bodies_.records.size(); ++i) {
    FxEntity& entity = *bodies_.records[i].handle;
    auto snapshot = std::make_unique<FxEntity::Snapshot>();
    snapshot->record = bodies_.records[i];
    snapshot->record.handle.reset();
    snapshot->sim = bodies_.sims[i];
    entity.detached_ = std::move(snapshot);
    entity.world_ = nullptr;
  }
}

}  // namespace detail

const detail::BodyRecord& FxEntity::record() const {
  return world_ ? world_->bodies().records[packed_index_] : detached_->record;
}

const detail::BodySim& FxEntity::sim() const { return world_ ? world_->bodies().sims[packed_index_] : detached_->sim; }

detail::BodySim& FxEntity::live_sim(const char* operation) {
  if (!world_) throw FxInvalidArgument(std::string("FxEntity::") + operation + ": expected an entity in a scene");
  return world_->sim(packed_index_);
}

FxBodyType FxEntity::type() const { return record().type; }
const FxShape& FxEntity::shape() const { return record().shape; }
const FxMaterial& FxEntity::material() const { return record().material; }
float FxEntity::mass() const { return record().mass; }
float FxEntity::rotational_inertia() const { return record().rotational_inertia; }
FxVec2f FxEntity::position() const { return sim().origin; }
double FxEntity::precise_x() const { return precise_value(sim().origin.x, sim().carry.x); }
double FxEntity::precise_y() const { return precise_value(sim().origin.y, sim().carry.y); }
float FxEntity::angle() const { return sim().rotation.angle(); }
FxRot FxEntity::rotation() const { return sim().rotation; }
FxVec2f FxEntity::world_center() const { return sim().origin + rotate(sim().rotation, sim().local_center); }
FxVec2f FxEntity::linear_velocity() const { return sim().linear_velocity; }
float FxEntity::angular_velocity() const { return sim().angular_velocity; }
FxAABB FxEntity::aabb() const { return sim().aabb; }
bool FxEntity::is_awake() const { return record().awake; }

void FxEntity::set_transform(FxVec2f position, float angle) {
  if (!is_finite(position) || std::fabs(position.x) > detail::max_coordinate ||
      std::fabs(position.y) > detail::max_coordinate || !std::isfinite(angle)) {
    throw FxInvalidArgument("FxEntity::set_transform: position, angle: expected finite values within +-1e7 m");
  }
  detail::BodySim& body = live_sim("set_transform");
  body.origin = position;
  body.carry = {};
  body.rotation = FxRot::from_angle(angle);
  world_->wake_body(packed_index_);
  world_->refresh_aabb(packed_index_);
}

void FxEntity::set_linear_velocity(FxVec2f velocity) {
  if (!is_finite(velocity)) throw FxInvalidArgument("FxEntity::set_linear_velocity: velocity: expected finite components");
  if (type() == FxBodyType::static_body) return;
  detail::BodySim& body = live_sim("set_linear_velocity");
  body.linear_velocity = velocity;
  detail::clamp_velocity(world_->settings(), body);
  wake();
  world_->refresh_aabb(packed_index_);  // its next step's motion may leave its fat box
}

void FxEntity::set_angular_velocity(float velocity) {
  if (!std::isfinite(velocity)) throw FxInvalidArgument("FxEntity::set_angular_velocity: velocity: expected a finite number");
  if (type() == FxBodyType::static_body) return;
  detail::BodySim& body = live_sim("set_angular_velocity");
  body.angular_velocity = velocity;
  detail::clamp_velocity(world_->settings(), body);
  wake();
}

void FxEntity::apply_linear_impulse(FxVec2f impulse, FxVec2f world_point) {
  if (!is_finite(impulse) || !is_finite(world_point)) {
    throw FxInvalidArgument("FxEntity::apply_linear_impulse: impulse, world_point: expected finite components");
  }
  detail::BodySim& body = live_sim("apply_linear_impulse");
  if (type() != FxBodyType::dynamic) return;
  body.linear_velocity += body.inv_mass * impulse;
  body.angular_velocity += body.inv_inertia * cross(world_point - world_center(), impulse);
  detail::clamp_velocity(world_->settings(), body);
  wake();
  world_->refresh_aabb(packed_index_);  // its next step's motion may leave its fat box
}

void FxEntity::apply_force(FxVec2f force) {
  if (!is_finite(force)) throw FxInvalidArgument("FxEntity::apply_force: force: expected finite components");
  detail::BodySim& body = live_sim("apply_force");
  if (type() != FxBodyType::dynamic) return;
  body.force += force;
  wake();
}

void FxEntity::wake() {
  if (world_) world_->wake_body(packed_index_);
}

}  // namespace fx2d
