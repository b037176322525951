// libFuzzer target: arbitrary bytes as a result file, read the way `compare` and `report` read
// one.
//
// Invariant checked: read_results_h5 either returns a ResultSet or throws one InputError with a
// one-line message; any other exception, a crash or a sanitizer report is a bug. The reader
// takes a path, so each input is written to one file per process (reused across inputs, removed
// at exit) in the temporary directory.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "errors.h"
#include "results_h5.h"

namespace {

class ScratchFile {
 public:
  ScratchFile()
      : path_((std::filesystem::temp_directory_path() /
               ("fx2d-results-fuzz-" + std::to_string(getpid()) + ".h5"))
                  .string()) {}
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  ~ScratchFile() { std::remove(path_.c_str()); }

  const std::string& write(const std::uint8_t* data, std::size_t size) {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    if (!out) {
      std::fprintf(stderr, "results_reader_fuzz: cannot write %s\n", path_.c_str());
      std::abort();
    }
    return path_;
  }

 private:
  std::string path_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static ScratchFile scratch;
  try {
    fxbench::read_results_h5(scratch.write(data, size));
  } catch (const fxbench::InputError& error) {
    if (std::string(error.what()).find('\n') != std::string::npos) {
      std::fprintf(stderr, "results_reader_fuzz: error message longer than one line: %s\n", error.what());
      std::abort();
    }
  }
  return 0;
}
