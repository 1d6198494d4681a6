// The parsers' fuzz targets (issue 17): one function per input the tools
// read from users. Each returns normally on any input: bad input is an
// InputError and is swallowed; anything else (another exception, a crash,
// a sanitizer report) is a bug. Used by the libFuzzer harnesses (fuzz_*.cpp,
// -DSTAC_FUZZ=ON, clang) and by the corpus replay in the default suite
// (fuzz_replay_test).
#pragma once

#include <cstddef>
#include <cstdint>

namespace stac::fuzz {

// parseLog, then what the tools do next with a log: the data-row check, the
// sensors inferred from its header on the hand24 robot, and the binding.
void logReader(const std::uint8_t* data, std::size_t size);
// parseSensorsYaml on the hand24 robot; what it accepts must write back
// (sensorsToYaml) to a file it accepts again.
void sensorsReader(const std::uint8_t* data, std::size_t size);
// RobotModel::fromString.
void urdfLoader(const std::uint8_t* data, std::size_t size);
// Any URDF the loader accepts can be patched (urdf_patch.hpp), with a
// marker on every link, and the patched text loads again.
void urdfPatcher(const std::uint8_t* data, std::size_t size);

}  // namespace stac::fuzz
