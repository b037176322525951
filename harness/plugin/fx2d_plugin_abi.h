/* The C ABI between fx2d-bench and an engine plugin: one build of Fx2D in a shared library.
 *
 * Why C: two builds of Fx2D (two git revisions, or two sets of build flags) are loaded into one
 * process side by side, so that they are timed on the same machine state, allocator and harness.
 * Each plugin holds its own static copy of Fx2D with every symbol hidden; nothing of C++ (no
 * class layout, no std::string, no exception) crosses between the harness and a plugin, only the
 * plain structs below and one exported function, fx2d_bench_plugin_v1().
 *
 * Invariants: a plugin exports exactly one symbol, FX2D_BENCH_PLUGIN_ENTRY; the table it returns
 * begins with abi_version, and a loader reads nothing else of a table whose abi_version is not
 * the one it was compiled with; no function of the table throws or aborts on bad input (create
 * reports it in its error buffer and returns NULL); every pointer a scene holds is read only
 * during create.
 *
 * Units as in harness/scene/scene_spec.h: metres, radians, seconds, kg/m^2; doubles throughout, each
 * plugin converts to its engine's own precision exactly as the built-in engine does. */
#ifndef FX2D_BENCH_PLUGIN_ABI_H
#define FX2D_BENCH_PLUGIN_ABI_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Raised on any change to a struct or function below; a loader refuses any other version. */
#define FX2D_BENCH_PLUGIN_ABI_VERSION 4
/* The one exported symbol, by name, for dlsym(). Its name and the table's layout are version 1's;
 * version 2 added relax_passes and max_push_speed to Fx2dBenchSettings, version 3 bullet to
 * Fx2dBenchBody, version 4 workers to Fx2dBenchSettings. */
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
  int32_t bullet;                 /* 1: swept against fast dynamic bodies too (FxEntityDef::bullet) */
} Fx2dBenchBody;

typedef struct Fx2dBenchJoint {
  int32_t kind;                   /* Fx2dBenchJointKind */
  int32_t body_a;                 /* indices into Fx2dBenchScene::bodies */
  int32_t body_b;
  Fx2dBenchVec2 local_anchor_a;   /* body-local metres */
  Fx2dBenchVec2 local_anchor_b;
  double length;                  /* distance joint rest length; < 0: as built */
} Fx2dBenchJoint;

typedef struct Fx2dBenchSettings {
  int32_t substeps;
  int32_t velocity_passes;
  int32_t sleeping;               /* 0 or 1 */
  int32_t relax_passes;           /* >= 1; 0: the engine's default */
  double max_push_speed;          /* m/s, > 0; 0: the engine's default */
  int32_t workers;                /* threads a step may use, >= 1; 0: the engine's default */
} Fx2dBenchSettings;

typedef struct Fx2dBenchScene {
  Fx2dBenchVec2 gravity;          /* m/s^2 */
  double dt;                      /* seconds per step */
  const Fx2dBenchBody* bodies;
  int32_t body_count;
  const Fx2dBenchJoint* joints;
  int32_t joint_count;
  Fx2dBenchSettings fx2d;
} Fx2dBenchScene;

typedef struct Fx2dBenchBodyState {
  Fx2dBenchVec2 position;         /* body origin, metres */
  double angle;                   /* radians */
  Fx2dBenchVec2 linear_velocity;  /* m/s */
  double angular_velocity;        /* rad/s */
} Fx2dBenchBodyState;

/* One built scene inside a plugin. */
typedef struct Fx2dBenchInstance Fx2dBenchInstance;

typedef struct Fx2dBenchPluginV1 {
  uint32_t abi_version;           /* FX2D_BENCH_PLUGIN_ABI_VERSION; always the first member */
  /* The engine library's own version, e.g. "0.1.0". */
  const char* (*library_version)(void);
  /* Which build this is, e.g. "a1b2c3d (HEAD~1) -DFX2D_NATIVE=ON"; may be empty. */
  const char* (*build_description)(void);
  /* Builds `scene`; NULL on failure, with a one-line reason in error[0..error_size). */
  Fx2dBenchInstance* (*create)(const Fx2dBenchScene* scene, char* error, size_t error_size);
  void (*destroy)(Fx2dBenchInstance* instance);
  /* Advances one time step of the scene's dt. */
  void (*step)(Fx2dBenchInstance* instance);
  /* The engine's own phase split: count, names, and the last step's milliseconds per phase. The
   * list is data, not layout: plugins of different revisions may name different phases
   * (RESULTS_FORMAT.md, "Fx2D's phase names"), with no change of abi_version. */
  int32_t (*phase_count)(void);
  const char* (*phase_name)(int32_t phase);
  void (*read_phases)(const Fx2dBenchInstance* instance, double* ms, int32_t count);
  /* Touching contact manifolds after the last step. */
  int32_t (*contact_count)(const Fx2dBenchInstance* instance);
  /* Poses and velocities of the first `count` bodies, in the scene's body order. */
  void (*read_state)(const Fx2dBenchInstance* instance, Fx2dBenchBodyState* out, int32_t count);
} Fx2dBenchPluginV1;

typedef const Fx2dBenchPluginV1* (*Fx2dBenchPluginEntry)(void);

/* The same table under an internal name, for a program that links one build statically
 * (fx2d-bench's built-in "fx2d" engine). Hidden inside a plugin, so never exported there. */
const Fx2dBenchPluginV1* fx2d_bench_plugin_table(void);

#ifdef __cplusplus
}
#endif

#endif /* FX2D_BENCH_PLUGIN_ABI_H */
