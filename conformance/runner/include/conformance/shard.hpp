// shard.hpp: which part of a run this process is, from the flags or from the batch system that
// started it.
//
// Implements: the shard index and count of `refraster conformance run`, from, in this order,
// - the flags --shard-index and --shard-count (each wins over what an engine says);
// - GoogleTest's GTEST_SHARD_INDEX and GTEST_TOTAL_SHARDS (ctest, Bazel, gtest-parallel);
// - GitLab CI parallel jobs: CI_NODE_INDEX (1-based) and CI_NODE_TOTAL;
// - Kubernetes Indexed Jobs: JOB_COMPLETION_INDEX, the count from --shard-count or
//   REFRASTER_SHARD_COUNT (a Job does not tell its pods its completions);
// - Slurm job arrays: SLURM_ARRAY_TASK_ID, counted from SLURM_ARRAY_TASK_MIN with
//   SLURM_ARRAY_TASK_STEP (default 1), the count SLURM_ARRAY_TASK_COUNT or, without it,
//   (MAX - MIN) / STEP + 1;
// with every value checked (an integer, 0 <= index < count), and which of them decided, for
// the record of every result. The first engine with its index variable set decides; an engine
// that names an index but no count is an error, never a guess.
//
// Deliberately does not: read the environment itself (the caller passes a lookup, so that
// tests need no process environment), or split cases (suite.hpp: case i of the sorted
// selection runs on shard i % count).
#pragma once

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

#include "refraster/error.hpp"

namespace conformance {

// The most shards a run may be split into (docs/limits.md): far more than there are machines
// to run them, and small enough that a merge's list of missing shards stays short.
inline constexpr int kMaxShardCount = 4096;

struct Shard {
    int index = 0;
    int count = 1;
    // What decided: "flags", "gtest", "gitlab", "kubernetes", "slurm", or "none" (one shard).
    std::string source = "none";
    friend bool operator==(const Shard&, const Shard&) = default;
};

class ShardError : public refraster::Error {
  public:
    explicit ShardError(const std::string& message)
        : refraster::Error(refraster::ExitClass::BadInput, message) {}
};

// A variable's value, or nullopt when it is not set.
using EnvLookup = std::function<std::optional<std::string>(const std::string&)>;
// The process's environment (getenv).
EnvLookup process_environment();

// Throws ShardError with one line naming the variable or flag at fault.
Shard resolve_shard(std::optional<int> index_flag, std::optional<int> count_flag,
                    const EnvLookup& env);

// "2/8 (gitlab)": for records and progress lines.
std::string to_string(const Shard& s);

}  // namespace conformance
