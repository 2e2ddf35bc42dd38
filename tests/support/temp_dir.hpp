// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Temporary folders for tests.
//
// Interface:
//   TempDir dir("ameoto-units");          // a fresh $TMPDIR/ameoto-units-XXXXXX, or std::runtime_error
//   dir.path() / "ameotod.service"        // std::filesystem::path
//   ~TempDir                              // removes the folder with everything in it
//
//   std::string wav = temp_path("a.wav"); // a path in one folder per test process, created on first
//                                         // use and removed at exit; set AMEOTO_KEEP_TEST_FILES=1 to
//                                         // keep it (its name is printed) and look at a failure's files

#include <stdlib.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace ameoto::test {

// Creates $TMPDIR/PREFIX-XXXXXX with a unique suffix.
inline std::filesystem::path make_temp_dir(const std::string& prefix) {
    std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp " + pattern + ": " + std::strerror(errno));
    return pattern;
}

class TempDir {
public:
    explicit TempDir(const std::string& prefix = "ameoto-test") : path_(make_temp_dir(prefix)) {}
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

inline std::string temp_path(const std::string& name) {
    struct ProcessDir {
        std::filesystem::path path = make_temp_dir("ameoto-test");
        ~ProcessDir() {
            if (std::getenv("AMEOTO_KEEP_TEST_FILES")) {
                std::fprintf(stderr, "test files kept in %s\n", path.c_str());
                return;
            }
            std::error_code ec;
            std::filesystem::remove_all(path, ec);
        }
    };
    static const ProcessDir dir;
    return (dir.path / name).string();
}

}  // namespace ameoto::test
