// profile_io.hpp: reference profiles as files and command-line overrides.
//
// Implements: a profile file is a JSON object of the parameters refraster::profile_parameters
// lists, each a string ({"name": "llvmpipe-22.3", "tie_rule": "left-bottom", ...}); missing
// keys keep the built-in llvmpipe-22.3 values, unknown keys are errors. `--profile` takes a
// built-in name or a file; each `--profile-set key=value` then overrides one parameter.
// A profile whose rules differ from the built-in it is named after is renamed by its
// differences ("llvmpipe-22.3+tie_rule=right-top"), so that no result, trace or profile file
// names a built-in whose rules did not run; a name of the user's own is kept.
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

// Where a profile named by `name_or_path` comes from, as provenance records it: "built-in"
// for a built-in name, else the file's path.
std::string profile_source(const std::string& name_or_path);

// Applies "key=value" overrides in order.
void apply_profile_overrides(refraster::Profile& p, const std::vector<std::string>& overrides);

// Renames `p` by its differences from the built-in its name starts with (see above).
void name_by_rules(refraster::Profile& p);

// Every rule of the profile as "key=value;key=value" (the name left out): what provenance
// records, so that a result says which rules ran whatever the profile was called.
std::string profile_rules(const refraster::Profile& p);

std::string profile_to_json(const refraster::Profile& p);

}  // namespace harness
