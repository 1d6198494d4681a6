// libFuzzer entry point: stac::fuzz::logReader (fuzz_targets.hpp).
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  stac::fuzz::logReader(data, size);
  return 0;
}
