// Runs a fuzz target without libFuzzer: its seeds, then deterministic mutations of them (bytes flipped, set to
// edge values, cut, repeated, inserted), so that ctest covers the parsers' error paths in every build.
//   TARGET [--iterations N] [--seed S] [--write-corpus DIR]
#include <cstring>
#include <fstream>
#include <iostream>
#include <random>
#include <string>

#include "test/fuzz/fuzz_target.hpp"

namespace {

constexpr std::uint8_t EDGE_BYTES[] = {0x00, 0x01, 0x7f, 0x80, 0xff, '\n', ' ', '#', '.', '-', '9', ':'};

std::string mutate(std::string input, std::mt19937_64& random) {
    const auto pick = [&](std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(random() % n); };
    const int mutations = 1 + static_cast<int>(random() % 4);
    for (int i = 0; i < mutations; ++i) {
        switch (random() % 6) {
            case 0:  // flip one bit
                if (!input.empty())
                    input[pick(input.size())] ^= static_cast<char>(1u << (random() % 8));
                break;
            case 1:  // an edge value
                if (!input.empty())
                    input[pick(input.size())] = static_cast<char>(EDGE_BYTES[pick(sizeof EDGE_BYTES)]);
                break;
            case 2:  // cut the tail
                input.resize(pick(input.size() + 1));
                break;
            case 3: {  // remove a range
                const std::size_t at = pick(input.size() + 1);
                input.erase(at, pick(input.size() - at + 1));
                break;
            }
            case 4: {  // repeat a range
                const std::size_t at = pick(input.size() + 1);
                const std::string part = input.substr(at, pick(input.size() - at + 1));
                input.insert(pick(input.size() + 1), part);
                break;
            }
            default:  // insert random bytes
                for (std::size_t n = 1 + pick(8); n > 0; --n)
                    input.insert(input.begin() + static_cast<std::ptrdiff_t>(pick(input.size() + 1)),
                                 static_cast<char>(random()));
                break;
        }
    }
    return input;
}

void run(const std::string& input) {
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
}

}  // namespace

int main(int argc, char** argv) {
    long iterations = 20'000;
    std::uint64_t seed = 1;
    std::string corpus_dir;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (i + 1 < argc && arg == "--iterations") {
            iterations = std::stol(argv[++i]);
        } else if (i + 1 < argc && arg == "--seed") {
            seed = std::stoull(argv[++i]);
        } else if (i + 1 < argc && arg == "--write-corpus") {
            corpus_dir = argv[++i];
        } else {
            std::cerr << argv[0] << ": unknown argument '" << arg
                      << "'; usage: [--iterations N] [--seed S] [--write-corpus DIR]\n";
            return 2;
        }
    }
    const std::vector<std::string> seeds = tgw::fuzz::seeds();
    if (!corpus_dir.empty()) {
        for (std::size_t i = 0; i < seeds.size(); ++i) {
            std::ofstream(corpus_dir + "/seed-" + std::to_string(i), std::ios::binary) << seeds[i];
        }
        std::cout << "wrote " << seeds.size() << " seeds to " << corpus_dir << '\n';
        return 0;
    }
    for (const std::string& s : seeds)
        run(s);
    std::mt19937_64 random(seed);
    for (long i = 0; i < iterations; ++i)
        run(mutate(seeds[static_cast<std::size_t>(random() % seeds.size())], random));
    std::cout << argv[0] << ": " << seeds.size() << " seeds and " << iterations << " mutations (seed " << seed
              << "), every property held\n";
    return 0;
}
