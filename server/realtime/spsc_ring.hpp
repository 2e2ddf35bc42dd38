// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A fixed-capacity single-producer single-consumer ring of samples with bulk write and read, for
// audio leaving the render thread (to the WAV writer). Same memory-ordering scheme as SpscQueue.
//
// Interface:
//   SpscRing<float> ring(frames * channels);   // allocates once
//   producer: ring.write_available(); ring.write(data, n)   // all or nothing; false when no room
//   consumer: std::size_t got = ring.read(out, max);         // up to max, 0 when empty

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace ameoto {

template <typename T>
class SpscRing {
    static_assert(std::is_trivially_copyable_v<T>);

public:
    explicit SpscRing(std::size_t capacity) : buffer_(capacity + 1) {}

    std::size_t capacity() const { return buffer_.size() - 1; }

    std::size_t write_available() const {
        const std::size_t w = write_.load(std::memory_order_relaxed);
        const std::size_t r = read_.load(std::memory_order_acquire);
        return (r + buffer_.size() - w - 1) % buffer_.size();
    }

    bool write(const T* data, std::size_t n) {
        if (n > write_available()) return false;
        const std::size_t w = write_.load(std::memory_order_relaxed);
        const std::size_t first = std::min(n, buffer_.size() - w);
        std::copy(data, data + first, buffer_.begin() + static_cast<std::ptrdiff_t>(w));
        std::copy(data + first, data + n, buffer_.begin());
        write_.store((w + n) % buffer_.size(), std::memory_order_release);
        return true;
    }

    std::size_t read(T* out, std::size_t max) {
        const std::size_t r = read_.load(std::memory_order_relaxed);
        const std::size_t w = write_.load(std::memory_order_acquire);
        const std::size_t available = (w + buffer_.size() - r) % buffer_.size();
        const std::size_t n = std::min(max, available);
        const std::size_t first = std::min(n, buffer_.size() - r);
        std::copy(buffer_.begin() + static_cast<std::ptrdiff_t>(r), buffer_.begin() + static_cast<std::ptrdiff_t>(r + first), out);
        std::copy(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(n - first), out + first);
        read_.store((r + n) % buffer_.size(), std::memory_order_release);
        return n;
    }

private:
    std::vector<T> buffer_;
    alignas(64) std::atomic<std::size_t> write_{0};
    alignas(64) std::atomic<std::size_t> read_{0};
};

}  // namespace ameoto
