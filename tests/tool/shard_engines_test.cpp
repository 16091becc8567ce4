// The batch-system examples of docs/examples/ (a GitLab CI job with `parallel:`, a Kubernetes
// Indexed Job, a Slurm job array): each parsed (YAML through yaml-cpp), and the variables each
// engine sets exercised by running three shards as separate processes, whose results together
// are the unsharded run's, each record naming its shard.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <map>
#include <nlohmann/json.hpp>
#include <regex>

#include "test_util.hpp"

namespace {

const std::filesystem::path kSource = REFRASTER_SOURCE_DIR;

// Every variable an engine might have left in the test's own environment, unset.
const std::string kClean = testutil::kUnsetShardVariables;

struct Record {
    std::string status;
    nlohmann::json shard;
};

std::map<std::string, Record> run(const std::string& vars, const std::filesystem::path& out) {
    const std::string cmd = kClean + vars + " " + testutil::shell_quote(testutil::refraster_bin()) +
                            " conformance run --cases 'smoke.*' --against ref --output " +
                            testutil::shell_quote(out.string()) + " > /dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()) >> 8, 0) << cmd;
    std::map<std::string, Record> m;
    std::istringstream in(testutil::read_text(out / "results.jsonl"));
    for (std::string line; std::getline(in, line);) {
        const auto j = nlohmann::json::parse(line);
        m[j["case"].get<std::string>()] = {j["status"].get<std::string>(), j["shard"]};
    }
    return m;
}

// Three shards from `vars(i)`: disjoint, together the unsharded run, each record naming
// shard i of 3 and `source`.
void expect_partition(const std::function<std::string(int)>& vars, int count,
                      const std::string& source) {
    testutil::TempDir dir;
    std::map<std::string, std::string> all;
    for (int i = 0; i < count; ++i) {
        SCOPED_TRACE(vars(i));
        const auto got = run(vars(i), dir.path() / ("s" + std::to_string(i)));
        EXPECT_FALSE(got.empty());
        for (const auto& [name, r] : got) {
            EXPECT_TRUE(all.emplace(name, r.status).second) << name << " ran on two shards";
            EXPECT_EQ(r.shard["index"], i) << name;
            EXPECT_EQ(r.shard["count"], count) << name;
            EXPECT_EQ(r.shard["source"], source) << name;
        }
    }
    std::map<std::string, std::string> whole;
    for (const auto& [name, r] : run("", dir.path() / "whole")) {
        whole[name] = r.status;
        EXPECT_EQ(r.shard["count"], 1);
        EXPECT_EQ(r.shard["source"], "none");
    }
    EXPECT_EQ(all, whole);
}

TEST(ShardEngines, GitlabParallelJob) {
    const YAML::Node ci = YAML::LoadFile((kSource / "docs/examples/gitlab-ci.yml").string());
    const YAML::Node job = ci["conformance"];
    ASSERT_TRUE(job.IsMap());
    const int parallel = job["parallel"].as<int>();
    EXPECT_EQ(parallel, 3);
    bool runs = false;
    for (const auto& line : job["script"])
        runs =
            runs || line.as<std::string>().find("refraster conformance run") != std::string::npos;
    EXPECT_TRUE(runs);
    expect_partition(
        [&](int i) {
            return "CI_NODE_INDEX=" + std::to_string(i + 1) +
                   " CI_NODE_TOTAL=" + std::to_string(parallel);
        },
        parallel, "gitlab");
}

TEST(ShardEngines, KubernetesIndexedJob) {
    const YAML::Node job =
        YAML::LoadFile((kSource / "docs/examples/kubernetes-indexed-job.yaml").string());
    EXPECT_EQ(job["kind"].as<std::string>(), "Job");
    EXPECT_EQ(job["spec"]["completionMode"].as<std::string>(), "Indexed");
    const int completions = job["spec"]["completions"].as<int>();
    const YAML::Node container = job["spec"]["template"]["spec"]["containers"][0];
    std::string count;
    for (const auto& e : container["env"])
        if (e["name"].as<std::string>() == "REFRASTER_SHARD_COUNT")
            count = e["value"].as<std::string>();
    // The manifest's count must be its completions, or shards would overlap or go missing.
    EXPECT_EQ(count, std::to_string(completions));
    EXPECT_NE(container["args"][0].as<std::string>().find("refraster conformance run"),
              std::string::npos);
    expect_partition(
        [&](int i) {
            return "JOB_COMPLETION_INDEX=" + std::to_string(i) + " REFRASTER_SHARD_COUNT=" + count;
        },
        completions, "kubernetes");
}

TEST(ShardEngines, SlurmJobArray) {
    const std::string script = testutil::read_text(kSource / "docs/examples/slurm-array.sh");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(script, m, std::regex(R"(#SBATCH --array=(\d+)-(\d+))")));
    const int lo = std::stoi(m[1]), hi = std::stoi(m[2]);
    EXPECT_NE(script.find("refraster conformance run"), std::string::npos);
    EXPECT_EQ(std::system(("bash -n " + testutil::shell_quote(
                                            (kSource / "docs/examples/slurm-array.sh").string()))
                              .c_str()),
              0);
    const int n = hi - lo + 1;
    expect_partition(
        [&](int i) {
            return "SLURM_ARRAY_TASK_ID=" + std::to_string(lo + i) +
                   " SLURM_ARRAY_TASK_MIN=" + std::to_string(lo) +
                   " SLURM_ARRAY_TASK_MAX=" + std::to_string(hi) +
                   " SLURM_ARRAY_TASK_COUNT=" + std::to_string(n) + " SLURM_ARRAY_TASK_STEP=1";
        },
        n, "slurm");
    // A stepped array (--array=10-14:2): the shard is the task's position in it.
    expect_partition(
        [&](int i) {
            return "SLURM_ARRAY_TASK_ID=" + std::to_string(10 + 2 * i) +
                   " SLURM_ARRAY_TASK_MIN=10 SLURM_ARRAY_TASK_MAX=14 SLURM_ARRAY_TASK_STEP=2";
        },
        3, "slurm");
}

TEST(ShardEngines, GoogleTestVariables) {
    expect_partition(
        [](int i) { return "GTEST_SHARD_INDEX=" + std::to_string(i) + " GTEST_TOTAL_SHARDS=3"; }, 3,
        "gtest");
}

TEST(ShardEngines, BadVariablesAreRefused) {
    testutil::TempDir dir;
    const std::string cmd = kClean + "JOB_COMPLETION_INDEX=1 " +
                            testutil::shell_quote(testutil::refraster_bin()) +
                            " conformance run --cases 'smoke.*' --against ref --output " +
                            testutil::shell_quote((dir.path() / "o").string()) + " 2>&1";
    const std::string out = testutil::command_output(cmd);
    EXPECT_NE(out.find("REFRASTER_SHARD_COUNT"), std::string::npos) << out;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "o" / "results.jsonl"));
}

}  // namespace
