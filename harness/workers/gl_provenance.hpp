// gl_provenance.hpp: what a worker records of the GL it really runs: the Mesa environment
// variables, the libraries mapped into the process, and Mesa's version.
#pragma once

#include <string>
#include <string_view>

namespace harness::gl {

// "K=V;K=V" for every variable that chooses the driver or changes its results
// (driver_env::selects_or_changes_driver), sorted so that equal environments give equal
// strings.
std::string mesa_environment();

// The Mesa, GL and Vulkan driver libraries this process has mapped (/proc/self/maps),
// ';'-separated, in the order first mapped: which build the worker really loaded, whatever the
// environment asked.
std::string loaded_gl_libraries();

// "22.3.6" from a GL_VERSION such as "4.5 (Core Profile) Mesa 22.3.6"; empty without "Mesa ".
std::string mesa_version_of(const std::string& gl_version);

// The installed version of a Debian package, from dpkg's database; empty when not found.
std::string debian_package_version(std::string_view package);

}  // namespace harness::gl
