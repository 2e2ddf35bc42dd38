// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A fixed-capacity, wait-free, single-producer single-consumer queue (after rigtorp's SPSCQueue).
//
// Interface:
//   SpscQueue<Command> q(1024);     // allocates capacity + 1 slots once, here and never again
//   producer thread: bool ok = q.try_push(value);   // false when full; never blocks or allocates
//   consumer thread: bool ok = q.try_pop(value);    // false when empty; never blocks or allocates
//   q.capacity(); q.size_approx();
//
// Exactly one thread pushes and exactly one pops. The write index is published with release and read
// with acquire, so a popped value is fully written. Each side caches the other's index and re-reads it
// only when the cache says full or empty, and the indices sit on separate cache lines, so the two
// threads do not share a written line in the common case. One slot is kept empty to tell full from
// empty without a counter. T must be trivially copyable: a slot is overwritten by assignment and never
// destroyed on the hot path.

#include <atomic>
#include <cstddef>
#include <new>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace ameoto {

template <typename T>
class SpscQueue {
    static_assert(std::is_trivially_copyable_v<T>, "SpscQueue carries plain data only");

public:
    explicit SpscQueue(std::size_t capacity) : slots_(capacity + 1) {
        if (capacity < 1) throw std::invalid_argument("SpscQueue capacity must be at least 1");
    }
    SpscQueue(const SpscQueue&) = delete;
    SpscQueue& operator=(const SpscQueue&) = delete;

    bool try_push(const T& value) noexcept {
        const std::size_t write = write_.load(std::memory_order_relaxed);
        std::size_t next = write + 1;
        if (next == slots_.size()) next = 0;
        if (next == read_cache_) {
            read_cache_ = read_.load(std::memory_order_acquire);
            if (next == read_cache_) return false;
        }
        slots_[write] = value;
        write_.store(next, std::memory_order_release);
        return true;
    }

    bool try_pop(T& value) noexcept {
        const std::size_t read = read_.load(std::memory_order_relaxed);
        if (read == write_cache_) {
            write_cache_ = write_.load(std::memory_order_acquire);
            if (read == write_cache_) return false;
        }
        value = slots_[read];
        std::size_t next = read + 1;
        if (next == slots_.size()) next = 0;
        read_.store(next, std::memory_order_release);
        return true;
    }

    std::size_t capacity() const noexcept { return slots_.size() - 1; }

    // Exact when called from either end with the other end idle; otherwise a snapshot.
    std::size_t size_approx() const noexcept {
        const std::size_t write = write_.load(std::memory_order_acquire);
        const std::size_t read = read_.load(std::memory_order_acquire);
        return write >= read ? write - read : write + slots_.size() - read;
    }

private:
    static constexpr std::size_t line = 64;
    std::vector<T> slots_;
    alignas(line) std::atomic<std::size_t> write_{0};
    alignas(line) std::size_t read_cache_ = 0;      // producer's copy of read_
    alignas(line) std::atomic<std::size_t> read_{0};
    alignas(line) std::size_t write_cache_ = 0;     // consumer's copy of write_
    static_assert(std::atomic<std::size_t>::is_always_lock_free);
};

}  // namespace ameoto
