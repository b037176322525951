// Reading a whole file that a user named: a scene, a policy, a comparison. The bound counts the
// bytes actually read, never the size a file reports, so a device (/dev/zero), a pipe or FIFO that
// streams without end, a /proc file or a huge sparse file is refused after at most `max_bytes` + 1
// bytes, in well under a second, while a scene piped from a generator (`run <(make-scene)`) still
// reads like a file.
#pragma once

#include <cstddef>
#include <string>

namespace fxbench {

// Every whole-file read of user input is held to this; the largest real input (a scene with an
// explicit body list, a night's comparison) is far below it.
inline constexpr std::size_t max_input_file_bytes = std::size_t{16} << 20;

// The contents of `path`. Throws InputError, one line naming the file: it cannot be opened or
// read, or it holds more than `max_bytes` bytes (`kind` names what was expected, e.g. "a scene file").
std::string read_bounded_file(const std::string& path, const std::string& kind,
                              std::size_t max_bytes = max_input_file_bytes);

// Refuses `path` unless it is a regular file (or a link to one), in one line that begins with
// `named` and says which: "no such file" when nothing is there, "not a regular file" for a device,
// a FIFO or a directory, which a library loader or HDF5 cannot read.
void require_regular_file(const std::string& path, const std::string& named);

}  // namespace fxbench
