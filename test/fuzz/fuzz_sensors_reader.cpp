// libFuzzer entry point: stac::fuzz::sensorsReader (fuzz_targets.hpp).
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  stac::fuzz::sensorsReader(data, size);
  return 0;
}
