// `fx2d-bench compare`'s reading of result files, shared with the tests that drive it.
#pragma once

#include <optional>
#include <string>

#include "analysis/compare.h"

namespace fxbench {

// Reads the files (read_results_h5) and judges them: B against A when b_path is given, the two
// builds of an `ab` file when A is one (compare_variants), else the engines within A against
// `baseline` (compare_engines). Throws InputError.
CompareReport compare_files(const std::string& a_path, const std::optional<std::string>& b_path,
                            const std::string& baseline, const CompareSettings& settings);

}  // namespace fxbench
