#include "clients/ameoto/udp_client.hpp"

#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace ameoto::client {
namespace {

struct AddressList {
    addrinfo* head = nullptr;
    ~AddressList() {
        if (head) freeaddrinfo(head);
    }
};

}  // namespace

std::unique_ptr<UdpClient> UdpClient::open(const Target& target, std::string& error) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_DGRAM;
    hints.ai_protocol = IPPROTO_UDP;
    AddressList list;
    const std::string port = std::to_string(target.port);
    if (const int rc = getaddrinfo(target.host.c_str(), port.c_str(), &hints, &list.head); rc != 0) {
        error = "cannot resolve host '" + target.host + "': " + gai_strerror(rc);
        return nullptr;
    }
    const addrinfo* chosen = list.head;
    for (const addrinfo* a = list.head; a; a = a->ai_next) {
        if (a->ai_family == AF_INET) {
            chosen = a;
            break;
        }
    }
    const int fd = ::socket(chosen->ai_family, chosen->ai_socktype | SOCK_CLOEXEC, chosen->ai_protocol);
    if (fd < 0) {
        error = std::string("cannot open a UDP socket: ") + std::strerror(errno);
        return nullptr;
    }
    if (::connect(fd, chosen->ai_addr, chosen->ai_addrlen) != 0) {
        error = "cannot reach " + target.describe() + ": " + std::strerror(errno);
        ::close(fd);
        return nullptr;
    }
    return std::unique_ptr<UdpClient>(new UdpClient(fd));
}

UdpClient::~UdpClient() { ::close(fd_); }

bool UdpClient::send(const std::vector<unsigned char>& bytes, std::string& error) {
    ssize_t sent = -1;
    do {
        sent = ::send(fd_, bytes.data(), bytes.size(), 0);
    } while (sent < 0 && errno == EINTR);
    if (sent < 0) {
        error = std::strerror(errno);
        return false;
    }
    if (static_cast<std::size_t>(sent) != bytes.size()) {
        error = "only " + std::to_string(sent) + " of " + std::to_string(bytes.size()) + " bytes went out";
        return false;
    }
    return true;
}

Received UdpClient::receive(Deadline deadline) {
    Received r;
    for (;;) {
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) {
            r.outcome = Received::Outcome::timeout;
            return r;
        }
        pollfd p{fd_, POLLIN, 0};
        const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 60'000)));
        if (ready < 0 && errno == EINTR) continue;
        if (ready < 0) {
            r.outcome = Received::Outcome::error;
            r.error = std::strerror(errno);
            return r;
        }
        if (ready == 0) continue;   // the loop re-checks the deadline
        // POLLERR (a pending ICMP error) also lands here: recv reports it as errno.
        r.bytes.resize(65536);
        const ssize_t n = ::recv(fd_, r.bytes.data(), r.bytes.size(), MSG_DONTWAIT);
        if (n >= 0) {
            r.bytes.resize(static_cast<std::size_t>(n));
            r.outcome = Received::Outcome::datagram;
            return r;
        }
        if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) continue;
        r.bytes.clear();
        r.outcome = errno == ECONNREFUSED ? Received::Outcome::refused : Received::Outcome::error;
        r.error = std::strerror(errno);
        return r;
    }
}

}  // namespace ameoto::client
