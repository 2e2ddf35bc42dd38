#include "server/osc/udp_endpoint.hpp"

#include <boost/asio/ip/address.hpp>

namespace ameoto {

UdpEndpoint::UdpEndpoint(boost::asio::io_context& io, const std::string& address, int port, Receiver receiver)
    : socket_(io), receiver_(std::move(receiver)) {
    const Endpoint local(boost::asio::ip::make_address(address), static_cast<unsigned short>(port));
    socket_.open(local.protocol());
    socket_.bind(local);   // throws boost::system::system_error with the reason (e.g. address in use)
    // A large receive buffer rides out bursts of messages while the control thread is busy.
    boost::system::error_code ignored;
    socket_.set_option(boost::asio::socket_base::receive_buffer_size(1 << 20), ignored);
    socket_.non_blocking(true);   // for draining what is already queued (receive); async operations are unaffected
    receive();
}

void UdpEndpoint::receive() {
    socket_.async_receive_from(boost::asio::buffer(buffer_), sender_, [this](const boost::system::error_code& ec, std::size_t size) {
        if (ec == boost::asio::error::operation_aborted) return;
        if (!ec) {
            receiver_(buffer_.data(), size, sender_);
            // Under a flood the datagrams already queued are read here, up to a bound so timers still run,
            // rather than each taking a trip through the event loop (a queued handler per datagram).
            for (int more = 0; more < 256 && socket_.is_open(); ++more) {
                boost::system::error_code again;
                const std::size_t n = socket_.receive_from(boost::asio::buffer(buffer_), sender_, 0, again);
                if (again) break;   // would block: nothing more waiting
                receiver_(buffer_.data(), n, sender_);
            }
        }
        if (socket_.is_open()) receive();
    });
}

void UdpEndpoint::send(const std::vector<unsigned char>& bytes, const Endpoint& to) {
    boost::system::error_code ignored;   // a client that went away is not the server's problem
    socket_.send_to(boost::asio::buffer(bytes), to, 0, ignored);
}

void UdpEndpoint::close() {
    boost::system::error_code ignored;
    socket_.close(ignored);
}

}  // namespace ameoto
