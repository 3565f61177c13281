// The checks of an MTL file's numbers that tinyobjloader does not make: it
// reads `nan` as 0 and passes negative colours and a zero index of
// refraction through, which would render as negative or made-up radiance.
#pragma once

#include <filesystem>
#include <string_view>

namespace nodetrace::tracer::detail {

// Throws SceneError naming `path`, the line and the value of the first
// colour (`Ka Kd Ks Ke Tf`), exponent (`Ns`), dissolve (`d Tr`), index of
// refraction (`Ni`) or roughness (`Pr`) that is not a finite number of at
// least 0 within float range, an `Ni` of 0, or a `Pr` of 0 or above 1.
// Lines whose first word after the keyword is not a number (`Kd spectral
// file.rfl`) are left to tinyobjloader.
void check_mtl_numbers(std::string_view text, const std::filesystem::path& path);

}  // namespace nodetrace::tracer::detail
