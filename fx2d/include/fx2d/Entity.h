// A rigid body with one collision shape.
//
// Entities are created by FxScene::create_entity() and held by std::shared_ptr; the handle stays
// valid after the entity is removed from its scene (it then reports the pose it had) and after the
// scene is destroyed. The scene stores entity data packed in arrays; packed_index() is the
// entity's position there. It is the same for every call between removals and shifts down only
// when an entity created earlier is removed, so iteration order is creation order.
#pragma once

#include <cstdint>
#include <memory>

#include "fx2d/Math.h"
#include "fx2d/Shape.h"

namespace fx2d {

namespace detail {
class World;
struct BodyRecord;
struct BodySim;
}  // namespace detail

enum class FxBodyType : std::uint8_t {
  static_body,  // never moves, infinite mass
  kinematic,    // moves with its set velocity, infinite mass, pushes dynamic bodies
  dynamic,      // moved by gravity, contacts and constraints
};

struct FxMaterial {
  float density = 1.0f;           // kg/m^2, > 0 for dynamic bodies
  float static_friction = 0.6f;   // dimensionless, >= 0: holds while the contact sticks
  float dynamic_friction = 0.6f;  // dimensionless, >= 0: resists while it slides
  float restitution = 0.0f;       // dimensionless, 0..1: bounce above the scene's threshold speed
};

// The mass properties a dynamic body may have (its shape times its density); create_entity
// refuses others. Any finite float mass is not enough: beyond these, an effective mass or an
// impulse in the solver would overflow float.
inline constexpr float fx_min_mass = 1.0e-9f;                 // kg
inline constexpr float fx_max_mass = 1.0e20f;                 // kg
inline constexpr float fx_min_rotational_inertia = 1.0e-18f;  // kg m^2
inline constexpr float fx_max_rotational_inertia = 1.0e32f;   // kg m^2

struct FxEntityDef {
  FxBodyType type = FxBodyType::dynamic;
  FxShape shape = FxShape::box(0.5f, 0.5f);
  FxMaterial material;
  FxVec2f position;               // body origin, world metres
  float angle = 0.0f;             // radians
  FxVec2f linear_velocity;        // m/s of the body origin
  float angular_velocity = 0.0f;  // rad/s
  float linear_damping = 0.0f;    // 1/s, >= 0
  float angular_damping = 0.0f;   // 1/s, >= 0
  bool can_sleep = true;
  // A bullet is kept from passing through dynamic bodies as well as static and kinematic ones,
  // at any speed up to FxSceneSettings::max_linear_speed: its motion over each step in which it
  // moves farther than half its inner size is swept against theirs (time of impact), at the cost
  // of that sweep. Every dynamic body has this against static and kinematic bodies; bullets do
  // not get it against other bullets.
  bool bullet = false;
};

class FxEntity {
 public:
  FxEntity(const FxEntity&) = delete;
  FxEntity& operator=(const FxEntity&) = delete;
  ~FxEntity();

  std::uint32_t packed_index() const { return packed_index_; }
  bool in_scene() const { return world_ != nullptr; }

  FxBodyType type() const;
  const FxShape& shape() const;
  const FxMaterial& material() const;
  float mass() const;                 // kg, 0 for static and kinematic bodies
  float rotational_inertia() const;   // kg m^2 about the centre of mass

  FxVec2f position() const;           // body origin, world metres (rounded to float)
  // The origin to twice float precision: position() less the accumulated rounding carry.
  double precise_x() const;
  double precise_y() const;
  float angle() const;                // radians in (-pi, pi]
  FxRot rotation() const;
  FxVec2f world_center() const;       // centre of mass, world metres
  FxVec2f linear_velocity() const;    // m/s of the centre of mass
  float angular_velocity() const;     // rad/s
  FxAABB aabb() const;                // tight world bounds as of the last step
  bool is_awake() const;

  // Teleports the body; wakes it. Finite values only (throws FxInvalidArgument).
  void set_transform(FxVec2f position, float angle);
  // Velocity setters and pushes wake the body. Finite values only.
  void set_linear_velocity(FxVec2f velocity);
  void set_angular_velocity(float velocity);
  void apply_linear_impulse(FxVec2f impulse, FxVec2f world_point);  // N s at a world point
  void apply_force(FxVec2f force);                                   // N at the centre, for the next step only
  void wake();

 private:
  friend class detail::World;
  FxEntity(detail::World* world, std::uint32_t packed_index);

  struct Snapshot;  // what the handle reports once detached from its scene
  const detail::BodyRecord& record() const;
  const detail::BodySim& sim() const;
  detail::BodySim& live_sim(const char* operation);  // throws unless in a scene

  detail::World* world_;
  std::uint32_t packed_index_;
  std::unique_ptr<Snapshot> detached_;
};

}  // namespace fx2d
