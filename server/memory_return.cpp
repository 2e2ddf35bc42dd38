#include "server/memory_return.hpp"

#include <malloc.h>

#include <cstdlib>
#include <cstring>

namespace ameoto {

void use_one_heap() {
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    if (std::getenv("MALLOC_ARENA_MAX") != nullptr || (tunables != nullptr && std::strstr(tunables, "arena_max") != nullptr)) return;
    ::mallopt(M_ARENA_MAX, 1);
}

void return_free_memory() { ::malloc_trim(0); }

}  // namespace ameoto
