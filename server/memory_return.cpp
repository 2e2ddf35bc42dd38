// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/memory_return.hpp"

#include <malloc.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

// AddressSanitizer replaces malloc, so glibc's thread cache is not in use: nothing to turn off. g++
// defines __SANITIZE_ADDRESS__ with -fsanitize=address; clang 14 only answers __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define AMEOTO_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define AMEOTO_ADDRESS_SANITIZER 1
#endif
#endif

namespace ameoto {

void run_without_thread_caches(char** argv) {
#if defined(AMEOTO_ADDRESS_SANITIZER)
    (void)argv;
#else
    const char* found = std::getenv("GLIBC_TUNABLES");
    const bool had = found != nullptr;
    const std::string before = had ? found : "";
    if (before.find("glibc.malloc.tcache_count") != std::string::npos) return;
    const std::string value = (before.empty() ? "" : before + ":") + "glibc.malloc.tcache_count=0";
    if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
    execv("/proc/self/exe", argv);
    // Still here: the exec failed (no /proc, say). Carry on with the cache, and leave the
    // environment as it was for the programs this one may start.
    if (had) setenv("GLIBC_TUNABLES", before.c_str(), 1);
    else unsetenv("GLIBC_TUNABLES");
#endif
}

void use_one_heap() {
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    if (std::getenv("MALLOC_ARENA_MAX") != nullptr || (tunables != nullptr && std::strstr(tunables, "arena_max") != nullptr)) return;
    ::mallopt(M_ARENA_MAX, 1);
}

void return_free_memory() { ::malloc_trim(0); }

}  // namespace ameoto
