// The two paths that gateway_hop_bench and throughput_bench compare in one process: a robot publisher's topic
// read directly in the robot domain, and its twin bridged by a Gateway to a base-camp reader in the WAN domain.
#pragma once

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "base/config_error.hpp"
#include "base/receive_buffer.hpp"
#include "test/bench/bench_support.hpp"

namespace tgw::bench {

/// The participants of both paths and the gateway between them.
class SideBySide {
  public:
    /// Creates the participants, then the gateway. Both readers' participants get `reader_receive_buffer_bytes`
    /// of SO_RCVBUF (0: the system's default; by default what the camp's tools ask for). False, after saying why
    /// (prefixed by `bench`), when DDS or the gateway's configuration refuses.
    bool set_up(const char* bench, const BenchDomains& d, const fdds::DomainParticipantQos& publisher_qos,
                const fdds::DomainParticipantQos& direct_qos, const tgw::dds::GatewayConfig& gateway_config,
                const base::Clock& clock,
                std::uint32_t reader_receive_buffer_bytes = base::DEFAULT_RECEIVE_BUFFER_BYTES) {
        tgw::test::use_transports_in_process();
        publisher_ = std::make_unique<tgw::test::TestParticipant>(d.robot, publisher_qos);
        direct_ = std::make_unique<tgw::test::TestParticipant>(
            d.robot, with_receive_buffer(direct_qos, reader_receive_buffer_bytes));
        basecamp_ = std::make_unique<tgw::test::TestParticipant>(
            d.wan, with_receive_buffer(tgw::test::TestParticipant::wan_qos(d.wan_reader_port, d.gateway_wan_port),
                                       reader_receive_buffer_bytes));
        if (!publisher_->ok() || !direct_->ok() || !basecamp_->ok()) {
            std::fprintf(stderr, "%s: cannot create the participants (domains %d, %d)\n", bench, d.robot, d.wan);
            return false;
        }
        try {
            gateway_ = std::make_unique<tgw::dds::Gateway>(gateway_config, clock);
        } catch (const base::ConfigError& e) {
            std::fprintf(stderr, "%s: %s\n", bench, e.what());
            return false;
        }
        return true;
    }

    /// The gateway first: its robot readers go before the publisher they read.
    void tear_down() {
        gateway_.reset();
        basecamp_.reset();
        direct_.reset();
        publisher_.reset();
    }

    tgw::dds::Gateway& gateway() { return *gateway_; }

    /// The publisher's writers on both paths: KEEP_LAST 100, no data sharing; transient local as Fast DDS's default
    /// (the gateway then keeps each instance's last sample for late joiners) unless `volatile_writer`, as a ROS 2
    /// node's.
    fdds::DataWriterQos writer_qos(bool reliable, bool volatile_writer = false) const {
        fdds::DataWriterQos q = publisher_->default_writer_qos();
        q.reliability().kind = reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
        if (volatile_writer) {
            q.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
        }
        q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        q.history().depth = 100;
        q.data_sharing().off();
        return q;
    }

    /// The readers on both paths: KEEP_LAST 1000, no data sharing.
    fdds::DataReaderQos reader_qos(bool reliable) const {
        fdds::DataReaderQos q = basecamp_->default_reader_qos();
        q.reliability().kind = reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
        q.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        q.history().depth = 1000;
        q.data_sharing().off();
        return q;
    }

    /// One pair of topics of one type, written by the publisher: `via` bridged to the base camp, `direct` read in
    /// the robot domain. Detaches its listeners when it goes: they usually die with the caller's scope.
    struct Pair {
        fdds::DataWriter* via_writer = nullptr;
        fdds::DataWriter* direct_writer = nullptr;
        fdds::DataReader* via_reader = nullptr;
        fdds::DataReader* direct_reader = nullptr;
        core::TopicId id = 0;  ///< the via topic in the gateway
        tgw::test::MatchCounter via_matches;
        tgw::test::MatchCounter direct_matches;

        ~Pair() {
            for (fdds::DataReader* reader : {via_reader, direct_reader}) {
                if (reader != nullptr) {
                    reader->set_listener(nullptr);
                }
            }
            for (fdds::DataWriter* writer : {via_writer, direct_writer}) {
                if (writer != nullptr) {
                    writer->set_listener(nullptr);
                }
            }
        }
    };

    /// Creates a Pair and waits, up to `timeout`, until the gateway bridged `via_topic` and every endpoint on
    /// both paths matched. Null, after saying why (prefixed by `bench`), otherwise. `Listener` has an atomic
    /// `matched` count.
    template <typename Listener>
    std::unique_ptr<Pair> open_pair(const char* bench, const std::string& via_topic, const std::string& direct_topic,
                                    const fdds::DataWriterQos& writer_qos, const fdds::DataReaderQos& via_qos,
                                    const fdds::DataReaderQos& direct_qos, Listener& via_listener,
                                    Listener& direct_listener, std::chrono::seconds timeout) {
        fdds::TypeSupport type(new tgw::idl::PaperMessagePubSubType());
        auto pair = std::make_unique<Pair>();
        pair->via_writer = publisher_->make_writer(via_topic, type, writer_qos, &pair->via_matches);
        pair->direct_writer = publisher_->make_writer(direct_topic, type, writer_qos, &pair->direct_matches);
        pair->via_reader = basecamp_->make_reader(via_topic, type, via_qos, &via_listener);
        pair->direct_reader = direct_->make_reader(direct_topic, type, direct_qos, &direct_listener);
        if (pair->via_writer == nullptr || pair->direct_writer == nullptr || pair->via_reader == nullptr ||
            pair->direct_reader == nullptr) {
            std::fprintf(stderr, "%s: cannot create the endpoints of %s\n", bench, via_topic.c_str());
            return nullptr;
        }
        if (!gateway_->wait_for_topic(via_topic, timeout)) {
            std::fprintf(stderr, "%s: %s was never bridged\n", bench, via_topic.c_str());
            return nullptr;
        }
        pair->id = gateway_->find_topic(via_topic)->id;
        const Pair& p = *pair;
        const bool matched = tgw::test::wait_until(
            [&] {
                return p.via_matches.matched.load() > 0 && via_listener.matched.load() > 0 &&
                       gateway_->wan_matched_readers(p.id) > 0 && gateway_->robot_matched_writers(p.id) > 0 &&
                       p.direct_matches.matched.load() > 0 && direct_listener.matched.load() > 0;
            },
            timeout);
        if (!matched) {
            std::fprintf(stderr, "%s: the endpoints of %s never matched\n", bench, via_topic.c_str());
            return nullptr;
        }
        return pair;
    }

  private:
    std::unique_ptr<tgw::test::TestParticipant> publisher_;
    std::unique_ptr<tgw::test::TestParticipant> direct_;
    std::unique_ptr<tgw::test::TestParticipant> basecamp_;
    std::unique_ptr<tgw::dds::Gateway> gateway_;
};

}  // namespace tgw::bench
