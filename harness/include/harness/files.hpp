// files.hpp: writing an output file so that it is either whole or absent.
//
// Implements: write_file_atomically, which writes beside the destination (a hidden
// ".NAME.partial-PID" file in the same directory), flushes, and renames over the destination,
// so a crash, a kill or a full disk never leaves a half-written file under the real name.
//
// Deliberately does not: fsync the directory (a power cut may lose the new file, never tear
// it), or write images (image_io.hpp renames the same way through OpenImageIO).
#pragma once

#include <filesystem>
#include <string_view>

namespace harness {

// Throws std::runtime_error naming the file when it cannot be written; the destination is
// then left as it was.
void write_file_atomically(const std::filesystem::path& path, std::string_view text);

}  // namespace harness
