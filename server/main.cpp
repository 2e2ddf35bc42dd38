// SPDX-License-Identifier: GPL-3.0-or-later
// ameotod: the ameoto rain server. Options: see --help (server/options.cpp).
#include <cstdio>
#include <iostream>

#include "server/daemon.hpp"
#include "server/memory_return.hpp"
#include "server/options.hpp"

int main(int argc, char** argv) {
    ameoto::run_without_thread_caches(argv);   // may execute ameotod again (server/memory_return.hpp)
    ameoto::use_one_heap();                    // before any thread starts
    const ameoto::ParsedOptions parsed = ameoto::parse_options(argc, argv);
    if (parsed.show_help) {
        std::cout << ameoto::usage();
        return 0;
    }
    if (parsed.show_version) {
        std::cout << "ameotod " AMEOTO_VERSION "\n";
        return 0;
    }
    if (!parsed.error.empty()) {
        std::cerr << "ameotod: " << parsed.error << "\n";
        return 2;
    }
    ameoto::Daemon daemon(parsed.options);
    return daemon.run();
}
