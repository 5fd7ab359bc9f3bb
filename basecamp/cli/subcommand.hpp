// How tm-basecamp's subcommands that live in files of their own plug into main: each adds itself to the app
// and hands back how to run it once the command line is parsed.
#pragma once

#include <CLI/CLI.hpp>

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/config_file.hpp"
#include "base/peer_transport.hpp"
#include "base/security_files.hpp"

namespace tgw::basecamp {

struct Subcommand {
    CLI::App* command = nullptr;
    /// Runs the parsed command and returns the exit code. May throw base::ConfigError (exit 2, message printed).
    std::function<int()> run;
    /// Its --config file, for a command that takes one (relay); else none.
    std::shared_ptr<base::ConfigFile> config = nullptr;
};

/// Where a live tool (stats, status, echo) subscribes: the domain, the link transport as `record` has it, and the
/// DDS Security identity on a secured WAN domain.
struct DomainOptions {
    int domain = 1;
    base::PeerTransport transport;
    std::string security_dir;  ///< empty: a plain participant
};

/// Adds --domain, --peer, --interface, --discovery-server, --receive-buffer and --security to `command` for `options`,
/// which must outlive the app.
void add_domain_options(CLI::App& command, DomainOptions& options);

/// Adds --discovery-server ADDR:PORT to `command`: the WAN participant a client of a Fast DDS Discovery Server.
void add_discovery_server_option(CLI::App& command, base::PeerTransport& transport);

/// Adds --receive-buffer BYTES to `command`: SO_RCVBUF of the WAN participant's UDP sockets.
void add_receive_buffer_option(CLI::App& command, base::PeerTransport& transport);

/// Adds --security DIR to `command`: the WAN participant's DDS Security identity (scripts/make-certs).
void add_security_option(CLI::App& command, std::string& dir);

/// The checked files of the identity directory `dir` given to --security, or none when `dir` is empty. Throws
/// base::ConfigError naming --security and the file at fault.
std::optional<base::SecurityFiles> security_files(const std::string& dir);

/// Where an MCAP file goes (record, export) and how: the file, its chunks' compression, the IDL of types other
/// than the project's for its schemas.
struct McapOptions {
    std::string path;
    std::string compression = "zstd";
    std::size_t chunk_bytes = 1 << 20;
    std::vector<std::string> idl_dirs;
};

/// Adds --mcap FILE (required when `required`), --compression, --chunk-size and --idl to `command` for `options`, which
/// must outlive the app.
void add_mcap_options(CLI::App& command, McapOptions& options, bool required);

/// Adds --idl DIR (repeatable) to `command`: directories of IDL files for types other than the project's.
void add_idl_option(CLI::App& command, std::vector<std::string>& dirs);

/// True once SIGINT or SIGTERM came after stop_on_signals(): long commands then end cleanly, their files whole.
const std::atomic<bool>& stop_requested();
void stop_on_signals();

}  // namespace tgw::basecamp
