// refraster::Error: every refusal the tool reports carries the class of its exit code (README.md,
// "Exit codes"): bad input 2, a backend failure 3. The tool's main maps the class, not the type,
// so a type given the wrong class would change the tool's exit code.
#include "refraster/error.hpp"

#include <gtest/gtest.h>

#include <exception>
#include <stdexcept>
#include <string>

#include "backends/wire.hpp"
#include "conformance/merge.hpp"
#include "conformance/shard.hpp"
#include "harness/backend.hpp"
#include "harness/image_io.hpp"
#include "harness/scene.hpp"
#include "harness/study.hpp"
#include "harness/teach.hpp"
#include "refraster/profile.hpp"

namespace {

using refraster::ExitClass;

// The class seen through the base, as main sees it; binding the reference also checks, at
// compile time, that E is a refraster::Error.
template <class E>
ExitClass class_through_base(const E& e) {
    const refraster::Error& base = e;
    return base.exit_class();
}

// Thrown, caught as refraster::Error: the class, and the message unchanged.
template <class E>
void expect_caught_as_error(const E& thrown, ExitClass want) {
    try {
        throw thrown;
    } catch (const refraster::Error& e) {
        EXPECT_EQ(e.exit_class(), want);
        EXPECT_STREQ(e.what(), thrown.what());
        return;
    }
    ADD_FAILURE() << "not caught as refraster::Error: " << thrown.what();
}

TEST(Error, ClassesAreTheToolsExitCodes) {
    EXPECT_EQ(static_cast<int>(ExitClass::BadInput), 2);
    EXPECT_EQ(static_cast<int>(ExitClass::BackendFailure), 3);
}

TEST(Error, SceneErrorIsBadInput) {
    const harness::SceneError e("s.json", "draws[0].primitive", "expected triangles");
    EXPECT_EQ(class_through_base(e), ExitClass::BadInput);
    EXPECT_STREQ(e.what(), "s.json: draws[0].primitive: expected triangles");
    expect_caught_as_error(e, ExitClass::BadInput);
}

TEST(Error, ProfileErrorIsBadInput) {
    EXPECT_EQ(class_through_base(refraster::ProfileError("p")), ExitClass::BadInput);
    expect_caught_as_error(refraster::ProfileError("unknown profile x"), ExitClass::BadInput);
    // What the tool refuses for an unknown built-in name.
    try {
        (void)refraster::builtin_profile("no-such-profile");
        ADD_FAILURE() << "an unknown profile was accepted";
    } catch (const refraster::Error& e) {
        EXPECT_EQ(e.exit_class(), ExitClass::BadInput);
    }
}

TEST(Error, WireErrorIsABackendFailure) {
    const harness::wire::WireError e("worker: truncated frame", 32);
    EXPECT_EQ(class_through_base(e), ExitClass::BackendFailure);
    EXPECT_EQ(e.error_number(), 32);
    expect_caught_as_error(e, ExitClass::BackendFailure);
}

TEST(Error, TeachErrorIsBadInput) {
    expect_caught_as_error(harness::TeachError("nothing to draw"), ExitClass::BadInput);
}

TEST(Error, StudyErrorIsBadInput) {
    expect_caught_as_error(harness::StudyError("unknown study x"), ExitClass::BadInput);
}

TEST(Error, ShardErrorIsBadInput) {
    expect_caught_as_error(conformance::ShardError("CI_NODE_INDEX=x"), ExitClass::BadInput);
}

TEST(Error, MergeErrorIsBadInput) {
    expect_caught_as_error(conformance::MergeError("a: no results"), ExitClass::BadInput);
}

TEST(Error, ImageIoErrorIsBadInput) {
    expect_caught_as_error(harness::ImageIoError("o.png: cannot write"), ExitClass::BadInput);
}

TEST(Error, BackendOptionErrorsAreBadInput) {
    expect_caught_as_error(harness::BackendOptionError("--egl-device x"), ExitClass::BadInput);
    expect_caught_as_error(harness::MesaPrefixError("--mesa-prefix /x: not a directory"),
                           ExitClass::BadInput);
    // A MesaPrefixError is still caught as the BackendOptionError it is.
    try {
        throw harness::MesaPrefixError("m");
    } catch (const harness::BackendOptionError& e) {
        EXPECT_EQ(e.exit_class(), ExitClass::BadInput);
    }
}

// Every error stays a std::exception (one unambiguous base), so the catch-alls of the tool and
// of the harness still see it.
TEST(Error, EveryErrorIsAStdException) {
    const auto caught_as_std = [](auto&& thrown) {
        try {
            throw thrown;
        } catch (const std::runtime_error&) {
            return true;
        } catch (...) {
            return false;
        }
    };
    EXPECT_TRUE(caught_as_std(harness::SceneError("f", "", "m")));
    EXPECT_TRUE(caught_as_std(refraster::ProfileError("m")));
    EXPECT_TRUE(caught_as_std(harness::wire::WireError("m")));
    EXPECT_TRUE(caught_as_std(harness::TeachError("m")));
    EXPECT_TRUE(caught_as_std(harness::StudyError("m")));
    EXPECT_TRUE(caught_as_std(conformance::ShardError("m")));
    EXPECT_TRUE(caught_as_std(conformance::MergeError("m")));
    EXPECT_TRUE(caught_as_std(harness::ImageIoError("m")));
    EXPECT_TRUE(caught_as_std(harness::BackendOptionError("m")));
    EXPECT_TRUE(caught_as_std(harness::MesaPrefixError("m")));
}

}  // namespace
