#include "basecamp/live/foxglove_server.hpp"

#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

#include "base/config_error.hpp"

namespace tgw::basecamp {

namespace {

using Server = websocketpp::server<websocketpp::config::asio>;
using Handle = websocketpp::connection_hdl;
using nlohmann::json;

constexpr char SUBPROTOCOL[] = "foxglove.websocket.v1";
constexpr std::uint8_t MESSAGE_DATA_OPCODE = 0x01;
/// Bytes a client may have waiting in its send buffer: past this its messages are skipped, not queued, so that a
/// slow laptop costs the relay neither memory nor the other clients their view.
constexpr std::size_t MAX_BUFFERED_BYTES = 8 << 20;

/// Status message levels of the protocol.
constexpr int STATUS_WARNING = 1;

struct Channel {
    std::uint32_t id = 0;
    std::string topic;
    std::string type_name;
    std::string schema;  ///< IDL text; empty when there is none
};

struct Client {
    std::map<std::uint32_t, std::uint32_t> channel_of;       ///< subscription id -> channel id
    std::map<std::uint32_t, std::uint32_t> subscription_of;  ///< channel id -> subscription id
};

json channel_json(const Channel& channel) {
    return {{"id", channel.id},         {"topic", channel.topic},
            {"encoding", "cdr"},        {"schemaName", channel.type_name},
            {"schema", channel.schema}, {"schemaEncoding", "omgidl"}};
}

void append_le(std::string& out, std::uint64_t value, int bytes) {
    for (int i = 0; i < bytes; ++i)
        out.push_back(static_cast<char>(value >> (8 * i)));
}

}  // namespace

class FoxgloveServer::Impl {
  public:
    Impl(std::uint16_t port, types::TypeLibrary types, const std::string& flag) : types_(std::move(types)) {
        server_.clear_access_channels(websocketpp::log::alevel::all);
        server_.clear_error_channels(websocketpp::log::elevel::all);
        server_.init_asio();
        server_.set_reuse_addr(true);
        server_.set_validate_handler([this](Handle handle) { return accept(handle); });
        server_.set_open_handler([this](Handle handle) { opened(handle); });
        server_.set_close_handler([this](Handle handle) { closed(handle); });
        server_.set_fail_handler([this](Handle handle) { closed(handle); });
        server_.set_message_handler(
            [this](Handle handle, Server::message_ptr message) { received(handle, message->get_payload()); });
        websocketpp::lib::error_code error;
        server_.listen(websocketpp::lib::asio::ip::tcp::v4(), port, error);
        if (!error)
            server_.start_accept(error);
        if (error)
            throw base::ConfigError(flag + ": cannot listen on port " + std::to_string(port) + ": " + error.message());
        port_ = server_.get_local_endpoint(error).port();
        thread_ = std::thread([this] { server_.run(); });
    }

    ~Impl() {
        // In the server's thread: stop accepting, say goodbye to each client, then let run() return.
        websocketpp::lib::asio::post(server_.get_io_service(), [this] {
            websocketpp::lib::error_code ignored;
            server_.stop_listening(ignored);
            std::lock_guard<std::mutex> lock(mutex_);
            for (const auto& [handle, client] : clients_)
                server_.close(handle, websocketpp::close::status::going_away, "tm-basecamp relay is stopping", ignored);
        });
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
        while (clients() > 0 && std::chrono::steady_clock::now() < deadline)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        server_.stop();
        thread_.join();
    }

    void add_topic(const TopicRecord& topic) {
        std::lock_guard<std::mutex> lock(mutex_);
        add_topic_nts(topic);
    }

    void add(const SampleRecord& sample) {
        std::lock_guard<std::mutex> lock(mutex_);
        auto known = channels_.find(sample.topic);
        if (known == channels_.end()) {
            TopicRecord topic;
            topic.topic = sample.topic;
            topic.type_name = sample.type_name;
            add_topic_nts(topic);
            known = channels_.find(sample.topic);
        }
        const std::uint32_t channel = known->second.id;
        for (const auto& [handle, client] : clients_) {
            const auto subscription = client.subscription_of.find(channel);
            if (subscription == client.subscription_of.end())
                continue;
            std::string frame;
            frame.reserve(1 + 4 + 8 + sample.payload.size());
            frame.push_back(static_cast<char>(MESSAGE_DATA_OPCODE));
            append_le(frame, subscription->second, 4);
            append_le(frame, static_cast<std::uint64_t>(sample.receive_ns), 8);
            frame.append(reinterpret_cast<const char*>(sample.payload.data()), sample.payload.size());
            websocketpp::lib::error_code error;
            const auto connection = server_.get_con_from_hdl(handle, error);
            if (error || connection->get_buffered_amount() > MAX_BUFFERED_BYTES)
                continue;
            connection->send(frame, websocketpp::frame::opcode::binary);
            sent_.fetch_add(1, std::memory_order_relaxed);
        }
    }

    std::uint16_t port() const { return port_; }

    std::size_t clients() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return clients_.size();
    }

    std::uint64_t sent() const { return sent_.load(); }

  private:
    /// The channel of `topic`, made on first sight; nullptr when it existed already.
    const Channel* channel_nts(const TopicRecord& topic) {
        if (channels_.count(topic.topic) != 0)
            return nullptr;
        Channel channel;
        channel.id = next_channel_++;
        channel.topic = topic.topic;
        channel.type_name = topic.type_name;
        channel.schema = types_.idl_text(topic.type_name);
        if (channel.schema.empty())
            channel.schema = topic.announced_idl;
        return &channels_.emplace(topic.topic, std::move(channel)).first->second;
    }

    /// add_topic() with the lock held.
    void add_topic_nts(const TopicRecord& topic) {
        const Channel* channel = channel_nts(topic);
        if (channel == nullptr)
            return;
        const std::string advertise = json{{"op", "advertise"}, {"channels", {channel_json(*channel)}}}.dump();
        for (const auto& [handle, client] : clients_)
            send_text(handle, advertise);
    }

    bool accept(Handle handle) {
        const auto connection = server_.get_con_from_hdl(handle);
        for (const std::string& offered : connection->get_requested_subprotocols()) {
            if (offered == SUBPROTOCOL) {
                connection->select_subprotocol(SUBPROTOCOL);
                return true;
            }
        }
        return false;  // not a client of the protocol
    }

    void opened(Handle handle) {
        std::lock_guard<std::mutex> lock(mutex_);
        clients_.emplace(handle, Client{});
        send_text(handle,
                  json{{"op", "serverInfo"},
                       {"name", "tm-basecamp relay"},
                       {"capabilities", json::array()},
                       {"supportedEncodings", json::array()},
                       {"metadata", json::object()},
                       {"sessionId", std::to_string(std::chrono::system_clock::now().time_since_epoch().count())}}
                      .dump());
        json channels = json::array();
        for (const auto& [topic, channel] : channels_)
            channels.push_back(channel_json(channel));
        if (!channels.empty())
            send_text(handle, json{{"op", "advertise"}, {"channels", channels}}.dump());
    }

    void closed(Handle handle) {
        std::lock_guard<std::mutex> lock(mutex_);
        clients_.erase(handle);
    }

    void received(Handle handle, const std::string& text) {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto client = clients_.find(handle);
        if (client == clients_.end())
            return;
        try {
            handle_request(handle, client->second, json::parse(text, nullptr, false));
        } catch (const json::exception& e) {  // a member of the wrong type
            warn(handle, std::string("malformed request: ") + e.what());
        }
    }

    void handle_request(Handle handle, Client& client, const json& request) {
        const std::string op = request.is_object() && request.contains("op") && request["op"].is_string()
                                   ? request["op"].get<std::string>()
                                   : "";
        if (op == "subscribe" && request.contains("subscriptions") && request["subscriptions"].is_array()) {
            for (const json& subscription : request["subscriptions"]) {
                const auto id = subscription.value("id", std::uint32_t{0});
                const auto channel = subscription.value("channelId", std::uint32_t{0});
                if (!known_channel(channel)) {
                    warn(handle, "no channel " + std::to_string(channel));
                    continue;
                }
                client.channel_of[id] = channel;
                client.subscription_of[channel] = id;
            }
        } else if (op == "unsubscribe" && request.contains("subscriptionIds") &&
                   request["subscriptionIds"].is_array()) {
            for (const json& id : request["subscriptionIds"]) {
                const auto it = client.channel_of.find(id.get<std::uint32_t>());
                if (it == client.channel_of.end())
                    continue;
                client.subscription_of.erase(it->second);
                client.channel_of.erase(it);
            }
        } else {
            warn(handle, "unsupported request: " + (op.empty() ? std::string("not JSON with an op") : op));
        }
    }

    bool known_channel(std::uint32_t id) const {
        for (const auto& [topic, channel] : channels_) {
            if (channel.id == id)
                return true;
        }
        return false;
    }

    void warn(Handle handle, const std::string& message) {
        send_text(handle, json{{"op", "status"}, {"level", STATUS_WARNING}, {"message", message}}.dump());
    }

    void send_text(Handle handle, const std::string& text) {
        websocketpp::lib::error_code ignored;  // a client gone meanwhile: its close handler cleans up
        server_.send(handle, text, websocketpp::frame::opcode::text, ignored);
    }

    Server server_;
    std::thread thread_;
    std::uint16_t port_ = 0;
    const types::TypeLibrary types_;
    mutable std::mutex mutex_;
    std::map<std::string, Channel> channels_;  ///< by topic
    std::uint32_t next_channel_ = 1;
    std::map<Handle, Client, std::owner_less<Handle>> clients_;
    std::atomic<std::uint64_t> sent_{0};
};

FoxgloveServer::FoxgloveServer(std::uint16_t port, types::TypeLibrary types, const std::string& flag)
    : impl_(std::make_unique<Impl>(port, std::move(types), flag)) {}

FoxgloveServer::~FoxgloveServer() = default;

void FoxgloveServer::add_topic(TopicRecord topic) {
    impl_->add_topic(topic);
}

void FoxgloveServer::add(SampleRecord sample) {
    impl_->add(sample);
}

std::uint16_t FoxgloveServer::port() const {
    return impl_->port();
}

std::size_t FoxgloveServer::clients() const {
    return impl_->clients();
}

std::uint64_t FoxgloveServer::messages_sent() const {
    return impl_->sent();
}

}  // namespace tgw::basecamp
