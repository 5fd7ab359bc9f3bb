#pragma once

// A fuzz target: LLVMFuzzerTestOneInput checks properties of the code under test for any bytes (abort() on a
// broken one), and seeds() gives well-formed inputs to start from. Built for libFuzzer with TGW_LIBFUZZER, or
// with replay_main.cpp, which runs the seeds and deterministic mutations of them under ctest.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace tgw::fuzz {

/// Well-formed inputs of this target.
std::vector<std::string> seeds();

[[noreturn]] inline void property_failed(const char* what, const char* file, int line) {
    std::fprintf(stderr, "fuzz property failed: %s (%s:%d)\n", what, file, line);
    std::abort();
}

}  // namespace tgw::fuzz

/// Like assert, in every build type: a fuzz input that breaks the property aborts, so the fuzzer keeps it.
#define TGW_FUZZ_CHECK(condition) \
    ((condition) ? static_cast<void>(0) : ::tgw::fuzz::property_failed(#condition, __FILE__, __LINE__))
