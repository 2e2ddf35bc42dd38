// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/open_and_send.hpp"

namespace ameoto::client {

std::unique_ptr<UdpClient> open_and_send(const Target& target, Transport transport, const std::vector<unsigned char>& message,
                                         const CommandIo& io, const std::string& prefix) {
    std::string error;
    auto client = UdpClient::open(target, error, transport);
    if (!client) {
        io.err << prefix << error << "\n";
        return nullptr;
    }
    if (!client->send(message, error)) {
        io.err << prefix << "cannot send to " << target.describe() << ": " << error << "\n";
        return nullptr;
    }
    return client;
}

}  // namespace ameoto::client
