// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// How ameotod's heap gives memory back: one heap for every thread, and its free pages returned to the
// kernel after a scene has been freed (both off the audio thread, which never allocates or frees).
//
// Interface:
//   run_without_thread_caches(argv);   // first thing in main(): returns only in the process that runs
//                                      // with glibc's per-thread caches off (see below)
//   use_one_heap();         // next in main(), before any thread starts
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
// (docs/soak.md, "How memory stays flat"). With one heap (mallopt M_ARENA_MAX 1; the audio thread takes no
// part, and the control and worker threads' allocations are few and off the real-time path) the same
// soak read the umbrella's heap at 50.7, 50.1, 50.3 MB a cycle apart. MALLOC_ARENA_MAX or
// GLIBC_TUNABLES in the environment, an operator's own choice, is left to rule.
//
// Why run_without_thread_caches: with one heap the soak's RSS still crept up by about 100 KiB a round
// of five scene loads (1.9 MiB an hour), though the heap in use was the same to the byte at every load
// of a scene. A scene build makes about 89 000 allocations, 60 000 of them short-lived (the lattice
// builders' index maps); glibc's per-thread cache (tcache: up to 7 freed blocks of each small size,
// handed back last in, first out, never merged with their neighbours) placed each build's blocks a
// little differently, leaving more pages with a live block on them. Loading the five scenes back to
// back (tests/bench/scene-cycle, null backend, no traffic), the umbrella's [heap] RSS rose 2.5 MiB in
// 15 rounds by default, 0.5 MiB with the tcache off (glibc.malloc.tcache_count=0), and 2.3 MiB with
// only the fast bins off (M_MXFAST 0); docs/soak.md ("Tried and left out") has the figures. glibc reads that setting only from GLIBC_TUNABLES when a
// process starts (mallopt has no tcache option), so ameotod, unless the environment already names
// glibc.malloc.tcache_count, executes itself again at once with it appended: same PID, arguments and
// environment otherwise, before any thread, file or socket exists. If that exec fails it carries on
// with the cache. The audio thread never allocates, so the cache's speed (tens of ns a call) is lost
// only on the control and worker threads. Skipped under AddressSanitizer, whose allocator is its own.

namespace ameoto {

void run_without_thread_caches(char** argv);
void use_one_heap();
void return_free_memory();

}  // namespace ameoto
