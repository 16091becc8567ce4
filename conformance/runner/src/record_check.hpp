// record_check.hpp: a results.jsonl record checked before anything is written from it.
//
// Implements: the shape of a record as harness::to_json_line writes it, field by field, as
// far as the reports, a merge and a resume read it (types, integer ranges, known statuses, a
// case name that case_name_problem accepts), with the JSON path of the first field at fault;
// and a record's identity, the fields that must be equal for records to be one run.
//
// Deliberately does not: refuse fields it does not know (a newer writer may add some).
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace conformance {

// nullopt for a good record, else "JSON_PATH: what is wrong" (e.g. "actual.seconds: not a
// number").
std::optional<std::string> record_problem(const nlohmann::json& record);

// Per side, the backend and the provenance that decides pixels (commit, profile and its
// rules, renderer, driver, Mesa and GL versions, fused arithmetic), as "side key" -> the
// value's JSON text; not the host's CPU flags or timings.
std::map<std::string, std::string> identity_of(const nlohmann::json& record);

// The first key whose values differ: "actual renderer \"a\" against \"b\"", or "" when equal.
std::string first_difference(const std::map<std::string, std::string>& a,
                             const std::map<std::string, std::string>& b);

// A JSON text for messages and pages: never throws on a string that is not UTF-8.
std::string dump_text(const nlohmann::json& value, int indent = -1);

}  // namespace conformance
