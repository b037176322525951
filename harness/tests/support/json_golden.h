// A JSON document compared with a golden file under goldens/, for the golden-output tests of
// fx2d-bench's --json outputs. With FX2D_UPDATE_GOLDENS=1 the golden is rewritten instead (and the
// test skipped), so goldens change only by that named command, never by hand.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace fxbench::bench_test {

// Ordered, so that a golden keeps the output's key order and a reordering shows as a change.
// `regenerate` is the command that rewrites this golden, quoted in the failure message.
inline void expect_json_golden(const nlohmann::ordered_json& actual, const std::string& golden_name,
                               const std::string& regenerate) {
  const std::filesystem::path golden = std::filesystem::path(FX2D_SOURCE_DIR) / "goldens" / golden_name;
  const char* update = std::getenv("FX2D_UPDATE_GOLDENS");
  if (update != nullptr && std::string(update) == "1") {
    std::ofstream(golden) << actual.dump(2) << '\n';
    GTEST_SKIP() << "rewrote " << golden;
  }
  std::ifstream file(golden);
  ASSERT_TRUE(file) << golden << " is missing; regenerate it with: " << regenerate;
  const auto expected = nlohmann::ordered_json::parse(file);
  // Not EXPECT_EQ, which would print both documents whole: the patch names what changed.
  EXPECT_TRUE(actual == expected) << golden_name << " differs (JSON patch from golden to actual): "
                              << nlohmann::ordered_json::diff(expected, actual).dump() << "\nIf the change is meant, "
                              << "regenerate it with: " << regenerate;
}

}  // namespace fxbench::bench_test
