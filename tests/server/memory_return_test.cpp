// SPDX-License-Identifier: GPL-3.0-or-later
// server/memory_return: ameotod's heap policy, tested in fresh processes (tests/support/heap_probe.cpp),
// since which arenas a process has depends on every thread that ever allocated in it.
#include <doctest/doctest.h>

#include <stdio.h>

#include <string>

#include "tests/support/sanitizer_bounds.hpp"

namespace {

// What the probe printed (its heap count, or its blocks in the fast bins), or -1 when it failed.
int probe(const std::string& mode, const std::string& environment = "") {
    const std::string command = "env -u MALLOC_ARENA_MAX -u GLIBC_TUNABLES " + environment + " " AMEOTO_HEAP_PROBE " " + mode;
    FILE* p = popen(command.c_str(), "r");
    REQUIRE(p != nullptr);
    int heaps = -1;
    if (std::fscanf(p, "%d", &heaps) != 1) heaps = -1;
    CHECK(pclose(p) == 0);
    return heaps;
}

}  // namespace

TEST_CASE("memory_return: use_one_heap keeps every thread on one heap; the environment's own choice rules") {
    // ASan replaces glibc's malloc, so there are no glibc arenas to count.
    if (ameoto::test::stop_here_if_sanitized("glibc's arenas: AddressSanitizer has its own allocator")) return;
    // Without it, glibc gives each new thread an arena of its own (up to 8 per core, so on any
    // machine): the main heap and 4 more.
    CHECK(probe("default") == 5);
    CHECK(probe("one") == 1);
    // An operator's MALLOC_ARENA_MAX is left in force (here 3: the main heap and two more).
    CHECK(probe("one", "MALLOC_ARENA_MAX=3") == 3);
}

TEST_CASE("memory_return: run_without_thread_caches runs the program again with glibc's thread cache off; the environment's own choice rules") {
    if (ameoto::test::stop_here_if_sanitized("glibc's thread cache: AddressSanitizer has its own allocator")) return;
    // Five small blocks freed: by default the thread's cache keeps them all (up to 7 of a size), so
    // none reach the fast bins; run again without the cache, all five do.
    CHECK(probe("cache") == 0);
    CHECK(probe("no-cache") == 5);
    // An operator's tcache_count is left in force (3 in the cache, 2 in the fast bins).
    CHECK(probe("no-cache", "GLIBC_TUNABLES=glibc.malloc.tcache_count=3") == 2);
    // Other tunables are kept beside the one added: the cache is off (all five in the fast bins) and
    // the operator's arena_max=2 still holds after the second execution (2 heaps for 4 threads, where
    // glibc alone gives 5: the first test case).
    CHECK(probe("no-cache", "GLIBC_TUNABLES=glibc.malloc.arena_max=2") == 5);
    CHECK(probe("no-cache-heaps", "GLIBC_TUNABLES=glibc.malloc.arena_max=2") == 2);
    CHECK(probe("no-cache-heaps") == 5);
}
