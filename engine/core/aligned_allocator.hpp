// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A std::allocator that aligns every block to Alignment bytes (a cache line: 64), for state arrays whose
// rows are loaded as whole vectors (the laned canopy: an AVX-512 load of a row that straddles two cache
// lines costs two). Build phase only, like any allocation.
//
// Interface:
//   std::vector<double, AlignedAllocator<double, 64>> v(n);   // v.data() % 64 == 0

#include <cstddef>
#include <new>

namespace ameoto {

template <class T, std::size_t Alignment = 64>
struct AlignedAllocator {
    using value_type = T;
    template <class U>
    struct rebind {
        using other = AlignedAllocator<U, Alignment>;
    };
    AlignedAllocator() = default;
    template <class U>
    AlignedAllocator(const AlignedAllocator<U, Alignment>&) {}
    T* allocate(std::size_t n) {
        return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t{Alignment}));
    }
    void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t{Alignment}); }
    template <class U>
    bool operator==(const AlignedAllocator<U, Alignment>&) const { return true; }
};

}  // namespace ameoto
