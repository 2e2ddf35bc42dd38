// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/osc/tcp_endpoint.hpp"

#include <boost/asio/ip/address.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>

#include <array>
#include <deque>

namespace ameoto {

namespace asio = boost::asio;
using asio::ip::tcp;

struct TcpEndpoint::Connection {
    explicit Connection(tcp::socket s, std::uint64_t i) : socket(std::move(s)), id(i) {}
    tcp::socket socket;
    std::uint64_t id;
    std::array<unsigned char, 4> size_bytes{};
    std::vector<unsigned char> body;
    std::deque<std::vector<unsigned char>> outgoing;   // framed replies, oldest first
    std::size_t pending = 0;                           // their bytes
    bool writing = false;
    bool open = true;
    std::size_t unhandled = 0;   // packets handed on by the receiver, not yet handled()
    bool paused = false;         // not reading until some of them are
};

TcpEndpoint::TcpEndpoint(const std::string& address, int port, TcpLimits limits, Receiver receiver, Closed closed)
    : acceptor_(io_), limits_(limits), receiver_(std::move(receiver)), closed_(std::move(closed)) {
    const tcp::endpoint local(asio::ip::make_address(address), static_cast<unsigned short>(port));
    acceptor_.open(local.protocol());
    acceptor_.set_option(tcp::acceptor::reuse_address(true));
    acceptor_.bind(local);   // throws boost::system::system_error with the reason
    acceptor_.listen();
    local_ = acceptor_.local_endpoint();
}

TcpEndpoint::~TcpEndpoint() { close(); }

void TcpEndpoint::start() {
    accept();
    thread_ = std::thread([this] { io_.run(); });
}

void TcpEndpoint::accept() {
    acceptor_.async_accept([this](const boost::system::error_code& ec, tcp::socket socket) {
        if (ec == asio::error::operation_aborted || !acceptor_.is_open()) return;
        if (!ec) {
            boost::system::error_code peer_error;
            const auto peer = socket.remote_endpoint(peer_error);
            if (peer_error || (admit_ && !admit_(peer.address()))) {
                boost::system::error_code ignored;   // not an allowed sender (--allow): closed, no reply
                socket.close(ignored);
            } else if (connections_.size() >= limits_.max_connections) {
                boost::system::error_code ignored;   // over the bound: refused by closing at once
                socket.close(ignored);
            } else {
                boost::system::error_code ignored;
                socket.set_option(tcp::no_delay(true), ignored);   // replies are small and wanted now
                auto c = std::make_shared<Connection>(std::move(socket), next_id_++);
                connections_[c->id] = c;
                read_size(c);
            }
        }
        accept();
    });
}

void TcpEndpoint::read_size(const std::shared_ptr<Connection>& c) {
    asio::async_read(c->socket, asio::buffer(c->size_bytes), [this, c](const boost::system::error_code& ec, std::size_t) {
        if (ec || !c->open) return drop(c);
        const std::uint32_t size = (std::uint32_t{c->size_bytes[0]} << 24) | (std::uint32_t{c->size_bytes[1]} << 16) |
                                   (std::uint32_t{c->size_bytes[2]} << 8) | std::uint32_t{c->size_bytes[3]};
        if (size == 0) return read_size(c);   // an empty packet: nothing to do
        if (size > limits_.max_packet) return drop(c);
        read_body(c, size);
    });
}

void TcpEndpoint::read_body(const std::shared_ptr<Connection>& c, std::size_t size) {
    c->body.resize(size);
    asio::async_read(c->socket, asio::buffer(c->body), [this, c](const boost::system::error_code& ec, std::size_t) {
        if (ec || !c->open) return drop(c);
        if (!receiver_(c->body.data(), c->body.size(), c->id)) ++c->unhandled;
        if (!c->open) return;
        if (c->unhandled >= limits_.max_unhandled) c->paused = true;
        else read_size(c);
    });
}

void TcpEndpoint::send(std::uint64_t connection, std::vector<unsigned char> bytes) {
    asio::post(io_, [this, connection, bytes = std::move(bytes)] { send_here(connection, bytes); });
}

void TcpEndpoint::handled(std::uint64_t connection) {
    asio::post(io_, [this, connection] {
        const auto found = connections_.find(connection);
        if (found == connections_.end()) return;   // closed meanwhile
        const auto c = found->second;
        if (c->unhandled > 0) --c->unhandled;
        if (c->paused && c->open && c->unhandled < limits_.max_unhandled) {
            c->paused = false;
            read_size(c);
        }
    });
}

void TcpEndpoint::send_here(std::uint64_t connection, const std::vector<unsigned char>& bytes) {
    const auto found = connections_.find(connection);
    if (found == connections_.end()) return;   // gone: not the server's problem
    const auto c = found->second;
    if (c->pending + bytes.size() + 4 > limits_.max_pending) return drop(c);   // it does not read its replies
    std::vector<unsigned char> framed(bytes.size() + 4);
    const auto n = static_cast<std::uint32_t>(bytes.size());
    framed[0] = static_cast<unsigned char>(n >> 24);
    framed[1] = static_cast<unsigned char>(n >> 16);
    framed[2] = static_cast<unsigned char>(n >> 8);
    framed[3] = static_cast<unsigned char>(n);
    std::copy(bytes.begin(), bytes.end(), framed.begin() + 4);
    c->pending += framed.size();
    c->outgoing.push_back(std::move(framed));
    if (!c->writing) write(c);
}

void TcpEndpoint::write(const std::shared_ptr<Connection>& c) {
    if (c->outgoing.empty() || !c->open) {
        c->writing = false;
        return;
    }
    c->writing = true;
    asio::async_write(c->socket, asio::buffer(c->outgoing.front()), [this, c](const boost::system::error_code& ec, std::size_t) {
        if (ec || !c->open) return drop(c);
        c->pending -= c->outgoing.front().size();
        c->outgoing.pop_front();
        write(c);
    });
}

void TcpEndpoint::drop(const std::shared_ptr<Connection>& c) {
    if (!c->open) return;
    c->open = false;
    boost::system::error_code ignored;
    c->socket.shutdown(tcp::socket::shutdown_both, ignored);
    c->socket.close(ignored);   // pending handlers finish with operation_aborted and let go of c
    connections_.erase(c->id);
    if (closed_) closed_(c->id);
}

void TcpEndpoint::close() {
    if (thread_.joinable()) {
        asio::post(io_, [this] {
            close_here();
            io_.stop();
        });
        thread_.join();
    }
    close_here();   // never started, or already closed: nothing left running
}

void TcpEndpoint::close_here() {
    boost::system::error_code ignored;
    acceptor_.close(ignored);
    while (!connections_.empty()) {
        const auto c = connections_.begin()->second;
        c->open = false;
        c->socket.close(ignored);
        connections_.erase(connections_.begin());
    }
}

}  // namespace ameoto
