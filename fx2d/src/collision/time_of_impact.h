// Time of impact between two convex shapes moving over one step, by conservative advancement:
// from the distance between the shapes at time t and a bound on how fast any of their points can
// close that distance, t advances by the largest amount that cannot make them touch, until the
// distance is within a tolerance of the target. The result is never past the first touch, so a
// shape placed there has not passed through the other (Mirtich, "Impulse-based Dynamic
// Simulation of Rigid Body Systems", 1996; Box2D's b2TimeOfImpact solves the same problem by
// separating-axis root finding). Only +, *, / and sqrt are used, so results agree bit for bit
// wherever IEEE 754 float arithmetic does. Nothing here allocates.
#pragma once

#include "fx2d/Math.h"
#include "fx2d/Shape.h"

namespace fx2d::detail {

// A body's motion over one step: its centre of mass moves on a line and its rotation turns by the
// normalised linear interpolation of the two rotations. Coordinates are relative to a nearby
// origin, as in collide.h.
struct Sweep {
  FxVec2f local_center;  // centre of mass in the body frame
  FxVec2f center0;       // centre of mass at the step's start
  FxVec2f center1;       // and at its end
  FxRot rotation0;
  FxRot rotation1;

  // The body's pose at fraction t in [0, 1] of the step.
  FxTransform at(float t) const;
  // A bound on how fast (radians per unit of t) the interpolated rotation turns, at any t.
  float max_turn_rate() const;
};

// The distance between two shapes and the unit direction from A's closest point to B's; a distance
// <= 0 means they overlap (then it is the deepest separating-axis separation).
struct Separation {
  float distance = 0.0f;
  FxVec2f normal;
};

// How far a turn about its body's centre of mass `local_center` can carry `shape`'s surface, per
// radian (metres): the farthest vertex's distance for a polygon, the centre's offset for a circle,
// whose surface turns in place about its centre.
float reach(const FxShape& shape, FxVec2f local_center);

Separation shape_separation(const FxShape& a, const FxTransform& xf_a, const FxShape& b, const FxTransform& xf_b);

// When two shapes first come within the target distance in a step, and whether they were already
// that close when it began (in contact).
struct TimeOfImpact {
  float fraction = 1.0f;  // of the step; 1 when they do not
  bool from_contact = false;
};

// The first fraction of the step at which the shapes come within `target` metres (to a quarter
// of it), or 1 when they do not in this step. Shapes that start within two targets may come one
// target closer than they started (into overlap, measured by the deepest separating axis), but
// not deeper than one target or than they started (less the tolerance): their contact keeps them
// apart, but a body that turns about the point it touches is still stopped before the rest of it
// passes in. If the advance has not converged after a bounded number of iterations the fraction
// reached is returned: it is still early.
TimeOfImpact time_of_impact(const FxShape& a, const Sweep& sweep_a, const FxShape& b, const Sweep& sweep_b,
                            float target);

}  // namespace fx2d::detail
