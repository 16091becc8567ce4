#include "texture_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <initializer_list>

namespace harness::texture_file {

namespace {

constexpr std::array<std::uint8_t, 8> kPngSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

// The real path of `path` (realpath(3): absolute, every symlink resolved); nullopt when a part
// of it does not exist or cannot be searched.
std::optional<std::string> real_path(const std::filesystem::path& path) {
    char* real = ::realpath(path.c_str(), nullptr);
    if (real == nullptr) return std::nullopt;
    std::string out(real);
    std::free(real);  // NOLINT(cppcoreguidelines-no-malloc): realpath's own allocation
    return out;
}

bool inside_any(const std::string& real, const std::vector<std::string>& roots) {
    return std::any_of(roots.begin(), roots.end(),
                       [&](const std::string& root) { return inside(real, root); });
}

// A file descriptor closed when it goes out of scope.
class Fd {
  public:
    explicit Fd(int fd) : fd_(fd) {}
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() {
        if (fd_ >= 0) ::close(fd_);
    }
    int get() const { return fd_; }

  private:
    int fd_;
};

// Reads exactly `n` bytes at the file's position into `out`; false on an error or a short file.
bool read_exactly(int fd, std::uint8_t* out, std::size_t n) {
    while (n > 0) {
        const ssize_t got = ::read(fd, out, n);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) return false;
        out += got;
        n -= static_cast<std::size_t>(got);
    }
    return true;
}

std::uint32_t u32_be(const std::uint8_t* p) {
    return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
           std::uint32_t{p[3]};
}

}  // namespace

std::vector<std::string> real_roots(const std::vector<std::filesystem::path>& folders) {
    std::vector<std::string> out;
    for (const auto& f : folders) {
        if (auto r = real_path(f.empty() ? std::filesystem::path(".") : f)) {
            out.push_back(std::move(*r));
        }
    }
    return out;
}

bool inside(const std::string& real, const std::string& root) {
    if (root.empty() || real.size() <= root.size()) return false;
    if (real.compare(0, root.size(), root) != 0) return false;
    // "/" ends in the separator; every other real path does not.
    return root.back() == '/' || real[root.size()] == '/';
}

FileBytes read_png_file(const std::filesystem::path& path, const std::vector<std::string>& roots,
                        std::uint64_t max_bytes) {
    FileBytes out;
    // Where the file really is, before anything is opened: nothing outside the roots is opened
    // (opening a device can do something).
    const auto real = real_path(path);
    if (!real || !inside_any(*real, roots)) return out;
    struct stat st {};
    if (::stat(real->c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return out;
    // O_NONBLOCK: a FIFO put in the file's place since would not block the open. O_NOFOLLOW: the
    // last part is no symlink (the real path has none).
    const Fd fd(::open(real->c_str(), O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY));
    if (fd.get() < 0) return out;
    if (::fstat(fd.get(), &st) != 0 || !S_ISREG(st.st_mode)) return out;
    // The file opened is the one the kernel names: a folder of the path replaced by a symlink
    // between realpath and open cannot lead outside the roots. Without /proc the check before
    // opening stands alone.
    std::array<char, PATH_MAX> opened{};
    const std::string link = "/proc/self/fd/" + std::to_string(fd.get());
    const ssize_t n = ::readlink(link.c_str(), opened.data(), opened.size());
    if (n >= static_cast<ssize_t>(opened.size())) return out;
    if (n > 0 && !inside_any(std::string(opened.data(), static_cast<std::size_t>(n)), roots)) {
        return out;
    }
    const auto size = static_cast<std::uint64_t>(st.st_size);
    std::array<std::uint8_t, kPngSignature.size()> signature{};
    if (size < signature.size() || !read_exactly(fd.get(), signature.data(), signature.size()) ||
        signature != kPngSignature) {
        return out;
    }
    out.size = size;
    if (size > max_bytes) {
        out.status = Status::TooLarge;
        return out;
    }
    out.bytes.resize(static_cast<std::size_t>(size));
    std::copy(signature.begin(), signature.end(), out.bytes.begin());
    if (!read_exactly(fd.get(), out.bytes.data() + signature.size(), out.bytes.size() - 8)) {
        out.bytes.clear();  // the file shrank while it was read
        return out;
    }
    out.status = Status::Ok;
    return out;
}

std::optional<PngHeader> png_header(std::span<const std::uint8_t> bytes) {
    // The signature, IHDR's length and type, its 13 bytes of data.
    if (bytes.size() < 8 + 8 + 13) return std::nullopt;
    if (!std::equal(kPngSignature.begin(), kPngSignature.end(), bytes.begin())) return std::nullopt;
    const std::uint8_t* c = bytes.data() + 8;
    if (u32_be(c) != 13 || std::memcmp(c + 4, "IHDR", 4) != 0) return std::nullopt;
    const std::uint8_t* d = c + 8;
    PngHeader h;
    h.width = u32_be(d);
    h.height = u32_be(d + 4);
    h.bit_depth = d[8];
    h.color_type = d[9];
    const std::uint8_t compression = d[10];
    const std::uint8_t filter = d[11];
    const std::uint8_t interlace = d[12];
    constexpr std::uint32_t kMaxSide = 0x7fffffffu;
    if (h.width < 1 || h.height < 1 || h.width > kMaxSide || h.height > kMaxSide) {
        return std::nullopt;
    }
    const auto depth_in = [&](std::initializer_list<int> allowed) {
        return std::find(allowed.begin(), allowed.end(), h.bit_depth) != allowed.end();
    };
    bool depth_ok = false;
    switch (h.color_type) {
        case 0:
            depth_ok = depth_in({1, 2, 4, 8, 16});
            break;
        case 3:
            depth_ok = depth_in({1, 2, 4, 8});
            break;
        case 2:
        case 4:
        case 6:
            depth_ok = depth_in({8, 16});
            break;
        default:
            break;
    }
    if (!depth_ok || compression != 0 || filter != 0 || interlace > 1) return std::nullopt;
    return h;
}

}  // namespace harness::texture_file
