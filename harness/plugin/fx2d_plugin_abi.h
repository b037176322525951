/* The C ABI between fx2d-bench and an engine plugin: one physics engine in a shared library.
 *
 * Any 2D engine can be measured by fx2d-bench through this header alone: the plugin says which
 * engine it is, which solver settings ("knobs") it reads, which scenes it can build, how it
 * splits a step into phases, and it builds, steps and reads back one scene at a time. Fx2D itself
 * is one such plugin (harness/plugin/fx2d_plugin.cpp), and Chipmunk2D another
 * (harness/engines/chipmunk/); harness/plugin/README.md walks through writing one.
 *
 * Why C: two builds of one engine (two git revisions, two sets of build flags) are loaded into one
 * process side by side, so that they are timed on the same machine state, allocator and harness.
 * Each plugin holds its own static copy of its engine with every symbol hidden; nothing of C++ (no
 * class layout, no std::string, no exception) crosses between the harness and a plugin, only the
 * plain structs below and one exported function, fx2d_bench_plugin_v1().
 *
 * Invariants: a plugin exports exactly one symbol, FX2D_BENCH_PLUGIN_ENTRY; the table it returns
 * begins with abi_version, and a loader reads nothing else of a table whose abi_version is not
 * the one it was compiled with; no function of the table throws or aborts on bad input (create
 * reports it in its error buffer and returns NULL); every pointer a scene holds is read only
 * during create; every pointer the table holds (names, knobs) lives as long as the library.
 *
 * Units as in harness/scene/scene_spec.h: metres, radians, seconds, kg/m^2; doubles throughout, each
 * plugin converts to its engine's own precision. */
#ifndef FX2D_BENCH_PLUGIN_ABI_H
#define FX2D_BENCH_PLUGIN_ABI_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Raised on any change to a struct or function below; a loader refuses any other version. */
#define FX2D_BENCH_PLUGIN_ABI_VERSION 4
/* The one exported symbol, by name, for dlsym(). Its name is version 1's, kept so that a loader
 * finds a plugin of any version and can name the version it refuses. Version 2 added Fx2D's
 * relax_passes and max_push_speed, version 3 the bullet flag, version 4 made the table
 * engine-neutral: the engine's name, knobs and capabilities, and settings as knob values. */
#define FX2D_BENCH_PLUGIN_ENTRY "fx2d_bench_plugin_v1"

typedef struct Fx2dBenchVec2 {
  double x;
  double y;
} Fx2dBenchVec2;

typedef enum Fx2dBenchBodyType {
  FX2D_BENCH_STATIC_BODY = 0,
  FX2D_BENCH_KINEMATIC_BODY = 1,
  FX2D_BENCH_DYNAMIC_BODY = 2
} Fx2dBenchBodyType;

typedef enum Fx2dBenchShapeKind {
  FX2D_BENCH_CIRCLE = 0,
  FX2D_BENCH_BOX = 1,
  FX2D_BENCH_POLYGON = 2
} Fx2dBenchShapeKind;

typedef enum Fx2dBenchJointKind {
  FX2D_BENCH_DISTANCE_JOINT = 0,
  FX2D_BENCH_REVOLUTE_JOINT = 1
} Fx2dBenchJointKind;

typedef struct Fx2dBenchBody {
  int32_t type;                   /* Fx2dBenchBodyType */
  int32_t shape;                  /* Fx2dBenchShapeKind */
  double radius;                  /* circle, metres */
  Fx2dBenchVec2 half_extents;     /* box, metres */
  const Fx2dBenchVec2* vertices;  /* polygon, body-local, counter-clockwise */
  int32_t vertex_count;
  Fx2dBenchVec2 position;         /* body origin, metres */
  double angle;                   /* radians */
  Fx2dBenchVec2 linear_velocity;  /* m/s */
  double angular_velocity;        /* rad/s */
  double density;                 /* kg/m^2 */
  double static_friction;         /* dimensionless, >= 0 */
  double dynamic_friction;        /* dimensionless, >= 0 */
  double restitution;             /* dimensionless, 0..1 */
  int32_t bullet;                 /* 1: continuous collision against fast dynamic bodies too */
} Fx2dBenchBody;

typedef struct Fx2dBenchJoint {
  int32_t kind;                   /* Fx2dBenchJointKind */
  int32_t body_a;                 /* indices into Fx2dBenchScene::bodies */
  int32_t body_b;
  Fx2dBenchVec2 local_anchor_a;   /* body-local metres */
  Fx2dBenchVec2 local_anchor_b;
  double length;                  /* distance joint rest length; < 0: as built */
} Fx2dBenchJoint;

/* One solver setting the engine reads from a scene's /solver/<name>/<knob> key. The harness
 * validates a scene's value against type and range, sweeps it (`sweep --axis ENGINE.KNOB=...`) and
 * lists it (`fx2d-bench engines`); the plugin receives every knob's value in create(). */
typedef enum Fx2dBenchKnobType {
  FX2D_BENCH_KNOB_INTEGER = 0, /* a whole number in [min, max] */
  FX2D_BENCH_KNOB_NUMBER = 1,  /* a real number in [min, max] */
  FX2D_BENCH_KNOB_BOOLEAN = 2  /* false or true, passed as 0 or 1 */
} Fx2dBenchKnobType;

typedef struct Fx2dBenchKnob {
  const char* name; /* the key under /solver/<engine>: lower case, digits, '_' */
  int32_t type;     /* Fx2dBenchKnobType */
  double min;       /* inclusive bounds; 0 and 1 for a boolean */
  double max;
  double default_value;    /* what create() receives when the scene leaves the key out */
  const char* description; /* one line, with units, e.g. "constraint iterations per step" */
} Fx2dBenchKnob;

/* Bits of Fx2dBenchCapabilities::shapes and ::joints: 1 << Fx2dBenchShapeKind, 1 << Fx2dBenchJointKind. */
#define FX2D_BENCH_BIT(kind) (1u << (kind))

/* What the engine can build. A scene needing anything else is refused before any measurement,
 * with a line naming what is missing, so create() never sees it. */
typedef struct Fx2dBenchCapabilities {
  uint32_t shapes;         /* FX2D_BENCH_BIT of each Fx2dBenchShapeKind it builds */
  uint32_t joints;         /* FX2D_BENCH_BIT of each Fx2dBenchJointKind it builds */
  int32_t sleeping;        /* 1: resting bodies can sleep (informational) */
  int32_t bullets;         /* 1: honours Fx2dBenchBody::bullet; 0: refuses scenes with bullets */
  int64_t max_bodies;      /* 0: no limit */
  double max_linear_speed; /* m/s, of any body at the start; 0: no limit */
} Fx2dBenchCapabilities;

typedef struct Fx2dBenchScene {
  Fx2dBenchVec2 gravity;          /* m/s^2 */
  double dt;                      /* seconds per step */
  const Fx2dBenchBody* bodies;
  int32_t body_count;
  const Fx2dBenchJoint* joints;
  int32_t joint_count;
  const double* settings; /* one value per knob, in Fx2dBenchPlugin::knobs order, validated */
  int32_t setting_count;  /* == knob_count */
} Fx2dBenchScene;

typedef struct Fx2dBenchBodyState {
  Fx2dBenchVec2 position;         /* body origin, metres */
  double angle;                   /* radians */
  Fx2dBenchVec2 linear_velocity;  /* m/s */
  double angular_velocity;        /* rad/s */
} Fx2dBenchBodyState;

/* One built scene inside a plugin. */
typedef struct Fx2dBenchInstance Fx2dBenchInstance;

typedef struct Fx2dBenchPlugin {
  uint32_t abi_version;           /* FX2D_BENCH_PLUGIN_ABI_VERSION; always the first member */
  /* The engine's name: lower case, digits, '_' (e.g. "fx2d", "chipmunk"); also the scene's
   * /solver/<name> block its knobs live in. */
  const char* name;
  /* The engine library's own version, e.g. "7.0.3". */
  const char* (*library_version)(void);
  /* Which build this is, e.g. "a1b2c3d (HEAD~1) -DFX2D_NATIVE=ON"; may be empty. */
  const char* (*build_description)(void);
  const Fx2dBenchKnob* knobs;
  int32_t knob_count;
  Fx2dBenchCapabilities capabilities;
  /* Builds `scene`; NULL on failure, with a one-line reason in error[0..error_size). */
  Fx2dBenchInstance* (*create)(const Fx2dBenchScene* scene, char* error, size_t error_size);
  void (*destroy)(Fx2dBenchInstance* instance);
  /* Advances one time step of the scene's dt. */
  void (*step)(Fx2dBenchInstance* instance);
  /* The engine's own phase split: count, names, and the last step's milliseconds per phase
   * (count 0 for an engine that reports only its total). The list is data, not layout: plugins
   * of different revisions may name different phases, with no change of abi_version. */
  int32_t (*phase_count)(void);
  const char* (*phase_name)(int32_t phase);
  void (*read_phases)(const Fx2dBenchInstance* instance, double* ms, int32_t count);
  /* Touching contact manifolds (body pairs in contact) after the last step. */
  int32_t (*contact_count)(const Fx2dBenchInstance* instance);
  /* Poses and velocities of the first `count` bodies, in the scene's body order. */
  void (*read_state)(const Fx2dBenchInstance* instance, Fx2dBenchBodyState* out, int32_t count);
} Fx2dBenchPlugin;

typedef const Fx2dBenchPlugin* (*Fx2dBenchPluginEntry)(void);

/* How a plugin marks its entry point, the one symbol it exports:
 *   extern "C" FX2D_BENCH_PLUGIN_EXPORT const Fx2dBenchPlugin* fx2d_bench_plugin_v1(void) { ... } */
#ifdef _WIN32
#define FX2D_BENCH_PLUGIN_EXPORT __declspec(dllexport)
#else
#define FX2D_BENCH_PLUGIN_EXPORT __attribute__((visibility("default")))
#endif

/* Fx2D's table under an internal name, for fx2d-bench, which links one build statically as its
 * built-in "fx2d" engine. Hidden inside a plugin, so never exported there. */
const Fx2dBenchPlugin* fx2d_bench_plugin_table(void);

#ifdef __cplusplus
}
#endif

#endif /* FX2D_BENCH_PLUGIN_ABI_H */
