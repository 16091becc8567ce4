// records.hpp: what a run or a merge accepts as a case name and as a results.jsonl, and where
// it may write a case's files.
//
// Implements: the case-name rule (components of letters, digits, '_' and '-', the first
// character not '-', joined by single dots; at most kMaxCaseNameBytes bytes), checked once
// where names enter (scene discovery, every record a merge or a resume reads); the bounds of a
// results.jsonl (a regular file, opened without blocking, of at most kMaxResultsBytes bytes,
// kMaxRecordBytes a line and kMaxRecords records); and the path of a file a run owns, checked
// to lie inside the output directory with nothing on the way that is a symbolic link.
//
// Deliberately does not: parse records (merge.cpp and suite.cpp do, through the checks of
// record_check.hpp), or decide which files a run owns (suite.cpp's list).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace conformance {

// NAME_MAX (255) less what a run adds to a case's name for its longest file: the partial
// file of an atomic write of an image, ".NAME.BACKEND.partial-PID.png" (backend names up to
// 24 bytes, a PID up to 7 digits: 47 bytes), with room to spare.
inline constexpr std::size_t kMaxCaseNameBytes = 200;
// A record of the shipped suite takes 1 to 3 KB; a message or explanation would have to be a
// thousand times longer to reach this.
inline constexpr std::size_t kMaxRecordBytes = std::size_t{1} << 20;
// The reports parse every record into memory (about ten times the text).
inline constexpr std::uint64_t kMaxResultsBytes = std::uint64_t{256} << 20;
inline constexpr std::size_t kMaxRecords = 1'000'000;

// nullopt for a good case name, else what is wrong with it ("character 7 is ' '").
std::optional<std::string> case_name_problem(std::string_view name);

// One line of a results.jsonl and its number (from 1).
struct ResultLine {
    std::size_t number = 0;
    std::string text;
};

struct ResultLines {
    std::vector<ResultLine> lines;  // every line that ends with a newline; empty ones too
    std::size_t torn_bytes = 0;     // a last line without its newline (a killed writer)
    std::uint64_t size = 0;         // the file's size in bytes
};

// Reads `file` within the bounds above: refuses (std::runtime_error naming the file, and the
// line where one is too long) anything that is not a regular file (a FIFO, a device such as
// /dev/zero, a directory) before reading from it, a file over kMaxResultsBytes, a line over
// kMaxRecordBytes and more than kMaxRecords lines. A file that does not exist is an error
// too; the caller decides whether to ask.
ResultLines read_result_lines(const std::filesystem::path& file);

// `output`/`dir`/`file` (`dir` one plain directory name or empty, `file` a plain file name).
// Throws std::runtime_error when either is not plain, when `dir` or the file exists as
// anything but a directory or a regular file (a symbolic link included), or when the path
// does not lie inside `output` once resolved.
std::filesystem::path output_file(const std::filesystem::path& output, std::string_view dir,
                                  std::string_view file);

// Throws std::runtime_error naming the first of output/cases, output/images and
// output/explain that exists as anything but a directory (a symbolic link included): a run or
// merge checks them before it removes or writes anything.
void check_output_folders(const std::filesystem::path& output);

// output_file(output, dir, name + suffix) for a case name that case_name_problem accepts;
// throws with its problem otherwise.
std::filesystem::path case_file(const std::filesystem::path& output, std::string_view dir,
                                std::string_view name, std::string_view suffix);

}  // namespace conformance
