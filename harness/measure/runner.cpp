// The measurement loop; invariants in runner.h.
#include "measure/runner.h"

#include <nlohmann/json.hpp>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "measure/clocks.h"
#include "measure/interrupt.h"
#include "metrics/accuracy.h"

namespace fxbench {
namespace {

// Every `every`-th step and the last one, steps counted from 1.
bool is_sampled(int step, int every, int steps) { return step % every == 0 || step == steps; }

int sample_count(int every, int steps) { return steps / every + (steps % every == 0 ? 0 : 1); }

// The engine's settings in the scene as "key=value ..." (engine_settings_json), so the record
// says what the engine ran with without the runner naming any engine.
std::string settings_of(const SceneSpec& scene, const EngineInfo& engine) {
  const nlohmann::json block = nlohmann::json::parse(engine_settings_json(engine, scene));
  std::string settings;
  for (const auto& [key, value] : block.items()) {
    if (!settings.empty()) settings += ' ';
    settings += key + "=" + value.dump();
  }
  return settings;
}

RunRecord empty_record(const SceneSpec& scene, const EngineInfo& info, const Engine& engine, const RunPlan& plan) {
  RunRecord record;
  record.engine = info.name;
  record.engine_version = info.version;
  record.engine_settings = settings_of(scene, info);
  record.scene = scene.name;
  record.scene_hash = scene.hash;
  record.bodies = bodies_of(scene);
  record.body_count = static_cast<int>(scene.bodies.size());
  record.steps = scene.steps;
  record.repeats = plan.repeats;
  record.warmup_steps = plan.warmup_steps;
  record.hash_every = plan.hash_every;
  const auto samples = static_cast<std::size_t>(plan.repeats) * static_cast<std::size_t>(scene.steps);
  record.wall_ms.resize(samples);
  record.cpu_ms.resize(samples);
  record.cycles.resize(samples);
  record.contacts.resize(samples);
  record.phase_names = engine.phase_names();
  record.phase_ms.resize(samples * record.phase_names.size());
  record.accuracy.reserve(static_cast<std::size_t>(sample_count(plan.accuracy_every, scene.steps)));
  record.state_hashes.reserve(static_cast<std::size_t>(sample_count(plan.hash_every, scene.steps)));
  return record;
}

std::unique_ptr<Engine> built_engine(const SceneSpec& scene, const EngineInfo& info) {
  std::unique_ptr<Engine> engine = info.make();
  engine->build(scene);
  return engine;
}

// Steps `engine` through one repeat, storing its per-step samples at `repeat` in `record`, and
// calls after_step(step) once each step's clocks have stopped. False if an interrupt cut it short.
template <class AfterStep>
bool time_repeat(Engine& engine, int repeat, RunRecord& record, AfterStep&& after_step) {
  const std::size_t phases = record.phase_names.size();
  for (int step = 0; step < record.steps; ++step) {
    if (interrupt_requested()) return false;  // interrupt.h: polled between steps, outside the clocks
    const auto sample = static_cast<std::size_t>(repeat) * static_cast<std::size_t>(record.steps) +
                        static_cast<std::size_t>(step);
    const ClockReading start = start_clocks();
    engine.step();
    const StepTiming timing = stop_clocks(start);
    record.wall_ms[sample] = timing.wall_ms;
    record.cpu_ms[sample] = timing.cpu_ms;
    record.cycles[sample] = timing.cycles;
    record.contacts[sample] = engine.contact_count();
    engine.read_phases(std::span<double>(record.phase_ms).subspan(sample * phases, phases));
    after_step(step + 1);
  }
  return true;
}

// What the first repeat records between steps: accuracy samples and state hashes.
class TrajectoryObserver {
 public:
  TrajectoryObserver(const SceneSpec& scene, const Engine& engine, const RunPlan& plan, RunRecord& record)
      : engine_(engine), plan_(plan), record_(record), probe_(scene, start_state(engine)) {
    states_.reserve(scene.bodies.size());
  }

  void operator()(int step) {
    const bool wants_accuracy = is_sampled(step, plan_.accuracy_every, record_.steps);
    const bool wants_hash = is_sampled(step, plan_.hash_every, record_.steps);
    if (!wants_accuracy && !wants_hash) return;
    engine_.read_state(states_);
    if (wants_accuracy) record_.accuracy.push_back(probe_.measure(step, states_));
    if (wants_hash) record_.state_hashes.push_back(state_hash(states_));
  }

 private:
  static std::vector<BodyState> start_state(const Engine& engine) {
    std::vector<BodyState> states;
    engine.read_state(states);
    return states;
  }

  const Engine& engine_;
  const RunPlan& plan_;
  RunRecord& record_;
  AccuracyProbe probe_;
  std::vector<BodyState> states_;
};

// interrupt.h: what an interrupted run keeps, its `completed` whole repeats.
RunRecord keep_completed_repeats(RunRecord record, int completed) {
  const auto samples = static_cast<std::size_t>(completed) * static_cast<std::size_t>(record.steps);
  record.repeats = completed;
  record.wall_ms.resize(samples);
  record.cpu_ms.resize(samples);
  record.cycles.resize(samples);
  record.contacts.resize(samples);
  record.phase_ms.resize(samples * record.phase_names.size());
  return record;
}

std::string final_state_hash(const Engine& engine) {
  std::vector<BodyState> states;
  engine.read_state(states);
  return state_hash(states);
}

}  // namespace

long planned_steps(const SceneSpec& scene, const RunPlan& plan) {
  return static_cast<long>(plan.warmup_steps) + static_cast<long>(plan.repeats) * scene.steps;
}

RunRecord measure_engine(const SceneSpec& scene, const EngineInfo& info, const RunPlan& plan,
                         const ProgressFn& progress) {
  if (scene.steps < 1 || plan.repeats < 1 || plan.warmup_steps < 0 || plan.hash_every < 1 || plan.accuracy_every < 1)
    throw std::invalid_argument("measure_engine: needs steps, repeats, hash_every, accuracy_every >= 1, warmup >= 0");
  RunProgress status{info.name, scene.name, 0, plan.repeats, 0};
  const auto report = [&] {
    if (progress) progress(status);
  };

  if (plan.warmup_steps > 0) {
    report();
    const std::unique_ptr<Engine> warmup = built_engine(scene, info);
    for (int step = 0; step < plan.warmup_steps; ++step) {
      if (interrupt_requested()) return {};  // interrupt.h
      warmup->step();
    }
    status.steps_done += plan.warmup_steps;
  }

  RunRecord record;
  for (int repeat = 0; repeat < plan.repeats; ++repeat) {
    status.repeat = repeat + 1;
    report();
    const std::unique_ptr<Engine> engine = built_engine(scene, info);
    if (repeat == 0) {
      record = empty_record(scene, info, *engine, plan);
      TrajectoryObserver observer(scene, *engine, plan, record);
      if (!time_repeat(*engine, repeat, record, observer)) return {};  // interrupt.h
      record.final_state_hash = record.state_hashes.back();
    } else {
      if (!time_repeat(*engine, repeat, record, [](int) {})) return keep_completed_repeats(std::move(record), repeat);
      if (final_state_hash(*engine) != record.final_state_hash) record.deterministic = false;
    }
    status.steps_done += scene.steps;
  }
  report();
  return record;
}

}  // namespace fxbench
