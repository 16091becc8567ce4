#include "conformance/deqp_runner.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <system_error>

namespace conformance {

namespace {

bool one_of(std::string_view w, std::initializer_list<std::string_view> words) {
    for (auto s : words)
        if (s == w) return true;
    return false;
}

// deqp-runner's TestStatus: the results dEQP itself reports, and the only ones that can sit
// inside UnexpectedImprovement(...).
bool is_test_status(std::string_view w) {
    return one_of(w, {"Pass", "Fail", "Crash", "Skip", "Warn", "Timeout"});
}

std::string improvement(std::string_view to) {
    return "UnexpectedImprovement(" + std::string(to) + ")";
}

// The significant digits of `v` in scientific form ("d.ddd" without the point) and its
// decimal exponent: the shortest that reads back as `v` without a precision, else `precision`
// digits after the first, correctly rounded from the exact value.
std::string scientific_digits(float v, std::optional<int> precision, int& exponent) {
    std::array<char, 192> buf{};
    const auto r =
        precision
            ? std::to_chars(buf.data(), buf.data() + buf.size(), static_cast<double>(v),
                            std::chars_format::scientific, *precision)
            : std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::scientific);
    const std::string_view sci(buf.data(), static_cast<std::size_t>(r.ptr - buf.data()));
    const auto e = sci.find('e');
    std::string digits;
    for (char c : sci.substr(0, e))
        if (c != '.') digits += c;
    exponent = std::atoi(std::string(sci.substr(e + 1)).c_str());
    return digits;
}

}  // namespace

std::optional<std::string> deqp_runner_word(std::string_view word) {
    if (is_test_status(word) || one_of(word, {"Flake", "KnownFlake", "Missing", "ExpectedFail"})) {
        return std::string(word);
    }
    constexpr std::string_view open = "UnexpectedImprovement(";
    if (word.size() > open.size() + 1 && word.substr(0, open.size()) == open &&
        word.back() == ')') {
        const auto inner = word.substr(open.size(), word.size() - open.size() - 1);
        if (is_test_status(inner)) return std::string(word);
        return std::nullopt;
    }
    // deqp-runner before UnexpectedImprovement wrote a pass against a listed failure so.
    if (word == "UnexpectedPass") return improvement("Pass");
    // This project's own words, from results.jsonl.
    if (word == "NotSupported") return "Skip";
    if (word == "InternalError") return "Fail";
    return std::nullopt;
}

std::string deqp_runner_status(std::string_view status, std::string_view raw_status) {
    if (status == "UnexpectedImprovement") {
        return improvement(raw_status.empty() ? "Fail" : deqp_runner_status(raw_status, ""));
    }
    if (const auto w = deqp_runner_word(status)) return *w;
    return "Fail";  // a word nobody knows is not a success
}

std::string reported_status(std::string_view status, std::string_view raw_status) {
    if (status == "UnexpectedPass" || status == "UnexpectedImprovement")
        return deqp_runner_status(status, raw_status);
    return std::string(status);
}

bool deqp_runner_is_success(std::string_view word) {
    return one_of(word, {"Pass", "Skip", "Warn", "Flake", "KnownFlake", "ExpectedFail"});
}

std::string deqp_runner_with_baseline(std::string_view result, std::string_view baseline) {
    // deqp-runner src/runner_results.rs, RunnerStatus::with_baseline, case by case.
    const auto in = [&](std::initializer_list<std::string_view> words) {
        return one_of(baseline, words);
    };
    if (result == "Fail") {
        if (in({"Fail", "ExpectedFail"})) return "ExpectedFail";
        // A fail where a crash or timeout was listed is a change to record.
        if (in({"Crash", "Timeout"})) return improvement("Fail");
    } else if (result == "Pass") {
        if (in({"Fail", "Crash", "Missing", "Timeout"})) return improvement("Pass");
    } else if (result == "Crash") {
        if (in({"Crash", "ExpectedFail"})) return "ExpectedFail";
    } else if (result == "Warn") {
        if (in({"Fail", "Crash"})) return improvement("Warn");
        if (in({"Warn"})) return "ExpectedFail";
    } else if (result == "Skip") {
        if (in({"Fail", "Crash", "Missing", "Timeout"})) return improvement("Skip");
    } else if (result == "Timeout") {
        if (in({"Timeout"})) return "ExpectedFail";
    }
    return std::string(result);
}

std::string deqp_runner_duration(float seconds) {
    // Rust's core::fmt for f32 without a precision: the shortest digits that read back as the
    // same f32 (flt2dec's shortest strategy), laid out as a plain decimal.
    if (std::isnan(seconds)) return "NaN";
    const std::string sign = std::signbit(seconds) ? "-" : "";
    if (std::isinf(seconds)) return sign + "inf";
    if (seconds == 0) return sign + "0";
    // std::to_chars in scientific form without a precision gives the shortest digits, and
    // among those the nearest to the exact value, as flt2dec does.
    const float magnitude = std::fabs(seconds);
    int exponent = 0;
    std::string digits = scientific_digits(magnitude, std::nullopt, exponent);
    // The two differ only when the exact value lies halfway between two shortest candidates:
    // std::to_chars rounds to the even one, flt2dec's Dragon fallback (format_shortest in
    // core/src/num/flt2dec/strategy/dragon.rs) rounds up. The exact decimal value of an f32
    // has at most 112 significant digits; 120 shows every one.
    const std::size_t n = digits.size();
    int exact_exponent = 0;
    const std::string exact = scientific_digits(magnitude, 120, exact_exponent);
    if (exact_exponent == exponent && exact.compare(0, n, digits) == 0 && exact[n] == '5' &&
        exact.find_first_not_of('0', n + 1) == std::string::npos) {
        // Rounded down at a tie: take the upper candidate, carrying as far as it goes.
        std::size_t i = n;
        while (i > 0 && digits[i - 1] == '9') digits[--i] = '0';
        if (i == 0) {
            digits.insert(digits.begin(), '1');
            digits.pop_back();
            ++exponent;
        } else {
            ++digits[i - 1];
        }
    }
    while (digits.size() > 1 && digits.back() == '0') digits.pop_back();
    // value = 0.digits x 10^point
    const int point = exponent + 1;
    const int n_digits = static_cast<int>(digits.size());
    std::string out;
    if (point <= 0) {
        out = "0." + std::string(static_cast<std::size_t>(-point), '0') + digits;
    } else if (point < n_digits) {
        out = digits.substr(0, static_cast<std::size_t>(point)) + "." +
              digits.substr(static_cast<std::size_t>(point));
    } else {
        out = digits + std::string(static_cast<std::size_t>(point - n_digits), '0');
    }
    return sign + out;
}

}  // namespace conformance
