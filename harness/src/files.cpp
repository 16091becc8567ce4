#include "harness/files.hpp"

#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <system_error>

namespace harness {

void write_file_atomically(const std::filesystem::path& path, std::string_view text) {
    const auto tmp = path.parent_path() / ("." + path.filename().string() + ".partial-" + std::to_string(::getpid()));
    {
        std::ofstream o(tmp, std::ios::binary | std::ios::trunc);
        if (!o) throw std::runtime_error(path.string() + ": cannot write");
        o.write(text.data(), static_cast<std::streamsize>(text.size()));
        o.flush();
        if (!o) {
            std::error_code ignored;
            std::filesystem::remove(tmp, ignored);
            throw std::runtime_error(path.string() + ": write failed");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throw std::runtime_error(path.string() + ": cannot write: " + ec.message());
    }
}

}  // namespace harness
