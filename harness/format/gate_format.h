// The nightly gate's verdict (analysis/gate_policy.h) as text: a terminal table or one JSON object
// (schema fx2d-bench.gate/1); and the fields a gate row and a history row share in JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "analysis/gate_policy.h"

namespace fxbench {

// The fields a gate row and a history row share, as JSON: engine, scene, bodies, metric, a, b,
// ratio, ci_low, ci_high and p_value (null for an exact row).
nlohmann::ordered_json ratio_json(const std::string& engine, const std::string& scene, int bodies,
                                  const std::string& metric, double a, double b, double ratio, double ci_low,
                                  double ci_high, std::optional<double> p_value);

std::string gate_table(const GateReport& report, const std::string& policy_path);

// `compare_paths` and `policy_path` are recorded as given on the command line.
nlohmann::ordered_json gate_json(const GateReport& report, const std::vector<std::string>& compare_paths,
                                 const std::string& policy_path);

}  // namespace fxbench
