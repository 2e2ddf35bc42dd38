// SPDX-License-Identifier: GPL-3.0-or-later
// heap_probe one|default: starts 4 threads that allocate at once, then prints how many heaps (arenas)
// glibc's malloc keeps, read from malloc_info's XML. With "one" it first calls use_one_heap(), as
// ameotod's main() does. Run by tests/server/memory_return_test.cpp in a process of its own: the
// arenas a process has depend on every thread that ever allocated in it.
// heap_probe cache|no-cache: frees five 24-byte blocks and prints how many of them glibc put in its
// fast bins (mallinfo2's smblks) rather than in the thread's cache, which takes up to 7 of a size
// (tcache_count). With "no-cache" it first calls run_without_thread_caches(argv), as ameotod's main()
// does: that executes the probe again with the cache off, so all five land in the fast bins.
// heap_probe no-cache-heaps: run_without_thread_caches(argv), then the heap count as for "default":
// shows that tunables already in GLIBC_TUNABLES (glibc.malloc.arena_max) survive the second execution.
#include <malloc.h>
#include <stdio.h>

#include <cstdlib>
#include <cstring>
#include <latch>
#include <string>
#include <thread>
#include <vector>

#include "server/memory_return.hpp"

int main(int argc, char** argv) {
    const std::string mode = argc == 2 ? argv[1] : "";
    const bool cache_mode = mode == "cache" || mode == "no-cache";
    if (mode != "one" && mode != "default" && mode != "no-cache-heaps" && !cache_mode) {
        std::fprintf(stderr, "usage: heap_probe one|default|no-cache-heaps|cache|no-cache\n");
        return 2;
    }
    if (mode == "no-cache" || mode == "no-cache-heaps") ameoto::run_without_thread_caches(argv);
    if (cache_mode) {
        void* blocks[5];
        const std::size_t fast_before = mallinfo2().smblks;
        for (auto*& b : blocks) b = std::malloc(24);
        for (auto* b : blocks) std::free(b);
        const std::size_t fast_after = mallinfo2().smblks;
        std::printf("%zu\n", fast_after - fast_before);
        return 0;
    }
    if (mode == "one") ameoto::use_one_heap();
    // All four alive at once (a thread that ends hands its arena on to the next one started).
    std::latch all_allocated(4);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&all_allocated] {
            std::vector<std::string> kept;
            for (int i = 0; i < 1000; ++i) kept.emplace_back(200, 'x');
            all_allocated.arrive_and_wait();
        });
    for (auto& t : threads) t.join();
    char* text = nullptr;
    std::size_t size = 0;
    FILE* out = open_memstream(&text, &size);
    if (out == nullptr || malloc_info(0, out) != 0) return 1;
    std::fclose(out);
    int heaps = 0;
    for (const char* at = text; (at = std::strstr(at, "<heap nr=")) != nullptr; at += 9) ++heaps;
    std::free(text);
    std::printf("%d\n", heaps);
    return 0;
}
