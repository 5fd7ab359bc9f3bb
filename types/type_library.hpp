// Every IDL type a program knows, by the fully scoped name DDS type names use ("tgw::idl::GatewayStatus",
// "std_msgs::msg::dds_::String_"), with the IDL text each came from (an MCAP recording's omgidl schema).
#pragma once

#include <cstdint>
#include <istream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "types/idl_type.hpp"

namespace tgw::types {

class TypeLibrary {
  public:
    /// The project's types and those of every IDL file under `idl_dirs` (add_idl_dir), references checked. Throws
    /// base::ConfigError "FLAG: FILE:LINE: ..." as add_idl_dir() and check_references() do.
    static TypeLibrary project_and(const std::vector<std::string>& idl_dirs, const std::string& flag);

    /// The project's own types (idl/*.idl of this source tree, embedded at build time). A file added later
    /// may declare one of them again: the later declaration wins.
    void add_project_types();

    /// Parses one IDL file's text; `file` names it in errors. #include lines are ignored: the included types
    /// must come through another add_idl(). Throws base::ConfigError "FILE:LINE: ...".
    void add_idl(std::istream& in, const std::string& file);

    /// Parses every .idl file under `dir` (subdirectories too, as ROS 2's share/PKG/msg/ layout has them), each
    /// file once however many directories name it. An #include is parsed first when it names a file under `dir`
    /// (or next to the including file). Throws
    /// base::ConfigError "FLAG: FILE:LINE: ..." when a file does not parse, or `dir` cannot be read.
    void add_idl_dir(const std::string& dir, const std::string& flag);

    /// Throws base::ConfigError "FILE:LINE: ..." naming the first type reference (a member's, a typedef's, a
    /// base struct's) that names no declared type.
    void check_references() const;

    /// The declaration named `scoped_name` ("tgw::idl::GatewayStatus"; a leading "::" is allowed); nullptr when
    /// there is none.
    const IdlDeclaration* find(const std::string& scoped_name) const;

    /// What `name` means where it was written (`scope`, "a::b"): looked up in that module, then each enclosing
    /// one, then at the top, as IDL scoping rules say. nullptr when nothing of that name is declared.
    const IdlDeclaration* resolve(const std::string& name, const std::string& scope) const;

    /// The value of the integer constant `name` as seen from `scope`; nullopt when there is none.
    std::optional<std::int64_t> constant(const std::string& name, const std::string& scope) const;

    /// The IDL text of the file that declares `type_name`, preceded by the files of the types it uses,
    /// dependencies first, each once: a self-contained schema. Empty when the type is unknown.
    std::string idl_text(const std::string& type_name) const;

    /// Every declared struct, sorted.
    std::vector<std::string> struct_names() const;

    // For parse_idl().

    /// Registers the text of a file being parsed; the index to declare its contents with.
    std::size_t add_source(const std::string& file, const std::string& text);
    /// Throws base::ConfigError "FILE:LINE: NAME is already declared at FILE:LINE" on a second declaration, unless
    /// the first came from add_project_types().
    void declare(IdlDeclaration declaration, std::size_t source);
    /// A later constant of the same name replaces the earlier (an #include parsed twice declares it twice).
    void declare_constant(const std::string& scoped_name, std::int64_t value);

  private:
    struct Source {
        std::string file;
        std::string text;
        bool replaceable = false;  ///< the project's embedded files
    };
    struct Entry {
        IdlDeclaration declaration;
        std::size_t source = 0;
    };

    template <typename Lookup>
    auto lookup_in_scopes(const std::string& name, const std::string& scope, Lookup lookup) const
        -> decltype(lookup(name));

    void collect_sources(const IdlType& type, std::set<std::string>& visited, std::vector<std::size_t>& order) const;
    void collect_sources(const std::string& scoped_name, std::set<std::string>& visited,
                         std::vector<std::size_t>& order) const;
    void check_type(const IdlType& type) const;

    std::vector<Source> sources_;
    std::map<std::string, Entry> declarations_;
    std::map<std::string, std::int64_t> constants_;
    std::set<std::string> parsed_files_;  ///< canonical paths of the files add_idl_dir() parsed
    bool loading_project_types_ = false;
};

}  // namespace tgw::types
