#pragma once
// How ameotod's heap gives memory back: one heap for every thread, and its free pages returned to the
// kernel after a scene has been freed (both off the audio thread, which never allocates or frees).
//
// Interface:
//   use_one_heap();         // first thing in main(), before any thread starts
//   return_free_memory();   // control thread, after deleting a retired scene; a few ms at most
//
// Why return_free_memory: a scene is tens of MB in many small blocks (every pooled drop's Body3D holds
// a dozen vectors; DropPool reserves them all up front). glibc keeps freed small blocks in its arenas for
// reuse, so every /scene/load left RSS higher though nothing leaked (heaptrack: 5 KB leaked, stdio's
// buffers, over 10 loads; RSS 29 MB -> 165 MB). malloc_trim(0) releases the free pages inside every
// arena (madvise MADV_DONTNEED), so RSS follows what the server really holds: the figure an operator
// (and the soak test, tests/bench/soak) watches for leaks.
//
// Why use_one_heap: glibc gives threads their own arenas (64 MiB regions) when they contend. Under
// JACK the scenes were built and freed across two of them, and what one arena kept (a scene's blocks
// still live, pages shared with them) moved between them from load to load: at the same point of the
// soak's scene cycle the two held 16-38 and 18-45 MB, so RSS read for one scene varied by tens of MB
// (docs/reliability.md, "Soak"). With one heap (mallopt M_ARENA_MAX 1; the audio thread takes no
// part, and the control and worker threads' allocations are few and off the real-time path) the same
// soak read the umbrella's heap at 50.7, 50.1, 50.3 MB a cycle apart. MALLOC_ARENA_MAX or
// GLIBC_TUNABLES in the environment, an operator's own choice, is left to rule.

namespace ameoto {

void use_one_heap();
void return_free_memory();

}  // namespace ameoto
