#include "harness/profile_io.hpp"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace harness {

namespace {

bool is_builtin(const std::string& name) {
    const auto names = refraster::builtin_profile_names();
    return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

void name_by_rules(refraster::Profile& p) {
    const std::string base = p.name.substr(0, p.name.find('+'));
    if (!is_builtin(base)) return;  // a name of the user's own: kept as given
    const auto mine = refraster::profile_parameters(p);
    const auto theirs = refraster::profile_parameters(refraster::builtin_profile(base));
    std::string changes;
    for (std::size_t i = 0; i < mine.size(); ++i) {
        if (mine[i].first == "name" || mine[i] == theirs[i]) continue;
        changes += (changes.empty() ? "+" : ",") + mine[i].first + "=" + mine[i].second;
    }
    p.name = base + changes;
}

std::string profile_source(const std::string& name_or_path) {
    return is_builtin(name_or_path) ? "built-in" : name_or_path;
}

refraster::Profile load_profile(const std::string& name_or_path) {
    if (is_builtin(name_or_path)) return refraster::builtin_profile(name_or_path);
    if (!std::filesystem::is_regular_file(name_or_path)) {
        const auto names = refraster::builtin_profile_names();
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
        throw refraster::ProfileError(name_or_path + ": neither a built-in profile (" + list +
                                      ") nor a file");
    }
    std::ifstream in(name_or_path);
    std::stringstream text;
    text << in.rdbuf();
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text.str());
    } catch (const nlohmann::json::parse_error& e) {
        throw refraster::ProfileError(name_or_path + ": invalid JSON: " + e.what());
    }
    if (!j.is_object()) throw refraster::ProfileError(name_or_path + ": expected a JSON object");
    refraster::Profile p;
    for (const auto& [key, value] : j.items()) {
        if (!value.is_string()) {
            throw refraster::ProfileError(name_or_path + ": " + key + ": expected a string value");
        }
        try {
            refraster::set_profile_parameter(p, key, value.get<std::string>());
        } catch (const refraster::ProfileError& e) {
            throw refraster::ProfileError(name_or_path + ": " + e.what());
        }
    }
    name_by_rules(p);
    return p;
}

void apply_profile_overrides(refraster::Profile& p, const std::vector<std::string>& overrides) {
    bool named = false;
    for (const auto& o : overrides) {
        const auto eq = o.find('=');
        if (eq == std::string::npos || eq == 0) {
            throw refraster::ProfileError("--profile-set " + o + ": expected key=value");
        }
        refraster::set_profile_parameter(p, o.substr(0, eq), o.substr(eq + 1));
        named = named || o.substr(0, eq) == "name";
    }
    // A rule the model does not read would rename the profile and change no pixel: refused,
    // judged on the profile with every override applied (one may open the route another uses).
    for (const auto& o : overrides) {
        const std::string key = o.substr(0, o.find('='));
        if (const auto why = refraster::unread_parameter(p, key))
            throw refraster::ProfileError("--profile-set " + o + ": not read under profile " +
                                          p.name + ": " + *why);
    }
    if (!named) name_by_rules(p);
}

std::string profile_rules(const refraster::Profile& p) {
    std::string out;
    for (const auto& [k, v] : refraster::profile_parameters(p)) {
        if (k != "name") out += (out.empty() ? "" : ";") + k + "=" + v;
    }
    return out;
}

std::string profile_to_json(const refraster::Profile& p) {
    nlohmann::ordered_json j;
    for (const auto& [k, v] : refraster::profile_parameters(p)) j[k] = v;
    return j.dump(2);
}

}  // namespace harness
