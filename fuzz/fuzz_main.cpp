// libFuzzer's entry point for one target; LIGHTBAKE_FUZZ_ENTRY names the fuzz_* function.

#include "fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return lb::LIGHTBAKE_FUZZ_ENTRY(data, size);
}
