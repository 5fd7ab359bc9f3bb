#include "types/type_library.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>

#include "base/config_error.hpp"
#include "types/embedded_idl.hpp"
#include "types/idl_parser.hpp"

namespace tgw::types {

namespace fs = std::filesystem;

namespace {

std::string read_all(std::istream& in) {
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TypeLibrary TypeLibrary::project_and(const std::vector<std::string>& idl_dirs, const std::string& flag) {
    TypeLibrary types;
    types.add_project_types();
    for (const std::string& dir : idl_dirs)
        types.add_idl_dir(dir, flag);
    try {
        types.check_references();
    } catch (const base::ConfigError& e) {
        throw base::ConfigError(flag + ": " + e.what());
    }
    return types;
}

void TypeLibrary::add_project_types() {
    loading_project_types_ = true;
    try {
        for (const EmbeddedIdl& file : embedded_idl_files())
            parse_idl(file.text, file.file, *this);
    } catch (...) {
        loading_project_types_ = false;
        throw;
    }
    loading_project_types_ = false;
}

void TypeLibrary::add_idl(std::istream& in, const std::string& file) {
    parse_idl(read_all(in), file, *this);
}

void TypeLibrary::add_idl_dir(const std::string& dir, const std::string& flag) {
    std::error_code error;
    if (!fs::is_directory(dir, error))
        throw base::ConfigError(flag + ": '" + dir + "' is not a directory");
    std::vector<fs::path> files;
    for (fs::recursive_directory_iterator it(dir, error), end; !error && it != end; it.increment(error)) {
        if (it->path().extension() == ".idl" && it->is_regular_file(error))
            files.push_back(it->path());
    }
    if (error)
        throw base::ConfigError(flag + ": cannot read '" + dir + "': " + error.message());
    std::sort(files.begin(), files.end());

    std::function<void(const fs::path&)> parse_file = [&](const fs::path& path) {
        // Each file once: a directory given twice, or inside another, declares nothing twice.
        if (!parsed_files_.insert(fs::weakly_canonical(path, error).string()).second)
            return;
        std::ifstream in(path, std::ios::binary);
        if (!in)
            throw base::ConfigError("cannot read '" + path.string() + "'");
        const auto include = [&](const IdlInclude& target) {
            for (const fs::path& candidate : {path.parent_path() / target.target, fs::path(dir) / target.target}) {
                if (fs::is_regular_file(candidate, error)) {
                    parse_file(candidate);
                    return;
                }
            }
            // Not in the directory: its types must come from another --idl, or check_references() names them.
        };
        parse_idl(read_all(in), path.string(), *this, include);
    };
    try {
        for (const fs::path& file : files)
            parse_file(file);
    } catch (const base::ConfigError& e) {
        throw base::ConfigError(flag + ": " + e.what());
    }
}

template <typename Lookup>
auto TypeLibrary::lookup_in_scopes(const std::string& name, const std::string& scope, Lookup lookup) const
    -> decltype(lookup(name)) {
    if (name.rfind("::", 0) == 0)
        return lookup(name.substr(2));
    std::string enclosing = scope;
    while (true) {
        if (auto found = lookup(enclosing.empty() ? name : enclosing + "::" + name))
            return found;
        if (enclosing.empty())
            return decltype(lookup(name)){};
        const std::size_t cut = enclosing.rfind("::");
        enclosing = cut == std::string::npos ? std::string() : enclosing.substr(0, cut);
    }
}

const IdlDeclaration* TypeLibrary::find(const std::string& scoped_name) const {
    const std::string name = scoped_name.rfind("::", 0) == 0 ? scoped_name.substr(2) : scoped_name;
    const auto it = declarations_.find(name);
    return it == declarations_.end() ? nullptr : &it->second.declaration;
}

const IdlDeclaration* TypeLibrary::resolve(const std::string& name, const std::string& scope) const {
    return lookup_in_scopes(name, scope, [this](const std::string& candidate) { return find(candidate); });
}

std::optional<std::int64_t> TypeLibrary::constant(const std::string& name, const std::string& scope) const {
    return lookup_in_scopes(name, scope, [this](const std::string& candidate) -> std::optional<std::int64_t> {
        const auto it = constants_.find(candidate);
        return it == constants_.end() ? std::nullopt : std::optional<std::int64_t>(it->second);
    });
}

void TypeLibrary::check_type(const IdlType& type) const {
    if (type.kind == IdlType::Kind::named && resolve(type.name, type.scope) == nullptr)
        throw base::ConfigError(type.where.text() + ": unknown type '" + type.name + "'");
    if (type.element)
        check_type(*type.element);
}

void TypeLibrary::check_references() const {
    for (const auto& [name, entry] : declarations_) {
        if (const auto* declared = std::get_if<IdlStruct>(&entry.declaration)) {
            if (declared->base) {
                check_type(*declared->base);
                if (!std::holds_alternative<IdlStruct>(*resolve(declared->base->name, declared->base->scope)))
                    throw base::ConfigError(declared->base->where.text() + ": '" + declared->base->name +
                                            "' is not a struct to inherit from");
            }
            for (const IdlMember& member : declared->members)
                check_type(member.type);
        } else if (const auto* alias = std::get_if<IdlTypedef>(&entry.declaration)) {
            check_type(alias->type);
        }
    }
}

void TypeLibrary::collect_sources(const IdlType& type, std::set<std::string>& visited,
                                  std::vector<std::size_t>& order) const {
    if (type.kind == IdlType::Kind::named) {
        if (const IdlDeclaration* declared = resolve(type.name, type.scope))
            collect_sources(declaration_name(*declared), visited, order);
    }
    if (type.element)
        collect_sources(*type.element, visited, order);
}

void TypeLibrary::collect_sources(const std::string& scoped_name, std::set<std::string>& visited,
                                  std::vector<std::size_t>& order) const {
    const auto it = declarations_.find(scoped_name);
    if (it == declarations_.end() || !visited.insert(scoped_name).second)
        return;
    if (const auto* declared = std::get_if<IdlStruct>(&it->second.declaration)) {
        if (declared->base)
            collect_sources(*declared->base, visited, order);
        for (const IdlMember& member : declared->members)
            collect_sources(member.type, visited, order);
    } else if (const auto* alias = std::get_if<IdlTypedef>(&it->second.declaration)) {
        collect_sources(alias->type, visited, order);
    }
    if (std::find(order.begin(), order.end(), it->second.source) == order.end())
        order.push_back(it->second.source);
}

std::string TypeLibrary::idl_text(const std::string& type_name) const {
    const IdlDeclaration* declared = find(type_name);
    if (declared == nullptr)
        return {};
    std::set<std::string> visited;
    std::vector<std::size_t> order;
    collect_sources(declaration_name(*declared), visited, order);
    std::string text;
    for (std::size_t source : order) {
        text += sources_[source].text;
        if (!text.empty() && text.back() != '\n')
            text += '\n';
    }
    return text;
}

std::vector<std::string> TypeLibrary::struct_names() const {
    std::vector<std::string> names;
    for (const auto& [name, entry] : declarations_) {
        if (std::holds_alternative<IdlStruct>(entry.declaration))
            names.push_back(name);
    }
    return names;
}

std::size_t TypeLibrary::add_source(const std::string& file, const std::string& text) {
    sources_.push_back({file, text, loading_project_types_});
    return sources_.size() - 1;
}

void TypeLibrary::declare(IdlDeclaration declaration, std::size_t source) {
    const std::string name = declaration_name(declaration);
    const auto it = declarations_.find(name);
    if (it == declarations_.end()) {
        declarations_.emplace(name, Entry{std::move(declaration), source});
        return;
    }
    if (!sources_[it->second.source].replaceable || sources_[source].replaceable)
        throw base::ConfigError(declaration_location(declaration).text() + ": " + name + " is already declared at " +
                                declaration_location(it->second.declaration).text());
    it->second = Entry{std::move(declaration), source};
}

void TypeLibrary::declare_constant(const std::string& scoped_name, std::int64_t value) {
    constants_[scoped_name] = value;
}

}  // namespace tgw::types
