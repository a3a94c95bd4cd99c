// libFuzzer entry point of one target (STSV_FUZZ_TARGET, set by tests/fuzz/CMakeLists.txt).
#include "tests/fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    stsv::fuzz::runTarget(STSV_FUZZ_TARGET, data, size);
    return 0;
}
