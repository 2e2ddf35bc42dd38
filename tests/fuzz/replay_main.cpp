// SPDX-License-Identifier: GPL-3.0-or-later
// fuzz_replay: feeds every file under the given folders (or the given files) to the fuzz entry, once
// each, in the normal build; CI runs it over tests/fuzz/corpus and tests/fuzz/crashes so every input
// that ever broke the receive path stays fixed. An input that breaks an invariant aborts, and ctest
// reports the file it was on (printed before each).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "tests/fuzz/receive_target.hpp"

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    std::vector<fs::path> files;
    for (int i = 1; i < argc; ++i) {
        const fs::path p = argv[i];
        if (fs::is_directory(p)) {
            for (const auto& e : fs::recursive_directory_iterator(p))
                if (e.is_regular_file() && e.path().filename().string()[0] != '.') files.push_back(e.path());
        } else if (fs::is_regular_file(p)) {
            files.push_back(p);
        } else {
            std::fprintf(stderr, "fuzz_replay: no file or folder %s\n", p.c_str());
            return 2;
        }
    }
    std::sort(files.begin(), files.end());
    if (files.empty()) {
        std::fprintf(stderr, "fuzz_replay: no inputs (usage: fuzz_replay FOLDER|FILE...)\n");
        return 2;
    }
    for (const fs::path& f : files) {
        std::fprintf(stderr, "%s\n", f.c_str());
        std::ifstream in(f, std::ios::binary);
        const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
    }
    std::printf("fuzz_replay: %zu inputs replayed, no invariant broken\n", files.size());
    return 0;
}
