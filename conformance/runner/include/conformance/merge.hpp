// merge.hpp: `refraster conformance merge`: one run's outputs from the outputs of its shards.
//
// Implements: reading each shard directory's results.jsonl (every record names its shard:
// shard.hpp), refusing what cannot be one run (a torn or unreadable record, shards of
// different counts, two directories claiming one shard, a case in two shards, records of
// another commit, profile, renderer, driver or Mesa version), naming the shards that are
// missing, then writing results.jsonl (the records, byte for byte), the images and explain
// views, and every report of reports.hpp into the output directory, as the unsharded run
// writes them. A missing shard does not stop the merge: its cases are absent from the report
// and the merge says so (merge.txt and the summary). The console's last line is run's: "N
// passed, M failed, K skipped".
//
// Deliberately does not: run or re-run anything, or merge runs whose shards came from
// different selections (a case in two shards is refused; a selection cannot be checked
// otherwise).
#pragma once

#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "conformance/suite.hpp"
#include "refraster/error.hpp"

namespace conformance {

class MergeError : public refraster::Error {
  public:
    explicit MergeError(const std::string& message)
        : refraster::Error(refraster::ExitClass::BadInput, message) {}
};

struct MergeSummary {
    std::size_t cases = 0;
    RunSummary counts;  // the merged records' statuses, counted as `run` counts them
    int shard_count = 1;
    std::vector<int> missing_shards;  // indexes in [0, shard_count) no directory holds
};

// Validates every input before writing anything; throws MergeError with one line naming the
// directory (and record or case) at fault.
MergeSummary merge_shards(const std::vector<std::filesystem::path>& shards,
                          const std::filesystem::path& output, std::ostream& console);

}  // namespace conformance
