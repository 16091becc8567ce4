// The shard a process is, from flags and from each batch system's variables.
#include "conformance/shard.hpp"

#include <gtest/gtest.h>

#include <map>

namespace {

using conformance::resolve_shard;
using conformance::Shard;
using conformance::ShardError;

conformance::EnvLookup env(std::map<std::string, std::string> vars) {
    return [vars](const std::string& name) -> std::optional<std::string> {
        const auto it = vars.find(name);
        if (it == vars.end()) return std::nullopt;
        return it->second;
    };
}

std::string error_of(std::optional<int> i, std::optional<int> n,
                     std::map<std::string, std::string> vars) {
    try {
        resolve_shard(i, n, env(std::move(vars)));
    } catch (const ShardError& e) {
        return e.what();
    }
    return "";
}

TEST(Shard, NothingSetIsOneShard) {
    EXPECT_EQ(resolve_shard({}, {}, env({})), (Shard{0, 1, "none"}));
    // GitLab's CI_NODE_TOTAL=1 of an ordinary job is no shard.
    EXPECT_EQ(resolve_shard({}, {}, env({{"CI_NODE_TOTAL", "1"}})), (Shard{0, 1, "none"}));
}

TEST(Shard, EachEngine) {
    EXPECT_EQ(resolve_shard({}, {}, env({{"GTEST_SHARD_INDEX", "2"}, {"GTEST_TOTAL_SHARDS", "5"}})),
              (Shard{2, 5, "gtest"}));
    // GitLab counts from 1.
    EXPECT_EQ(resolve_shard({}, {}, env({{"CI_NODE_INDEX", "1"}, {"CI_NODE_TOTAL", "4"}})),
              (Shard{0, 4, "gitlab"}));
    EXPECT_EQ(resolve_shard({}, {}, env({{"CI_NODE_INDEX", "4"}, {"CI_NODE_TOTAL", "4"}})),
              (Shard{3, 4, "gitlab"}));
    EXPECT_EQ(
        resolve_shard({}, {}, env({{"JOB_COMPLETION_INDEX", "6"}, {"REFRASTER_SHARD_COUNT", "7"}})),
        (Shard{6, 7, "kubernetes"}));
    // Kubernetes: the count from the flag.
    EXPECT_EQ(resolve_shard({}, 8, env({{"JOB_COMPLETION_INDEX", "6"}})),
              (Shard{6, 8, "flags+kubernetes"}));
    // Slurm: the position in the array, from MIN by STEP; the count from COUNT or MAX.
    EXPECT_EQ(resolve_shard({}, {},
                            env({{"SLURM_ARRAY_TASK_ID", "14"},
                                 {"SLURM_ARRAY_TASK_MIN", "10"},
                                 {"SLURM_ARRAY_TASK_STEP", "2"},
                                 {"SLURM_ARRAY_TASK_COUNT", "4"}})),
              (Shard{2, 4, "slurm"}));
    EXPECT_EQ(resolve_shard({}, {},
                            env({{"SLURM_ARRAY_TASK_ID", "3"},
                                 {"SLURM_ARRAY_TASK_MIN", "1"},
                                 {"SLURM_ARRAY_TASK_MAX", "5"}})),
              (Shard{2, 5, "slurm"}));
}

TEST(Shard, FlagsWin) {
    const std::map<std::string, std::string> gitlab{{"CI_NODE_INDEX", "2"}, {"CI_NODE_TOTAL", "3"}};
    EXPECT_EQ(resolve_shard(0, 2, env(gitlab)), (Shard{0, 2, "flags"}));
    EXPECT_EQ(resolve_shard(2, {}, env(gitlab)), (Shard{2, 3, "flags+gitlab"}));
    EXPECT_EQ(resolve_shard(1, 2, env({})), (Shard{1, 2, "flags"}));
    EXPECT_EQ(resolve_shard({}, 3, env({})), (Shard{0, 3, "flags"}));
}

TEST(Shard, EnginesInOrder) {
    // GoogleTest's variables first, then GitLab, Kubernetes, Slurm.
    EXPECT_EQ(resolve_shard({}, {},
                            env({{"GTEST_SHARD_INDEX", "0"},
                                 {"GTEST_TOTAL_SHARDS", "2"},
                                 {"CI_NODE_INDEX", "3"},
                                 {"CI_NODE_TOTAL", "3"}}))
                  .source,
              "gtest");
    EXPECT_EQ(resolve_shard({}, {},
                            env({{"CI_NODE_INDEX", "3"},
                                 {"CI_NODE_TOTAL", "3"},
                                 {"JOB_COMPLETION_INDEX", "0"},
                                 {"REFRASTER_SHARD_COUNT", "2"}}))
                  .source,
              "gitlab");
}

TEST(Shard, RefusesWhatItCannotTrust) {
    EXPECT_NE(error_of({}, {}, {{"JOB_COMPLETION_INDEX", "1"}}).find("REFRASTER_SHARD_COUNT"),
              std::string::npos);
    EXPECT_NE(error_of({}, {}, {{"CI_NODE_INDEX", "0"}, {"CI_NODE_TOTAL", "2"}}).find("1-based"),
              std::string::npos);
    EXPECT_NE(error_of({}, {}, {{"CI_NODE_INDEX", "5"}, {"CI_NODE_TOTAL", "4"}}).find("[0, 4)"),
              std::string::npos);
    EXPECT_NE(error_of({}, {}, {{"GTEST_SHARD_INDEX", "x1"}, {"GTEST_TOTAL_SHARDS", "2"}})
                  .find("GTEST_SHARD_INDEX='x1' is not an integer"),
              std::string::npos);
    EXPECT_NE(error_of({}, {}, {{"GTEST_TOTAL_SHARDS", "2"}}).find("give --shard-index"),
              std::string::npos);
    EXPECT_NE(error_of(3, {}, {}).find("needs --shard-count"), std::string::npos);
    EXPECT_NE(error_of({}, {},
                       {{"SLURM_ARRAY_TASK_ID", "3"},
                        {"SLURM_ARRAY_TASK_MIN", "0"},
                        {"SLURM_ARRAY_TASK_STEP", "2"},
                        {"SLURM_ARRAY_TASK_COUNT", "4"}})
                  .find("not in the array"),
              std::string::npos);
    EXPECT_NE(error_of({}, {}, {{"SLURM_ARRAY_TASK_ID", "3"}}).find("SLURM_ARRAY_TASK_COUNT"),
              std::string::npos);
    EXPECT_NE(error_of(0, 0, {}).find("below 1"), std::string::npos);
    // The most shards a run may have (docs/limits.md), from a flag or a variable alike.
    EXPECT_EQ(error_of(4095, 4096, {}), "");
    EXPECT_NE(error_of(0, 4097, {}).find("above 4096"), std::string::npos);
    EXPECT_NE(error_of({}, {}, {{"GTEST_SHARD_INDEX", "0"}, {"GTEST_TOTAL_SHARDS", "2000000000"}})
                  .find("above 4096"),
              std::string::npos);
}

}  // namespace
