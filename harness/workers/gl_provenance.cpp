// gl_provenance.cpp: see gl_provenance.hpp.
#include "gl_provenance.hpp"

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <vector>

#include "backends/driver_env.hpp"

namespace harness::gl {

std::string mesa_environment() {
    const auto vars = driver_env::driver_variables(driver_env::process_environment());
    std::string out;
    for (const auto& v : vars) {
        if (!out.empty()) out += ';';
        out += v;
    }
    return out;
}

std::string loaded_gl_libraries() {
    std::ifstream in("/proc/self/maps");
    std::vector<std::string> seen;
    for (std::string line; std::getline(in, line);) {
        const auto slash = line.find('/');
        if (slash == std::string::npos) continue;
        const std::string path = line.substr(slash);
        const std::string name = path.substr(path.rfind('/') + 1);
        const bool gl = name.starts_with("libOSMesa") || name.starts_with("libEGL") ||
                        name.starts_with("libGL") || name.starts_with("libOpenGL") ||
                        name.starts_with("libglapi") || name.starts_with("libgallium") ||
                        name.starts_with("libvulkan_") || name.find("_dri.so") != std::string::npos;
        if (gl && std::find(seen.begin(), seen.end(), path) == seen.end()) seen.push_back(path);
    }
    std::string out;
    for (const auto& p : seen) out += (out.empty() ? "" : ";") + p;
    return out;
}

std::string mesa_version_of(const std::string& gl_version) {
    const auto at = gl_version.find("Mesa ");
    if (at == std::string::npos) return {};
    const std::string rest = gl_version.substr(at + 5);
    return rest.substr(0, rest.find(' '));
}

std::string debian_package_version(std::string_view package) {
    std::ifstream in("/var/lib/dpkg/status");
    if (!in) return {};
    std::string line;
    bool in_package = false;
    bool installed = false;
    std::string version;
    auto finish = [&]() -> bool { return in_package && installed && !version.empty(); };
    while (std::getline(in, line)) {
        if (line.empty()) {
            if (finish()) return version;
            in_package = installed = false;
            version.clear();
            continue;
        }
        if (line.starts_with("Package: ")) {
            in_package = std::string_view(line).substr(9) == package;
        } else if (line.starts_with("Status: ")) {
            installed = line.ends_with(" installed");
        } else if (line.starts_with("Version: ")) {
            version = line.substr(9);
        }
    }
    return finish() ? version : std::string();
}

}  // namespace harness::gl
