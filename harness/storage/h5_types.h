// Small pieces shared by the HDF5 readers and writers: an owning identifier and how each C++
// number type is stored. Internal to the harness.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <utility>

namespace fxbench {

// Owns one HDF5 identifier and closes it with the matching H5?close; a failed creation leaves it
// invalid.
class H5Handle {
 public:
  H5Handle(hid_t id, herr_t (*closer)(hid_t)) : id_(id), close_(closer) {}
  H5Handle(H5Handle&& other) noexcept : id_(std::exchange(other.id_, -1)), close_(other.close_) {}
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;
  H5Handle& operator=(H5Handle&&) = delete;
  ~H5Handle() {
    if (id_ >= 0) close_(id_);
  }
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  // Closes now and says whether HDF5 succeeded: closing a file is where it is flushed.
  bool close() { return close_(std::exchange(id_, -1)) >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// Turns HDF5's automatic error-stack printing off for its lifetime, so that failures reach the
// user only as the harness's own one-line messages.
class SilentHdf5Errors {
 public:
  SilentHdf5Errors() {
    H5Eget_auto2(H5E_DEFAULT, &saved_function_, &saved_data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  SilentHdf5Errors(const SilentHdf5Errors&) = delete;
  SilentHdf5Errors& operator=(const SilentHdf5Errors&) = delete;
  ~SilentHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, saved_function_, saved_data_); }

 private:
  H5E_auto2_t saved_function_ = nullptr;
  void* saved_data_ = nullptr;
};

// How each C++ number type is stored (little-endian, fixed width) and held in memory.
template <class T>
struct H5Stored;
template <>
struct H5Stored<double> {
  static hid_t file_type() { return H5T_IEEE_F64LE; }
  static hid_t memory_type() { return H5T_NATIVE_DOUBLE; }
  static constexpr H5T_class_t type_class = H5T_FLOAT;
};
template <>
struct H5Stored<std::int32_t> {
  static hid_t file_type() { return H5T_STD_I32LE; }
  static hid_t memory_type() { return H5T_NATIVE_INT32; }
  static constexpr H5T_class_t type_class = H5T_INTEGER;
};
template <>
struct H5Stored<std::uint64_t> {
  static hid_t file_type() { return H5T_STD_U64LE; }
  static hid_t memory_type() { return H5T_NATIVE_UINT64; }
  static constexpr H5T_class_t type_class = H5T_INTEGER;
};
template <>
struct H5Stored<std::uint8_t> {
  static hid_t file_type() { return H5T_STD_U8LE; }
  static hid_t memory_type() { return H5T_NATIVE_UINT8; }
  static constexpr H5T_class_t type_class = H5T_INTEGER;
};

}  // namespace fxbench
