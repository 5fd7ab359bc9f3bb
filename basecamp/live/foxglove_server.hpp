// The Foxglove WebSocket protocol (foxglove.websocket.v1) for the relay: Foxglove, and any client of the protocol,
// connects to ws://BASECAMP:PORT and sees every relayed topic live, decoded with its omgidl schema, the gateway's
// status among them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "basecamp/sample/sample_consumer.hpp"
#include "types/type_library.hpp"

namespace tgw::basecamp {

/// Advertises each topic it is given as a channel (encoding cdr, schema omgidl: the IDL of `types`, else the one
/// the publisher's TypeObject gave) to every client, and sends each sample to the clients subscribed to its
/// channel, as received (log time = receive time). A client that subscribes to nothing costs a sample nothing but
/// a look at a table. The server runs in a thread of its own; add() and add_topic() may come from any thread.
class FoxgloveServer final : public SampleConsumer {
  public:
    /// Listens on `port` of every IPv4 interface (0: a free port, see port()). Throws base::ConfigError naming
    /// `flag` when it cannot.
    FoxgloveServer(std::uint16_t port, types::TypeLibrary types, const std::string& flag);
    /// Closes every connection and stops the thread.
    ~FoxgloveServer();
    FoxgloveServer(const FoxgloveServer&) = delete;
    FoxgloveServer& operator=(const FoxgloveServer&) = delete;

    void add_topic(TopicRecord topic) override;
    void add(SampleRecord sample) override;

    /// The port it listens on.
    std::uint16_t port() const;
    /// Clients connected now.
    std::size_t clients() const;
    /// Messages sent to clients so far, each subscriber counted.
    std::uint64_t messages_sent() const;

  private:
    class Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace tgw::basecamp
