// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The datagrams a flooded control thread has read but not yet handled, oldest first: bytes copied
// into a fixed ring, so that the kernel's receive queue stays short and a /status behind the flood
// is read (and answered) at once instead of waiting behind everything queued before it
// (docs/reliability.md, "Load").
//
// Interface:
//   DatagramBacklog backlog(max_datagrams, max_bytes);   // all memory allocated and touched here
//   if (!backlog.push(bytes, size, sender)) shed it;     // false when full (datagrams or bytes)
//   while (!backlog.empty()) { const auto& d = backlog.front(); ... d.data, d.size, d.sender; backlog.pop(); }
//   backlog.holds_from(sender)                           // anything of this sender waiting (keeps its order)
//   backlog.size();  backlog.bytes();
//
// Bounded in both count and bytes, and never allocating after construction: memory stays flat
// whatever the flood. A datagram larger than the free space is refused like any other when full.

#include <cstddef>
#include <vector>

#include "server/osc/peer.hpp"

namespace ameoto {

class DatagramBacklog {
public:
    struct Waiting {
        const unsigned char* data;
        std::size_t size;
        Peer sender;
    };

    DatagramBacklog(std::size_t max_datagrams, std::size_t max_bytes);
    bool push(const unsigned char* data, std::size_t size, const Peer& sender);
    const Waiting& front() const { return entries_[head_]; }
    void pop();
    bool empty() const { return count_ == 0; }
    std::size_t size() const { return count_; }
    std::size_t bytes() const { return used_bytes_; }
    std::size_t capacity() const { return entries_.size(); }
    bool holds_from(const Peer& sender) const;

private:
    std::vector<Waiting> entries_;   // a ring: head_ is the oldest, count_ of them
    std::vector<unsigned char> storage_;
    std::size_t head_ = 0, count_ = 0;
    // The bytes are a ring too: the oldest datagram's bytes start at read_, the next one goes at write_
    // (or at 0 when it does not fit before the end); used_bytes_ counts what is held, padding included.
    std::size_t read_ = 0, write_ = 0, used_bytes_ = 0;
    std::vector<std::size_t> spans_;  // per entry: bytes it holds in the ring, skipped end padding included
};

}  // namespace ameoto
