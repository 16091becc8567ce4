// files.hpp: writing an output file so that it is either whole or absent.
//
// Implements: write_atomically, which lets a writer fill a hidden file beside the destination
// (".STEM.partial-PID.EXT" in the same directory, the extension kept so that format-choosing
// writers such as OpenImageIO's still see it) and renames it over the destination only when
// the writer succeeded, so a crash, a kill or a full disk never leaves a half-written file
// under the real name; write_file_atomically, the same for text. Every file the tools write
// (scenes, results, reports, images, profiles, bench JSON) goes through here.
//
// Deliberately does not: fsync the directory (a power cut may lose the new file, never tear
// it).
#pragma once

#include <filesystem>
#include <functional>
#include <string_view>

namespace harness {

// Calls write(partial) and moves `partial` onto `path`. If write throws or the move fails, the
// partial file is removed, the destination is left as it was, and the error propagates
// (std::runtime_error naming `path` for a failed move).
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path& partial)>& write);

// Throws std::runtime_error naming the file when it cannot be written; the destination is
// then left as it was.
void write_file_atomically(const std::filesystem::path& path, std::string_view text);

}  // namespace harness
