// SPDX-License-Identifier: GPL-3.0-or-later
#include "clients/ameoto/reply_wait.hpp"

namespace ameoto::client {

WaitResult wait_for_replies(UdpClient& client, Deadline deadline,
                            const std::function<bool(const protocol::DecodedMessage&)>& on_message,
                            const std::function<void(const std::string&)>& on_bad_datagram) {
    WaitResult w;
    for (;;) {
        Received r = client.receive(deadline);
        switch (r.outcome) {
            case Received::Outcome::timeout: w.ending = WaitResult::Ending::timed_out; return w;
            case Received::Outcome::refused: w.ending = WaitResult::Ending::refused; return w;
            case Received::Outcome::error:
                w.ending = WaitResult::Ending::error;
                w.error = r.error;
                return w;
            case Received::Outcome::datagram: break;
        }
        const protocol::DecodedPacket packet = protocol::decode_packet(r.bytes.data(), r.bytes.size());
        if (!packet.error.empty()) {
            on_bad_datagram("ignored a reply that does not decode (" + packet.error + ")");
            continue;
        }
        for (const auto& message : packet.messages) {
            if (on_message(message)) {
                w.ending = WaitResult::Ending::stopped;
                return w;
            }
        }
    }
}

}  // namespace ameoto::client
