// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/osc/datagram_backlog.hpp"

#include <algorithm>
#include <cstring>

namespace ameoto {

DatagramBacklog::DatagramBacklog(std::size_t max_datagrams, std::size_t max_bytes)
    : entries_(max_datagrams), storage_(max_bytes, 0), spans_(max_datagrams, 0) {
    // Every page is written once here (the zeros above), so the resident size does not grow later
    // when a flood first fills the ring.
}

bool DatagramBacklog::push(const unsigned char* data, std::size_t size, const Peer& sender) {
    if (count_ == entries_.size() || size == 0) return false;
    std::size_t at = write_;
    std::size_t span = size;
    const bool wraps = write_ + size > storage_.size();
    if (count_ == 0) {
        // Empty: start at the beginning, the whole ring is free.
        if (size > storage_.size()) return false;
        read_ = write_ = at = 0;
        used_bytes_ = 0;
    } else if (write_ > read_) {
        // Not wrapped (the held bytes are [read_, write_)): free space is [write_, end) and [0, read_).
        if (wraps) {
            if (size > read_) return false;
            span = storage_.size() - write_ + size;   // the skipped end belongs to this entry
            at = 0;
        }
    } else if (write_ + size > read_) {
        return false;   // wrapped (write_ == read_: full): free space is [write_, read_) only
    }
    std::memcpy(storage_.data() + at, data, size);
    const std::size_t tail = (head_ + count_) % entries_.size();
    entries_[tail] = Waiting{storage_.data() + at, size, sender};
    spans_[tail] = span;
    write_ = at + size;
    used_bytes_ += span;
    ++count_;
    return true;
}

void DatagramBacklog::pop() {
    if (count_ == 0) return;
    used_bytes_ -= spans_[head_];
    read_ = static_cast<std::size_t>(entries_[head_].data - storage_.data()) + entries_[head_].size;
    head_ = (head_ + 1) % entries_.size();
    if (--count_ == 0) read_ = write_ = used_bytes_ = 0;
}

bool DatagramBacklog::holds_from(const Peer& sender) const {
    for (std::size_t i = 0; i < count_; ++i)
        if (entries_[(head_ + i) % entries_.size()].sender == sender) return true;
    return false;
}

}  // namespace ameoto
