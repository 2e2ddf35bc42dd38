// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The fuzz entry: one datagram's bytes through the daemon's receive path (protocol/receive.hpp:
// decode, validate), the replies it would send, and the scene changes it would make, with the
// invariants that must hold for any input. A broken invariant aborts (libFuzzer and the replay both
// report it as a crash).
//
// Interface:
//   extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);   // always 0
//
// Built twice: with clang and -fsanitize=fuzzer (tests/fuzz/run-fuzz, not CI), and with the normal
// build into fuzz_replay (tests/fuzz/replay_main.cpp), which CI runs over the corpus and the crashes.

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
