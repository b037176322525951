// Fx2D: a deterministic 2D rigid-body physics engine. Include this for the whole public API.
#pragma once

#include "fx2d/Constraint.h"
#include "fx2d/Contact.h"
#include "fx2d/Entity.h"
#include "fx2d/Math.h"
#include "fx2d/Profile.h"
#include "fx2d/Scene.h"
#include "fx2d/Shape.h"
#include "fx2d/Tasks.h"
#include "fx2d/Version.h"
