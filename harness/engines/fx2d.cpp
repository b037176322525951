// The Fx2D adapter: builds a SceneSpec into an FxScene and reports Fx2D's own stage profile as
// its phase split.
#include <stdexcept>
#include <string>

#include "engines/engines.h"
#include "fx2d/fx2d.h"

namespace fxbench {
namespace {

fx2d::FxVec2f to_fx(Vec2 v) { return {static_cast<float>(v.x), static_cast<float>(v.y)}; }

fx2d::FxShape make_shape(const BodySpec& body) {
  switch (body.shape) {
    case ShapeKind::circle:
      return fx2d::FxShape::circle(static_cast<float>(body.radius));
    case ShapeKind::box:
      return fx2d::FxShape::box(static_cast<float>(body.half_extents.x), static_cast<float>(body.half_extents.y));
    case ShapeKind::polygon: {
      std::vector<fx2d::FxVec2f> points;
      for (const Vec2& v : body.vertices) points.push_back(to_fx(v));
      return fx2d::FxShape::polygon(points);
    }
  }
  throw std::runtime_error("fx2d adapter: unknown shape kind");
}

fx2d::FxBodyType to_fx(BodyType type) {
  switch (type) {
    case BodyType::static_body: return fx2d::FxBodyType::static_body;
    case BodyType::kinematic: return fx2d::FxBodyType::kinematic;
    case BodyType::dynamic: return fx2d::FxBodyType::dynamic;
  }
  throw std::runtime_error("fx2d adapter: unknown body type");
}

class Fx2dEngine final : public Engine {
 public:
  std::vector<std::string> phase_names() const override {
    std::vector<std::string> names;
    for (int i = 0; i < fx2d::fx_stage_count; ++i) names.emplace_back(fx2d::stage_name(static_cast<fx2d::FxStage>(i)));
    return names;
  }

  void build(const SceneSpec& scene) override {
    fx2d::FxSceneSettings settings;
    settings.gravity = to_fx(scene.gravity);
    settings.dt = static_cast<float>(scene.dt);
    settings.substeps = scene.fx2d.substeps;
    settings.velocity_passes = scene.fx2d.velocity_passes;
    settings.sleeping = scene.fx2d.sleeping;
    try {
      scene_ = std::make_unique<fx2d::FxScene>(settings);
      for (const BodySpec& body : scene.bodies) entities_.push_back(scene_->create_entity(make_def(body)));
      for (const JointSpec& joint : scene.joints) scene_->add_constraint(make_joint(joint));
    } catch (const fx2d::FxInvalidArgument& error) {
      throw std::runtime_error(std::string("fx2d: ") + error.what());
    }
  }

  void step() override { scene_->step(); }

  void read_phases(std::span<double> ms) const override {
    const fx2d::FxProfile& profile = scene_->profile();
    for (std::size_t i = 0; i < ms.size(); ++i) ms[i] = profile.stage_ms[i];
  }

  int contact_count() const override { return scene_->contact_count(); }

  void read_state(std::vector<BodyState>& out) const override {
    out.resize(entities_.size());
    for (std::size_t i = 0; i < entities_.size(); ++i) {
      const fx2d::FxEntity& e = *entities_[i];
      out[i].position = {e.precise_x(), e.precise_y()};
      out[i].angle = e.angle();
      out[i].linear_velocity = {e.linear_velocity().x, e.linear_velocity().y};
      out[i].angular_velocity = e.angular_velocity();
    }
  }

 private:
  static fx2d::FxEntityDef make_def(const BodySpec& body) {
    fx2d::FxEntityDef def;
    def.type = to_fx(body.type);
    def.shape = make_shape(body);
    def.position = to_fx(body.position);
    def.angle = static_cast<float>(body.angle);
    def.linear_velocity = to_fx(body.linear_velocity);
    def.angular_velocity = static_cast<float>(body.angular_velocity);
    def.material.density = static_cast<float>(body.material.density);
    def.material.static_friction = static_cast<float>(body.material.static_friction);
    def.material.dynamic_friction = static_cast<float>(body.material.dynamic_friction);
    def.material.restitution = static_cast<float>(body.material.restitution);
    return def;
  }

  std::shared_ptr<fx2d::FxConstraint> make_joint(const JointSpec& joint) const {
    const auto& a = entities_.at(static_cast<std::size_t>(joint.body_a));
    const auto& b = entities_.at(static_cast<std::size_t>(joint.body_b));
    const fx2d::FxVec2f anchor_a = to_fx(joint.local_anchor_a);
    if (joint.kind == JointKind::distance) {
      return std::make_shared<fx2d::FxDistanceJoint>(a, b, anchor_a, to_fx(joint.local_anchor_b),
                                                     static_cast<float>(joint.length));
    }
    return std::make_shared<fx2d::FxRevoluteJoint>(a, b, a->position() + rotate(a->rotation(), anchor_a));
  }

  std::unique_ptr<fx2d::FxScene> scene_;
  std::vector<std::shared_ptr<fx2d::FxEntity>> entities_;
};

}  // namespace

std::unique_ptr<Engine> make_fx2d_engine() { return std::make_unique<Fx2dEngine>(); }

}  // namespace fxbench
