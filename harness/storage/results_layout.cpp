// How HDF5 sees a result file's records (results_layout.h): types, shapes, strings.
#include "storage/results_layout.h"

namespace fxbench::results_layout {

// AccuracySample as HDF5 sees it: in memory at the struct's own offsets, in the file packed
// little-endian.
H5Handle accuracy_type(bool in_memory) {
  H5Handle type(H5Tcreate(H5T_COMPOUND, sizeof(AccuracySample)), H5Tclose);
  std::size_t packed_offset = 0;
  for (const AccuracyField& field : accuracy_fields) {
    const hid_t member =
        field.is_integer
            ? (in_memory ? H5Stored<std::int32_t>::memory_type() : H5Stored<std::int32_t>::file_type())
            : (in_memory ? H5Stored<double>::memory_type() : H5Stored<double>::file_type());
    H5Tinsert(type.get(), field.name, in_memory ? field.offset : packed_offset, member);
    packed_offset += H5Tget_size(member);
  }
  if (!in_memory) H5Tset_size(type.get(), packed_offset);
  return type;
}

H5Handle utf8_string_type() {
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  return type;
}

// An empty shape is a scalar.
H5Handle space_of(const std::vector<hsize_t>& shape) {
  if (shape.empty()) return H5Handle(H5Screate(H5S_SCALAR), H5Sclose);
  return H5Handle(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr), H5Sclose);
}

std::size_t element_count(const std::vector<hsize_t>& shape) {
  std::size_t count = 1;
  for (hsize_t extent : shape) count *= extent;
  return count;
}

std::string shape_text(const std::vector<hsize_t>& shape) {
  std::string text = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) text += (i > 0 ? " x " : "") + std::to_string(shape[i]);
  return text + "]";
}

std::vector<const char*> c_strings(const std::vector<std::string>& strings) {
  std::vector<const char*> pointers;
  for (const std::string& text : strings) pointers.push_back(text.c_str());
  return pointers;
}

}  // namespace fxbench::results_layout
