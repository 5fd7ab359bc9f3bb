#include "basecamp/cli/subcommand.hpp"

#include <csignal>

#include "base/receive_buffer.hpp"

namespace tgw::basecamp {

namespace {

std::atomic<bool> g_stop{false};

void on_signal(int) {
    g_stop.store(true);
}

}  // namespace

void add_domain_options(CLI::App& command, DomainOptions& options) {
    command.add_option("--domain", options.domain, "DDS domain id (the WAN domain, or the camp's behind a relay)")
        ->check(CLI::Range(0, 232))
        ->capture_default_str();
    // One value per flag: a repeated flag adds one, and a positional argument after it stays one.
    command
        .add_option(
            "--peer", options.transport.peers,
            "IPv4 address or host name of the robot (repeatable): UDP unicast only, no multicast, no shared memory")
        ->allow_extra_args(false);
    command.add_option("--interface", options.transport.interface,
                       "interface name or IPv4 address to bind every socket to");
    add_discovery_server_option(command, options.transport);
    add_receive_buffer_option(command, options.transport);
    add_security_option(command, options.security_dir);
}

void add_receive_buffer_option(CLI::App& command, base::PeerTransport& transport) {
    command
        .add_option("--receive-buffer", transport.receive_buffer_bytes,
                    "bytes of UDP receive buffer on the WAN: room for large samples while the tool is busy (capped "
                    "by net.core.rmem_max)")
        ->check(CLI::Range(base::MIN_RECEIVE_BUFFER_BYTES, base::MAX_RECEIVE_BUFFER_BYTES))
        ->capture_default_str();
}

void add_discovery_server_option(CLI::App& command, base::PeerTransport& transport) {
    command.add_option("--discovery-server", transport.discovery_server,
                       "ADDR:PORT of a Fast DDS Discovery Server (fastdds discovery -i 0 -l ADDR -p PORT): discovery "
                       "through it, UDP unicast only; instead of --peer");
}

void add_security_option(CLI::App& command, std::string& dir) {
    command.add_option("--security", dir,
                       "DDS Security on the WAN participant (authentication, encryption, access control) with this "
                       "identity directory, made by scripts/make-certs (DIR/basecamp); checked at start");
}

std::optional<base::SecurityFiles> security_files(const std::string& dir) {
    if (dir.empty())
        return std::nullopt;
    return base::SecurityFiles::load(dir, "--security");
}

void add_idl_option(CLI::App& command, std::vector<std::string>& dirs) {
    command
        .add_option("--idl", dirs,
                    "a directory of IDL files (repeatable, subdirectories too) for types other than the project's")
        ->check(CLI::ExistingDirectory)
        ->allow_extra_args(false);
}

void add_mcap_options(CLI::App& command, McapOptions& options, bool required) {
    CLI::Option* mcap = command.add_option(
        "--mcap", options.path, "an MCAP file to write: one channel per topic, CDR as received, omgidl schemas");
    if (required)
        mcap->required();
    command
        .add_option("--compression", options.compression,
                    "the MCAP file's chunk compression: zstd, lz4 or none (for readers without decompressors)")
        ->check(CLI::IsMember({"zstd", "lz4", "none"}))
        ->capture_default_str();
    command
        .add_option("--chunk-size", options.chunk_bytes,
                    "bytes of messages per MCAP chunk, before compression: a reader seeks by chunk")
        ->check(CLI::Range(std::size_t{1024}, std::size_t{1} << 30))
        ->capture_default_str();
    add_idl_option(command, options.idl_dirs);
}

const std::atomic<bool>& stop_requested() {
    return g_stop;
}

void stop_on_signals() {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
}

}  // namespace tgw::basecamp
