// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Gives each OSC sender a small index, so a command crossing to the audio thread can say whom to
// answer (/synced, /fail busy) without carrying an address.
//
// Interface:
//   ClientTable<Endpoint> clients;
//   std::uint16_t i = clients.index_of(sender);   // finds or adds; the oldest entry is reused when full
//   const Endpoint& to = clients.at(i);
//   clients.size()                                 // senders known, for notices to all of them

#include <cstdint>
#include <vector>

namespace ameoto {

template <typename Endpoint>
class ClientTable {
public:
    static constexpr std::size_t capacity = 4096;

    std::uint16_t index_of(const Endpoint& sender) {
        for (std::size_t i = 0; i < entries_.size(); ++i)
            if (entries_[i] == sender) return static_cast<std::uint16_t>(i);
        if (entries_.size() < capacity) {
            entries_.push_back(sender);
            return static_cast<std::uint16_t>(entries_.size() - 1);
        }
        const std::size_t slot = next_reuse_++ % capacity;
        entries_[slot] = sender;
        return static_cast<std::uint16_t>(slot);
    }

    const Endpoint& at(std::uint16_t index) const { return entries_.at(index); }
    std::size_t size() const { return entries_.size(); }

private:
    std::vector<Endpoint> entries_;
    std::size_t next_reuse_ = 0;
};

}  // namespace ameoto
