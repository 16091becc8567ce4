// profile_io.hpp: reference profiles as files and command-line overrides.
//
// Implements: a profile file is a JSON object of the parameters refraster::profile_parameters
// lists, each a string ({"name": "llvmpipe-22.3", "tie_rule": "left-bottom", ...}); missing
// keys keep the built-in llvmpipe-22.3 values, unknown keys are errors. `--profile` takes a
// built-in name or a file; each `--profile-set key=value` then overrides one parameter.
//
// Deliberately does not: validate combinations (every combination is a profile).
#pragma once

#include <string>
#include <vector>

#include "refraster/profile.hpp"

namespace harness {

// A built-in name or a path to a profile file; throws refraster::ProfileError with the file
// name and the offending key.
refraster::Profile load_profile(const std::string& name_or_path);

// Applies "key=value" overrides in order.
void apply_profile_overrides(refraster::Profile& p, const std::vector<std::string>& overrides);

std::string profile_to_json(const refraster::Profile& p);

}  // namespace harness
