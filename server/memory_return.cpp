#include "server/memory_return.hpp"

#include <malloc.h>

namespace ameoto {

void return_free_memory() { ::malloc_trim(0); }

}  // namespace ameoto
