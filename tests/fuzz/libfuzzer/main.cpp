// libFuzzer entry point of one target (STSV_FUZZ_TARGET, set by tests/fuzz/CMakeLists.txt), with
// a custom mutator: half of the mutations are libFuzzer's own (bytes), half put an extreme value
// in place of one number of a still valid file (tests/fuzz/value_mutator.h).
#include "tests/fuzz/fuzz_targets.h"
#include "tests/fuzz/value_mutator.h"

#include <cstring>
#include <string>

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t maxSize);

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    stsv::fuzz::runTarget(STSV_FUZZ_TARGET, data, size);
    return 0;
}

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t maxSize,
                                               unsigned int seed) {
    if (seed % 2 == 0) return LLVMFuzzerMutate(data, size, maxSize);
    const std::string mutated =
        stsv::fuzz::mutateValue(std::string(reinterpret_cast<const char*>(data), size), seed / 2);
    if (mutated.size() > maxSize) return LLVMFuzzerMutate(data, size, maxSize);
    std::memcpy(data, mutated.data(), mutated.size());
    return mutated.size();
}
