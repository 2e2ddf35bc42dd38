// SPDX-License-Identifier: GPL-3.0-or-later
// The scene folder (server/scene_store.hpp): built-ins first, files by name only, atomic saves.
#include "server/scene_store.hpp"

#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "tests/support/temp_dir.hpp"

using ameoto::SceneDescription;
using ameoto::SceneStore;

namespace {
std::string error_of(const SceneStore& store, const std::string& name) {
    try {
        store.load(name);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}
std::string file_error_of(const std::filesystem::path& path) {
    try {
        SceneStore::read_file(path);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST_CASE("scene store: built-ins, then NAME.scene; a save reads back the same scene") {
    ameoto::test::TempDir dir("ameoto-scenes");
    const SceneStore store(dir.path() / "scenes");   // created on the first save
    CHECK(store.load("pond").name == "pond");
    CHECK(error_of(store, "mine").find("no scene named 'mine'") != std::string::npos);
    SceneDescription s = *ameoto::builtin_scene("street");
    s.name = "mine";
    s.rain.rate_mm_per_h = 33.0;
    store.save("mine", s);
    CHECK(std::filesystem::is_regular_file(dir.path() / "scenes" / "mine.scene"));
    CHECK(store.load("mine") == s);
    // Saving again replaces it whole; no temporary file is left behind.
    s.rain.rate_mm_per_h = 44.0;
    store.save("mine", s);
    CHECK(store.load("mine").rain.rate_mm_per_h == 44.0);
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path() / "scenes")) {
        (void)entry;
        ++files;
    }
    CHECK(files == 1);
}

TEST_CASE("scene store: names are not paths; links and junk are refused with the file and line") {
    ameoto::test::TempDir dir("ameoto-scenes");
    const SceneStore store(dir.path());
    for (const char* bad : {"../etc/passwd", "/etc/passwd", "a/b", "..", "x.scene"}) {
        CAPTURE(bad);
        CHECK(error_of(store, bad).find("is not 1-32 of") != std::string::npos);
        CHECK_THROWS(store.save(bad, *ameoto::builtin_scene("pond")));
    }
    // A link in the folder, even to a valid scene elsewhere, is not followed.
    const auto outside = dir.path() / "outside.txt";
    std::ofstream(outside) << "ameoto-scene 1\nname outside\n";
    std::filesystem::create_symlink(outside, dir.path() / "linked.scene");
    CHECK(error_of(store, "linked").find("is a link") != std::string::npos);
    // A malformed file: its path, line and key.
    std::ofstream(dir.path() / "broken.scene") << "ameoto-scene 1\n# fine\nrain rate=fast\n";
    CHECK(error_of(store, "broken") == (dir.path() / "broken.scene").string() + ":3: rate: 'fast' is not a number");
    std::ofstream(dir.path() / "newer.scene") << "ameoto-scene 7\n";
    CHECK(error_of(store, "newer").find("needs a newer ameoto") != std::string::npos);
    // A huge file is refused before it is read.
    std::ofstream(dir.path() / "huge.scene") << std::string(100000, '#');
    CHECK(error_of(store, "huge").find("larger than 64 KiB") != std::string::npos);
    std::filesystem::create_directory(dir.path() / "folder.scene");
    CHECK(error_of(store, "folder").find("not a regular file") != std::string::npos);
}

TEST_CASE("scene store: a save that cannot finish leaves the old file whole") {
    ameoto::test::TempDir dir("ameoto-scenes");
    const SceneStore store(dir.path());
    SceneDescription s = *ameoto::builtin_scene("forest");
    s.name = "keep";
    store.save("keep", s);
    // A stale temporary file from a crashed save changes nothing: loads read the real file, and the
    // next save picks a fresh temporary name (O_EXCL) and still replaces the file atomically.
    std::ofstream(dir.path() / (".keep.scene.tmp" + std::to_string(::getpid()) + "-0")) << "ameoto-scene 1\nrain rate=1";
    CHECK(store.load("keep") == s);
    s.rain.rate_mm_per_h = 12.0;
    store.save("keep", s);
    CHECK(store.load("keep").rain.rate_mm_per_h == 12.0);
    // An invalid scene is refused before anything is written.
    SceneDescription bad = s;
    bad.rain.rate_mm_per_h = -5.0;
    CHECK_THROWS(store.save("keep", bad));
    CHECK(store.load("keep").rain.rate_mm_per_h == 12.0);
}

TEST_CASE("scene store: a save never writes through a link, at the scene's name or at the temporary name") {
    ameoto::test::TempDir dir("ameoto-scenes");
    ameoto::test::TempDir elsewhere("ameoto-outside");
    const SceneStore store(dir.path());
    const auto read = [](const std::filesystem::path& p) {
        std::ifstream in(p);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    const auto victim = elsewhere.path() / "victim.txt";
    std::ofstream(victim) << "not a scene\n";
    // NAME.scene is a link out of the folder: the save replaces the link with the scene (rename does
    // not follow links); the file it pointed at is untouched.
    std::filesystem::create_symlink(victim, dir.path() / "out.scene");
    SceneDescription s = *ameoto::builtin_scene("street");
    s.name = "out";
    store.save("out", s);
    CHECK(read(victim) == "not a scene\n");
    CHECK_FALSE(std::filesystem::is_symlink(dir.path() / "out.scene"));
    CHECK(store.load("out") == s);
    // A link planted at the temporary name the save tries first: O_EXCL|O_NOFOLLOW refuses it and the
    // save takes the next name.
    std::filesystem::create_symlink(victim, dir.path() / (".planted.scene.tmp" + std::to_string(::getpid()) + "-0"));
    s.name = "planted";
    store.save("planted", s);
    CHECK(read(victim) == "not a scene\n");
    CHECK(store.load("planted") == s);
    // Names that are not names: empty, too long, with a NUL in them.
    for (const std::string& bad : {std::string(), std::string(33, 'a'), std::string("a\0b", 3), std::string("a\nb")}) {
        // (what() is a C string: a NUL in the name ends the message there)
        CHECK(error_of(store, bad).rfind("scene name '", 0) == 0);
        CHECK_THROWS(store.save(bad, s));
    }
    // Nothing was written outside the folder.
    CHECK(std::distance(std::filesystem::directory_iterator(elsewhere.path()), {}) == 1);
}

TEST_CASE("scene store: read_file takes a path (ameotod's --scene FILE.scene), links included; errors name the file, line and key") {
    ameoto::test::TempDir dir("ameoto-scene-file");
    const auto path = dir.path() / "elsewhere" / "my.scene";
    std::filesystem::create_directories(path.parent_path());
    SceneDescription s = *ameoto::builtin_scene("forest");
    s.name = "from-a-file";
    s.rain.rate_mm_per_h = 7.5;
    std::ofstream(path) << ameoto::format_scene(s);
    CHECK(SceneStore::read_file(path) == s);
    // The command line is trusted: a link is followed (a folder's NAME.scene never is).
    std::filesystem::create_symlink(path, dir.path() / "linked.scene");
    CHECK(SceneStore::read_file(dir.path() / "linked.scene") == s);
    // Malformed: the file, the line and the key, as SceneFileError carries them.
    const auto broken = dir.path() / "broken.scene";
    std::ofstream(broken) << "ameoto-scene 1\nname fine\nrain rate=900\n";
    try {
        SceneStore::read_file(broken);
        FAIL("a malformed file was read");
    } catch (const ameoto::SceneFileError& e) {
        CHECK(e.file() == broken.string());
        CHECK(e.line() == 3);
        CHECK(e.field() == "rate");
        CHECK(std::string(e.what()) == broken.string() + ":3: rate: 900 mm/h is outside 0..500");
    }
    // Missing, a folder, a FIFO (refused, not waited on), too large.
    CHECK(file_error_of(dir.path() / "nowhere.scene") == "cannot open " + (dir.path() / "nowhere.scene").string() + ": No such file or directory");
    std::filesystem::create_directory(dir.path() / "folder.scene");
    CHECK(file_error_of(dir.path() / "folder.scene").find("not a regular file") != std::string::npos);
    REQUIRE(::mkfifo((dir.path() / "pipe.scene").c_str(), 0600) == 0);
    CHECK(file_error_of(dir.path() / "pipe.scene").find("not a regular file") != std::string::npos);
    std::ofstream(dir.path() / "huge.scene") << std::string(100000, '#');
    CHECK(file_error_of(dir.path() / "huge.scene").find("larger than 64 KiB") != std::string::npos);
}
