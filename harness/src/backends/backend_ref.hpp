// backend_ref.hpp: the reference rasterizer behind the Backend interface.
#pragma once

#include <memory>

#include "harness/backend.hpp"

namespace harness {

std::unique_ptr<Backend> make_ref_backend(const BackendOptions& options);

}  // namespace harness
