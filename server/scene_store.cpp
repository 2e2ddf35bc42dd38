// SPDX-License-Identifier: GPL-3.0-or-later
#include "server/scene_store.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace ameoto {

namespace {

std::string os_error(const std::string& what, const std::filesystem::path& path) {
    return what + " " + path.string() + ": " + std::strerror(errno);
}

struct Fd {
    int fd = -1;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

}  // namespace

std::filesystem::path SceneStore::default_folder() {
    if (const char* xdg = std::getenv("XDG_DATA_HOME"); xdg && xdg[0] == '/') return std::filesystem::path(xdg) / "ameoto" / "scenes";
    if (const char* home = std::getenv("HOME"); home && home[0] == '/')
        return std::filesystem::path(home) / ".local" / "share" / "ameoto" / "scenes";
    return std::filesystem::path("scenes");
}

std::filesystem::path SceneStore::path_of(const std::string& name) const {
    if (!is_scene_name(name)) throw std::runtime_error("scene name '" + name + "' is not 1-32 of A-Z a-z 0-9 - _");
    return folder_ / (name + ".scene");
}

namespace {

// An open scene file: a regular file of at most 64 KiB, read whole and parsed under its path's name.
SceneDescription read_open_file(const Fd& f, const std::filesystem::path& path) {
    struct stat st {};
    if (::fstat(f.fd, &st) != 0) throw std::runtime_error(os_error("cannot stat", path));
    if (!S_ISREG(st.st_mode)) throw std::runtime_error(path.string() + " is not a regular file");
    if (st.st_size > static_cast<off_t>(max_scene_file_bytes))
        throw SceneFileError(path.string(), 0, "", "file of " + std::to_string(st.st_size) + " bytes is larger than 64 KiB");
    std::string text(static_cast<std::size_t>(st.st_size), '\0');
    std::size_t got = 0;
    while (got < text.size()) {
        const ssize_t n = ::read(f.fd, text.data() + got, text.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw std::runtime_error(os_error("cannot read", path));
        if (n == 0) break;
        got += static_cast<std::size_t>(n);
    }
    text.resize(got);
    return parse_scene(text, path.string());
}

}  // namespace

SceneDescription SceneStore::load(const std::string& name) const {
    if (auto built_in = builtin_scene(name)) return *built_in;
    const std::filesystem::path path = path_of(name);
    Fd f;
    f.fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (f.fd < 0) {
        if (errno == ENOENT) throw std::runtime_error("no scene named '" + name + "' (built in: umbrella, pond, tin-roof, forest, street; none in " + folder_.string() + ")");
        if (errno == ELOOP) throw std::runtime_error(path.string() + " is a link: scenes are read only from the folder itself");
        throw std::runtime_error(os_error("cannot open", path));
    }
    return read_open_file(f, path);
}

SceneDescription SceneStore::read_file(const std::filesystem::path& path) {
    Fd f;
    f.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);   // a FIFO is refused below, not waited on
    if (f.fd < 0) throw std::runtime_error(os_error("cannot open", path));
    return read_open_file(f, path);
}

void SceneStore::save(const std::string& name, const SceneDescription& scene) const {
    const std::filesystem::path path = path_of(name);
    if (const std::string why = validate_scene(scene); !why.empty()) throw std::runtime_error("the scene is not valid: " + why);
    std::error_code ec;
    std::filesystem::create_directories(folder_, ec);
    if (ec) throw std::runtime_error("cannot create the scene folder " + folder_.string() + ": " + ec.message());
    const std::string text = format_scene(scene);
    // A fresh temporary name in the same folder (so the rename is atomic on the same file system).
    std::filesystem::path temporary;
    Fd f;
    for (int attempt = 0; attempt < 100 && f.fd < 0; ++attempt) {
        temporary = folder_ / ("." + name + ".scene.tmp" + std::to_string(::getpid()) + "-" + std::to_string(attempt));
        f.fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (f.fd < 0 && errno != EEXIST) throw std::runtime_error(os_error("cannot create", temporary));
    }
    if (f.fd < 0) throw std::runtime_error("cannot create a temporary file in " + folder_.string());
    auto abandon = [&](const std::string& why) {
        ::unlink(temporary.c_str());
        throw std::runtime_error(why);
    };
    std::size_t written = 0;
    while (written < text.size()) {
        const ssize_t n = ::write(f.fd, text.data() + written, text.size() - written);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) abandon(os_error("cannot write", temporary));
        written += static_cast<std::size_t>(n);
    }
    if (::fsync(f.fd) != 0) abandon(os_error("cannot sync", temporary));
    if (::close(f.fd) != 0) {
        f.fd = -1;
        abandon(os_error("cannot close", temporary));
    }
    f.fd = -1;
    if (::rename(temporary.c_str(), path.c_str()) != 0) abandon(os_error("cannot rename into", path));
    Fd dir;
    dir.fd = ::open(folder_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir.fd >= 0) ::fsync(dir.fd);   // the rename itself durable
}

}  // namespace ameoto
