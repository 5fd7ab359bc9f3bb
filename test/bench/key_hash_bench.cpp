// What the gateway spends on a keyed sample whose publisher sent no key hash (telemetry-gateway --idl): the key
// hash computed from the payload (types::KeyHasher), against copying the same payload, which the gateway does for
// every sample anyway (LaneListener), in one run.
//
//   copy/N   the payload of N bytes copied into a fresh vector
//   hash/N   its key hash: the payload decoded as the type, the key serialized big endian
//
// The type is Cyclone's cross-vendor KeyedBlob's shape with a sequence of N octets after the key.
#include <benchmark/benchmark.h>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "types/key_hash.hpp"

namespace {

const char* const IDL = R"(
module bench {
    @final struct KeyedFrame {
        @key long id;
        unsigned long seq;
        long long stamp_ns;
        sequence<octet> data;
    };
};)";

std::vector<std::uint8_t> payload_of(std::size_t data_bytes) {
    // CDR_LE: id, seq, padding to 8, stamp_ns, the sequence's length, its octets.
    std::vector<std::uint8_t> bytes = {0x00, 0x01, 0x00, 0x00};
    const auto put = [&bytes](std::uint64_t value, std::size_t size) {
        for (std::size_t i = 0; i < size; ++i)
            bytes.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
    };
    put(7, 4);
    put(42, 4);
    put(1'700'000'000'000'000'000ULL, 8);
    put(data_bytes, 4);
    for (std::size_t i = 0; i < data_bytes; ++i)
        bytes.push_back(static_cast<std::uint8_t>(i));
    return bytes;
}

void copy(benchmark::State& state) {
    const std::vector<std::uint8_t> payload = payload_of(static_cast<std::size_t>(state.range(0)));
    for (auto _ : state) {
        std::vector<std::uint8_t> copied(payload.begin(), payload.end());
        benchmark::DoNotOptimize(copied.data());
    }
}

void hash(benchmark::State& state) {
    tgw::types::TypeLibrary types;
    std::istringstream idl(IDL);
    types.add_idl(idl, "bench.idl");
    std::string why;
    const auto hasher = tgw::types::KeyHasher::for_type(types, "bench::KeyedFrame", why);
    if (!hasher) {
        state.SkipWithError(why.c_str());
        return;
    }
    const std::vector<std::uint8_t> payload = payload_of(static_cast<std::size_t>(state.range(0)));
    for (auto _ : state) {
        auto key = hasher->hash(payload.data(), payload.size(), why);
        benchmark::DoNotOptimize(key);
    }
}

BENCHMARK(copy)->Arg(16)->Arg(1500)->Arg(6000);
BENCHMARK(hash)->Arg(16)->Arg(1500)->Arg(6000);

}  // namespace

BENCHMARK_MAIN();
