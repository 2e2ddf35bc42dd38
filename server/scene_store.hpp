// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Where scenes come from and go: the built-in ones, and the user's scene folder.
//
// Interface:
//   SceneStore store(SceneStore::default_folder());   // $XDG_DATA_HOME/ameoto/scenes or ~/.local/share/...
//   SceneDescription s = store.load("pond");           // built in first, then FOLDER/NAME.scene; throws
//                                                      // SceneFileError (file, line, field) or std::runtime_error
//   store.save("my-rain", s);                          // atomically; throws std::runtime_error with the reason
//   store.path_of("my-rain")                           // FOLDER/my-rain.scene
//   SceneDescription s = SceneStore::read_file("x/my.scene");   // any path (ameotod's --scene FILE.scene);
//                                                      // throws like load
//
// Names are names (scene_description.hpp's is_scene_name: 1-32 of A-Z a-z 0-9 - _), checked here again,
// so nothing is read or written outside the folder. A file is opened with O_NOFOLLOW (a link in the
// folder, to anywhere, is refused) and must be a regular file of at most 64 KiB. read_file is for a
// path the user gave on the command line, which is trusted: it follows links, and only the size and
// regular-file checks apply.
// Saving: written to a new temporary file in the folder (O_EXCL), fsync'd, renamed over NAME.scene, and
// the folder fsync'd: a crash at any point leaves the old file or the new one whole, never a mixture.

#include <filesystem>
#include <string>

#include "engine/scene/scene_description.hpp"

namespace ameoto {

class SceneStore {
public:
    explicit SceneStore(std::filesystem::path folder) : folder_(std::move(folder)) {}
    static std::filesystem::path default_folder();

    SceneDescription load(const std::string& name) const;
    static SceneDescription read_file(const std::filesystem::path& path);
    void save(const std::string& name, const SceneDescription& scene) const;
    std::filesystem::path path_of(const std::string& name) const;
    const std::filesystem::path& folder() const { return folder_; }

private:
    std::filesystem::path folder_;
};

}  // namespace ameoto
