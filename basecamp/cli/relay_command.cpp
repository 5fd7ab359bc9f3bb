#include "basecamp/cli/relay_command.hpp"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>

#include "base/config_error.hpp"
#include "base/dds_security.hpp"
#include "base/event_loop.hpp"
#include "base/interface_addresses.hpp"
#include "base/peer_transport.hpp"
#include "base/receive_buffer.hpp"
#include "base/wan_address.hpp"
#include "basecamp/capture/backfill_archive.hpp"
#include "basecamp/cli/progress_line.hpp"
#include "basecamp/live/foxglove_server.hpp"
#include "basecamp/recording/sample_store.hpp"
#include "basecamp/relay/camp_domain_transport.hpp"
#include "basecamp/relay/compact_unpacker.hpp"
#include "basecamp/relay/relay.hpp"
#include "basecamp/sample/consumer_fan_out.hpp"
#include "sensor/link_state_watch.hpp"
#include "types/type_library.hpp"

namespace tgw::basecamp {

namespace {

struct RelayOptions {
    int domain = 1;
    int local_domain = 0;
    double duration_s = 0.0;
    base::PeerTransport transport;
    base::PeerTransport local_transport;
    std::string security_dir;
    std::vector<std::string> uplink;
    double channel_bps = 0;
    bool measure_channel = false;
    std::string out;
    double report_period_s = 1.0;
    std::uint16_t foxglove_port = 0;
    CLI::Option* foxglove = nullptr;
    std::vector<std::string> idl_dirs;
};

/// Follows the camp's WAN interface (--interface) in a thread of its own: when the address the relay is bound to
/// is gone and the interface has another (a DHCP lease, the laptop moved to another radio), it hands that over
/// once, so the relay is made anew on it.
class WanAddressFollower {
  public:
    WanAddressFollower(const std::string& name_or_address, std::string bound)
        : interface_(base::resolve_interface_name(name_or_address)),
          bound_(std::move(bound)),
          watch_(interface_, [this](const sensor::LinkState& state) { on_change(state); }) {
        watch_.start();
    }

    /// The address to bind to now, once per change; none while the bound one stands.
    std::optional<std::string> take_new_address() {
        std::lock_guard<std::mutex> lock(mutex_);
        std::optional<std::string> taken = std::move(pending_);
        pending_.reset();
        return taken;
    }

    const std::string& interface() const { return interface_; }

  private:
    void on_change(const sensor::LinkState& state) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (state.addresses.empty() ||
            std::find(state.addresses.begin(), state.addresses.end(), bound_) != state.addresses.end()) {
            return;
        }
        bound_ = state.addresses.front();
        pending_ = bound_;
    }

    const std::string interface_;
    std::mutex mutex_;
    std::string bound_;                   // under mutex_
    std::optional<std::string> pending_;  // under mutex_
    sensor::LinkStateWatch watch_;        // last: its thread calls on_change
};

/// Looks the relay's --peer host names up again every PEER_LOOKUP_PERIOD, in a thread of its own (a base::EventLoop; a
/// robot on DHCP, known by its name): says once when one resolves to another address than before, so that the relay is
/// made anew announcing to it. A lookup that fails keeps the last address.
class PeerNameFollower {
  public:
    static constexpr std::chrono::seconds PEER_LOOKUP_PERIOD{5};

    /// `peers` as given to --peer, all of them resolved once already (base::resolve_peers).
    explicit PeerNameFollower(std::vector<std::string> peers) : peers_(std::move(peers)), known_(lookup()) {
        loop_.start();
        loop_.post_every(PEER_LOOKUP_PERIOD, [this] { look(); });
    }
    ~PeerNameFollower() { loop_.stop(); }
    PeerNameFollower(const PeerNameFollower&) = delete;
    PeerNameFollower& operator=(const PeerNameFollower&) = delete;

    /// What resolves to another address since the last call ("robot1.local is 10.0.0.9"); empty when nothing does.
    std::string take_change() {
        std::lock_guard<std::mutex> lock(mutex_);
        std::string changed = std::move(changed_);
        changed_.clear();
        return changed;
    }

  private:
    std::vector<std::string> lookup() const {
        std::vector<std::string> addresses;
        for (const std::string& peer : peers_)
            addresses.push_back(base::lookup_ipv4(peer).value_or(""));
        return addresses;
    }

    void look() {
        const std::vector<std::string> now = lookup();  // the resolver may take seconds
        std::lock_guard<std::mutex> lock(mutex_);
        for (std::size_t i = 0; i < now.size(); ++i) {
            if (!now[i].empty() && now[i] != known_[i]) {
                known_[i] = now[i];
                changed_ += (changed_.empty() ? "" : ", ") + peers_[i] + " is " + now[i];
            }
        }
    }

    const std::vector<std::string> peers_;
    std::mutex mutex_;
    std::vector<std::string> known_;  // under mutex_
    std::string changed_;             // under mutex_
    base::EventLoop loop_;            // last: its tasks use the members above
};

void print_summary(const Relay& relaying, const std::map<std::string, std::uint64_t>& relayed) {
    for (const auto& [topic, count] : relayed)
        std::cout << "  " << topic << ": " << count << " samples relayed\n";
    if (const CompactUnpacker* compact = relaying.compact()) {
        const auto c = compact->counts();
        std::cout << "  compact WAN: " << c.bundles << " bundles taken (" << c.rejected_bundles << " rejected, "
                  << c.lost_bundles << " lost on the way), " << c.entries << " entries, " << c.relayed
                  << " samples relayed, " << c.unknown_entries << " never described by a catalog entry, "
                  << c.incomplete_samples << " chunked samples incomplete, " << c.undecodable_entries
                  << " compressed entries undecodable\n";
    }
    for (const auto& [gateway, bps] : relaying.channel_grants())
        std::cout << "  last grant to gateway " << gateway << ": " << static_cast<long long>(bps) << " bit/s\n";
    if (const std::optional<double> newcomers = relaying.newcomer_share())
        std::cout << "  last newcomers' share: " << static_cast<long long>(*newcomers) << " bit/s\n";
    if (const std::optional<ChannelReading> channel = relaying.channel_reading())
        std::cout << "  channel measured: " << static_cast<long long>(channel->channel_bps) << " bit/s ("
                  << core::to_string(channel->verdict) << "), " << channel->datagrams << " datagrams received ("
                  << channel->stamped_datagrams << " stamped by their sender, " << channel->lost_datagrams
                  << " lost on the way)\n";
    for (const passthrough::UplinkCount& up : relaying.uplink_counts())
        std::cout << "  uplink " << up.from_topic << ": " << up.received << " commands taken from the camp, "
                  << up.delivered << " onto the WAN, " << up.no_reader << " written while no gateway listened (lost), "
                  << up.expired << " past their Lifespan (dropped), " << up.failed << " failed\n";
}

int run_relay(const RelayOptions& options) {
    // Checked first: nothing is created when an identity's file is missing or tampered with.
    const auto security = security_files(options.security_dir);
    if (options.local_domain == options.domain)
        throw base::ConfigError("--local-domain: must differ from --domain (" + std::to_string(options.domain) +
                                "), or every sample would come back to the relay");
    auto* factory = eprosima::fastdds::dds::DomainParticipantFactory::get_instance();
    // The WAN participant's QoS, bound to `address` when given (the interface's new one), else as the flags say.
    const auto wan_qos = [&](const std::string& address) {
        auto qos = factory->get_default_participant_qos();
        base::PeerTransport transport = options.transport;
        if (!address.empty())
            transport.interface = address;
        base::apply_peer_transport(qos, transport, options.domain);
        // The WAN participant only: the camp's own domain stays plain, for programs with their defaults.
        if (security)
            base::apply_dds_security(qos, *security);
        return qos;
    };
    base::warn_if_receive_buffer_capped(std::cerr, "tm-basecamp relay", "--receive-buffer",
                                        options.transport.receive_buffer_bytes);
    const auto first_wan_qos = wan_qos("");
    auto local_qos = factory->get_default_participant_qos();
    const std::vector<std::string> camp_addresses =
        apply_camp_domain_transport(local_qos, options.local_transport, options.transport, options.local_domain);
    std::vector<SampleConsumer*> consumers;
    std::unique_ptr<SampleStore> store;
    std::unique_ptr<BackfillArchive> backfill;
    if (!options.out.empty()) {
        store = std::make_unique<SampleStore>(options.out, "--out");
        backfill = std::make_unique<BackfillArchive>(*store);  // before any sample: it takes the store's acks
        consumers.push_back(store.get());
    }
    std::unique_ptr<FoxgloveServer> foxglove_server;
    if (options.foxglove->count() > 0) {
        foxglove_server = std::make_unique<FoxgloveServer>(
            options.foxglove_port, types::TypeLibrary::project_and(options.idl_dirs, "--idl"), "--foxglove-port");
        consumers.push_back(foxglove_server.get());
    }
    ConsumerFanOut taken_off_the_wan(consumers);
    const auto make_relay = [&](const eprosima::fastdds::dds::DomainParticipantQos& qos) {
        auto relay = std::make_unique<Relay>(
            options.domain, qos, options.local_domain, local_qos, consumers.empty() ? nullptr : &taken_off_the_wan,
            base::from_seconds(options.report_period_s), options.uplink, options.channel_bps, options.measure_channel);
        if (backfill) {
            relay->archive_backfill(*backfill);
        }
        return relay;
    };
    std::unique_ptr<Relay> relaying = make_relay(first_wan_qos);
    std::unique_ptr<WanAddressFollower> follower;
    std::string bound;  // the address the relay is bound to now; empty: as the flags say
    if (!options.transport.interface.empty()) {
        bound = base::resolve_ipv4(options.transport.interface, "--interface");
        follower = std::make_unique<WanAddressFollower>(options.transport.interface, bound);
    }
    std::unique_ptr<PeerNameFollower> names;
    if (std::any_of(options.transport.peers.begin(), options.transport.peers.end(),
                    [](const std::string& peer) { return !base::is_ipv4(peer); })) {
        names = std::make_unique<PeerNameFollower>(options.transport.peers);
    }
    stop_on_signals();
    std::cout << "tm-basecamp relay: WAN domain " << options.domain << " -> local domain " << options.local_domain
              << "; " << describe_camp_domain(camp_addresses, options.local_transport, options.transport);
    if (foxglove_server)
        std::cout << ", Foxglove on ws://0.0.0.0:" << foxglove_server->port();
    std::cout << std::endl;

    const auto relayed = [&] { return relaying->relayed(); };
    const auto duration = options.duration_s > 0 ? base::from_seconds(options.duration_s) : base::Duration::max() / 2;
    run_with_progress(
        duration, stop_requested(),
        [&](base::Duration slice) {
            std::string why;
            if (follower) {
                if (const std::optional<std::string> address = follower->take_new_address()) {
                    // The old participant announced an address nobody can reach: the robots hear the new one, as
                    // a relay started now, from its announcements to their --peer addresses.
                    why = "WAN interface " + follower->interface() + " has " + *address + " now";
                    bound = *address;
                }
            }
            if (names) {
                if (const std::string peers_now = names->take_change(); !peers_now.empty())
                    why += (why.empty() ? "--peer " : "; --peer ") + peers_now + " now";
            }
            if (!why.empty()) {
                std::optional<eprosima::fastdds::dds::DomainParticipantQos> qos;
                try {
                    qos = wan_qos(bound);  // before the participant goes: a lookup may fail
                } catch (const base::ConfigError& error) {
                    std::cerr << "tm-basecamp relay: " << why << ", but " << error.what()
                              << ": relaying on as before\n";
                }
                if (qos) {
                    std::cout << "tm-basecamp relay: " << why
                              << ": the relay's WAN participant is made anew (the camp's domain stays)" << std::endl;
                    try {
                        relaying->remake_wan(*qos);
                    } catch (const base::ConfigError& error) {
                        std::cerr << "tm-basecamp relay: " << error.what()
                                  << ": nothing on the WAN until the next change of address or name\n";
                    }
                }
            }
            relaying->run(slice, stop_requested());
        },
        [&] { return "relaying: " + topics_and_samples(relayed()); });
    if (store) {
        store->flush();
        std::cout << "  recorded in " << options.out << ": " << store->rows_written() << " rows, "
                  << store->write_errors() << " write errors\n";
        if (backfill->received() > 0) {
            std::cout << "  backfill: " << backfill->received() << " samples from the robots' logs, "
                      << store->duplicate_backfill_rows() << " of them stored before\n";
        }
    }
    print_summary(*relaying, relayed());
    if (foxglove_server)
        std::cout << "  Foxglove: " << foxglove_server->messages_sent() << " messages sent to clients\n";
    return 0;
}

}  // namespace

Subcommand add_relay_command(CLI::App& app) {
    auto options = std::make_shared<RelayOptions>();
    options->local_transport.interface_flag = "--local-interface";
    CLI::App* relay = app.add_subcommand(
        "relay", "the camp's one participant on the WAN domain: every topic republished into the camp's own domain");
    relay->add_option("--domain", options->domain, "the WAN domain's id")->check(CLI::Range(0, 232));
    relay->add_option("--peer", options->transport.peers,
                      "IPv4 address or host name of the robot (repeatable; a name is looked up again every 5 s, and a "
                      "new address makes the relay anew): UDP unicast only on the WAN, no multicast");
    relay->add_option("--interface", options->transport.interface,
                      "interface name or IPv4 address to bind the WAN participant's sockets to (followed: on a new "
                      "address the relay is made anew on it)");
    add_discovery_server_option(*relay, options->transport);
    add_receive_buffer_option(*relay, options->transport);
    relay
        ->add_option("--local-domain", options->local_domain,
                     "the camp's own domain: every topic appears there, for programs with their vendors' defaults")
        ->check(CLI::Range(0, 232))
        ->required();
    add_security_option(*relay, options->security_dir);
    relay->add_option("--local-interface", options->local_transport.interface,
                      "interface name or IPv4 address the camp's domain uses (default: every interface but the WAN's, "
                      "loopback included, as they are at start)");
    relay->add_option("--uplink", options->uplink,
                      "a topic the camp's programs may publish to the robots (commands: rt/NAME/cmd_vel, for a gateway "
                      "with --robot-name NAME --uplink rt/cmd_vel), carried from the camp's domain onto the WAN; "
                      "repeatable, nothing else goes that way");
    CLI::Option* channel_rate = relay->add_option(
        "--channel-rate", options->channel_bps,
        "experimental (docs/fleet-channel.md): bit/s of the radio channel the gateways share; each gateway with "
        "--channel-grants gets its share of 90 % of it on tgw/grant every second, the fleet's shortest TTLs "
        "first; the other 10 % is the share of gateways that join");
    channel_rate->check(CLI::PositiveNumber);
    relay
        ->add_flag("--measure-channel", options->measure_channel,
                   "experimental: measure what the channel delivers (what arrives, what is lost, how long it took) and "
                   "grant shares of that, with --channel-rate as its upper bound")
        ->needs(channel_rate);
    relay->add_option("--out", options->out, "also record every sample taken off the WAN, as 'record' does (SQLite)");
    relay
        ->add_option("--report-period", options->report_period_s,
                     "seconds between receiver reports to each gateway (tgw/receiver_report); 0: none")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    relay->add_option("--duration", options->duration_s, "seconds to relay; until SIGINT/SIGTERM without it")
        ->check(CLI::PositiveNumber);
    options->foxglove = relay->add_option(
        "--foxglove-port", options->foxglove_port,
        "serve every relayed topic live to Foxglove (WebSocket, foxglove.websocket.v1) on this TCP port");
    add_idl_option(*relay, options->idl_dirs);
    return {relay, [options] { return run_relay(*options); }, std::make_shared<base::ConfigFile>(*relay)};
}

}  // namespace tgw::basecamp
