#include "conformance/shard.hpp"

#include <charconv>
#include <cstdlib>

namespace conformance {

EnvLookup process_environment() {
    return [](const std::string& name) -> std::optional<std::string> {
        const char* v = std::getenv(name.c_str());
        if (v == nullptr) return std::nullopt;
        return std::string(v);
    };
}

namespace {

// A decimal integer, the whole of the text; a ShardError naming `what` otherwise.
long parse_integer(const std::string& what, const std::string& text) {
    long v = 0;
    const char* end = text.data() + text.size();
    const auto [p, ec] = std::from_chars(text.data(), end, v);
    if (text.empty() || ec != std::errc() || p != end)
        throw ShardError(what + "='" + text + "' is not an integer");
    return v;
}

struct EngineShard {
    std::optional<long> index;
    std::optional<long> count;
    std::string source;
    std::string index_name;  // for messages
    std::string count_name;
};

std::optional<EngineShard> from_engines(const EnvLookup& env) {
    const auto get = [&](const char* name) -> std::optional<long> {
        const auto v = env(name);
        if (!v) return std::nullopt;
        return parse_integer(name, *v);
    };
    if (env("GTEST_SHARD_INDEX") || env("GTEST_TOTAL_SHARDS")) {
        return EngineShard{get("GTEST_SHARD_INDEX"), get("GTEST_TOTAL_SHARDS"), "gtest",
                           "GTEST_SHARD_INDEX", "GTEST_TOTAL_SHARDS"};
    }
    // GitLab sets CI_NODE_TOTAL (1) in every job and CI_NODE_INDEX only in parallel ones.
    if (env("CI_NODE_INDEX")) {
        const long i = *get("CI_NODE_INDEX");
        if (i < 1) throw ShardError("CI_NODE_INDEX=" + std::to_string(i) + " is not 1-based");
        return EngineShard{i - 1, get("CI_NODE_TOTAL"), "gitlab", "CI_NODE_INDEX", "CI_NODE_TOTAL"};
    }
    if (env("JOB_COMPLETION_INDEX")) {
        return EngineShard{get("JOB_COMPLETION_INDEX"), get("REFRASTER_SHARD_COUNT"), "kubernetes",
                           "JOB_COMPLETION_INDEX", "REFRASTER_SHARD_COUNT"};
    }
    if (env("SLURM_ARRAY_TASK_ID")) {
        const long id = *get("SLURM_ARRAY_TASK_ID");
        const long min = get("SLURM_ARRAY_TASK_MIN").value_or(0);
        const long step = get("SLURM_ARRAY_TASK_STEP").value_or(1);
        if (step < 1) throw ShardError("SLURM_ARRAY_TASK_STEP=" + std::to_string(step) + " < 1");
        if (id < min || (id - min) % step != 0)
            throw ShardError("SLURM_ARRAY_TASK_ID=" + std::to_string(id) +
                             " is not in the array from SLURM_ARRAY_TASK_MIN=" +
                             std::to_string(min) + " by " + std::to_string(step));
        std::optional<long> count = get("SLURM_ARRAY_TASK_COUNT");
        if (!count) {
            if (const auto max = get("SLURM_ARRAY_TASK_MAX")) count = (*max - min) / step + 1;
        }
        return EngineShard{(id - min) / step, count, "slurm", "SLURM_ARRAY_TASK_ID",
                           "SLURM_ARRAY_TASK_COUNT (or SLURM_ARRAY_TASK_MAX)"};
    }
    return std::nullopt;
}

}  // namespace

Shard resolve_shard(std::optional<int> index_flag, std::optional<int> count_flag,
                    const EnvLookup& env) {
    const std::optional<EngineShard> engine = from_engines(env);
    Shard s;
    long index = 0, count = 1;
    if (engine) {
        s.source = engine->source;
        if (!engine->index && !index_flag)
            throw ShardError(engine->count_name + " is set but " + engine->index_name +
                             " is not: give --shard-index");
        if (!engine->count && !count_flag)
            throw ShardError(engine->index_name + " names this shard but " + engine->count_name +
                             " does not give the count: give --shard-count" +
                             (engine->source == "kubernetes" ? " or REFRASTER_SHARD_COUNT" : ""));
        index = engine->index.value_or(0);
        count = engine->count.value_or(1);
    }
    if (index_flag || count_flag) {
        if (!engine) {
            if (index_flag && !count_flag)
                throw ShardError("--shard-index " + std::to_string(*index_flag) +
                                 " needs --shard-count");
            s.source = "flags";
        } else {
            s.source = "flags+" + engine->source;
        }
        if (index_flag) index = *index_flag;
        if (count_flag) count = *count_flag;
        if (index_flag && count_flag) s.source = "flags";
    }
    if (count < 1) throw ShardError("the shard count " + std::to_string(count) + " is below 1");
    if (count > kMaxShardCount)
        throw ShardError("the shard count " + std::to_string(count) + " is above " +
                         std::to_string(kMaxShardCount) + " (docs/limits.md)");
    if (index < 0 || index >= count)
        throw ShardError("the shard index " + std::to_string(index) + " is not in [0, " +
                         std::to_string(count) + ")" +
                         (s.source == "gitlab" ? " (CI_NODE_INDEX is 1-based)" : ""));
    s.index = static_cast<int>(index);
    s.count = static_cast<int>(count);
    return s;
}

std::string to_string(const Shard& s) {
    return std::to_string(s.index) + "/" + std::to_string(s.count) + " (" + s.source + ")";
}

}  // namespace conformance
