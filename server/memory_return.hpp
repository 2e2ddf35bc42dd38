#pragma once
// Gives the heap's free pages back to the kernel after a scene has been freed (off the audio thread).
//
// Interface:
//   return_free_memory();   // control thread, after deleting a retired scene; a few ms at most
//
// Why: a scene is tens of MB in many small blocks (every pooled drop's Body3D holds a dozen vectors;
// DropPool reserves them all up front). glibc keeps freed small blocks in its arenas for reuse, and the
// worker thread that builds scenes and the main thread that built the first one allocate from different
// arenas, so every /scene/load left RSS higher though nothing leaked (heaptrack: 5 KB leaked, stdio's
// buffers, over 10 loads; RSS 29 MB -> 165 MB). malloc_trim(0) releases the free pages inside every
// arena (madvise MADV_DONTNEED), so RSS follows what the server really holds: the figure an
// operator (and the soak test, tests/bench/soak) watches for leaks. The audio thread never allocates or
// frees, and the pages of the live scene are not free, so it is not affected.

namespace ameoto {

void return_free_memory();

}  // namespace ameoto
