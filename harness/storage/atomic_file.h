// Replacing a file so that a crash, a SIGKILL or a power cut at any moment leaves at its path
// either the old file or the complete new one, never a mix, a torn tail or nothing.
//
// Invariant: the new content is written to a temporary file beside the target (same directory,
// so the same file system, where rename(2) is atomic), fsynced, renamed over the target, and then
// the directory is fsynced, because the rename is an update of the directory: without that fsync
// a power cut can bring back the old name, or neither. A process killed part-way leaves at most
// its own `<path>.tmp.<pid>`, which no reader ever opens.
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace fxbench {

// Called at each moment of a replacement, in order: "written" (`write` returned; the temporary
// file is complete), "synced" (it is on disk; the rename is next), "renamed" (the new file is in
// place and the rename is on disk). Throwing before "renamed" abandons the replacement: the
// temporary is removed, the target untouched, and the exception propagates.
using AtomicWriteStage = std::function<void(std::string_view stage)>;

// Replaces (or creates) `path` with what `write` writes. `write` receives the temporary's name,
// `path + ".tmp." + pid`, and must create that file, write all of it and close it; it may throw.
// On any exception, from `write`, `at_stage` or the file system, the temporary is removed, `path`
// is as it was, and the exception propagates. A failed fsync or rename throws InputError naming
// `path` and the system's reason (a full disk, a read-only directory).
//
// Example: write_atomically("history.h5", [&](const std::string& temporary) { write_h5(temporary); });
void write_atomically(const std::string& path, const std::function<void(const std::string& temporary)>& write,
                      const AtomicWriteStage& at_stage = {});

}  // namespace fxbench
