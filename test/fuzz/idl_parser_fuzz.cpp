// --idl DIR comes from an operator's files: any text gives types or a ConfigError naming the file and line, and
// whatever types it gives decode any payload to a value or an error (recursive types, typedef loops and huge
// arrays included).
#include <sstream>

#include "base/config_error.hpp"
#include "test/fuzz/fuzz_target.hpp"
#include "types/cdr_decoder.hpp"
#include "types/embedded_idl.hpp"
#include "types/type_library.hpp"

namespace tgw::fuzz {

std::vector<std::string> seeds() {
    std::vector<std::string> texts;
    for (const types::EmbeddedIdl& file : types::embedded_idl_files())
        texts.emplace_back(file.text);
    // What ROS 2 generates from a .msg, with the rest of the subset.
    texts.emplace_back(R"idl(#include "std_msgs/msg/Header.idl"
module sensor_msgs {
  module msg {
    module Imu_Constants {
      const uint8 FRAMES = 2;
      const string NAME = "imu";
    };
    typedef double double__9[9];
    enum Status { OK, @value(3) STALE };
    @verbatim (language="comment", text="An IMU (inertial) reading")
    @appendable struct Base { @key uint32 id; };
    struct Imu : Base {
      double__9 covariance;
      float grid[Imu_Constants::FRAMES][3];
      string<16> frame_id;
      sequence<sequence<int8, 4>> nested;
      Status status;
      boolean ok; char c; octet o; long long big; unsigned short small;
    };
    struct Node { sequence<Node> children; };
  };
};
)idl");
    return texts;
}

}  // namespace tgw::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace tgw;
    const std::string text(reinterpret_cast<const char*>(data), size);
    types::TypeLibrary types;
    try {
        std::istringstream in(text);
        types.add_idl(in, "fuzz.idl");
        types.check_references();
    } catch (const base::ConfigError& e) {
        TGW_FUZZ_CHECK(std::string(e.what()).rfind("fuzz.idl:", 0) == 0);
        return 0;
    }
    static const std::vector<std::uint8_t> PAYLOADS[] = {
        {0x00, 0x01, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00, 'a', 'b', 'c', 'd', 0x00},
        {0x00, 0x09, 0x00, 0x00, 0x08, 0x00, 0x00, 0x00, 0xff, 0xff, 0xff, 0xff, 0x01, 0x00, 0x00, 0x00},
        {0x00, 0x00, 0x00, 0x00, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff},
    };
    const std::vector<std::string> names = types.struct_names();
    for (std::size_t i = 0; i < names.size() && i < 16; ++i) {
        TGW_FUZZ_CHECK(types.idl_text(names[i]).rfind(text, 0) == 0);
        for (const auto& payload : PAYLOADS) {
            const types::CdrDecodeResult result = types::decode_cdr(payload.data(), payload.size(), names[i], types);
            TGW_FUZZ_CHECK(result.value.has_value() == result.error.empty());
        }
    }
    return 0;
}
