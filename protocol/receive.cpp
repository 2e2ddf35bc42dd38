#include "protocol/receive.hpp"

namespace ameoto::protocol {

std::string packet_address(const unsigned char* data, std::size_t size) {
    if (size >= 8 && std::string(reinterpret_cast<const char*>(data), 7) == "#bundle") return "#bundle";
    std::string address;
    for (std::size_t i = 0; i < size && i < 64 && data[i] != 0; ++i) address += static_cast<char>(data[i]);
    return address.empty() || address[0] != '/' ? std::string("") : address;
}

ReceivedPacket receive_packet(const void* data, std::size_t size, const ProtocolContext& context) {
    ReceivedPacket out;
    DecodedPacket packet = decode_packet(data, size);
    if (!packet.error.empty()) {
        out.fail_address = packet_address(static_cast<const unsigned char*>(data), size);
        out.fail_reason = std::move(packet.error);
        return out;
    }
    out.messages.reserve(packet.messages.size());
    for (auto& message : packet.messages) {
        Validation v = validate(message, context);
        out.messages.push_back({std::move(message), std::move(v)});
    }
    return out;
}

}  // namespace ameoto::protocol
