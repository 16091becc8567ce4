// refraster fingerprint against OSMesa: llvmpipe comes back as llvmpipe-22.3 and softpipe as
// softpipe-22.3, every probed rule decided (harness/fingerprint.hpp).
#include <gtest/gtest.h>

#include "harness/backend.hpp"
#include "harness/fingerprint.hpp"
#include "refraster/profile.hpp"

namespace {

harness::FingerprintResult fingerprint_osmesa(harness::Driver driver) {
    harness::BackendOptions o;
    o.kind = harness::BackendKind::OSMesa;
    o.driver = driver;
    const auto backend = harness::make_backend(o);
    return harness::fingerprint(*backend);
}

TEST(FingerprintOsmesa, LlvmpipeIsLlvmpipe223) {
    const auto r = fingerprint_osmesa(harness::Driver::Llvmpipe);
    EXPECT_TRUE(r.complete()) << harness::fingerprint_text(r);
    EXPECT_EQ(r.profile, refraster::llvmpipe_22_3_profile()) << harness::fingerprint_text(r);
}

TEST(FingerprintOsmesa, SoftpipeIsSoftpipe223) {
    const auto r = fingerprint_osmesa(harness::Driver::Softpipe);
    EXPECT_TRUE(r.complete()) << harness::fingerprint_text(r);
    EXPECT_EQ(r.profile, refraster::softpipe_22_3_profile()) << harness::fingerprint_text(r);
}

}  // namespace
