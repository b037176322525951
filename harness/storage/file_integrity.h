// The seal on an HDF5 file fx2d-bench writes: a header in the file's HDF5 user block that lets
// the reader prove the file is byte for byte what the writer closed, before libhdf5 reads it.
//
// Why: libhdf5 trusts its input; some corrupt files crash or hang it inside its own parser
// (reproducers in harness/fuzz/crashes/results_reader/). Such a file is refused here instead.
//
// Invariant: a sealed file is a 512-byte HDF5 user block followed by the HDF5 file proper
// (libhdf5 and h5py find the superblock at byte 512 and ignore the user block). The user block
// holds this text, zero-padded to 512 bytes, in exactly this form:
//   fx2d-bench sealed HDF5 file
//   format 1
//   length <the whole file's length in bytes, 20 decimal digits>
//   checksum fnv1a64 <16 hex digits>
// where the checksum is FNV-1a 64 of the length (8 bytes, little-endian) followed by every byte
// after the user block. FNV-1a changes its state bijectively with each byte, so any change
// confined to one byte always changes the checksum; a truncation or extension changes the length.
// Layout for users: harness/RESULTS_FORMAT.md, "Integrity header".
#pragma once

#include <cstddef>
#include <string>

namespace fxbench {

// The user block to reserve at creation: H5Pset_userblock(creation_properties, h5_seal_bytes).
inline constexpr std::size_t h5_seal_bytes = 512;

// Writes the seal into the user block of `path`, a closed HDF5 file created with a user block of
// h5_seal_bytes; call it after the last change to the file (reopening it for writing later
// breaks the seal; seal again after). Throws std::runtime_error if the file cannot be read or
// written, or has no such user block (sealing it would overwrite the HDF5 superblock).
void seal_h5_file(const std::string& path);

// Whether `path` begins with the seal's first line: written by fx2d-bench, whether intact or not.
bool carries_h5_seal(const std::string& path);

// Throws InputError, one line naming `path`, unless its seal is present, of format 1, and
// matches its length and checksum: "not an fx2d-bench result file (no fx2d-bench header)",
// "corrupt or truncated (checksum mismatch)" and the like. Reads the file once, in fixed-size
// chunks, and a file whose length disagrees with its header not at all past the header.
void verify_h5_seal(const std::string& path);

}  // namespace fxbench
