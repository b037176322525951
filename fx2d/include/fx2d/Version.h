// The library's version, as the build recorded it ("major.minor.patch").
#pragma once

#include <string_view>

namespace fx2d {

std::string_view fx_version();

}  // namespace fx2d
