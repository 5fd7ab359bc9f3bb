// The project's own IDL files, read into the program at build time (types/embed_idl.cmake writes the source
// into the build tree), so that the programs know the project's types with no --idl flag.
#pragma once

#include <vector>

namespace tgw::types {

struct EmbeddedIdl {
    const char* file;  ///< "idl/GatewayStatus.idl"
    const char* text;
};

/// Every idl/*.idl of the source tree the program was built from, sorted by name.
const std::vector<EmbeddedIdl>& embedded_idl_files();

}  // namespace tgw::types
