#include "harness/files.hpp"

#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace harness {

void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path& partial)>& write) {
    const auto partial =
        path.parent_path() / ("." + path.stem().string() + ".partial-" +
                              std::to_string(::getpid()) + path.extension().string());
    std::error_code ignored;
    try {
        write(partial);
    } catch (...) {
        std::filesystem::remove(partial, ignored);
        throw;
    }
    std::error_code ec;
    std::filesystem::rename(partial, path, ec);
    if (ec) {
        std::filesystem::remove(partial, ignored);
        throw std::runtime_error(path.string() +
                                 ": cannot move the file into place: " + ec.message());
    }
}

void write_file_atomically(const std::filesystem::path& path, std::string_view text) {
    write_atomically(path, [&](const std::filesystem::path& partial) {
        std::ofstream o(partial, std::ios::binary | std::ios::trunc);
        if (!o) throw std::runtime_error(path.string() + ": cannot write");
        o.write(text.data(), static_cast<std::streamsize>(text.size()));
        o.flush();
        if (!o) throw std::runtime_error(path.string() + ": write failed");
    });
}

}  // namespace harness
