// The factories of the engine adapters, one per translation unit in engines/, and the only names
// those units export. engines/registry.cpp lists them; nothing else should call them directly
// except tests of one adapter.
#pragma once

#include <memory>

#include "engines/engine.h"

namespace fxbench {

std::unique_ptr<Engine> make_fx2d_engine();
// The built-in Fx2D's registry entry: its plugin table's name, knobs and capabilities.
EngineInfo fx2d_engine_info();
std::unique_ptr<Engine> make_box2d_engine();
// The built-in Box2D's registry entry: its linked-in plugin table's name, knobs and capabilities.
EngineInfo box2d_engine_info();
std::unique_ptr<Engine> make_ode_engine();
// The built-in ODE's registry entry: its linked-in plugin table's name, knobs and capabilities.
EngineInfo ode_engine_info();

// How far ODE's bodies have left the plane z = 0, the largest over all bodies. ODE simulates in
// 3D and the adapter holds it to 2D with plane-2D joints plus a flattening pass after each step;
// this is the check that the 2D emulation held. Every field is zero when it did.
struct OutOfPlaneDrift {
  double position_z = 0.0;          // |z| of a body origin, metres
  double linear_velocity_z = 0.0;   // |vz|, m/s
  double angular_velocity_xy = 0.0; // largest of |wx|, |wy|, rad/s
  double rotation_off_z = 0.0;      // largest |R[2]|, |R[6]|, |R[8]|, |R[9]| (0 for a rotation about z)
};

// `engine` must come from make_ode_engine() and be built; throws std::invalid_argument otherwise.
OutOfPlaneDrift ode_out_of_plane_drift(const Engine& engine);

}  // namespace fxbench
